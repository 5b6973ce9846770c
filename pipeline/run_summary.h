// The run's summary in report.json: the columns of Liu et al. 2013, Table 1 (issue 8 item 4) under
// the names the issue gives them, gathered from the stages' entries by the driver once a run has
// reached its route's last stage (a stage run by hand leaves the summary as it was).
#pragma once

#include <string>
#include <vector>

#include "core/stage_file.h"

namespace volts::pipeline {

/// The summary of `report` (report.json's content) for a run of `stages` (the route's stages,
/// in order; the last one made the Bézier elements):
/// - `route_stages`: `stages`;
/// - `tmesh_nodes`, `irregular_nodes_surface`, `irregular_nodes_interior`: stages.tmesh's
///   `nodes` and irregular counts (null on a route without tmesh);
/// - `bezier_elements`, `global_functions`, `min_scaled_jacobian`, `max_scaled_jacobian`,
///   `frac_scaled_jacobian_above_0_5`, `hausdorff_rel`, `volume_rel_error`,
///   `partition_of_unity_error`, `certified_valid`, `certified_invalid`, `undecided`: the last
///   stage's (null where it has none);
/// - `time_s`: each stage's `time_s` and their sum as `total` (seconds).
/// Throws core::InvalidInputError when a stage of `stages` has no entry or no time_s, naming it.
core::Json run_summary(const core::Json& report, const std::vector<std::string>& stages);

}  // namespace volts::pipeline
