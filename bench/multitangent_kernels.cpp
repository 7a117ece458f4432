// Multi-tangent dual numbers side by side: kanesens::math::MultiDual<N>, ceres::Jet<double, N>
// and Eigen's AutoDiffScalar<Matrix<double, N, 1>>, with the single-tangent Dual and plain
// double as references, on the kernels the dynamics spends its time in:
//   rotation   R = R_P · Rodrigues(a, q), then the world inertia R I_b Rᵀ (3×3 products)
//   inertia    a body's compact spatial inertia applied to a motion vector and the bias force
//              v ×* (I v) (spatial_inertia kernel of kane/spatial.hpp)
//   cholesky   a 6×6 SPD factorisation and solve on the AD type (what differentiating through
//              the solve costs), and for MultiDual the factorisation of the value part reused for
//              the N tangent right-hand sides (cholesky_reuse)
//   sincos     sin and cos of a vector of angles
// Every input carries N dense random tangents.
//
// Modes:
//   multitangent_kernels [google-benchmark flags]      wall-clock (Google Benchmark)
//   multitangent_kernels --count KERNEL TYPE N ITERS   runs one kernel ITERS times between
//       CALLGRIND_START/STOP_INSTRUMENTATION (valgrind --tool=callgrind --instr-atstart=no)
// bench/multitangent_table.py runs both and writes the JSON and the table. Built with
// -DKANESENS_BENCH=ON (bench/CMakeLists.txt).
#include <benchmark/benchmark.h>
#include <valgrind/callgrind.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <unsupported/Eigen/AutoDiff>

#include <ceres/jet.h>

#include "math/dual.hpp"
#include "math/multi_dual.hpp"

namespace {

using kanesens::math::Dual;
using kanesens::math::MultiDual;
template <int N> using Jet = ceres::Jet<double, N>;
template <int N> using EigenAD = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

// ---- uniform access to value and tangents -----------------------------------------------
template <class S> struct AD;
template <> struct AD<double> {
  static constexpr int n = 0;
  static double make(double v, const double*) { return v; }
  static double val(double x) { return x; }
  static double tan(double, int) { return 0; }
};
template <> struct AD<Dual> {
  static constexpr int n = 1;
  static Dual make(double v, const double* t) { return Dual(v, t[0]); }
  static double val(const Dual& x) { return x.v; }
  static double tan(const Dual& x, int) { return x.d; }
};
template <int N> struct AD<MultiDual<N>> {
  static constexpr int n = N;
  static MultiDual<N> make(double v, const double* t) {
    MultiDual<N> x(v);
    for (int i = 0; i < N; ++i) x.set_d(i, t[i]);
    return x;
  }
  static double val(const MultiDual<N>& x) { return x.v; }
  static double tan(const MultiDual<N>& x, int i) { return x.d(i); }
};
template <int N> struct AD<Jet<N>> {
  static constexpr int n = N;
  static Jet<N> make(double v, const double* t) {
    Jet<N> x(v);
    for (int i = 0; i < N; ++i) x.v[i] = t[i];
    return x;
  }
  static double val(const Jet<N>& x) { return x.a; }
  static double tan(const Jet<N>& x, int i) { return x.v[i]; }
};
template <int N> struct AD<EigenAD<N>> {
  static constexpr int n = N;
  static EigenAD<N> make(double v, const double* t) {
    EigenAD<N> x;
    x.value() = v;
    for (int i = 0; i < N; ++i) x.derivatives()[i] = t[i];
    return x;
  }
  static double val(const EigenAD<N>& x) { return x.value(); }
  static double tan(const EigenAD<N>& x, int i) { return x.derivatives()[i]; }
};

template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S> using Vec6 = Eigen::Matrix<S, 6, 1>;

std::mt19937& rng() {
  static std::mt19937 g(7);
  return g;
}
template <class S>
S random_scalar(double lo = -1, double hi = 1) {
  std::uniform_real_distribution<double> u(lo, hi), t(-1, 1);
  std::array<double, 32> tangents{};
  for (double& x : tangents) x = t(rng());
  return AD<S>::make(u(rng()), tangents.data());
}

// ---- kernels ------------------------------------------------------------------------------
template <class S>
Mat3<S> axis_angle(const Vec3<double>& a, const S& q) {
  using std::cos, std::sin;
  const S c = cos(q), s = sin(q), v = S(1) - c;
  Mat3<S> R;
  R << c + a[0] * a[0] * v, a[0] * a[1] * v - a[2] * s, a[0] * a[2] * v + a[1] * s,
       a[1] * a[0] * v + a[2] * s, c + a[1] * a[1] * v, a[1] * a[2] * v - a[0] * s,
       a[2] * a[0] * v - a[1] * s, a[2] * a[1] * v + a[0] * s, c + a[2] * a[2] * v;
  return R;
}

template <class S>
struct RotationKernel {
  Mat3<S> R_P, I_b;
  S q;
  Vec3<double> a{0.48, 0.6, 0.64};
  RotationKernel() {
    for (int i = 0; i < 9; ++i) {
      R_P(i) = random_scalar<S>();
      I_b(i) = random_scalar<S>();
    }
    q = random_scalar<S>();
  }
  Mat3<S> run() const {
    const Mat3<S> R = R_P * axis_angle<S>(a, q);
    return R * I_b * R.transpose();
  }
};

template <class S>
Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return Vec3<S>(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

template <class S>
struct InertiaKernel {
  S m;
  Vec3<S> h;
  Mat3<S> I;
  Vec6<S> V;
  InertiaKernel() {
    m = random_scalar<S>(1, 2);
    for (int i = 0; i < 3; ++i) h[i] = random_scalar<S>();
    for (int i = 0; i < 9; ++i) I(i) = random_scalar<S>();
    for (int i = 0; i < 6; ++i) V[i] = random_scalar<S>();
  }
  Vec6<S> apply(const Vec6<S>& x) const {
    const Vec3<S> w = x.template head<3>(), v = x.template tail<3>();
    Vec6<S> r;
    r.template head<3>() = I * w + cross<S>(h, v);
    r.template tail<3>() = m * v - cross<S>(h, w);
    return r;
  }
  Vec6<S> run() const {  // I V + V ×* (I V)
    const Vec6<S> p = apply(V);
    const Vec3<S> w = V.template head<3>(), v = V.template tail<3>();
    const Vec3<S> t = p.template head<3>(), F = p.template tail<3>();
    Vec6<S> r;
    r.template head<3>() = t + cross<S>(w, t) + cross<S>(v, F);
    r.template tail<3>() = F + cross<S>(w, F);
    return r;
  }
};

constexpr int kChol = 6;

// Uᵀ U = A, then x = A⁻¹ b, column-major upper factor in place (kane/cholesky.hpp's algorithm).
template <class S>
void cholesky_solve(S* A, S* x, int n) {
  using std::sqrt;
  for (int j = 0; j < n; ++j) {
    S* Uj = A + j * n;
    S d = Uj[j];
    for (int k = 0; k < j; ++k) d -= Uj[k] * Uj[k];
    Uj[j] = sqrt(d);
    const S inv = S(1) / Uj[j];
    for (int i = j + 1; i < n; ++i) {
      S* Ui = A + i * n;
      S s = Ui[j];
      for (int k = 0; k < j; ++k) s -= Uj[k] * Ui[k];
      Ui[j] = s * inv;
    }
  }
  for (int i = 0; i < n; ++i) {
    const S* Ui = A + i * n;
    S s = x[i];
    for (int k = 0; k < i; ++k) s -= Ui[k] * x[k];
    x[i] = s / Ui[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const S* Ui = A + i * n;
    x[i] /= Ui[i];
    for (int k = 0; k < i; ++k) x[k] -= x[i] * Ui[k];
  }
}

// The value part factored once, the tangents solved with that factor (dynamics'
// apply_mass_inverse): M0 x_i = b_i − M_i x0, pack operations on the tangents.
template <int N>
void cholesky_solve_reuse(const MultiDual<N>* A, MultiDual<N>* x, int n) {
  double U[kChol * kChol], x0[kChol];
  for (int i = 0; i < n * n; ++i) U[i] = A[i].v;
  for (int i = 0; i < n; ++i) x0[i] = x[i].v;
  cholesky_solve<double>(U, x0, n);  // U now holds the factor
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) x[i].subtract_tangents(A[k * n + i], x0[k]);  // symmetric
  for (int i = 0; i < n; ++i) {
    const double* Ui = U + i * n;
    MultiDual<N> s = x[i];
    for (int k = 0; k < i; ++k) s -= Ui[k] * x[k];
    x[i] = s / Ui[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const double* Ui = U + i * n;
    x[i] /= Ui[i];
    const MultiDual<N> xi = x[i];
    for (int k = 0; k < i; ++k) x[k] -= Ui[k] * xi;
  }
  for (int i = 0; i < n; ++i) x[i].v = x0[i];
}

template <class S>
struct CholeskyKernel {
  std::array<S, kChol * kChol> A;
  std::array<S, kChol> b;
  CholeskyKernel() {
    // A = B Bᵀ + n·1 with B random: SPD with random tangents that keep it symmetric.
    std::array<S, kChol * kChol> B;
    for (S& x : B) x = random_scalar<S>();
    for (int i = 0; i < kChol; ++i)
      for (int j = 0; j < kChol; ++j) {
        S s = S(i == j ? kChol : 0);
        for (int k = 0; k < kChol; ++k) s += B[i * kChol + k] * B[j * kChol + k];
        A[j * kChol + i] = s;
      }
    for (S& x : b) x = random_scalar<S>();
  }
  std::array<S, kChol> run() const {
    std::array<S, kChol * kChol> U = A;
    std::array<S, kChol> x = b;
    cholesky_solve<S>(U.data(), x.data(), kChol);
    return x;
  }
};

template <class S>
struct CholeskyReuseKernel : CholeskyKernel<S> {
  std::array<S, kChol> run() const {
    std::array<S, kChol> x = this->b;
    cholesky_solve_reuse(this->A.data(), x.data(), kChol);
    return x;
  }
};

constexpr int kAngles = 8;
template <class S>
struct SinCosKernel {
  std::array<S, kAngles> x;
  SinCosKernel() {
    for (S& v : x) v = random_scalar<S>(-3, 3);
  }
  S run() const {
    using std::cos, std::sin;
    S s = S(0);
    for (const S& v : x) s += sin(v) * cos(v);
    return s;
  }
};

template <class S> double checksum(const S& x) {
  double c = AD<S>::val(x);
  for (int i = 0; i < AD<S>::n; ++i) c += AD<S>::tan(x, i);
  return c;
}
template <class M> double checksum_all(const M& m) {
  double c = 0;
  for (const auto& x : m) c += checksum(x);
  return c;
}
template <class S, int R, int C> double checksum_all(const Eigen::Matrix<S, R, C>& m) {
  double c = 0;
  for (int i = 0; i < m.size(); ++i) c += checksum(m(i));
  return c;
}

template <template <class> class K, class S>
void bm(benchmark::State& state) {
  K<S> k;
  for (auto _ : state) {
    auto r = k.run();
    benchmark::DoNotOptimize(r);
    benchmark::ClobberMemory();
  }
  state.counters["tangents"] = AD<S>::n;
}

// --count: one kernel, a fixed number of runs, instrumented by callgrind.
template <template <class> class K, class S>
int count(long iters) {
  K<S> k;
  double sink = 0;
  CALLGRIND_START_INSTRUMENTATION;
  for (long i = 0; i < iters; ++i) {
    auto r = k.run();
    benchmark::DoNotOptimize(r);
  }
  CALLGRIND_STOP_INSTRUMENTATION;
  {
    auto r = k.run();
    if constexpr (std::is_same_v<decltype(r), S>) sink = checksum(r);
    else sink = checksum_all(r);
  }
  std::printf("%.17g\n", sink);
  return 0;
}

// Registers / dispatches every (kernel, type, N) of the table.
template <template <class> class K>
struct Kernel {
  template <class S>
  static void add(const std::string& name, const std::string& type, int n) {
    benchmark::RegisterBenchmark((name + "/" + type + "/" + std::to_string(n)).c_str(), bm<K, S>);
  }
  template <class S>
  static bool dispatch(const std::string& type, int n, const std::string& want_type, int want_n, long iters,
                       int& rc) {
    if (type != want_type || n != want_n) return false;
    rc = count<K, S>(iters);
    return true;
  }
};

template <template <class> class K, int N>
void for_types(const std::string& name, bool with_reference) {
  if (with_reference) {
    Kernel<K>::template add<double>(name, "double", 0);
    Kernel<K>::template add<Dual>(name, "Dual", 1);
  }
  Kernel<K>::template add<MultiDual<N>>(name, "MultiDual", N);
  Kernel<K>::template add<Jet<N>>(name, "ceres::Jet", N);
  Kernel<K>::template add<EigenAD<N>>(name, "Eigen::AutoDiffScalar", N);
}

template <template <class> class K, int N>
bool count_types(const std::string& type, int n, long iters, int& rc) {
  return Kernel<K>::template dispatch<double>("double", 0, type, n, iters, rc) ||
         Kernel<K>::template dispatch<Dual>("Dual", 1, type, n, iters, rc) ||
         Kernel<K>::template dispatch<MultiDual<N>>("MultiDual", N, type, n, iters, rc) ||
         Kernel<K>::template dispatch<Jet<N>>("ceres::Jet", N, type, n, iters, rc) ||
         Kernel<K>::template dispatch<EigenAD<N>>("Eigen::AutoDiffScalar", N, type, n, iters, rc);
}

template <template <class> class K>
void register_kernel(const std::string& name) {
  for_types<K, 1>(name, true);
  for_types<K, 2>(name, false);
  for_types<K, 4>(name, false);
  for_types<K, 6>(name, false);
  for_types<K, 8>(name, false);
  for_types<K, 16>(name, false);
}
template <template <class> class K>
bool count_kernel(const std::string& type, int n, long iters, int& rc) {
  return count_types<K, 1>(type, n, iters, rc) || count_types<K, 2>(type, n, iters, rc) ||
         count_types<K, 4>(type, n, iters, rc) || count_types<K, 6>(type, n, iters, rc) ||
         count_types<K, 8>(type, n, iters, rc) || count_types<K, 16>(type, n, iters, rc);
}

template <int N>
void register_reuse() {
  benchmark::RegisterBenchmark(("cholesky_reuse/MultiDual/" + std::to_string(N)).c_str(),
                               bm<CholeskyReuseKernel, MultiDual<N>>);
}
template <int N>
bool count_reuse(const std::string& type, int n, long iters, int& rc) {
  if (type != "MultiDual" || n != N) return false;
  rc = count<CholeskyReuseKernel, MultiDual<N>>(iters);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 6 && std::string(argv[1]) == "--count") {
    const std::string kernel = argv[2], type = argv[3];
    const int n = std::atoi(argv[4]);
    const long iters = std::atol(argv[5]);
    int rc = 2;
    bool found = false;
    if (kernel == "rotation") found = count_kernel<RotationKernel>(type, n, iters, rc);
    else if (kernel == "inertia") found = count_kernel<InertiaKernel>(type, n, iters, rc);
    else if (kernel == "cholesky") found = count_kernel<CholeskyKernel>(type, n, iters, rc);
    else if (kernel == "sincos") found = count_kernel<SinCosKernel>(type, n, iters, rc);
    else if (kernel == "cholesky_reuse")
      found = count_reuse<1>(type, n, iters, rc) || count_reuse<2>(type, n, iters, rc) ||
              count_reuse<4>(type, n, iters, rc) || count_reuse<6>(type, n, iters, rc) ||
              count_reuse<8>(type, n, iters, rc) || count_reuse<16>(type, n, iters, rc);
    if (!found) std::fprintf(stderr, "unknown kernel/type/N\n");
    return found ? rc : 2;
  }
  register_kernel<RotationKernel>("rotation");
  register_kernel<InertiaKernel>("inertia");
  register_kernel<CholeskyKernel>("cholesky");
  register_kernel<SinCosKernel>("sincos");
  register_reuse<1>();
  register_reuse<2>();
  register_reuse<4>();
  register_reuse<6>();
  register_reuse<8>();
  register_reuse<16>();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
