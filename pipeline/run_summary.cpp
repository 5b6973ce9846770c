#include "run_summary.h"

#include <algorithm>

#include "core/errors.h"

namespace volts::pipeline {

core::Json run_summary(const core::Json& report, const std::vector<std::string>& stages) {
  if (stages.empty()) throw core::InvalidInputError("run_summary: no stages");
  const auto it = report.find("stages");
  auto entry = [&](const std::string& stage) -> const core::Json& {
    if (it == report.end() || !it->is_object() || !it->contains(stage) || !(*it)[stage].is_object())
      throw core::InvalidInputError("report.json: no entry for stage " + stage + " (run it first)");
    return (*it)[stage];
  };
  // A figure of one stage, null where that stage does not report it.
  auto figure = [](const core::Json& s, const char* key) { return s.contains(key) ? s[key] : core::Json(nullptr); };
  core::Json sum = core::Json::object();
  sum["route_stages"] = stages;
  const bool tmesh = std::find(stages.begin(), stages.end(), "tmesh") != stages.end();
  const core::Json none = core::Json::object();
  const core::Json& t = tmesh ? entry("tmesh") : none;
  sum["tmesh_nodes"] = figure(t, "nodes");
  sum["irregular_nodes_surface"] = figure(t, "irregular_nodes_surface");
  sum["irregular_nodes_interior"] = figure(t, "irregular_nodes_interior");
  const core::Json& last = entry(stages.back());
  for (const char* k : {"bezier_elements", "global_functions", "min_scaled_jacobian", "max_scaled_jacobian", "frac_scaled_jacobian_above_0_5",
                        "hausdorff_rel", "volume_rel_error", "partition_of_unity_error", "certified_valid", "certified_invalid", "undecided"})
    sum[k] = figure(last, k);
  core::Json times = core::Json::object();
  double total = 0;
  for (const std::string& stage : stages) {
    const core::Json& s = entry(stage);
    if (!s.contains("time_s") || !s["time_s"].is_number())
      throw core::InvalidInputError("report.json: stage " + stage + " has no time_s");
    times[stage] = s["time_s"];
    total += s["time_s"].get<double>();
  }
  times["total"] = total;
  sum["time_s"] = times;
  return sum;
}

}  // namespace volts::pipeline
