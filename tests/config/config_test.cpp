// The YAML config: defaults, every documented key, and clear errors naming the key path.
#include <gtest/gtest.h>

#include <filesystem>

#include "config/config.h"
#include "tmesh/optimize.h"
#include "core/errors.h"

using namespace volts;

namespace {
std::string config_error(const std::string& yaml) {
  try {
    config::parse_config(yaml, "test.yaml");
  } catch (const core::ConfigError& e) {
    return e.what();
  }
  return "<no error>";
}
}  // namespace

TEST(Config, DefaultYamlEqualsBuiltInDefaults) {
  // configs/default.yaml documents every key with its default: it must parse and agree with the structs.
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  const config::Config builtin;
  EXPECT_EQ(file.tmesh.level, builtin.tmesh.level);
  EXPECT_EQ(file.tmesh.degree, builtin.tmesh.degree);
  EXPECT_DOUBLE_EQ(file.classify.sharp_angle_deg, builtin.classify.sharp_angle_deg);
  EXPECT_DOUBLE_EQ(file.classify.corner_angle_deg, builtin.classify.corner_angle_deg);
  EXPECT_EQ(file.polycube.weights, builtin.polycube.weights);
  EXPECT_EQ(file.extract.gauss_points, builtin.extract.gauss_points);
  EXPECT_EQ(file.extract.boundary_samples, builtin.extract.boundary_samples);
  EXPECT_EQ(file.input.resolution, builtin.input.resolution);
  EXPECT_DOUBLE_EQ(file.input.bulge, builtin.input.bulge);
}

// The optimizer's joint rounds and the connector maps' smoothing bound: documented defaults equal
// the library's own (tmesh::OptimizeParams), and the keys survive the effective-config round trip.
TEST(Config, JointOptimizationAndConnectorSmoothingKeys) {
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  const tmesh::OptimizeParams op;
  EXPECT_EQ(file.tmesh.joint_rounds, op.joint_rounds);
  EXPECT_EQ(file.tmesh.joint_evaluations, op.joint_evaluations);
  EXPECT_DOUBLE_EQ(file.tmesh.joint_sharpness, op.joint_sharpness);
  EXPECT_DOUBLE_EQ(file.tmesh.joint_window, op.joint_window);
  // Cycles: the library runs one unless asked (the fit stage's repair); the stage's default is 10.
  EXPECT_EQ(file.tmesh.optimize_cycles, tmesh::Params{}.optimize_cycles);
  EXPECT_EQ(file.tmesh.optimize_cycles, 10);
  EXPECT_EQ(op.cycles, 1);
  EXPECT_EQ(file.tmesh.trilinear_sweeps, op.trilinear_sweeps);
  // The corner-hex guard: on in the stage, off in the library (the fit route's repair, the twist tests).
  EXPECT_EQ(file.tmesh.trilinear_guard, tmesh::Params{}.trilinear_guard);
  EXPECT_TRUE(file.tmesh.trilinear_guard);
  EXPECT_FALSE(op.trilinear_guard);
  EXPECT_DOUBLE_EQ(file.polycube.connector_smooth_below_ratio, polycube::Params{}.connector_smooth_below_ratio);
  const auto c = config::parse_config(
      "tmesh: {joint_rounds: 30, joint_evaluations: 250, joint_sharpness: 150, optimize_cycles: 3, trilinear_sweeps: 7, trilinear_guard: false}\npolycube: {connector_smooth_below_ratio: 0.5}\n", "t");
  const auto d = config::parse_config(config::to_yaml(c), "emitted");
  EXPECT_EQ(d.tmesh.joint_rounds, 30);
  EXPECT_EQ(d.tmesh.joint_evaluations, 250);
  EXPECT_EQ(d.tmesh.optimize_cycles, 3);
  EXPECT_EQ(d.tmesh.trilinear_sweeps, 7);
  EXPECT_FALSE(d.tmesh.trilinear_guard);
  EXPECT_NE(config_error("tmesh: {optimize_cycles: 0}\n").find("tmesh.optimize_cycles: 0 is out of range [1, 100]"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {trilinear_sweeps: 101}\n").find("tmesh.trilinear_sweeps: 101 is out of range [0, 100]"), std::string::npos);
  EXPECT_DOUBLE_EQ(d.tmesh.joint_sharpness, 150);
  EXPECT_DOUBLE_EQ(d.polycube.connector_smooth_below_ratio, 0.5);
  EXPECT_NE(config_error("tmesh: {joint_rounds: 101}\n").find("tmesh.joint_rounds: 101 is out of range [0, 100]"), std::string::npos);
}

// Surface sliding: on by default, sliding once every element is certified valid (the library's
// default too); "start" survives the round trip, and an unknown mode is refused naming the key.
TEST(Config, SlideSurfaceKeys) {
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  EXPECT_TRUE(file.tmesh.slide_surface);
  EXPECT_EQ(file.tmesh.slide_from, "valid");
  EXPECT_EQ(tmesh::OptimizeParams{}.slide_from, tmesh::OptimizeParams::SlideFrom::valid);
  EXPECT_EQ(file.tmesh.slide_sharp_curves, tmesh::OptimizeParams{}.slide_sharp_curves);
  EXPECT_TRUE(file.tmesh.rim_pillow_lenses);
  EXPECT_EQ(file.tmesh.pillow_thickness, "physical");
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {pillow_thickness: parametric}\n", "t")), "emitted").tmesh.pillow_thickness,
            "parametric");
  EXPECT_NE(config_error("tmesh: {pillow_thickness: thick}\n").find("tmesh.pillow_thickness"), std::string::npos);
  // Adaptive levels: documented defaults are the library's, round trip, ranges.
  EXPECT_DOUBLE_EQ(file.tmesh.epsilon_rel, tmesh::Params{}.epsilon_rel);
  EXPECT_EQ(file.tmesh.max_level, tmesh::Params{}.max_level);
  EXPECT_EQ(file.tmesh.deviation_samples, tmesh::Params{}.deviation_samples);
  const auto lv = config::parse_config(config::to_yaml(config::parse_config("tmesh: {epsilon_rel: 0.001, max_level: 5, deviation_samples: 3}\n", "t")), "emitted");
  EXPECT_DOUBLE_EQ(lv.tmesh.epsilon_rel, 0.001);
  EXPECT_EQ(lv.tmesh.max_level, 5);
  EXPECT_EQ(lv.tmesh.deviation_samples, 3);
  EXPECT_NE(config_error("tmesh: {deviation_samples: 1}\n").find("tmesh.deviation_samples"), std::string::npos);
  // The check grid: documented defaults are the library's, round trip, ranges (1 point is no grid).
  EXPECT_EQ(file.tmesh.check_points, tmesh::OptimizeParams{}.check_points);
  EXPECT_EQ(file.tmesh.check_tolerance, tmesh::OptimizeParams{}.check_tolerance);
  const auto ck = config::parse_config(config::to_yaml(config::parse_config("tmesh: {check_points: 0, check_tolerance: 0.1}\n", "t")), "emitted");
  EXPECT_EQ(ck.tmesh.check_points, 0);
  EXPECT_EQ(ck.tmesh.check_tolerance, 0.1);
  for (const char* bad : {"tmesh: {check_points: 1}\n", "tmesh: {check_points: 33}\n", "tmesh: {check_tolerance: -0.1}\n"})
    EXPECT_NE(config_error(bad).find("tmesh.check_"), std::string::npos) << bad;
  EXPECT_NE(config_error("tmesh: {epsilon_rel: -0.1}\n").find("tmesh.epsilon_rel"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {max_level: 8}\n").find("tmesh.max_level"), std::string::npos);
  EXPECT_EQ(file.tmesh.refine, tmesh::Params{}.refine);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {refine: cube}\n", "t")), "emitted").tmesh.refine, "cube");
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {refine: spans}\n", "t")), "emitted").tmesh.refine, "spans");
  EXPECT_NE(config_error("tmesh: {refine: all}\n").find("tmesh.refine"), std::string::npos);
  EXPECT_EQ(file.tmesh.h_refine, tmesh::Params{}.h_refine);
  EXPECT_EQ(file.extract.dense_points, extract::Params{}.dense_points);
  EXPECT_EQ(file.tmesh.grid_points, tmesh::Params{}.grid_points);
  EXPECT_EQ(tmesh::Params{}.grid_points, tmesh::OptimizeParams{}.grid_points);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {grid_points: 3}\n", "t")), "emitted").tmesh.grid_points, 3);
  EXPECT_NE(config_error("tmesh: {grid_points: 1}\n").find("tmesh.grid_points"), std::string::npos);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("extract: {dense_points: 0}\n", "t")), "emitted").extract.dense_points, 0);
  EXPECT_NE(config_error("extract: {dense_points: 1}\n").find("extract.dense_points"), std::string::npos);
  EXPECT_NE(config_error("extract: {dense_points: 17}\n").find("extract.dense_points"), std::string::npos);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {h_refine: 2}\n", "t")), "emitted").tmesh.h_refine, 2);
  EXPECT_NE(config_error("tmesh: {h_refine: 4}\n").find("tmesh.h_refine"), std::string::npos);
  EXPECT_EQ(file.extract.json_operators, extract::Params{}.json_operators);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("extract: {json_operators: kronecker}\n", "t")), "emitted").extract.json_operators, "kronecker");
  EXPECT_NE(config_error("extract: {json_operators: dense}\n").find("extract.json_operators"), std::string::npos);
  EXPECT_EQ(file.tmesh.pillow_splits, tmesh::Params{}.pillow_splits);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {pillow_splits: 3}\n", "t")), "emitted").tmesh.pillow_splits, 3);
  for (const char* bad : {"tmesh: {pillow_splits: 0}\n", "tmesh: {pillow_splits: 9}\n", "tmesh: {pillow_splits: two}\n",
                          "tmesh: {pillow_splits: 2, pillow_layers: 0}\n"})
    EXPECT_NE(config_error(bad).find("tmesh.pillow_splits"), std::string::npos) << bad;
  EXPECT_EQ(file.tmesh.rim_pillow_lenses, tmesh::Params{}.rim_pillow_lenses);
  EXPECT_TRUE(file.tmesh.fold_retry);
  EXPECT_EQ(file.tmesh.fold_retry, tmesh::OptimizeParams{}.fold_retry);
  const auto c = config::parse_config("tmesh: {slide_surface: false, slide_from: start, slide_sharp_curves: true, rim_pillow_lenses: false, fold_retry: false}\n", "t");
  const auto d = config::parse_config(config::to_yaml(c), "emitted");
  EXPECT_FALSE(d.tmesh.fold_retry);
  EXPECT_NE(config_error("tmesh: {fold_retry: twice}\n").find("tmesh.fold_retry: must be true or false"), std::string::npos);
  EXPECT_FALSE(d.tmesh.rim_pillow_lenses);
  EXPECT_FALSE(d.tmesh.slide_surface);
  EXPECT_TRUE(d.tmesh.slide_sharp_curves);
  EXPECT_EQ(d.tmesh.slide_from, "start");
  const std::string e = config_error("tmesh: {slide_from: always}\n");
  EXPECT_NE(e.find("tmesh.slide_from"), std::string::npos) << e;
  EXPECT_NE(e.find("'always' is not one of"), std::string::npos) << e;
}

// The joint rounds' method: CCSAQ in the shipped config and the library alike, "lbfgs" survives
// the round trip, anything else is refused naming the key.
TEST(Config, JointMethodKey) {
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  EXPECT_EQ(file.tmesh.joint_method, "ccsaq");
  EXPECT_EQ(file.tmesh.joint_method, tmesh::Params{}.joint_method);
  EXPECT_EQ(tmesh::OptimizeParams{}.joint_method, tmesh::OptimizeParams::JointMethod::ccsaq);
  EXPECT_EQ(config::parse_config(config::to_yaml(config::parse_config("tmesh: {joint_method: lbfgs}\n", "t")), "emitted").tmesh.joint_method, "lbfgs");
  const std::string e = config_error("tmesh: {joint_method: bfgs}\n");
  EXPECT_NE(e.find("tmesh.joint_method"), std::string::npos) << e;
  EXPECT_NE(e.find("'bfgs' is not one of"), std::string::npos) << e;
}

TEST(Config, ValuesAreRead) {
  const auto c = config::parse_config("input: {generate: torus, resolution: 32}\ntmesh: {level: 5}\nclassify: {sharp_angle_deg: 45.5}\n", "t");
  EXPECT_EQ(c.input.generate, "torus");
  EXPECT_EQ(c.input.resolution, 32);
  EXPECT_EQ(c.tmesh.level, 5);
  EXPECT_DOUBLE_EQ(c.classify.sharp_angle_deg, 45.5);
}

TEST(Config, EmittedYamlParsesBackToTheSameConfig) {
  const auto c = config::parse_config("input: {file: /x/y.obj}\ntmesh: {level: 4, degree: 2}\npolycube: {weights: uniform}\n", "t");
  const auto d = config::parse_config(config::to_yaml(c), "emitted");
  EXPECT_EQ(d.input.file, "/x/y.obj");
  EXPECT_EQ(d.tmesh.level, 4);
  EXPECT_EQ(d.tmesh.degree, 2);
  EXPECT_EQ(d.polycube.weights, "uniform");
}

TEST(Config, UnknownKeysAreErrorsWithTheirPath) {
  EXPECT_NE(config_error("tmesh: {levle: 3}\n").find("test.yaml: unknown key 'tmesh.levle'"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {levle: 3}\n").find("known here: check_points, check_tolerance, continuity, degree, deviation_samples, epsilon_rel, fold_retry, grid_points, h_refine, joint_evaluations, joint_method, joint_rounds, joint_sharpness, joint_window, level"), std::string::npos);
  EXPECT_NE(config_error("clasify: {}\n").find("unknown key 'clasify'"), std::string::npos);
  EXPECT_NE(config_error("split: {foo: 1}\n").find("unknown key 'split.foo'"), std::string::npos);
}

// yaml-cpp keeps a key given twice and lookups see the first: a second `tmesh:` section would be
// dropped without a word.
TEST(Config, KeysGivenTwiceInOneMapAreErrorsWithTheirLine) {
  const std::string top = config_error("input: {generate: torus}\ntmesh: {level: 2}\ntmesh: {level: 5}\n");
  EXPECT_NE(top.find("test.yaml: line 3: key 'tmesh' appears twice"), std::string::npos) << top;
  const std::string nested = config_error("tmesh:\n  level: 2\n  degree: 3\n  level: 4\n");
  EXPECT_NE(nested.find("line 4: key 'level' appears twice"), std::string::npos) << nested;
  const std::string flow = config_error("split: {hole: torus, hole: cube}\n");
  EXPECT_NE(flow.find("key 'hole' appears twice"), std::string::npos) << flow;
  // The same key in different maps is fine.
  EXPECT_EQ(config::parse_config("tmesh: {level: 2}\npolycube: {smooth_sweeps: 3}\ntet2hex: {degree: 2}\n", "t").tmesh.level, 2);
}

// tmesh.continuity: auto (the default) is c2 for cubics and c0 for every other degree, resolved
// when read so that the effective config and the report name what ran; c0 stays on request.
TEST(Config, ContinuityDefaultsToC2ForCubicsOnly) {
  EXPECT_EQ(config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml").tmesh.continuity, "c2");
  EXPECT_EQ(config::parse_config("input: {generate: torus}\n", "t").tmesh.continuity, "c2");
  EXPECT_EQ(config::parse_config("tmesh: {continuity: auto}\n", "t").tmesh.continuity, "c2");
  EXPECT_EQ(config::parse_config("tmesh: {degree: 2}\n", "t").tmesh.continuity, "c0");
  EXPECT_EQ(config::parse_config("tmesh: {degree: 4, continuity: auto}\n", "t").tmesh.continuity, "c0");
  EXPECT_EQ(config::parse_config("tmesh: {continuity: c0}\n", "t").tmesh.continuity, "c0");
  const std::string emitted = config::to_yaml(config::parse_config("tmesh: {degree: 2}\n", "t"));
  EXPECT_NE(emitted.find("continuity: c0"), std::string::npos) << emitted;
  EXPECT_EQ(config::parse_config(emitted, "emitted").tmesh.continuity, "c0");
  EXPECT_EQ(tmesh::Params{}.continuity, "auto");
  EXPECT_EQ(tmesh::continuity_mode(tmesh::Params{}), "c2");
}

TEST(Config, WrongTypesAndRangesAreErrorsWithTheirPath) {
  EXPECT_NE(config_error("tmesh: {continuity: c1}\n").find("tmesh.continuity"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {continuity: c2, degree: 2}\n").find("tmesh.continuity: c2 is for cubic splines"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {level: three}\n").find("tmesh.level: must be an integer, got 'three'"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {level: 9}\n").find("tmesh.level: 9 is out of range [1, 7]"), std::string::npos);
  EXPECT_NE(config_error("classify: {sharp_angle_deg: 0}\n").find("classify.sharp_angle_deg: 0 is out of range"), std::string::npos);
  EXPECT_NE(config_error("classify: {sharp_angle_deg: .nan}\n").find("classify.sharp_angle_deg"), std::string::npos);
  EXPECT_NE(config_error("route: magic\n").find("route: 'magic' is not one of: fit, polycube, tet"), std::string::npos);
  EXPECT_NE(config_error("tmesh: 3\n").find("tmesh: must be a mapping"), std::string::npos);
  EXPECT_NE(config_error("tmesh: {level: }\n").find("tmesh.level: has no value"), std::string::npos);
  EXPECT_NE(config_error("input: {file: a.obj, generate: box}\n").find("not both"), std::string::npos);
  EXPECT_NE(config_error("tmesh: [1, 2\n").find("not valid YAML"), std::string::npos);
}

// Route tet: the tet2hex section, its defaults in configs/default.yaml, round trip and errors.
TEST(Config, TetRouteSection) {
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  const config::Config builtin;
  EXPECT_EQ(file.tet2hex.degree, builtin.tet2hex.degree);
  EXPECT_EQ(file.tet2hex.curve_boundary, builtin.tet2hex.curve_boundary);
  EXPECT_EQ(file.tet2hex.tetgen.keep_boundary, builtin.tet2hex.tetgen.keep_boundary);
  EXPECT_DOUBLE_EQ(file.tet2hex.tetgen.max_radius_edge_ratio, builtin.tet2hex.tetgen.max_radius_edge_ratio);
  EXPECT_DOUBLE_EQ(file.tet2hex.remesh_edge_rel, builtin.tet2hex.remesh_edge_rel);
  EXPECT_EQ(file.tet2hex.certify.max_depth, builtin.tet2hex.certify.max_depth);
  EXPECT_EQ(file.tet2hex.optimize_cycles, builtin.tet2hex.optimize_cycles);
  EXPECT_DOUBLE_EQ(file.tet2hex.optimize_target, builtin.tet2hex.optimize_target);
  EXPECT_EQ(file.tet2hex.optimize_grid_points, builtin.tet2hex.optimize_grid_points);
  const auto c = config::parse_config(
      "route: tet\ntet2hex: {degree: 2, curve_boundary: false, max_volume_rel: 0.01, remesh_edge_rel: 0.05, optimize_cycles: 2, optimize_target: 0.4, "
      "optimize_grid_points: 2}\n",
      "t");
  const auto d = config::parse_config(config::to_yaml(c), "emitted");
  EXPECT_EQ(d.route, "tet");
  EXPECT_EQ(d.tet2hex.degree, 2);
  EXPECT_FALSE(d.tet2hex.curve_boundary);
  EXPECT_DOUBLE_EQ(d.tet2hex.tetgen.max_volume_rel, 0.01);
  EXPECT_DOUBLE_EQ(d.tet2hex.remesh_edge_rel, 0.05);
  EXPECT_EQ(d.tet2hex.optimize_cycles, 2);
  EXPECT_DOUBLE_EQ(d.tet2hex.optimize_target, 0.4);
  EXPECT_EQ(d.tet2hex.optimize_grid_points, 2);
  EXPECT_NE(config_error("tet2hex: {optimize_grid_points: 1}\n").find("tet2hex.optimize_grid_points"), std::string::npos);
  EXPECT_NE(config_error("tet2hex: {optimize_target: 0}\n").find("tet2hex.optimize_target"), std::string::npos);
  EXPECT_NE(config_error("tet2hex: {optimize_cycles: 101}\n").find("tet2hex.optimize_cycles"), std::string::npos);
  EXPECT_NE(config_error("tet2hex: {degree: 5}\n").find("tet2hex.degree: 5 is out of range [1, 4]"), std::string::npos);
  EXPECT_NE(config_error("tet2hex: {curve_boundary: maybe}\n").find("tet2hex.curve_boundary: must be true or false"), std::string::npos);
  EXPECT_NE(config_error("tet2hex: {max_radius_edge_ratio: 1.0}\n").find("tet2hex.max_radius_edge_ratio"), std::string::npos);
  EXPECT_NE(config_error("tet2hex: {degre: 2}\n").find("unknown key 'tet2hex.degre'"), std::string::npos);
}

// Route fit: the fit section, its defaults in configs/default.yaml, round trip and errors.
TEST(Config, FitRouteSection) {
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  const config::Config builtin;
  EXPECT_EQ(file.fit.pillow.elements, builtin.fit.pillow.elements);
  EXPECT_EQ(file.fit.pillow.degree, builtin.fit.pillow.degree);
  EXPECT_EQ(file.fit.gfd.samples, builtin.fit.gfd.samples);
  EXPECT_EQ(file.fit.gfd.sweeps, builtin.fit.gfd.sweeps);
  EXPECT_EQ(file.fit.gfd.g1_sweeps, builtin.fit.gfd.g1_sweeps);
  EXPECT_EQ(file.fit.gfd.halvings, builtin.fit.gfd.halvings);
  EXPECT_EQ(file.fit.gfd.repair_sweeps, builtin.fit.gfd.repair_sweeps);
  EXPECT_EQ(file.fit.cube.weights, builtin.fit.cube.weights);
  EXPECT_DOUBLE_EQ(file.fit.cube.tet_max_volume_rel, builtin.fit.cube.tet_max_volume_rel);
  EXPECT_DOUBLE_EQ(file.fit.cube.segmentation.smoothness, builtin.fit.cube.segmentation.smoothness);
  EXPECT_EQ(file.fit.optimize_sweeps, builtin.fit.optimize_sweeps);
  const auto c = config::parse_config("route: fit\nfit: {elements: 6, degree: 4, sweeps: 5, weights: uniform, segmentation_smoothness: 1.5, optimize_sweeps: 7}\n", "t");
  const auto d = config::parse_config(config::to_yaml(c), "emitted");
  EXPECT_EQ(d.route, "fit");
  EXPECT_EQ(d.fit.pillow.elements, 6);
  EXPECT_EQ(d.fit.pillow.degree, 4);
  EXPECT_EQ(d.fit.gfd.sweeps, 5);
  EXPECT_EQ(d.fit.cube.weights, "uniform");
  EXPECT_DOUBLE_EQ(d.fit.cube.segmentation.smoothness, 1.5);
  EXPECT_EQ(d.fit.optimize_sweeps, 7);
  EXPECT_NE(config_error("fit: {elements: 0}\n").find("fit.elements: 0 is out of range [1, 32]"), std::string::npos);
  EXPECT_NE(config_error("fit: {degree: 1}\n").find("fit.degree: 1 is out of range [2, 5]"), std::string::npos);
  EXPECT_NE(config_error("fit: {weights: cotan}\n").find("fit.weights"), std::string::npos);
  EXPECT_NE(config_error("fit: {element: 2}\n").find("unknown key 'fit.element'"), std::string::npos);
}

// Every config the project ships (configs/, examples/) passes the strict checks: a renamed key or a
// value out of range there would stop a user's first run.
TEST(Config, EveryShippedConfigLoads) {
  int n = 0;
  for (const char* dir : {"configs", "examples"})
    for (const auto& e : std::filesystem::directory_iterator(std::string(VOLTS_SOURCE_DIR) + "/" + dir)) {
      if (e.path().extension() != ".yaml") continue;
      EXPECT_NO_THROW(config::load_config(e.path().string())) << e.path();
      ++n;
    }
  EXPECT_GE(n, 10);
}

TEST(Config, MissingFileIsInvalidInput) {
  EXPECT_THROW(config::load_config("/nonexistent/volts.yaml"), core::InvalidInputError);
}

TEST(Config, ExtractExportsIsAListOfKnownNames) {
  const config::Config builtin;
  EXPECT_EQ(builtin.extract.exports, (std::vector<std::string>{"vtu", "bext", "json", "msh", "png"}));
  const config::Config file = config::load_config(std::string(VOLTS_SOURCE_DIR) + "/configs/default.yaml");
  EXPECT_EQ(file.extract.exports, builtin.extract.exports);
  const auto c = config::parse_config("extract: {exports: [json, msh]}\n", "t");
  EXPECT_EQ(c.extract.exports, (std::vector<std::string>{"json", "msh"}));
  EXPECT_EQ(config::parse_config(config::to_yaml(c), "emitted").extract.exports, c.extract.exports);
  EXPECT_TRUE(config::parse_config("extract: {exports: []}\n", "t").extract.exports.empty());
  EXPECT_NE(config_error("extract: {exports: [vtu, stl]}\n").find("extract.exports: 'stl' is not one of: vtu, bext, json, msh, png"),
            std::string::npos);
  EXPECT_NE(config_error("extract: {exports: vtu}\n").find("extract.exports: must be a list of names"), std::string::npos);
}
