// Workspace<S>: all scratch for evaluating a Model with scalar S (double, or Dual for exact
// derivatives). Allocated once (constructor); the evaluation functions never allocate.
// Sizes in comments: nb bodies, nj joints, nu speeds.
#pragma once
#include <array>
#include <vector>

#include "math/dual.hpp"
#include "math/planar.hpp"
#include "math/spatial.hpp"
#include "model/model.hpp"

// The scalars the dynamics is compiled for: double, Dual (one tangent), Dual2 (second order:
// eigenvalue and extremum sensitivities) and the multi-tangent widths of the blocked Jacobian and
// sensitivity passes. Each .cpp instantiates its templates with
// KANESENS_FOR_EACH_DYNAMICS_SCALAR(ITS_MACRO) (it includes math/dual2.hpp and math/multi_dual.hpp).
#define KANESENS_FOR_EACH_DYNAMICS_SCALAR(X) X(double) X(Dual) X(math::Dual2) KANESENS_FOR_EACH_MULTI_DUAL(X)

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

// Where the constraint system is structurally nonzero, from the Model alone (built once per
// workspace; dynamics/constraint_solve.cpp). Speed lists are closed under Model::speed_parent and
// listed parents first (dynamics/tree_factor.hpp).
struct ConstraintSparsity {
  explicit ConstraintSparsity(const Model& model);
  // Row i of A: the ancestor closure C_i of the speeds it can involve.
  std::vector<int> closure_start, closure;  // m + 1 offsets, speeds
  // Column j of M⁻¹ Aᵀ: T_j, the speeds below C_j (where M⁻¹ a_j can be nonzero).
  std::vector<int> support_start, support;  // m + 1 offsets, speeds
  // (A M⁻¹ Aᵀ)_ij is zero unless C_i and C_j share a speed: envelope_first[i] is the first such
  // j (the envelope of row i is [envelope_first[i], i]; Cholesky fills nothing outside it).
  std::vector<int> envelope_first;  // m
  std::size_t envelope_entries = 0, support_entries = 0;
};

// An articulated-body inertia [A B; Bᵀ C] at a body's Q (dynamics/articulated_body.cpp): the
// symmetric blocks A (rotational) and C (translational) by their entries xx, yy, zz, xy, xz, yz,
// B by rows.
template <class S>
struct ArticulatedInertiaT {
  S A[6], B[9], C[6];
};
using ArticulatedInertia = ArticulatedInertiaT<double>;

// Frames (math/spatial.hpp): every body's spatial quantities are taken at its reference point,
// the joint point Q_b of its inboard joint (on the body), with world-aligned axes; a joint's
// offset r_J = Q_child − Q_parent (small: a body length) moves them between neighbours. Bodies
// know their place in the world only through their tree's anchor (the world position of the
// root body's Q) plus the offset from it (tree_position): world positions are formed on request
// (dynamics/frames.hpp) and never enter the equations of motion.
template <class S>
struct Workspace {
  explicit Workspace(const Model& model);

  // Parameter stage (set_parameters).
  std::vector<S> parameters;        // np
  std::vector<S> values;            // one per expression slot
  std::vector<S> mass;              // nb
  std::vector<Mat3<S>> inertia_body;  // nb, central, body frame
  std::vector<Vec3<S>> reference_point;  // nb: Q_b in b's frame (its joint's child_point)
  std::vector<SpatialInertia<S>> inertia_local;  // nb: at Q_b, body-frame components
  std::vector<char> inertia_constant;  // nb: inertia_local carries no tangent (a plain number on
                                       //     S; rotate_constant_inertia applies)
  std::vector<char> inertia_diagonal;  // nb: inertia_local's I is diagonal, its off-diagonal
                                       //     entries exact zeros without tangents
                                       //     (rotate_diagonal_inertia applies)
  std::vector<int> inertia_h_axis;     // nb: k when inertia_local's h lies along e_k (its other
                                       //     components exact zeros without tangents), −1 otherwise
  std::vector<Vec3<S>> joint_axis, joint_axis2, plane_e1, plane_e2;  // nj, unit (0 if degenerate)
  std::vector<int> joint_axis_index;  // nj: i when joint_axis is exactly e_i (a rotation about it
                                      //     moves two columns), −1 otherwise or if it has a tangent
  std::vector<int> joint_axis2_index;  // nj: the same for joint_axis2
  std::vector<Vec3<S>> parent_point, child_point;                    // nj
  std::vector<Vec3<S>> joint_lever;  // nj: Q_P to the joint's parent point at q = 0, parent frame
                                     //     (root joints: the parent point, world)
  std::vector<int> joint_lever_axis;  // nj: k when joint_lever lies along e_k (as inertia_h_axis)
  std::vector<int> coordinate_angles;  // q offsets of the joint angles whose cos and sin the
                                       //     position stage takes (dynamics/joint_angles.hpp),
                                       //     in pairs (the last repeated)
  Vec3<S> gravity;
  Mat3<S> identity;                 // the ground's rotation

  // Position stage (q).
  std::vector<Mat3<S>> R;           // nb: body → world rotation
  std::vector<double> angle_cos, angle_sin;  // nq: cos, sin of the coordinate_angles' values
  std::vector<Vec3<S>> joint_offset;  // nj: r_J = Q_child − Q_parent, world components (roots: 0)
  std::vector<Vec3<S>> tree_anchor;   // nj, root joints only: world position of the child's Q
  std::vector<Vec3<S>> tree_position;  // nb: Q_b − its tree's anchor, world components
  std::vector<Vec6<S>> partial;     // nu: partial velocity of each speed, spatial, at the Q of
                                    //     its joint's child: (Ω_k, 0) rotation, (0, L_k) translation
  std::vector<SpatialInertia<S>> spatial_inertia;  // nb, at Q_b (3-D evaluation only)

  // Velocity stage (u).
  std::vector<Vec6<S>> velocity;   // nb: spatial velocity at Q_b (ω, v_Q)
  std::vector<Vec6<S>> bias_acceleration;  // nb: spatial acceleration at Q_b with u̇ = 0

  // Dynamics.
  std::vector<SpatialInertia<S>> composite_inertia;  // nb: subtree spatial inertia at Q_b (3-D)
  std::vector<Vec3<S>> speed_offset;  // nu: Q of speed k's body − Q of Model::speed_parent[k]'s
                                      //     (0 on the same body or a root; 3-D mass matrix)
  // The 3-D mass matrix's columns in pairs (l, l2) with speed_parent[l2] = l, which share their
  // walk to the root (l2 = −1: l alone); every speed once.
  std::vector<std::array<int, 2>> mass_matrix_columns;
  std::vector<Vec6<S>> wrench;     // nb: applied minus inertial (u̇ = 0) force vector at Q_b,
                                   //     then summed over the subtree
  bool mass_matrix_full = false;   // every pair of speeds moves a common body (a chain): no zeros
  // M is factored along the tree (dynamics/tree_factor.hpp) when it has structural zeros; for a
  // chain both factorisations do the same arithmetic and the dense one vectorises. Tests set it
  // to compare the two.
  bool tree_factor = false;
  MatX<S> mass_matrix;             // nu×nu; entries of unrelated speeds stay zero
  VecX<S> forcing;                 // nu
  MatX<S> cholesky;                // nu×nu: upper triangle = U, mass_matrix = Uᵀ U (U = Lᵀ), or
                                   //        the tree factor LᵀDL (tree_factor)
  std::vector<double> inverse_pivots;  // nu: 1/U(j, j) of the dense factor on double (its solve)
  // evaluate_rhs finds u̇ by the articulated-body algorithm (articulated_body_accelerations)
  // instead of M and its factor: set by the constructor, on every scalar, for unconstrained chains
  // whose joints have at most one speed each, and on double for unconstrained 3-D chains of at
  // least kArticulatedBodyMinSpeeds speeds, where it is the faster. M, its factor and f are then not formed by evaluate_rhs
  // (evaluate_mass_matrix_and_forcing still forms them); callers that read them after
  // evaluate_rhs turn it off (set_articulated_body).
  bool articulated_body = false;
  std::vector<ArticulatedInertiaT<S>> articulated_inertia;  // nb: I^A at Q_b (sized only when articulated_body)
  std::vector<std::array<S, 6>> articulated_bias;  // nb: p^A at Q_b, then the acceleration less the bias
  std::vector<std::array<S, 6>> articulated_columns;  // nu: U'/D at the parent's point (joints of one
                                                      //     speed), U_k = I^A s_k (several)
  std::vector<Mat6<double>> joint_inverse;  // nj: (Sᵀ I^A S)⁻¹ in the leading nu_j × nu_j block (several speeds)
  // The sweep from the leaves adds each child's share to its parent's slots, which therefore
  // hold the children's sums only: the first child of a parent to be swept (articulated_first,
  // per joint) writes them, the others add, and a body's own inertia and bias join them when
  // its joint is swept (articulated_has_children, per body).
  std::vector<unsigned char> articulated_first;         // nj
  std::vector<unsigned char> articulated_has_children;  // nb
  // Multi-tangent scalars: the factor of M's value (as cholesky) and one value solve;
  // the tangents are solved with it (apply_mass_inverse).
  Eigen::MatrixXd value_factor;    // nu×nu
  Eigen::VectorXd value_solution;  // nu
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
  ConstraintSparsity constraint_sparsity;
  // Solve with the sparsity above (dynamics/constraint_solve.cpp) when it saves work: needs
  // tree_factor; tests set it to compare with the dense solve.
  bool sparse_constraints = false;
  // General constraints (dynamics/constraints.cpp): q and the parameters as duals, nq and np
  // entries, and a position function's gradient: the coordinates' adjoints (nq) and its tape
  // (empty when the model has no general constraint).
  std::vector<DualT<S>> general_q1, general_p1, general_gradient;
  model::expr::Tape<DualT<S>> general_tape;

  // Planar evaluation (Model::evaluate_planar(); math/planar.hpp). R, joint_offset,
  // tree_anchor, tree_position and velocity are still filled (forces and energies read them);
  // the rest is planar, at the same reference points.
  std::vector<PVec<S>> partial_planar;             // nu: (Ω_z, L_x, L_y)
  std::vector<PlanarInertia<S>> inertia_planar;    // nb, at Q_b
  std::vector<PlanarInertia<S>> composite_planar;  // nb, subtree at Q_b
  std::vector<PVec<S>> velocity_planar, bias_planar, wrench_planar;  // nb
  // The articulated-body algorithm on the planar path (sized only when articulated_body).
  // On every scalar: dual passes of a planar chain take the recursion too (O(n), not M's O(n³)).
  std::vector<std::array<S, 6>> articulated_inertia_planar;  // nb: entries 00, 11, 22, 01, 02, 12
  std::vector<std::array<S, 3>> articulated_bias_planar;     // nb: p^A, then δa
  std::vector<std::array<S, 3>> articulated_columns_planar;  // nu: U'/D at the parent's point
  std::vector<Vec6<S>> prefix;  // ≤ 7: a joint's V_P + Σ_{c<k} s_c u_c (carried frames' velocity)
};

// The fewest speeds of a chain with multi-speed joints (spherical, free, …) for which the
// articulated-body algorithm beats forming and factoring M on double; on chains of one-speed
// joints it is the faster at every length (`kanesens bench rhs` on the spatial chains of docs/benchmarks.md).
inline constexpr int kArticulatedBodyMinSpeeds = 28;

// Turns the articulated-body evaluation on (sizing its arrays) or off; it stays off on a model
// with constraints (their multipliers need M's factor), and on a model evaluated with the planar
// path unless each of its joints has at most one speed. On scalars other than double the 3-D
// recursion too needs joints of at most one speed.
template <class S>
void set_articulated_body(const Model& model, Workspace<S>& ws, bool on);
// Whether evaluate_rhs finds u̇ by the articulated-body recursion: turned on, and sized for the
// path (planar or 3-D) the model is evaluated with now.
template <class S>
bool uses_articulated_body(const Model& model, const Workspace<S>& ws) {
  const auto nb = static_cast<std::size_t>(model.nbody());
  if (!ws.articulated_body) return false;
  if (model.evaluate_planar()) return ws.articulated_inertia_planar.size() == nb;
  return ws.articulated_inertia.size() == nb;
}

// Evaluates parameter-only expressions and the derived per-body/per-joint constants.
template <class S>
void set_parameters(const Model& model, Workspace<S>& ws, const S* parameters);

}  // namespace kanesens::dynamics
