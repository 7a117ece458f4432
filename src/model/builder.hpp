// The scene builder shared by model/build_model.cpp (parameters, bodies, joints, topology,
// expressions, forces) and model/build_constraints.cpp (constraints and the nominal check):
// one pass over a SceneSpec that fills a Model and names the file, line and key of any bad input.
// Internal to the model layer.
#pragma once
#include <map>
#include <string>
#include <unordered_map>

#include "model/build_model.hpp"

namespace kanesens::model::detail {

bool is_identifier(const std::string& s);

class Builder {
 public:
  Builder(const SceneSpec& spec, const std::map<std::string, double>& overrides)
      : spec_(spec), overrides_(overrides) {}
  Model build();

 private:
  [[noreturn]] void fail(const SourceLocation& w, const std::string& key, const std::string& what);
  void build_parameters();
  Slot add(const ExprText& e, bool allow_state);
  Slot add_text(const std::string& text, const SourceLocation& w, const std::string& key);
  Slot3 add3(const Vec3Text& v, bool allow_state) { return {add(v[0], allow_state), add(v[1], allow_state), add(v[2], allow_state)}; }
  void build_bodies();
  int body_ref(const std::string& name, const SourceLocation& w, const std::string& key);
  void build_joints();
  void build_topology();
  void build_state_names();
  void build_joint_expressions();
  void build_forces();
  // Model::planar's criterion, on the expressions (not the nominal values), so that it holds for
  // every parameter set.
  bool is_planar() const;
  int joint_ref(const std::string& name, const SourceLocation& w, const std::string& key);
  void build_constraints();
  void check_nominal();

  const SceneSpec& spec_;
  const std::map<std::string, double>& overrides_;
  Model m_;
  expr::NameTable param_names_, state_names_, position_names_;
  std::unordered_map<std::string, int> body_index_, joint_index_;  // name → index (linear build)
};

}  // namespace kanesens::model::detail
