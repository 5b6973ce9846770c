// pipeline::run_summary: Table 1's columns under the names, from the stages' entries.
#include "run_summary.h"

#include <gtest/gtest.h>

#include "core/errors.h"

using namespace volts;

namespace {

core::Json polycube_route_report() {
  core::Json r;
  r["stages"]["classify"] = {{"time_s", 0.25}, {"corners", 8}};
  r["stages"]["split"] = {{"time_s", 0.5}};
  r["stages"]["polycube"] = {{"time_s", 1.0}};
  r["stages"]["tmesh"] = {{"time_s", 2.0}, {"nodes", 11240}, {"irregular_nodes_surface", 0}, {"irregular_nodes_interior", 160}};
  r["stages"]["extract"] = {{"time_s", 0.125},
                            {"bezier_elements", 4096},
                            {"global_functions", 10880},
                            {"min_scaled_jacobian", 0.53},
                            {"max_scaled_jacobian", 1.0},
                            {"frac_scaled_jacobian_above_0_5", 1.0},
                            {"hausdorff_rel", 1e-3},
                            {"volume_rel_error", 4e-4},
                            {"partition_of_unity_error", 4e-16},
                            {"certified_valid", 4096},
                            {"certified_invalid", 0},
                            {"undecided", 0}};
  return r;
}

}  // namespace

TEST(RunSummary, GathersTable1sColumnsFromTheStagesAndSumsTheirTimes) {
  const core::Json r = polycube_route_report();
  const core::Json s = pipeline::run_summary(r, {"classify", "split", "polycube", "tmesh", "extract"});
  EXPECT_EQ(s["tmesh_nodes"], 11240);
  EXPECT_EQ(s["irregular_nodes_surface"], 0);
  EXPECT_EQ(s["irregular_nodes_interior"], 160);
  for (const char* k : {"bezier_elements", "global_functions", "min_scaled_jacobian", "max_scaled_jacobian", "frac_scaled_jacobian_above_0_5",
                        "hausdorff_rel", "volume_rel_error", "partition_of_unity_error", "certified_valid", "certified_invalid", "undecided"})
    EXPECT_EQ(s[k], r["stages"]["extract"][k]) << k;
  EXPECT_EQ(s["time_s"]["tmesh"], 2.0);
  EXPECT_DOUBLE_EQ(s["time_s"]["total"].get<double>(), 0.25 + 0.5 + 1.0 + 2.0 + 0.125);
  EXPECT_EQ(s["route_stages"].size(), 5u);
}

TEST(RunSummary, OtherRoutesHaveNoTMeshColumnsAndOnlyTheirStagesTimes) {
  core::Json r = polycube_route_report();
  r["stages"]["tet2hex"] = {{"time_s", 3.0}, {"bezier_elements", 27428}, {"min_scaled_jacobian", 0.008}};
  const core::Json s = pipeline::run_summary(r, {"tet2hex"});
  EXPECT_TRUE(s["tmesh_nodes"].is_null());  // a stale tmesh entry of another route is not this run's
  EXPECT_TRUE(s["irregular_nodes_interior"].is_null());
  EXPECT_EQ(s["bezier_elements"], 27428);
  EXPECT_TRUE(s["hausdorff_rel"].is_null());  // not reported by that stage
  EXPECT_DOUBLE_EQ(s["time_s"]["total"].get<double>(), 3.0);
  EXPECT_FALSE(s["time_s"].contains("extract"));
}

TEST(RunSummary, RefusesAStageWithoutItsEntryOrTime) {
  core::Json r = polycube_route_report();
  r["stages"].erase("polycube");
  try {
    pipeline::run_summary(r, {"classify", "split", "polycube", "tmesh", "extract"});
    FAIL() << "no polycube entry";
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("polycube"), std::string::npos) << e.what();
  }
  r = polycube_route_report();
  r["stages"]["split"].erase("time_s");
  EXPECT_THROW(pipeline::run_summary(r, {"classify", "split", "polycube", "tmesh", "extract"}), core::InvalidInputError);
  EXPECT_THROW(pipeline::run_summary(core::Json::object(), {"tet2hex"}), core::InvalidInputError);
  EXPECT_THROW(pipeline::run_summary(r, {}), core::InvalidInputError);
}
