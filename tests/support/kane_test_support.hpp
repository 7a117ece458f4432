// Helpers shared by the C++ tests (the verification tests tests/unit/test_kane_*.cpp,
// tests/regression/test_closed_form_trajectories.cpp, test_sensitivities_fd.cpp, and others).
// Deliberately small: building a model from inline YAML or a scene file, output grids, random
// states, quaternion algebra written independently of src/ (so the tests do not reuse the code
// they check).
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "model/build_model.hpp"
#include "dynamics/workspace.hpp"
#include "model/scene/parse_scene.hpp"
#include "layers.hpp"

namespace kanesens::testing {

inline Model model_from_text(const std::string& yaml, const std::string& name = "inline.yaml") {
  return build_model(parse_scene_text(yaml, name));
}

// The model of a scene file of the repository (path relative to its root, e.g. configs/x.yaml).
inline Model model_from_source_file(const std::string& path) {
  return build_model(parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/" + path));
}

// `outputs` ≥ 2 output times evenly spaced on [0, end].
inline std::vector<double> output_grid(double end, int outputs) {
  std::vector<double> t;
  for (int k = 0; k < outputs; ++k) t.push_back(end * k / (outputs - 1));
  return t;
}

// Hamilton product a ⊗ b of quaternions (w, x, y, z).
inline Eigen::Vector4d quat_mul(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

// Rotation matrix of a unit quaternion (w, x, y, z), child → parent, via v' = q ⊗ (0,v) ⊗ q*.
inline Eigen::Matrix3d quat_to_matrix(const Eigen::Vector4d& q) {
  Eigen::Matrix3d R;
  const Eigen::Vector4d qc(q[0], -q[1], -q[2], -q[3]);
  for (int c = 0; c < 3; ++c) {
    Eigen::Vector4d v = Eigen::Vector4d::Zero();
    v[c + 1] = 1;
    R.col(c) = quat_mul(quat_mul(q, v), qc).tail<3>();
  }
  return R;
}

inline Eigen::Matrix3d skew3(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
  return m;
}
inline Eigen::Vector3d unskew3(const Eigen::Matrix3d& W) {
  // Average the two copies of each entry of a (nearly) skew-symmetric matrix.
  return {0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1))};
}

// Kinematic differential equations written independently of src/dynamics: q̇ = u for every joint
// coordinate except quaternions, where q̇ = ½ q ⊗ (0, ω) (ω in child components).
inline std::vector<double> qdot_of(const Model& m, const double* q, const double* u) {
  std::vector<double> qd(m.nq);
  for (const Joint& J : m.joints) {
    if (J.quaternion_offset < 0) {
      for (int k = 0; k < J.nq; ++k) qd[J.q_offset + k] = u[J.u_offset + k];
      continue;
    }
    const int lin = J.type == JointType::free ? 3 : 0;
    for (int k = 0; k < lin; ++k) qd[J.q_offset + k] = u[J.u_offset + k];
    const double* e = q + J.quaternion_offset;
    const double* w = u + J.u_offset + lin;
    const Eigen::Vector4d d = 0.5 * quat_mul(Eigen::Vector4d(e[0], e[1], e[2], e[3]),
                                             Eigen::Vector4d(0, w[0], w[1], w[2]));
    for (int c = 0; c < 4; ++c) qd[J.quaternion_offset + c] = d[c];
  }
  return qd;
}

// A random state: every coordinate ~ U(-range_q, range_q), quaternions uniformly random unit
// quaternions, speeds ~ U(-range_u, range_u).
inline std::vector<double> random_state(const Model& m, std::mt19937_64& rng, double range_q = 1.0,
                                        double range_u = 1.0) {
  std::uniform_real_distribution<double> uq(-range_q, range_q), uu(-range_u, range_u);
  std::normal_distribution<double> gauss;
  std::vector<double> y(m.nstate());
  for (int i = 0; i < m.nq; ++i) y[i] = uq(rng);
  for (const Joint& J : m.joints) {
    if (J.quaternion_offset < 0) continue;
    Eigen::Vector4d e(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
    e.normalize();
    for (int c = 0; c < 4; ++c) y[J.quaternion_offset + c] = e[c];
  }
  for (int i = 0; i < m.nu; ++i) y[m.nq + i] = uu(rng);
  return y;
}

inline double max_abs(const Eigen::MatrixXd& a) {
  return a.cwiseAbs().maxCoeff();
}

}  // namespace kanesens::testing
