#include "model/joint_types.hpp"

namespace kanesens::model {

void set_joint_kind(Joint& j) {
  const std::string& n = j.name;
  switch (j.type) {
    case JointType::revolute:
    case JointType::prismatic:
      j.coordinate_names = {n + ".q"};
      j.speed_names = {n + ".u"};
      j.speeds = {SpeedAxis{j.type == JointType::revolute}};
      break;
    case JointType::cylindrical:
      j.coordinate_names = {n + ".q1", n + ".q2"};
      j.speed_names = {n + ".u1", n + ".u2"};
      j.speeds = {SpeedAxis{true}, SpeedAxis{false}};
      break;
    case JointType::universal:
      j.coordinate_names = {n + ".q1", n + ".q2"};
      j.speed_names = {n + ".u1", n + ".u2"};
      j.speeds = {SpeedAxis{true}, SpeedAxis{true}};
      j.speeds[1].carriers = 1;
      break;
    case JointType::planar:
      j.coordinate_names = {n + ".q1", n + ".q2", n + ".q3"};
      j.speed_names = {n + ".u1", n + ".u2", n + ".u3"};
      j.speeds = {SpeedAxis{false}, SpeedAxis{false}, SpeedAxis{true}};
      j.speeds[2].carriers = 2;
      break;
    case JointType::spherical:
      j.coordinate_names = {n + ".qw", n + ".qx", n + ".qy", n + ".qz"};
      j.speed_names = {n + ".wx", n + ".wy", n + ".wz"};
      for (int a = 0; a < 3; ++a) j.speeds.push_back(SpeedAxis{true, true, {-1, -1, -1}, a, 3});
      j.quaternion_offset = 0;
      break;
    case JointType::free:
      j.coordinate_names = {n + ".x", n + ".y", n + ".z", n + ".qw", n + ".qx", n + ".qy", n + ".qz"};
      j.speed_names = {n + ".vx", n + ".vy", n + ".vz", n + ".wx", n + ".wy", n + ".wz"};
      for (int a = 0; a < 3; ++a) j.speeds.push_back(SpeedAxis{false});
      for (int a = 0; a < 3; ++a) j.speeds.push_back(SpeedAxis{true, true, {-1, -1, -1}, a, 6});
      j.quaternion_offset = 3;
      break;
    case JointType::weld: break;
  }
}

}  // namespace kanesens::model
