#include <cctype>
#include <span>
#include <string_view>
#include <utility>

#include "study/output_spec.hpp"

namespace kanesens::study {
namespace {

using sim::OutputKind;

constexpr std::pair<std::string_view, OutputKind> kKinds[] = {
    {"position", OutputKind::position},
    {"velocity", OutputKind::velocity},
    {"acceleration", OutputKind::acceleration},
    {"orientation", OutputKind::orientation},
    {"angular_velocity", OutputKind::angular_velocity},
    {"constraint_force", OutputKind::constraint_force},
    {"joint_load", OutputKind::joint_load},
    {"force_element", OutputKind::force_element},
    {"energy", OutputKind::energy},
    {"eigenvalues", OutputKind::eigenvalues}};

// A list of names (coordinates:, speeds:).
std::vector<std::string> read_names(const YAML::Node& n, const std::string& key, const model::YamlReader& r) {
  if (!n.IsSequence() || n.size() == 0) r.fail(n, key, "expected a list of names, found " + model::describe(n));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n.size(); ++i) out.push_back(r.read_string(n[i], key + "[" + std::to_string(i) + "]"));
  return out;
}

// type: eigenvalues — at: initial (required), count:, coordinates:, speeds:.
void parse_eigenvalues(OutputSpec& o, const YAML::Node& n, const std::string& key, const model::YamlReader& r) {
  r.check_keys(n, key, {"type", "at", "count", "coordinates", "speeds"});
  const YAML::Node at = r.required(n, "at", key);
  if (!at.IsScalar() || at.Scalar() != "initial")
    r.fail(at, key + ".at", "expected initial (the eigenvalues at the consistent initial state), found " + model::describe(at));
  o.reduce_where = r.location(at);
  if (const YAML::Node c = n["count"]) {
    const std::int64_t k = r.read_integer(c, key + ".count");
    if (k < 1 || k > 100000) r.fail(c, key + ".count", "expected a whole number from 1 (the eigenvalues kept, least stable first)");
    o.count = static_cast<long>(k);
  }
  if (const YAML::Node c = n["coordinates"]) {
    o.coordinates = read_names(c, key + ".coordinates", r);
    o.coordinates_where = r.location(c);
  }
  if (const YAML::Node s = n["speeds"]) {
    o.speeds = read_names(s, key + ".speeds", r);
    o.speeds_where = r.location(s);
  }
}

bool is_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

OutputSpec parse_one(const std::string& name, const YAML::Node& key_node, const YAML::Node& n,
                     const model::YamlReader& r) {
  const std::string key = "outputs." + name;
  OutputSpec o;
  o.name = name;
  o.where = r.location(key_node);
  if (!is_name(name))
    r.fail(key_node, key, "an output name is letters, digits and '_', not starting with a digit");
  r.require_map(n, key);
  if (n["type"]) {
    o.kind = r.read_choice<OutputKind>(n["type"], key + ".type", std::span(kKinds));
    const char* target = nullptr;
    switch (o.kind) {
      case OutputKind::position:
      case OutputKind::velocity:
      case OutputKind::acceleration: r.check_keys(n, key, {"type", "body", "point"}); target = "body"; break;
      case OutputKind::orientation:
      case OutputKind::angular_velocity: r.check_keys(n, key, {"type", "body"}); target = "body"; break;
      case OutputKind::constraint_force: r.check_keys(n, key, {"type", "constraint"}); target = "constraint"; break;
      case OutputKind::joint_load: r.check_keys(n, key, {"type", "joint"}); target = "joint"; break;
      case OutputKind::force_element: r.check_keys(n, key, {"type", "force"}); target = "force"; break;
      case OutputKind::energy: r.check_keys(n, key, {"type", "kind"}); break;
      case OutputKind::eigenvalues: parse_eigenvalues(o, n, key, r); return o;
      default: break;
    }
    if (target) {
      const YAML::Node t = r.required(n, target, key);
      o.target = r.read_string(t, key + "." + target);
      o.target_key = key + "." + target;
      o.target_where = r.location(t);
    }
    if (n["point"]) o.point = r.read_vec3(n["point"], key + ".point");
    if (o.kind == OutputKind::energy && n["kind"])
      o.energy = r.read_choice<sim::EnergyKind>(
          n["kind"], key + ".kind",
          {{"kinetic", sim::EnergyKind::kinetic}, {"potential", sim::EnergyKind::potential},
           {"total", sim::EnergyKind::total}});
    return o;
  }
  if (n["expression"]) {
    r.check_keys(n, key, {"expression"});
    o.kind = OutputKind::expression;
    o.expression = r.read_expr(n["expression"], key + ".expression");
    return o;
  }
  if (n["of"]) {
    r.check_keys(n, key, {"of", "at", "reduce", "at_event", "occurrence"});
    o.kind = OutputKind::reduction;
    o.expression = r.read_expr(n["of"], key + ".of");
    if ((n["at"] ? 1 : 0) + (n["reduce"] ? 1 : 0) + (n["at_event"] ? 1 : 0) > 1)
      r.fail(n, key, "give one of 'at' (a time or end), 'reduce' (integral, mean, rms, max, min, argmax, argmin) or 'at_event' (an event's name)");
    if (n["occurrence"] && !n["at_event"]) r.fail(n["occurrence"], key + ".occurrence", "'occurrence' goes with 'at_event'");
    if (const YAML::Node at = n["at"]) {
      o.reduce = sim::Reduction::at;
      o.reduce_where = r.location(at);
      if (at.IsScalar() && at.Scalar() == "end") o.at_end = true;
      else if (at.IsScalar()) {
        try {
          o.at = r.read_number(at, key + ".at");
        } catch (const InputError&) {
          r.fail(at, key + ".at", "expected a time (a number) or end, found " + model::describe(at));
        }
      } else {
        r.fail(at, key + ".at", "expected a time (a number) or end, found " + model::describe(at));
      }
    } else if (const YAML::Node red = n["reduce"]) {
      o.reduce_where = r.location(red);
      o.reduce = r.read_choice<sim::Reduction>(red, key + ".reduce",
                                                {{"integral", sim::Reduction::integral},
                                                 {"mean", sim::Reduction::mean},
                                                 {"rms", sim::Reduction::rms},
                                                 {"max", sim::Reduction::max},
                                                 {"min", sim::Reduction::min},
                                                 {"argmax", sim::Reduction::argmax},
                                                 {"argmin", sim::Reduction::argmin}});
    } else if (const YAML::Node ev = n["at_event"]) {
      o.reduce_where = r.location(ev);
      o.reduce = sim::Reduction::at_event;
      o.at_event = r.read_string(ev, key + ".at_event");
      if (const YAML::Node k = n["occurrence"]) {
        o.occurrence = static_cast<long>(r.read_integer(k, key + ".occurrence"));
        if (o.occurrence < 1) r.fail(k, key + ".occurrence", "expected a whole number >= 1 (1 is the first occurrence), found " + model::describe(k));
      }
    } else {
      r.fail(n, key, "'of' needs 'at' (a time or end), 'reduce' (integral, mean, rms, max, min, argmax, argmin) or 'at_event' (an event's name)");
    }
    return o;
  }
  r.fail(n, key, "expected 'type' (position, velocity, ...), 'expression' or 'of' (with at or reduce)");
}

}  // namespace

std::vector<OutputSpec> parse_outputs(const YAML::Node& node, const model::YamlReader& r) {
  std::vector<OutputSpec> out;
  if (!node || node.IsNull()) return out;
  r.require_map(node, "outputs");
  for (const auto& kv : node) {
    const std::string name = r.read_string(kv.first, "outputs");
    for (const OutputSpec& o : out)
      if (o.name == name) r.fail(kv.first, "outputs." + name, "output '" + name + "' is defined twice");
    out.push_back(parse_one(name, kv.first, kv.second, r));
  }
  return out;
}

std::vector<OutputSpec> parse_events(const YAML::Node& node, const model::YamlReader& r,
                                     const std::vector<OutputSpec>& outputs) {
  std::vector<OutputSpec> out;
  if (!node || node.IsNull()) return out;
  r.require_sequence(node, "events");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node n = node[i];
    const std::string at = "events[" + std::to_string(i) + "]";
    r.require_map(n, at);
    r.check_keys(n, at, {"name", "when", "direction", "action", "max_count"});
    const YAML::Node name_node = r.required(n, "name", at);
    OutputSpec o;
    o.name = r.read_string(name_node, at + ".name");
    o.where = r.location(name_node);
    o.event = true;
    if (!is_name(o.name))
      r.fail(name_node, at + ".name", "an event name is letters, digits and '_', not starting with a digit");
    for (const OutputSpec& p : outputs)
      if (p.name == o.name) r.fail(name_node, at + ".name", "'" + o.name + "' is already the name of an output");
    for (const OutputSpec& p : out)
      if (p.name == o.name) r.fail(name_node, at + ".name", "event '" + o.name + "' is defined twice");
    const std::string key = o.key();
    o.kind = OutputKind::reduction;
    o.reduce = sim::Reduction::event;
    o.expression = r.read_expr(r.required(n, "when", key), key + ".when");
    if (n["direction"])
      o.direction = r.read_choice<int>(n["direction"], key + ".direction", {{"rising", 1}, {"falling", -1}, {"both", 0}});
    if (n["action"])
      o.stop = r.read_choice<bool>(n["action"], key + ".action", {{"record", false}, {"stop", true}});
    o.max_count = 1000000;
    o.recorded_times = 100;
    if (n["max_count"]) {
      o.max_count = static_cast<long>(r.read_integer(n["max_count"], key + ".max_count"));
      if (o.max_count < 1) r.fail(n["max_count"], key + ".max_count", "expected a whole number >= 1, found " + model::describe(n["max_count"]));
      if (o.max_count > 100000)
        r.fail(n["max_count"], key + ".max_count", "at most 100000 (each occurrence's time is kept per sample); leave it out to count without a limit and keep the first 100 times");
      o.recorded_times = o.max_count;
    }
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace kanesens::study
