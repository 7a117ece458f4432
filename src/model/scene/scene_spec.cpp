#include "model/scene/scene_spec.hpp"

namespace kanesens::model {

const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::revolute: return "revolute";
    case JointType::prismatic: return "prismatic";
    case JointType::cylindrical: return "cylindrical";
    case JointType::universal: return "universal";
    case JointType::planar: return "planar";
    case JointType::spherical: return "spherical";
    case JointType::free: return "free";
    case JointType::weld: return "weld";
  }
  return "?";
}

const char* force_kind_name(ForceKind k) {
  switch (k) {
    case ForceKind::spring_damper: return "spring_damper";
    case ForceKind::force: return "force";
    case ForceKind::torque: return "torque";
  }
  return "?";
}

const char* constraint_kind_name(ConstraintKind k) {
  switch (k) {
    case ConstraintKind::coincident: return "coincident";
    case ConstraintKind::distance: return "distance";
    case ConstraintKind::coupler: return "coupler";
    case ConstraintKind::general: return "general";
    case ConstraintKind::rolling: return "rolling";
  }
  return "?";
}

}  // namespace kanesens::model
