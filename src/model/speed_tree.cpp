#include "model/speed_tree.hpp"

#include <cstddef>
#include <vector>

namespace kanesens::model {

void derive_speed_tree(Model& m) {
  const int nb = m.nbody();
  const std::vector<int>& order = m.joint_order;
  m.ancestor_speeds.assign(nb, {});
  for (int ji : order) {
    const Joint& j = m.joints[ji];
    std::vector<int> speeds = j.parent >= 0 ? m.ancestor_speeds[j.parent] : std::vector<int>{};
    for (int k = 0; k < j.nu; ++k) speeds.push_back(j.u_offset + k);
    m.ancestor_speeds[j.child] = speeds;
  }
  m.speed_parent.assign(static_cast<std::size_t>(m.nu), -1);
  m.speed_rotation.assign(static_cast<std::size_t>(m.nu), 0);
  m.speed_body.assign(static_cast<std::size_t>(m.nu), -1);
  for (const Joint& j : m.joints)
    for (int k = 0; k < j.nu; ++k) {
      const auto s = static_cast<std::size_t>(j.u_offset + k);
      m.speed_rotation[s] = j.speeds[static_cast<std::size_t>(k)].rotation ? 1 : 0;
      m.speed_body[s] = j.child;
    }
  m.speed_order.clear();
  for (int ji : order) {
    const Joint& j = m.joints[ji];
    const std::vector<int>& speeds = m.ancestor_speeds[j.child];  // ends with j's speeds
    for (int k = 0; k < j.nu; ++k) {
      const std::size_t at = speeds.size() - static_cast<std::size_t>(j.nu - k);
      m.speed_parent[static_cast<std::size_t>(j.u_offset + k)] = at > 0 ? speeds[at - 1] : -1;
      m.speed_order.push_back(j.u_offset + k);
    }
  }
  m.moves.assign(nb, std::vector<unsigned char>(m.nu, 0));
  for (int b = 0; b < nb; ++b)
    for (int k : m.ancestor_speeds[b]) m.moves[b][k] = 1;
  for (int ji : order) {
    const Joint& j = m.joints[ji];
    m.bodies[j.child].root_joint = j.parent >= 0 ? m.bodies[j.parent].root_joint : ji;
  }
}

}  // namespace kanesens::model
