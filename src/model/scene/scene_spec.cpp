#include "model/scene/scene_spec.hpp"

namespace kanesens::model {

const char* joint_type_name(JointType t) { return name_of(kJointTypes, t).data(); }
const char* force_kind_name(ForceKind k) { return name_of(kForceKinds, k).data(); }
const char* constraint_kind_name(ConstraintKind k) { return name_of(kConstraintKinds, k).data(); }

}  // namespace kanesens::model
