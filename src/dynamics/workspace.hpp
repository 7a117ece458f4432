// Workspace<S>: all scratch for evaluating a Model with scalar S (double, or Dual for exact
// derivatives). Allocated once (constructor); the evaluation functions never allocate.
// Sizes in comments: nb bodies, nj joints, nu speeds.
#pragma once
#include <vector>

#include "math/dual.hpp"
#include "math/planar.hpp"
#include "math/spatial.hpp"
#include "model/model.hpp"

namespace kanesens::dynamics {

// The vocabulary of the layers below: the scalar types and the algebra (math), the model.
using math::Dual;
using math::DualT;
using math::Mat3;
using math::Mat6;
using math::MatX;
using math::PlanarInertia;
using math::PVec;
using math::SpatialInertia;
using math::value_of;
using math::Vec3;
using math::Vec6;
using math::VecX;
namespace expr = model::expr;
using model::Constraint;
using model::Force;
using model::Joint;
using model::JointType;
using model::Model;
using model::Slot;
using model::Slot3;
using model::SpeedAxis;

template <class S>
struct Workspace {
  explicit Workspace(const Model& model);

  // Parameter stage (set_parameters).
  std::vector<S> parameters;        // np
  std::vector<S> values;            // one per expression slot
  std::vector<S> mass;              // nb
  std::vector<Mat3<S>> inertia_body;  // nb, central, body frame
  std::vector<Vec3<S>> joint_axis, joint_axis2, plane_e1, plane_e2;  // nj, unit (0 if degenerate)
  std::vector<Vec3<S>> parent_point, child_point;                    // nj
  Vec3<S> gravity;

  // Position stage (q).
  std::vector<Mat3<S>> R;        // nb: body → world rotation
  std::vector<Vec3<S>> com;      // nb: mass-center position, world
  std::vector<Vec3<S>> joint_point;  // nj: joint point Q (on the child), world
  std::vector<Vec6<S>> partial;  // nu: spatial partial velocity of each speed, (Ω_k, L_k + Q×Ω_k)
  std::vector<Mat3<S>> inertia_world;  // nb, central (3-D evaluation only)
  std::vector<SpatialInertia<S>> spatial_inertia;  // nb, at O (3-D evaluation only)

  // Velocity stage (u).
  std::vector<Vec6<S>> velocity;   // nb: spatial velocity (ω, v_O)
  std::vector<Vec6<S>> bias_acceleration;  // nb: spatial acceleration with u̇ = 0

  // Dynamics.
  std::vector<SpatialInertia<S>> composite_inertia;  // nb: subtree spatial inertia at O (3-D)
  std::vector<Vec6<S>> wrench;     // nb: applied minus inertial (u̇ = 0) force vector at O, then
                                   //     summed over the subtree
  MatX<S> mass_matrix;             // nu×nu
  VecX<S> forcing;                 // nu
  MatX<S> cholesky;                // nu×nu: upper triangle = U, mass_matrix = Uᵀ U (U = Lᵀ)
  VecX<S> udot;                    // nu
  VecX<S> qdot;                    // nq
  S time = S(0);

  // Constraints (m = model.nconstraint_rows rows of A u + a0 = 0).
  MatX<S> constraint_matrix;       // m×nu: A
  VecX<S> constraint_bias;         // m: −(Ȧu + ȧ0), minus the Baumgarte terms when enabled
  VecX<S> velocity_residual;       // m: A u + a0
  VecX<S> position_residual;       // m: g(q, t) of holonomic rows, 0 for the others
  VecX<S> multipliers;             // m: λ, with M u̇ = f + Aᵀλ
  MatX<S> minv_at;                 // nu×m: M⁻¹ Aᵀ
  MatX<S> schur;                   // m×m: A M⁻¹ Aᵀ
  MatX<S> schur_factor;            // m×m: its pivoted Cholesky factor (lower, permuted)
  VecX<S> schur_rhs;               // m
  MatX<S> nullspace;               // m×m scratch for redundant constraints
  VecX<S> scratch_m, scratch_nu;   // m, nu
  std::vector<int> schur_pivots;   // m
  int constraint_rank = 0;         // rank of A M⁻¹ Aᵀ at the last solve
  // General constraints (dynamics/constraints.cpp): q and the parameters as first- and second-order
  // duals, nq and np entries (empty when the model has no general constraint).
  std::vector<DualT<S>> general_q1, general_p1;
  std::vector<DualT<DualT<S>>> general_q2, general_p2;

  // Planar evaluation (Model::evaluate_planar(); math/planar.hpp). R, com, joint_point and
  // velocity are still filled (forces and energies read them); the rest is planar.
  std::vector<PVec<S>> partial_planar;             // nu: (Ω_z, L + Q×Ω)_{z,x,y}
  std::vector<PlanarInertia<S>> inertia_planar;    // nb, at O
  std::vector<PlanarInertia<S>> composite_planar;  // nb, subtree at O
  std::vector<PVec<S>> velocity_planar, bias_planar, wrench_planar;  // nb
  std::vector<Vec6<S>> prefix;  // ≤ 7: a joint's V_P + Σ_{c<k} s_c u_c (carried frames' velocity)
};

// Evaluates parameter-only expressions and the derived per-body/per-joint constants.
template <class S>
void set_parameters(const Model& model, Workspace<S>& ws, const S* parameters);

}  // namespace kanesens::dynamics
