// The hot path allocates nothing: evaluate_rhs and
// evaluate_mass_matrix_and_forcing on double, Dual and the multi-tangent MultiDual, and the
// solvers' callbacks of KaneProblem (rhs, Jacobian, all sensitivity right-hand sides at once),
// counted by replacing the global operator new for this test program.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "math/dual.hpp"
#include "math/multi_dual.hpp"
#include "sim/kane_problem.hpp"
#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "dynamics/embedding.hpp"
#include "model/scene/parse_scene.hpp"
#include "test_scenes.hpp"
#include "../support/layers.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

void* counted_alloc(std::size_t n, std::size_t align = 0) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (n == 0) n = 1;
  void* p = align > alignof(std::max_align_t) ? std::aligned_alloc(align, (n + align - 1) / align * align)
                                              : std::malloc(n);
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void* operator new(std::size_t n, std::align_val_t a) { return counted_alloc(n, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return counted_alloc(n, static_cast<std::size_t>(a)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try { return counted_alloc(n); } catch (...) { return nullptr; }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try { return counted_alloc(n); } catch (...) { return nullptr; }
}
// These replacements pair malloc with free themselves; GCC (at -O1, inlining a new expression
// into one of them) takes the free for a mismatched delete.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

using namespace kanesens::testing;

namespace {

// Allocations made while `f` runs.
template <class F>
long allocations_during(F&& f) {
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations.load();
}

template <class S>
void expect_no_allocation(const Model& m) {
  Workspace<S> ws(m);
  const std::vector<double> p0 = m.nominal_parameters();
  const std::vector<S> p(p0.begin(), p0.end());
  set_parameters(m, ws, p.data());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1, 1);
  std::vector<S> y(m.nstate()), ydot(m.nstate());
  for (auto& v : y) v = S(uni(rng));
  for (const Joint& J : m.joints)
    if (J.quaternion_offset >= 0) y[J.quaternion_offset] = y[J.quaternion_offset] + S(2.0);
  if constexpr (std::is_same_v<S, Dual>) y[0].d = 1.0;  // a Jacobian column
  if constexpr (math::is_multi_dual_v<S>)
    for (std::size_t r = 0; r < y.size(); ++r)
      y[r].set_tangents([&](int i) { return i == static_cast<int>(r) % S::tangents ? 1.0 : 0.5; }, S::tangents);
  const S t(0.3);
  evaluate_rhs(m, ws, t, y.data(), ydot.data());  // warm-up, outside the count
  const long n = allocations_during([&] {
    for (int i = 0; i < 3; ++i) {
      evaluate_rhs(m, ws, t, y.data(), ydot.data());
      evaluate_mass_matrix_and_forcing(m, ws, t, y.data(), y.data() + m.nq);
    }
  });
  EXPECT_EQ(n, 0) << m.name << ": " << n << " heap allocations in 3 evaluations";
}

struct Case {
  const char* name;
  Model model;
};
std::vector<Case> cases() {
  auto text = [](const std::string& t) { return build_model(parse_scene_text(t, "scene.yaml")); };
  auto file = [](const char* name) {
    return build_model(parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/" + name));
  };
  std::vector<Case> c;
  c.push_back({"chain", text(test_scenes::chain_scene(8))});
  c.push_back({"chain_tilted", text(test_scenes::chain_scene(8, 0.1))});
  // long enough for the articulated-body evaluation on double
  c.push_back({"chain_tilted_long", text(test_scenes::chain_scene(dynamics::kArticulatedBodyMinSpeeds, 0.1))});
  c.push_back({"spherical", text(test_scenes::kSphericalScene)});
  c.push_back({"free", text(test_scenes::kFreeScene)});
  c.push_back({"forces", text(test_scenes::kForcesScene)});
  c.push_back({"n_four_bar", text(test_scenes::n_four_bar(6))});  // the tree factor and the sparse constraint solve
  c.push_back({"andrews", file("andrews.yaml")});        // general position constraints (their gradients)
  c.push_back({"knife_edge", file("knife_edge.yaml")});  // a general velocity constraint
  c.push_back({"arm_3d", file("arm_3d.yaml")});          // a universal joint about two coordinate axes
  return c;
}

}  // namespace

TEST(NoAllocation, CounterSeesAllocations) {
  // The counter itself works (otherwise the tests below prove nothing).
  const long n = allocations_during([] {
    auto* v = new std::vector<double>(100);
    delete v;
  });
  EXPECT_EQ(n, 2);
}

TEST(NoAllocation, EvaluateRhsDouble) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
    expect_no_allocation<double>(c.model);
  }
}

TEST(NoAllocation, EvaluateRhsDual) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
    expect_no_allocation<Dual>(c.model);
  }
}

TEST(NoAllocation, EvaluateRhsMultiDual) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
#define KANESENS_EXPECT_NO_ALLOCATION(S) expect_no_allocation<S>(c.model);
    KANESENS_FOR_EACH_MULTI_DUAL(KANESENS_EXPECT_NO_ALLOCATION)  // every compiled width
#undef KANESENS_EXPECT_NO_ALLOCATION
  }
}

TEST(NoAllocation, EmbeddingIncludingARepartition) {
  // The embedding's RHS, and its re-arrangement of A_d's band when the partition changes.
  const int n = 6;
  const Model m = build_model(parse_scene_text(test_scenes::n_four_bar(n), "scene.yaml"));
  Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  set_parameters(m, ws, p.data());
  std::vector<double> q(static_cast<std::size_t>(m.nq)), u(static_cast<std::size_t>(m.nu));
  for (int i = 0; i < m.nq; ++i) {
    q[static_cast<std::size_t>(i)] = i <= n ? 0.7 : -0.7;
    u[static_cast<std::size_t>(i)] = i <= n ? -1.4 : 1.4;
  }
  evaluate_constraints(m, ws, 0.3, q.data(), u.data());
  const EmbeddingSets sets = choose_embedding(ws.constraint_matrix);
  ASSERT_EQ(sets.independent.size(), 1u);
  EmbeddingSets other = sets;  // another crank as the independent speed
  other.independent = {sets.independent[0] == 2 ? 3 : 2};
  other.dependent.clear();
  for (int k = 0; k < m.nu; ++k)
    if (k != other.independent[0]) other.dependent.push_back(k);
  EmbeddingScratch<double> sc(m, sets);
  auto reduced = [&](const EmbeddingSets& s) {
    std::vector<double> y(q);
    y.push_back(u[static_cast<std::size_t>(s.independent[0])]);
    return y;
  };
  const std::vector<double> y1 = reduced(sets), y2 = reduced(other);
  std::vector<double> ydot(y1.size());
  ASSERT_TRUE(embedded_rhs(m, ws, sc, sets, 0.3, y1.data(), ydot.data()));  // warm-up
  bool ok = true;
  const long count = allocations_during([&] {
    ok = embedded_rhs(m, ws, sc, other, 0.3, y2.data(), ydot.data()) && ok;
    ok = embedded_rhs(m, ws, sc, sets, 0.3, y1.data(), ydot.data()) && ok;
  });
  EXPECT_TRUE(ok);
  EXPECT_TRUE(sc.arranged_for(sets));
  EXPECT_EQ(count, 0) << count << " heap allocations";
}

TEST(NoAllocation, SolverCallbacks) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
    const Model& m = c.model;
    std::vector<InputRef> refs;
    for (int i = 0; i < m.nparam() && i < 5; ++i) refs.push_back({InputRef::Kind::parameter, i, m.parameters[static_cast<std::size_t>(i)].name});
    refs.push_back({InputRef::Kind::initial_condition, 0, "q0"});
    KaneProblem p(m, refs);
    p.set_sample(SampleInputs(m));
    const int n = p.size(), ns = static_cast<int>(refs.size());
    std::vector<double> y(static_cast<std::size_t>(n)), ydot(y.size()), J(y.size() * y.size());
    p.initial_state(y.data());
    std::vector<std::vector<double>> s(static_cast<std::size_t>(ns), std::vector<double>(y.size(), 0.1)), sd(s);
    std::vector<const double*> sp;
    std::vector<double*> sdp;
    for (int i = 0; i < ns; ++i) {
      sp.push_back(s[static_cast<std::size_t>(i)].data());
      sdp.push_back(sd[static_cast<std::size_t>(i)].data());
    }
    auto all = [&] {
      p.rhs(0.2, y.data(), ydot.data());
      p.jacobian(0.2, y.data(), ydot.data(), J.data());
      p.jacobian_times(0.2, y.data(), ydot.data(), s[0].data(), sd[0].data());
      p.sensitivity_rhs_all(0.2, y.data(), ydot.data(), ns, sp.data(), sdp.data());
      p.rhs_with_sensitivities(0.2, y.data(), ns, sp.data(), ydot.data(), sdp.data());
    };
    all();  // warm-up, outside the count
    const long count = allocations_during([&] { all(); });
    EXPECT_EQ(count, 0) << m.name << ": " << count << " heap allocations";
  }
}

// What a trajectory records at each output of a constrained scene: λ with its sensitivities
// (one sensitivity: the single-tangent path; six: the multi-tangent passes) and the residuals of
// the constraints and of their sensitivities.
TEST(NoAllocation, RecordingConstrainedOutputs) {
  for (const auto& c : cases()) {
    const Model& m = c.model;
    if (m.nconstraint_rows == 0) continue;
    for (int ns : {1, 6}) {
      SCOPED_TRACE(std::string(c.name) + ", " + std::to_string(ns) + " sensitivities");
      std::vector<InputRef> refs;
      for (int i = 0; i < ns; ++i) refs.push_back({InputRef::Kind::initial_condition, i % m.nstate(), "y0"});
      KaneProblem p(m, refs);
      p.set_sample(SampleInputs(m));
      const int n = p.size();
      std::vector<double> y(static_cast<std::size_t>(n)), lambda(static_cast<std::size_t>(m.nconstraint_rows)),
          dlambda(lambda.size() * static_cast<std::size_t>(ns));
      p.initial_state(y.data());
      std::vector<std::vector<double>> s(static_cast<std::size_t>(ns), std::vector<double>(y.size(), 0.1));
      std::vector<const double*> sp;
      for (const auto& si : s) sp.push_back(si.data());
      double position = 0, velocity = 0, sum = 0;
      auto record = [&] {
        p.multipliers_and_sensitivities(0.2, y.data(), sp.data(), lambda.data(), dlambda.data());
        p.multiplier_sensitivities(0.2, y.data(), sp.data(), dlambda.data());
        p.constraint_residuals(0.2, y.data(), position, velocity);
        sum += position + velocity;
        for (int i = 0; i < ns; ++i) {
          p.sensitivity_constraint_residuals(0.2, y.data(), i, sp[static_cast<std::size_t>(i)], position, velocity);
          sum += position + velocity;
        }
      };
      record();  // warm-up, outside the count
      const long count = allocations_during(record);
      EXPECT_EQ(count, 0) << count << " heap allocations";
      EXPECT_TRUE(std::isfinite(sum));
    }
  }
}
