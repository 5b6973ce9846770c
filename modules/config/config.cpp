#include "config/config.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace volts::config {
namespace {

// A mapping whose keys are checked: get() marks keys as known; finish() rejects the rest.
class Section {
 public:
  Section(YAML::Node node, std::string path, const std::string& source) : node_(node), path_(std::move(path)), source_(source) {
    if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) fail(path_.empty() ? "the config must be a mapping" : "must be a mapping");
  }

  Section section(const std::string& key) {
    known_.insert(key);
    return Section(child(key), join(key), source_);
  }

  void get(const std::string& key, std::string& value, const std::set<std::string>& allowed = {}) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    if (!n.IsScalar()) fail_key(key, "must be a string");
    value = n.as<std::string>();
    if (!allowed.empty() && !allowed.count(value)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail_key(key, "'" + value + "' is not one of: " + list);
    }
  }

  void get(const std::string& key, bool& value) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    try {
      value = n.as<bool>();
    } catch (const YAML::Exception&) {
      fail_key(key, "must be true or false, got '" + scalar(n) + "'");
    }
  }

  void get(const std::string& key, int& value, int lo, int hi) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    try {
      value = n.as<int>();
    } catch (const YAML::Exception&) {
      fail_key(key, "must be an integer, got '" + scalar(n) + "'");
    }
    if (value < lo || value > hi) fail_key(key, std::to_string(value) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }

  void get(const std::string& key, double& value, double lo, double hi) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    try {
      value = n.as<double>();
    } catch (const YAML::Exception&) {
      fail_key(key, "must be a number, got '" + scalar(n) + "'");
    }
    if (!(value >= lo && value <= hi)) {
      std::ostringstream s;
      s << value << " is out of range [" << lo << ", " << hi << "]";
      fail_key(key, s.str());
    }
  }

  /// A list of exactly `size` finite numbers.
  void get(const std::string& key, std::vector<double>& value, std::size_t size) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    if (!n.IsSequence() || n.size() != size) fail_key(key, "must be a list of " + std::to_string(size) + " numbers");
    std::vector<double> v;
    for (const auto& x : n) {
      double d = 0;
      try {
        d = x.as<double>();
      } catch (const YAML::Exception&) {
        fail_key(key, "must be a list of numbers, got '" + scalar(x) + "'");
      }
      if (!std::isfinite(d)) fail_key(key, "must hold finite numbers");
      v.push_back(d);
    }
    value = v;
  }

  /// A list of names, each one of `allowed`.
  void get(const std::string& key, std::vector<std::string>& value, const std::vector<std::string>& allowed) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    if (!n.IsSequence()) fail_key(key, "must be a list of names (" + list + ")");
    std::vector<std::string> v;
    for (const auto& x : n) {
      if (!x.IsScalar()) fail_key(key, "must be a list of names (" + list + ")");
      if (std::find(allowed.begin(), allowed.end(), x.Scalar()) == allowed.end())
        fail_key(key, "'" + x.Scalar() + "' is not one of: " + list);
      v.push_back(x.Scalar());
    }
    value = v;
  }

  /// A list of exactly `count` points [x, y, z].
  void get(const std::string& key, std::vector<std::array<double, 3>>& value, std::size_t count) {
    YAML::Node n = lookup(key);
    if (!n.IsDefined()) return;
    if (!n.IsSequence() || n.size() != count) fail_key(key, "must be a list of " + std::to_string(count) + " points [x, y, z]");
    std::vector<std::array<double, 3>> v;
    for (const auto& p : n) {
      if (!p.IsSequence() || p.size() != 3) fail_key(key, "each point must be [x, y, z]");
      std::array<double, 3> q{};
      for (int k = 0; k < 3; ++k) {
        try {
          q[k] = p[k].as<double>();
        } catch (const YAML::Exception&) {
          fail_key(key, "must hold numbers, got '" + scalar(p[k]) + "'");
        }
        if (!std::isfinite(q[k])) fail_key(key, "must hold finite numbers");
      }
      v.push_back(q);
    }
    value = v;
  }

  void finish() const {
    if (!node_.IsDefined() || !node_.IsMap()) return;
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar())
        throw core::ConfigError(source_ + ": a key that is not a plain name (line " + std::to_string(kv.first.Mark().line + 1) + ")");
      const std::string k = kv.first.as<std::string>();
      if (!known_.count(k)) {
        std::string list;
        for (const auto& a : known_) list += (list.empty() ? "" : ", ") + a;
        throw core::ConfigError(source_ + ": unknown key '" + join(k) + "'" + (list.empty() ? "" : " (known here: " + list + ")"));
      }
    }
  }

 private:
  // Const access: yaml-cpp's non-const operator[] would insert the missing key.
  YAML::Node child(const std::string& key) const {
    if (!node_.IsDefined() || !node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& c = node_;
    return c[key];
  }
  YAML::Node lookup(const std::string& key) {
    known_.insert(key);
    YAML::Node n = child(key);
    if (n.IsDefined() && n.IsNull()) fail_key(key, "has no value");
    return n;
  }
  static std::string scalar(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : "<not a scalar>"; }
  std::string join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  [[noreturn]] void fail(const std::string& what) const { throw core::ConfigError(source_ + ": " + (path_.empty() ? "" : path_ + ": ") + what); }
  [[noreturn]] void fail_key(const std::string& key, const std::string& what) const {
    throw core::ConfigError(source_ + ": " + join(key) + ": " + what);
  }

  YAML::Node node_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> known_;
};

Config bind_config(const YAML::Node& root, const std::string& source) {
  Config c;
  c.source = source;
  Section top(root, "", source);
  top.get("route", c.route, {"polycube", "tet", "fit"});
  {
    Section s = top.section("input");
    s.get("file", c.input.file);
    s.get("generate", c.input.generate);
    s.get("resolution", c.input.resolution, 4, 512);
    s.get("bulge", c.input.bulge, 0.0, 0.35);
    s.finish();
    if (!c.input.file.empty() && !c.input.generate.empty())
      throw core::ConfigError(source + ": input: give either 'file' or 'generate', not both");
  }
  {
    Section s = top.section("classify");
    s.get("sharp_angle_deg", c.classify.sharp_angle_deg, 1.0, 179.0);
    s.get("corner_angle_deg", c.classify.corner_angle_deg, 1.0, 179.0);
    s.finish();
  }
  {
    Section s = top.section("split");
    s.get("extreme_points", c.split.extreme_points, 2);
    s.get("cross_section_plane", c.split.cross_section_plane, 6);
    s.get("cross_section_point", c.split.cross_section_point, 1);
    s.get("torus_cubes", c.split.torus_cubes, 4, 16);
    s.get("hole", c.split.hole, {"auto", "torus", "difference"});
    s.get("genus2", c.split.genus2, {"auto", "disk", "connector"});
    s.get("connector_cut", c.split.connector_cut, 0.05, 0.95);
    s.get("connector_end", c.split.connector_end, {"level", "shoulder"});
    s.finish();
  }
  {
    Section s = top.section("polycube");
    s.get("weights", c.polycube.weights, {"mean-value", "uniform"});
    s.get("tet_max_volume_rel", c.polycube.tet_max_volume_rel, 1e-6, 1.0);
    s.get("smooth_sweeps", c.polycube.smooth_sweeps, 0, 10000);
    s.get("smooth_below_ratio", c.polycube.smooth_below_ratio, 0.0, 1.0);
    s.get("connector_smooth_below_ratio", c.polycube.connector_smooth_below_ratio, 0.0, 1.0);
    s.get("sharp_lines", c.polycube.sharp_lines);
    s.get("profile", c.polycube.profile, {"auto", "square"});
    s.finish();
  }
  {
    Section s = top.section("tmesh");
    s.get("level", c.tmesh.level, 1, 7);
    s.get("degree", c.tmesh.degree, 1, 5);
    s.get("pillow_layers", c.tmesh.pillow_layers, 0, 4);
    s.get("optimize_sweeps", c.tmesh.optimize_sweeps, 0, 100);
    s.get("stop_at", c.tmesh.stop_at, 0.0, 1.0);
    s.get("joint_rounds", c.tmesh.joint_rounds, 0, 100);
    s.get("optimize_cycles", c.tmesh.optimize_cycles, 1, 100);
    s.get("trilinear_sweeps", c.tmesh.trilinear_sweeps, 0, 100);
    s.get("trilinear_guard", c.tmesh.trilinear_guard);
    s.get("joint_evaluations", c.tmesh.joint_evaluations, 1, 100000);
    s.get("grid_points", c.tmesh.grid_points, 2, 8);
    s.get("check_points", c.tmesh.check_points, 0, 32);
    if (c.tmesh.check_points == 1) throw core::ConfigError(source + ": tmesh.check_points: must be 0 (no check) or in [2, 32], got 1");
    s.get("check_tolerance", c.tmesh.check_tolerance, 0.0, 1.0);
    s.get("joint_sharpness", c.tmesh.joint_sharpness, 1e-3, 1000.0);
    s.get("joint_window", c.tmesh.joint_window, 0.0, 1.0);
    s.get("joint_method", c.tmesh.joint_method, {"ccsaq", "lbfgs"});
    s.get("slide_surface", c.tmesh.slide_surface);
    s.get("slide_from", c.tmesh.slide_from, {"stall", "start", "valid"});
    s.get("slide_sharp_curves", c.tmesh.slide_sharp_curves);
    s.get("fold_retry", c.tmesh.fold_retry);
    s.get("rim_pillow_lenses", c.tmesh.rim_pillow_lenses);
    s.get("pillow_thickness", c.tmesh.pillow_thickness, {"physical", "parametric"});
    s.get("epsilon_rel", c.tmesh.epsilon_rel, 0.0, 1.0);
    s.get("deviation_samples", c.tmesh.deviation_samples, 2, 64);
    s.get("max_level", c.tmesh.max_level, 1, 7);
    s.get("h_refine", c.tmesh.h_refine, 0, 3);
    s.get("pillow_splits", c.tmesh.pillow_splits, 1, 8);
    if (c.tmesh.pillow_splits > 1 && c.tmesh.pillow_layers == 0)
      throw core::ConfigError(source + ": tmesh.pillow_splits " + std::to_string(c.tmesh.pillow_splits) + " needs a pillow to split (tmesh.pillow_layers is 0)");
    s.get("continuity", c.tmesh.continuity, {"auto", "c0", "c2"});
    c.tmesh.continuity = tmesh::continuity_mode(c.tmesh);  // the effective config names what ran
    if (c.tmesh.continuity == "c2" && c.tmesh.degree != 3)
      throw core::ConfigError(source + ": tmesh.continuity: c2 is for cubic splines (tmesh.degree 3), got degree " + std::to_string(c.tmesh.degree));
    s.get("refine", c.tmesh.refine, {"boundary", "cube", "spans"});
    s.finish();
  }
  {
    Section s = top.section("extract");
    s.get("gauss_points", c.extract.gauss_points, 0, 10);
    s.get("boundary_samples", c.extract.boundary_samples, 2, 64);
    s.get("dense_points", c.extract.dense_points, 0, 16);
    if (c.extract.dense_points == 1) throw core::ConfigError(source + ": extract.dense_points: must be 0 or in [2, 16], got 1");
    s.get("certify_max_depth", c.extract.certify.max_depth, 0, 20);
    s.get("exports", c.extract.exports, extract::export_names());
    s.get("json_operators", c.extract.json_operators, {"triplets", "kronecker"});
    s.finish();
  }
  {
    Section s = top.section("tet2hex");
    auto& t = c.tet2hex;
    s.get("max_radius_edge_ratio", t.tetgen.max_radius_edge_ratio, 0.0, 10.0);
    if (t.tetgen.max_radius_edge_ratio > 0 && t.tetgen.max_radius_edge_ratio < 1.1)
      throw core::ConfigError(source + ": tet2hex.max_radius_edge_ratio: must be 0 (off) or in [1.1, 10]");
    s.get("min_dihedral_deg", t.tetgen.min_dihedral_deg, 0.0, 30.0);
    s.get("max_volume_rel", t.tetgen.max_volume_rel, 0.0, 1.0);
    // Lower bounds keep the mesh within memory: at least 1/max_volume_rel tets, and about
    // 1/remesh_edge_rel^2 surface triangles.
    if (t.tetgen.max_volume_rel > 0 && t.tetgen.max_volume_rel < 1e-5)
      throw core::ConfigError(source + ": tet2hex.max_volume_rel: must be 0 (off) or in [1e-05, 1] (more than 100000 tets otherwise)");
    s.get("keep_boundary", t.tetgen.keep_boundary);
    s.get("remesh_edge_rel", t.remesh_edge_rel, 0.0, 0.5);
    if (t.remesh_edge_rel > 0 && t.remesh_edge_rel < 0.005)
      throw core::ConfigError(source + ": tet2hex.remesh_edge_rel: must be 0 (off) or in [0.005, 0.5] (about a million triangles otherwise)");
    s.get("degree", t.degree, 1, 4);
    s.get("curve_boundary", t.curve_boundary);
    s.get("gauss_points", t.gauss_points, 0, 10);
    s.get("boundary_samples", t.boundary_samples, 2, 64);
    s.get("certify_max_depth", t.certify.max_depth, 0, 20);
    s.get("optimize_cycles", t.optimize_cycles, 0, 100);
    s.get("optimize_target", t.optimize_target, 0.0, 1.0);
    s.get("optimize_grid_points", t.optimize_grid_points, 2, 8);
    if (!(t.optimize_target > 0)) throw core::ConfigError(source + ": tet2hex.optimize_target: must be in (0, 1]");
    s.finish();
  }
  {
    Section s = top.section("fit");
    auto& f = c.fit;
    s.get("elements", f.pillow.elements, 1, 32);
    s.get("degree", f.pillow.degree, 2, 5);
    s.get("samples", f.gfd.samples, 1, 16);
    s.get("sweeps", f.gfd.sweeps, 0, 1000);
    s.get("g1_sweeps", f.gfd.g1_sweeps, 0, 1000);
    s.get("fairness_sweeps", f.gfd.fairness_sweeps, 0, 1000);
    s.get("halvings", f.gfd.halvings, 0, 30);
    s.get("start_rounds", f.gfd.start_rounds, 0, 60);
    s.get("repair_sweeps", f.gfd.repair_sweeps, 0, 1000);
    s.get("weights", f.cube.weights, {"mean-value", "uniform"});
    s.get("tet_max_volume_rel", f.cube.tet_max_volume_rel, 1e-6, 1.0);
    s.get("smooth_sweeps", f.cube.smooth_sweeps, 0, 10000);
    s.get("segmentation_smoothness", f.cube.segmentation.smoothness, 0.0, 10.0);
    s.get("optimize_sweeps", f.optimize_sweeps, 0, 100);
    s.finish();
  }
  top.finish();
  return c;
}

}  // namespace

namespace {

/// yaml-cpp parses nested collections recursively, so deep nesting ("[[[[..." or "- - - -...")
/// would overflow the stack. A config is two levels deep: refuse more than kMaxNesting levels of
/// flow brackets, or a line that starts deeper than kMaxIndent columns (indentation and "- ").
void check_nesting(const std::string& text, const std::string& source) {
  constexpr int kMaxNesting = 32, kMaxIndent = 128;
  int depth = 0, line = 1, column = 0;
  bool line_start = true;
  char quote = 0;
  for (const char c : text) {
    if (c == '\n') {
      ++line;
      column = 0;
      line_start = true;
      quote = 0;  // an apostrophe in a comment must not hide the next lines
      continue;
    }
    if (line_start) {
      if (c == ' ' || c == '\t' || c == '-') {
        if (++column > kMaxIndent)
          throw core::ConfigError(source + ": line " + std::to_string(line) + " is nested too deeply (more than " +
                                  std::to_string(kMaxIndent) + " columns of indentation)");
        continue;
      }
      line_start = false;
    }
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        throw core::ConfigError(source + ": line " + std::to_string(line) + " is nested too deeply (more than " +
                                std::to_string(kMaxNesting) + " levels of brackets)");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

// A key given twice in one map: yaml-cpp keeps both and lookups see the first, so the second
// (say, a second `tmesh:` section) would be ignored without a word.
void check_duplicate_keys(const YAML::Node& node, const std::string& source) {
  if (node.IsSequence()) {
    for (const YAML::Node& x : node) check_duplicate_keys(x, source);
    return;
  }
  if (!node.IsMap()) return;
  std::set<std::string> seen;
  for (const auto& kv : node) {
    if (kv.first.IsScalar() && !seen.insert(kv.first.Scalar()).second)
      throw core::ConfigError(source + ": line " + std::to_string(kv.first.Mark().line + 1) + ": key '" + kv.first.Scalar() +
                              "' appears twice in the same map (merge the two)");
    check_duplicate_keys(kv.second, source);
  }
}

}  // namespace

Config parse_config(const std::string& text, const std::string& source) {
  check_nesting(text, source);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw core::ConfigError(source + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
  try {
    check_duplicate_keys(root, source);
    return bind_config(root, source);
  } catch (const YAML::Exception& e) {
    // What the binding did not foresee, e.g. a key that is itself a map ("? {a: 1}: 2"; fuzz_config).
    throw core::ConfigError(source + ": unexpected YAML structure (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
}

Config load_config(const std::string& path) {
  Config c = parse_config(core::read_text_file(path), path);
  if (!c.input.file.empty() && std::filesystem::path(c.input.file).is_relative())
    c.input.file = (std::filesystem::path(path).parent_path() / c.input.file).lexically_normal().string();
  return c;
}

std::string to_yaml(const Config& c) {
  YAML::Emitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "route" << YAML::Value << c.route;
  e << YAML::Key << "input" << YAML::Value << YAML::BeginMap;
  if (!c.input.file.empty()) e << YAML::Key << "file" << YAML::Value << c.input.file;
  if (!c.input.generate.empty()) e << YAML::Key << "generate" << YAML::Value << c.input.generate;
  e << YAML::Key << "resolution" << YAML::Value << c.input.resolution;
  e << YAML::Key << "bulge" << YAML::Value << c.input.bulge << YAML::EndMap;
  e << YAML::Key << "classify" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "sharp_angle_deg" << YAML::Value << c.classify.sharp_angle_deg;
  e << YAML::Key << "corner_angle_deg" << YAML::Value << c.classify.corner_angle_deg << YAML::EndMap;
  e << YAML::Key << "split" << YAML::Value << YAML::BeginMap;
  if (!c.split.extreme_points.empty()) {
    e << YAML::Key << "extreme_points" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const auto& p : c.split.extreme_points) e << YAML::Flow << YAML::BeginSeq << p[0] << p[1] << p[2] << YAML::EndSeq;
    e << YAML::EndSeq;
  }
  if (!c.split.cross_section_plane.empty()) e << YAML::Key << "cross_section_plane" << YAML::Value << YAML::Flow << c.split.cross_section_plane;
  if (!c.split.cross_section_point.empty()) {
    const auto& p = c.split.cross_section_point[0];
    e << YAML::Key << "cross_section_point" << YAML::Value << YAML::Flow << YAML::BeginSeq << YAML::Flow << YAML::BeginSeq << p[0] << p[1]
      << p[2] << YAML::EndSeq << YAML::EndSeq;
  }
  e << YAML::Key << "torus_cubes" << YAML::Value << c.split.torus_cubes;
  e << YAML::Key << "hole" << YAML::Value << c.split.hole;
  e << YAML::Key << "genus2" << YAML::Value << c.split.genus2;
  e << YAML::Key << "connector_cut" << YAML::Value << c.split.connector_cut;
  e << YAML::Key << "connector_end" << YAML::Value << c.split.connector_end << YAML::EndMap;
  e << YAML::Key << "polycube" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "weights" << YAML::Value << c.polycube.weights;
  e << YAML::Key << "tet_max_volume_rel" << YAML::Value << c.polycube.tet_max_volume_rel;
  e << YAML::Key << "smooth_sweeps" << YAML::Value << c.polycube.smooth_sweeps;
  e << YAML::Key << "smooth_below_ratio" << YAML::Value << c.polycube.smooth_below_ratio;
  e << YAML::Key << "connector_smooth_below_ratio" << YAML::Value << c.polycube.connector_smooth_below_ratio;
  e << YAML::Key << "sharp_lines" << YAML::Value << c.polycube.sharp_lines;
  e << YAML::Key << "profile" << YAML::Value << c.polycube.profile << YAML::EndMap;
  e << YAML::Key << "tmesh" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "level" << YAML::Value << c.tmesh.level;
  e << YAML::Key << "degree" << YAML::Value << c.tmesh.degree;
  e << YAML::Key << "pillow_layers" << YAML::Value << c.tmesh.pillow_layers;
  e << YAML::Key << "optimize_sweeps" << YAML::Value << c.tmesh.optimize_sweeps;
  e << YAML::Key << "stop_at" << YAML::Value << c.tmesh.stop_at;
  e << YAML::Key << "joint_rounds" << YAML::Value << c.tmesh.joint_rounds;
  e << YAML::Key << "optimize_cycles" << YAML::Value << c.tmesh.optimize_cycles;
  e << YAML::Key << "trilinear_sweeps" << YAML::Value << c.tmesh.trilinear_sweeps;
  e << YAML::Key << "trilinear_guard" << YAML::Value << c.tmesh.trilinear_guard;
  e << YAML::Key << "joint_evaluations" << YAML::Value << c.tmesh.joint_evaluations;
  e << YAML::Key << "grid_points" << YAML::Value << c.tmesh.grid_points;
  e << YAML::Key << "check_points" << YAML::Value << c.tmesh.check_points;
  e << YAML::Key << "check_tolerance" << YAML::Value << c.tmesh.check_tolerance;
  e << YAML::Key << "joint_sharpness" << YAML::Value << c.tmesh.joint_sharpness;
  e << YAML::Key << "joint_window" << YAML::Value << c.tmesh.joint_window;
  e << YAML::Key << "joint_method" << YAML::Value << c.tmesh.joint_method;
  e << YAML::Key << "slide_surface" << YAML::Value << c.tmesh.slide_surface;
  e << YAML::Key << "slide_from" << YAML::Value << c.tmesh.slide_from;
  e << YAML::Key << "slide_sharp_curves" << YAML::Value << c.tmesh.slide_sharp_curves;
  e << YAML::Key << "fold_retry" << YAML::Value << c.tmesh.fold_retry;
  e << YAML::Key << "rim_pillow_lenses" << YAML::Value << c.tmesh.rim_pillow_lenses;
  e << YAML::Key << "pillow_thickness" << YAML::Value << c.tmesh.pillow_thickness;
  e << YAML::Key << "epsilon_rel" << YAML::Value << c.tmesh.epsilon_rel;
  e << YAML::Key << "deviation_samples" << YAML::Value << c.tmesh.deviation_samples;
  e << YAML::Key << "max_level" << YAML::Value << c.tmesh.max_level;
  e << YAML::Key << "refine" << YAML::Value << c.tmesh.refine;
  e << YAML::Key << "h_refine" << YAML::Value << c.tmesh.h_refine;
  e << YAML::Key << "pillow_splits" << YAML::Value << c.tmesh.pillow_splits;
  e << YAML::Key << "continuity" << YAML::Value << c.tmesh.continuity << YAML::EndMap;
  e << YAML::Key << "extract" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "gauss_points" << YAML::Value << c.extract.gauss_points;
  e << YAML::Key << "boundary_samples" << YAML::Value << c.extract.boundary_samples;
  e << YAML::Key << "dense_points" << YAML::Value << c.extract.dense_points;
  e << YAML::Key << "certify_max_depth" << YAML::Value << c.extract.certify.max_depth;
  e << YAML::Key << "exports" << YAML::Value << YAML::Flow << c.extract.exports;
  e << YAML::Key << "json_operators" << YAML::Value << c.extract.json_operators << YAML::EndMap;
  const auto& t = c.tet2hex;
  e << YAML::Key << "tet2hex" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "max_radius_edge_ratio" << YAML::Value << t.tetgen.max_radius_edge_ratio;
  e << YAML::Key << "min_dihedral_deg" << YAML::Value << t.tetgen.min_dihedral_deg;
  e << YAML::Key << "max_volume_rel" << YAML::Value << t.tetgen.max_volume_rel;
  e << YAML::Key << "keep_boundary" << YAML::Value << t.tetgen.keep_boundary;
  e << YAML::Key << "remesh_edge_rel" << YAML::Value << t.remesh_edge_rel;
  e << YAML::Key << "degree" << YAML::Value << t.degree;
  e << YAML::Key << "curve_boundary" << YAML::Value << t.curve_boundary;
  e << YAML::Key << "gauss_points" << YAML::Value << t.gauss_points;
  e << YAML::Key << "boundary_samples" << YAML::Value << t.boundary_samples;
  e << YAML::Key << "certify_max_depth" << YAML::Value << t.certify.max_depth;
  e << YAML::Key << "optimize_cycles" << YAML::Value << t.optimize_cycles;
  e << YAML::Key << "optimize_target" << YAML::Value << t.optimize_target;
  e << YAML::Key << "optimize_grid_points" << YAML::Value << t.optimize_grid_points << YAML::EndMap;
  const auto& f = c.fit;
  e << YAML::Key << "fit" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "elements" << YAML::Value << f.pillow.elements;
  e << YAML::Key << "degree" << YAML::Value << f.pillow.degree;
  e << YAML::Key << "samples" << YAML::Value << f.gfd.samples;
  e << YAML::Key << "sweeps" << YAML::Value << f.gfd.sweeps;
  e << YAML::Key << "g1_sweeps" << YAML::Value << f.gfd.g1_sweeps;
  e << YAML::Key << "fairness_sweeps" << YAML::Value << f.gfd.fairness_sweeps;
  e << YAML::Key << "halvings" << YAML::Value << f.gfd.halvings;
  e << YAML::Key << "start_rounds" << YAML::Value << f.gfd.start_rounds;
  e << YAML::Key << "repair_sweeps" << YAML::Value << f.gfd.repair_sweeps;
  e << YAML::Key << "weights" << YAML::Value << f.cube.weights;
  e << YAML::Key << "tet_max_volume_rel" << YAML::Value << f.cube.tet_max_volume_rel;
  e << YAML::Key << "smooth_sweeps" << YAML::Value << f.cube.smooth_sweeps;
  e << YAML::Key << "segmentation_smoothness" << YAML::Value << f.cube.segmentation.smoothness;
  e << YAML::Key << "optimize_sweeps" << YAML::Value << f.optimize_sweeps << YAML::EndMap;
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

}  // namespace volts::config
