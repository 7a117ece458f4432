// A study's quantities of interest, resolved against the model: what to evaluate, in which
// order, and what each evaluation needs (docs/reference/study.md, "outputs"). Built once per
// run by the study layer (study/build_outputs.cpp), immutable, shared by every sample and rank;
// evaluated by sim/output_eval.hpp and driven per sample by sim/output_recorder.hpp.
//
// Every output is a node; each node owns `components.size()` consecutive value slots in one flat
// array (values[nvalues]), and expressions read other outputs by slot (expr::VarKind::quantity).
// A series node is evaluated at (t, y) at every output time; a scalar node gives one number per
// sample: a reduction of a one-component series node (`at` a time, `integral`, `mean`, `rms`)
// or an expression of scalar nodes and parameters. Hidden nodes are not recorded: the series an
// `of:` expression defines, and the multipliers of a constraint read by name in an expression.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "model/expr/expression.hpp"
#include "model/model.hpp"

namespace kanesens::sim {

enum class OutputKind : unsigned char {
  position, velocity, acceleration, orientation, angular_velocity,  // of a body (point)
  constraint_force, joint_load, force_element, energy,
  expression,  // of t, states, λ, parameters and other outputs
  reduction,   // one number per sample from a series: `of:` with `at:` or `reduce:`
  eigenvalues  // one number per sample each: the linearized system's eigenvalues at the initial state
};
enum class EnergyKind : unsigned char { kinetic, potential, total };
// event: the first time `of` crosses zero in a direction and the number of crossings (an
// `events:` entry; components NAME.time, NAME.count), located by the integrator.
// max, min, argmax, argmin: the extreme value of `of` over the sample and its time, among the
// roots of its rate (located by the integrator) and the two ends.
// at_event: the value of `of` at the k-th occurrence of an event.
enum class Reduction : unsigned char { at, integral, mean, rms, event, max, min, argmax, argmin, at_event };
inline bool is_extremum(Reduction r) {
  return r == Reduction::max || r == Reduction::min || r == Reduction::argmax || r == Reduction::argmin;
}
// What evaluating a node needs: parameters only, the position stage (and state expressions),
// the velocity stage, or the whole right-hand side (u̇ and λ).
enum class Level : unsigned char { parameters, position, velocity, acceleration };

// The component suffixes of a kind ("x", "y", "z"; "qw", ...; "fx", ...; "length", ...), or an
// empty list for a one-number kind. constraint_force: the constraint's row suffixes (its rows
// "C.x", "C.y" → "x", "y"; a one-row constraint → none).
std::vector<std::string> output_component_suffixes(OutputKind kind, const model::Model& m, int constraint);
// The level a kind needs by itself (expressions and reductions: from what they read).
Level kind_level(OutputKind kind, EnergyKind energy);

struct OutputNode {
  std::string name;  // the user's, or "work.of" / the constraint's name for hidden nodes
  OutputKind kind = OutputKind::expression;
  bool series = true;     // false: one number per sample
  bool recorded = true;   // false: hidden
  int slot = 0;           // first value slot
  std::vector<std::string> components;  // full component names, one per slot ("tip.x" or "ke")
  Level level = Level::position;
  std::vector<int> depends;  // node indices it reads (expressions, the series a reduction reduces)

  // Kind parameters (model indices; -1 when not used).
  int body = -1, joint = -1, constraint = -1, force = -1;
  EnergyKind energy = EnergyKind::total;
  std::array<model::expr::Expression, 3> point;  // body-frame point, expressions of parameters
  model::expr::Expression expression;            // kind expression (series or scalar)
  Reduction reduce = Reduction::at;              // kind reduction
  int of = -1;                                   //   the node reduced (series, one component)
  double at = 0;                                 //   Reduction::at: the time
  int quadrature = -1;                           //   integral, mean, rms: its quadrature component
  int direction = 0;                             //   event: +1 rising, −1 falling, 0 both
  bool stop = false;                             //   event: its first occurrence ends the sample
  long max_count = 0;                            //   event: occurrences counted at most
  long recorded_times = 0;                       //   event: occurrence times kept (/events/NAME/time)
  int event = -1;                                //   at_event: the event node
  long occurrence = 1;                           //   at_event: which occurrence (1 = the first)
  // Kind eigenvalues (sim/eigenvalue_outputs.hpp): the reduced coordinates and speeds (fixed
  // by the nominal sample), and how many eigenvalues are kept (components re0, im0, re1, ...).
  std::vector<std::string> linear_coordinates, linear_speeds;
  int eigenvalue_count = 0;
};

// The series nodes to evaluate for one purpose, dependencies first, and the level they need.
struct OutputProgram {
  std::vector<int> nodes;
  Level level = Level::parameters;
  bool empty() const { return nodes.empty(); }
};

struct OutputPlan {
  std::vector<OutputNode> nodes;  // in evaluation order: every node after the nodes it reads
  int nvalues = 0;

  // What is recorded, in the user's order: series value slots and their names, scalar ones.
  std::vector<int> series_slots, scalar_slots;
  std::vector<std::string> series_names, scalar_names;

  OutputProgram record;      // at every output time: the recorded series
  OutputProgram at;          // at the `at:` times: the series they read
  OutputProgram integrands;  // inside the integration: the series integral/mean/rms read
  OutputProgram events;      // inside the integration: the event functions
  std::vector<int> event_nodes;          // the event nodes (Reduction::event), in node order
  long event_occurrences = 0;            // the most occurrence times an event keeps (0: no events)
  OutputProgram extrema;                 // at the roots of their rates and the ends: the series extrema read
  std::vector<int> extremum_nodes;       // the max, min, argmax, argmin nodes, in node order
  OutputProgram at_event;                // at events: the series at_event reductions read
  std::vector<int> at_event_nodes;       // the at_event nodes, in node order
  std::vector<double> at_times;          // distinct `at:` times, increasing
  std::vector<int> quadrature_nodes;     // per quadrature component: its reduction node
  std::vector<int> scalar_expressions;   // scalar expression nodes, in evaluation order

  bool empty() const { return nodes.empty(); }
  int node_of_slot(int slot) const;
};

// Evaluation order of nodes given each node's dependencies: every node after the ones it
// depends on, otherwise in index order. If the dependencies have a cycle, returns {} and sets
// `cycle` to its nodes (n0 → n1 → ... → n0, n0 repeated at the end).
std::vector<int> order_outputs(const std::vector<std::vector<int>>& depends, std::vector<int>& cycle);

// Given nodes in evaluation order with their kinds, `series`, `recorded`, `depends` and slots
// set: fills each node's level, the programs, at_times, quadrature components and the recorded
// lists (recorded in `user_order`, node indices).
void finish_output_plan(OutputPlan& plan, const std::vector<int>& user_order);

}  // namespace kanesens::sim
