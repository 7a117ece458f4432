// The linearized equations of a constrained multibody system about a consistent state
// (docs/linearization.md): ẋ = A x + B w, with x the independent coordinates and speeds that
// remain after the constraints are solved and ignorable coordinates are dropped, and w the
// parameters named as inputs. A and B are exact: every column is one evaluation of the
// right-hand side on dual numbers.
//
// Coordinates. Perturbations of q are taken in a chart with one coordinate per speed: a joint
// coordinate itself, or for a quaternion (free, spherical joints) the small rotation vector δθ in
// child-frame components, q = q* ⊗ (1, δθ/2) normalised, named `J.rx`, `J.ry`, `J.rz`. Its rate
// is the chart's: δθ̇ = ω + ½ δθ × ω.
//
// Constraints. The position constraints h(q) = 0 — the holonomic rows, a `rolling` constraint's
// normal row (its contact height) among them — fix rank(∂h/∂q) dependent coordinates; the
// velocity constraints A u + a0 = 0 (all rows, holonomic or not) fix rank(A) dependent speeds. A nonholonomic system
// therefore keeps more coordinates than speeds. Each perturbed state is made consistent exactly
// to first order: δq_d = −(∂h/∂q_d)⁻¹ ∂h/∂q_i δq_i, u_d solved from the constraints in duals.
//
// Ignorable coordinates. An independent coordinate or speed that nothing depends on at this
// state — its column of A is zero — is dropped, repeatedly (dropping a zero column removes one
// zero eigenvalue and leaves the others): positions along symmetry directions, wheel angles, and
// at a symmetric steady motion the speed of the motion itself.
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace kanesens::sim {

struct LinearizeOptions {
  // The coordinates / speeds to keep, by name, in this order; empty: chosen as documented above.
  // Every other independent one must be ignorable at the state.
  std::vector<std::string> coordinates, speeds;
  std::vector<int> inputs;  // parameter indices: the columns of B
  // A column is zero when its entries are at most this times A's largest entry.
  double ignorable_tolerance = 1e-10;
};

struct Linearization {
  std::vector<std::string> coordinates, speeds;  // x = [coordinates; speeds]
  std::vector<std::string> dependent_coordinates, dependent_speeds;
  std::vector<std::string> dropped;  // ignorable coordinates and speeds, dropped
  Eigen::MatrixXd A, B;              // n×n, n×(number of inputs)
  Eigen::VectorXd rates;             // ẋ at the state: zero at an equilibrium or a steady motion
  double position_residual = 0;      // max |h(q)| at the state
  double velocity_residual = 0;      // max |A u + a0| at the state
};

// The chart's coordinate names, one per speed (see above).
std::vector<std::string> chart_coordinate_names(const model::Model& model);

// Linearizes about y = [q; u] (nstate) at time t with the given parameter values (np). Throws
// InputError when a named coordinate or speed is unknown, dependent, or leaves a non-ignorable one
// out, and std::runtime_error when u̇ cannot be computed at the state (evaluate_rhs fails).
Linearization linearize(const model::Model& model, const std::vector<double>& parameters, double t,
                        const std::vector<double>& y, const LinearizeOptions& options = {});

// A direction in (parameters, state): tangents ṗ (np) and ẏ (nstate).
struct LinearizeDirection {
  std::vector<double> parameters, state;
};
// The same, and for each direction the derivative of A along it, dA[i] = d/dε A(p + ε ṗ, y + ε ẏ),
// in the same reduced coordinates — exact: second derivatives of the right-hand side, one dual
// of dual numbers (math/dual2.hpp) per state direction, the constraint solves differentiated
// too. The caller keeps y + ε ẏ consistent (ẏ tangent to the constraints) if it wants the
// derivative along the constraint manifold.
Linearization linearize(const model::Model& model, const std::vector<double>& parameters, double t,
                        const std::vector<double>& y, const LinearizeOptions& options,
                        const std::vector<LinearizeDirection>& directions, std::vector<Eigen::MatrixXd>& dA);

}  // namespace kanesens::sim
