// The tree of speeds derived from the joints' tree: which speeds move each body, each speed's
// parent speed (the branch-induced sparsity of M: Featherstone 2008 §6.5) and each body's root
// joint. Run by build_model once the joints are in topological order (Model::joint_order).
#pragma once
#include "model/model.hpp"

namespace kanesens::model {

// Fills m.ancestor_speeds, m.speed_parent, m.speed_order, m.moves and the bodies' root_joint
// from m.joints, m.bodies and m.joint_order.
void derive_speed_tree(Model& m);

}  // namespace kanesens::model
