#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "util/error.hpp"
#include "workprecision.hpp"

namespace kanesens::bench {

using namespace kanesens::model;
using namespace kanesens::sim;

// Diagnostics of a recorded trajectory (its own outputs only).
Diagnostics diagnose(const Model& m, const std::vector<double>& times, const Trajectory& tr, std::size_t ns,
                     int outputs) {
  Diagnostics d;
  const std::size_t n = static_cast<std::size_t>(m.nstate());
  const std::size_t T = static_cast<std::size_t>(std::max(outputs, 0));
  if (T == 0) return d;
  if (!tr.energy.empty()) {
    d.energy_drift = 0;
    for (std::size_t k = 0; k < T; ++k) d.energy_drift = std::max(d.energy_drift, std::abs(tr.energy[k] - tr.energy[0]));
    d.energy_drift_final = tr.energy[T - 1] - tr.energy[0];
  }
  for (const Joint& J : m.joints) {
    if (J.quaternion_offset < 0) continue;
    if (std::isnan(d.quaternion_drift)) d.quaternion_drift = 0;
    for (std::size_t k = 0; k < T; ++k) {
      const double* e = &tr.states[k * n + static_cast<std::size_t>(J.quaternion_offset)];
      const double norm = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
      d.quaternion_drift = std::max(d.quaternion_drift, std::abs(norm - 1));
    }
  }
  if (!tr.position_residual.empty()) {
    d.position_residual = d.velocity_residual = 0;
    for (std::size_t k = 0; k < T; ++k) {
      d.position_residual = std::max(d.position_residual, tr.position_residual[k]);
      d.velocity_residual = std::max(d.velocity_residual, tr.velocity_residual[k]);
    }
  }
  if (ns > 0 && !tr.sensitivities.empty() && T > 1) {
    std::vector<double> lognorm(T);
    for (std::size_t k = 0; k < T; ++k) {
      double s2 = 0;
      for (std::size_t j = 0; j < n * ns; ++j) s2 += tr.sensitivities[k * n * ns + j] * tr.sensitivities[k * n * ns + j];
      lognorm[k] = 0.5 * std::log(s2);
    }
    d.sens_norm_final = std::exp(lognorm[T - 1]);
    d.sens_rate = (lognorm[T - 1] - lognorm[0]) / (times[T - 1] - times[0]);
    // Least-squares slope over the second half of the outputs reached.
    const std::size_t k0 = T / 2;
    double st = 0, sl = 0, stt = 0, stl = 0, cnt = 0;
    for (std::size_t k = k0; k < T; ++k) {
      st += times[k];
      sl += lognorm[k];
      stt += times[k] * times[k];
      stl += times[k] * lognorm[k];
      cnt += 1;
    }
    const double den = cnt * stt - st * st;
    if (cnt >= 2 && den > 0) d.sens_slope = (cnt * stl - st * sl) / den;
  }
  return d;
}

Errors compare(const Setup& s, const Trajectory& tr, std::size_t ns, const Solution& ref) {
  Errors e;
  const std::size_t n = static_cast<std::size_t>(s.model.nstate());
  const std::size_t R = ref.index.size();
  double sum2 = 0, linf = 0;
  bool finite = true;
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t i = 0; i < n; ++i) {
      const double d = tr.states[ref.index[r] * n + i] - ref.states[r * n + i];
      if (!std::isfinite(d)) finite = false;
      sum2 += d * d;
      linf = std::max(linf, std::abs(d));
    }
  if (!finite) return e;  // failed run: outputs past the failure are NaN
  e.l2 = std::sqrt(sum2 / static_cast<double>(R * n));
  e.linf = linf;
  const std::size_t last = ref.index[R - 1];
  e.final_rel = e.final_abs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double yr = ref.states[(R - 1) * n + i];
    const double d = std::abs(tr.states[last * n + i] - yr);
    const double rel = d / std::max(std::abs(yr), s.o.error_floor);
    e.final_abs = std::max(e.final_abs, d);
    if (rel >= e.final_rel) {
      e.final_rel = rel;
      e.worst_component = s.model.state_names[i];
    }
  }
  if (!ref.energy.empty() && !tr.energy.empty()) {
    e.energy_error = 0;
    for (std::size_t r = 0; r < R; ++r) e.energy_error = std::max(e.energy_error, std::abs(tr.energy[ref.index[r]] - ref.energy[r]));
  }
  if (ns > 0 && !tr.sensitivities.empty() && !ref.sensitivities.empty()) {
    double s2 = 0;
    for (std::size_t r = 0; r < R; ++r)
      for (std::size_t j = 0; j < n * ns; ++j) {
        const double d = tr.sensitivities[ref.index[r] * n * ns + j] - ref.sensitivities[r * n * ns + j];
        s2 += d * d;
      }
    e.sens_l2 = std::sqrt(s2 / static_cast<double>(R * n * ns));
    e.sens_final_rel = 0;
    for (std::size_t p = 0; p < ns; ++p) {
      double scale = 0;
      for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(ref.sensitivities[((R - 1) * n + i) * ns + p]));
      for (std::size_t i = 0; i < n; ++i) {
        const double sr = ref.sensitivities[((R - 1) * n + i) * ns + p];
        const double d = std::abs(tr.sensitivities[(last * n + i) * ns + p] - sr);
        const double den = std::max(std::abs(sr), s.o.error_floor * scale);
        e.sens_final_rel = std::max(e.sens_final_rel, den > 0 ? d / den : d);
      }
    }
  }
  return e;
}

Solution load_reference(const Setup& s, std::size_t ns) {
  const std::string& path = s.o.reference_file;
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError({path, 0, 0}, "--reference-file", std::string("cannot read: ") + e.what());
  }
  if (!doc["time"] || !doc["states"]) throw InputError({path, 0, 0}, "--reference-file", "needs 'time' and 'states'");
  const std::size_t n = static_cast<std::size_t>(s.model.nstate());
  std::vector<std::size_t> column(n);
  for (std::size_t i = 0; i < n; ++i) column[i] = i;
  if (doc["state_names"]) {
    std::map<std::string, std::size_t> where;
    for (std::size_t i = 0; i < doc["state_names"].size(); ++i) where[doc["state_names"][i].as<std::string>()] = i;
    for (std::size_t i = 0; i < n; ++i) {
      auto it = where.find(s.model.state_names[i]);
      if (it == where.end()) throw InputError({path, 0, 0}, "--reference-file", "no state named '" + s.model.state_names[i] + "'");
      column[i] = it->second;
    }
  }
  auto num = [](const YAML::Node& v) { return v.IsNull() ? nan_value : v.as<double>(); };
  Solution ref;
  const double scale = std::max(1.0, std::abs(s.times.back()));
  for (std::size_t r = 0; r < doc["time"].size(); ++r) {
    const double t = num(doc["time"][r]);
    auto it = std::find_if(s.times.begin(), s.times.end(), [&](double x) { return std::abs(x - t) <= 1e-9 * scale; });
    if (it == s.times.end())
      throw InputError({path, 0, 0}, "--reference-file", "time " + std::to_string(t) + " is not an output time of the study");
    ref.index.push_back(static_cast<std::size_t>(it - s.times.begin()));
    const YAML::Node row = doc["states"][r];
    for (std::size_t i = 0; i < n; ++i) ref.states.push_back(num(row[column[i]]));
    if (ns > 0 && doc["sensitivities"] && doc["sensitivities"].size() > r) {
      const YAML::Node sr = doc["sensitivities"][r];
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t p = 0; p < ns; ++p) ref.sensitivities.push_back(num(sr[column[i]][p]));
    }
  }
  if (ref.index.empty()) throw InputError({path, 0, 0}, "--reference-file", "has no times");
  if (ref.sensitivities.size() != ref.index.size() * n * ns) ref.sensitivities.clear();
  return ref;
}

}  // namespace kanesens::bench
