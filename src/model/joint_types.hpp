// What each joint type is: its coordinates and speeds, their names, and the motion of each
// speed (model.hpp SpeedAxis). The table behind docs/reference/scene.md's joint list.
#pragma once
#include "model/model.hpp"

namespace kanesens::model {

// Fills j.coordinate_names, j.speed_names, j.speeds and j.quaternion_offset (relative to the
// joint's first coordinate) from j.type and j.name.
void set_joint_kind(Joint& j);

}  // namespace kanesens::model
