// Benchmark (not a test) of the whole polycube pipeline against Liu et al. 2013, Table 1: runs
// `volts run CONFIG --workdir DIR/<model>` (the built driver, in its own process group, killed after
// --timeout seconds) on each model and prints, per model, the Table 1 columns read from report.json
// (T-mesh nodes, irregular nodes surface/interior, Bézier elements, worst/best scaled Jacobian) plus
// certified valid/total, hausdorff_rel, volume_rel_error, the time of every stage and the wall time,
// the paper's row where one exists (2.93 GHz Xeon, 2013) and the targets with PASS/FAIL.
// A model whose run fails gets the stage that failed and the first line of its error; the benchmark
// goes on. The table is printed twice: aligned text, then Markdown (for docs/benchmarks.md).
// Configs are configs/default.yaml with only the input set, extract.exports [vtu] (the solver
// exports are not part of the paper's construction time; --all-exports keeps them) and a model's
// own config lines where it has any, quoted next to its input. With --repeat N every model runs N
// times: the wall time is the median (one run's wall varies by ~0.1 s on this machine, as much as
// the eight's distance to its target), and the runs' figures must agree (the pipeline is
// deterministic; a disagreement marks the model `nondeterministic`).
// Usage: bench_pipeline [--models a,b] [--workdir DIR] [--timeout S] [--json FILE] [--models-dir DIR]
//                       [--volts PATH] [--all-exports] [--repeat N] [--list]
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/log.h"
#include "core/stage_file.h"
#include "models/models.h"

using volts::core::Json;
namespace fs = std::filesystem;

namespace {

const char* const kStages[] = {"classify", "split", "polycube", "tmesh", "extract"};

// Liu et al. 2013, Table 1 (2.93 GHz Xeon).
struct Paper {
  const char* name;
  long nodes, elements;
  double worst_sj, seconds;
};
const Paper kTorus{"torus", 5920, 3072, 0.42, 11.8};
const Paper kEight{"eight", 8323, 4096, 0.31, 15.5};
const Paper kRod{"rod", 27198, 27296, 0.34, 99.1};
const Paper kAssembly{"assembly", 25788, 10408, 0.27, 104.2};

struct Model {
  std::string name, generate, file;  // generate: a volts-make-model generator; file: under the models dir
  int resolution = 24;
  const Paper* paper = nullptr;
  double sj_target = -2;  // worst scaled Jacobian target; < -1: none
  // Config lines on top of the defaults (the issue allows "at most a few config lines each",
  // quoted with the model's input in the table).
  std::string config = "";
};

const std::vector<Model>& all_models() {
  static const std::vector<Model> list = {
      {"torus", "torus", "", 24, &kTorus, 0.5},
      {"cinolib_torus", "", "cinolib_torus.obj", 24, &kTorus, 0.5},
      {"eight", "", "cfwen_eight.off", 24, &kEight, 0.4},
      // Adaptive levels (tmesh.epsilon_rel): the slabs whose boundary misses the surface by more
      // than 0.002 of the diagonal one level finer, T-junctions where levels differ.
      {"eight-adaptive", "", "cfwen_eight.off", 24, &kEight, 0.4, "tmesh: {epsilon_rel: 0.002}"},
      // Defaults (examples/rod.yaml, since session 33): split.genus2 auto cuts the shank near its
      // eyes (0.85) where 0.5 fails, its small end on the shoulder; optimized at level 2, the
      // connector's surface at 3, refined once.
      {"rod", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4},
      // At least the paper's element count: optimized at level 3 (max_level 4), refined to 4.
      {"rod-level4", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {level: 4, max_level: 5}"},
      // The same count from the defaults' optimization (level 2, the connector at 3), refined twice:
      // 8 times the defaults' elements, every figure as good, in about half rod-level4's time.
      {"rod-h2", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {level: 4, max_level: 5, h_refine: 2}"},
      // At least the paper's count from the defaults' optimization, refined across the surface
      // only (tmesh.pillow_splits: the pillow slabs' elements split in 3 there; boundary layers).
      {"rod-layers", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {pillow_splits: 3}"},
      // The same, stopping once the worst reaches 0.42 (tmesh.stop_at; 0.45 until session 47): the
      // issue's 0.4 with a margin for extract's 7^3 grid, sooner.
      {"rod-layers-fast", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {pillow_splits: 3, stop_at: 0.42}"},
      // Robustness: the rod at other bounds on a joint round's evaluations (100 by default since
      // session 42, 300 before). The optimizer's path is chaotic — a small change ends elsewhere —
      // so each should end all valid too. rod-e300 is the old default; rod-e200 leaves one fold
      // (docs/status.md "Session 42").
      {"rod-e75", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {joint_evaluations: 75}"},
      {"rod-e90", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {joint_evaluations: 90}"},
      {"rod-e110", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {joint_evaluations: 110}"},
      {"rod-e125", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {joint_evaluations: 125}"},
      {"rod-e200", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {joint_evaluations: 200}"},
      {"rod-e300", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {joint_evaluations: 300}"},
      // Adaptivity per block (T-junctions) against per element face (knot planes, tmesh.refine
      // spans, session 45) at one ε below the torus' unrefined deviation (1.0e-3).
      {"torus-eps", "torus", "", 24, &kTorus, 0.5, "tmesh: {epsilon_rel: 0.001}"},
      {"torus-spans", "torus", "", 24, &kTorus, 0.5, "tmesh: {epsilon_rel: 0.001, refine: spans}"},
      {"eight-spans", "", "cfwen_eight.off", 24, &kEight, 0.4, "tmesh: {epsilon_rel: 0.002, refine: spans}"},
      // C0 across every block face (tmesh.continuity c0; the default until session 51, which made
      // auto - c2 for cubics - the default): the figures and the global functions against C2's.
      {"torus-c0", "torus", "", 24, &kTorus, 0.5, "tmesh: {continuity: c0}"},
      {"eight-c0", "", "cfwen_eight.off", 24, &kEight, 0.4, "tmesh: {continuity: c0}"},
      {"rod-c0", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {continuity: c0}"},
      {"assembly-c0", "assembly", "", 24, &kAssembly, 0.27, "tmesh: {continuity: c0}"},
      {"rod-layers-c0", "", "loopycuts_rod_rem.obj", 24, &kRod, 0.4, "tmesh: {pillow_splits: 3, stop_at: 0.42, continuity: c0}"},
      {"mechanical08-c0", "", "loopycuts_mechanical08_rem.obj", 24, nullptr, -2, "tmesh: {continuity: c0}"},
      {"cube-with-hole-c0", "cube-with-hole", "", 24, nullptr, -2, "tmesh: {continuity: c0}"},
      {"plate-c0", "plate", "", 24, nullptr, -2, "tmesh: {continuity: c0}"},
      {"tube", "", "vhacd_tube1.off", 24, nullptr},
      {"mechanical08", "", "loopycuts_mechanical08_rem.obj", 24, nullptr},
      {"cube-with-hole", "cube-with-hole", "", 24, nullptr},
      // The assembly's base alone: one cube minus four virtual cylinders (genus 4).
      {"plate", "plate", "", 24, nullptr},
      // Issue 8 sets no worst-SJ target for the assembly; the paper's 0.27 is the one to beat
      // (issue 7: "volts must do better on the same kind of models"). The polycube route since
      // session 49: the plate's boxes and the ring's cubes as one pillowed complex (docs/assembly_plan.md).
      {"assembly", "assembly", "", 24, &kAssembly, 0.27},
      // The assembly through the tet route (the route for any closed surface; before session 49 the
      // only one that finished it): TetGen tets of a coarser remesh, four certified Bézier hexes
      // each (not the paper's construction; compare with care).
      {"assembly-tet", "assembly", "", 24, &kAssembly, 0.27, "route: tet\ntet2hex: {remesh_edge_rel: 0.03}"},
      // The same with tmesh's optimizer on the hexes (examples/assembly-tet.yaml; slow: minutes).
      {"assembly-tet-opt", "assembly", "", 24, &kAssembly, 0.27,
       "route: tet\ntet2hex: {remesh_edge_rel: 0.03, optimize_cycles: 1, optimize_target: 0.2}"},
      // Generated rings of rectilinear profiles (volts-make-model): a plus (profile ring) and an L (square ring).
      {"washer", "washer", "", 48, nullptr},
      {"flanged-ring", "flanged-ring", "", 48, nullptr},
  };
  return list;
}

struct Target {
  std::string name, value, limit;
  bool pass = false;
};

struct Result {
  std::string model, input, status = "ok", failed_stage, error;
  Json report = Json::object();  // stages.* of report.json
  double wall_s = 0;               // the median over the runs (--repeat)
  std::vector<double> wall_runs_s;  // every run's
  std::vector<Target> targets;
  std::optional<bool> gmsh_ok;  // `gmsh bezier.msh -check` (--all-exports, gmsh installed)
  std::string gmsh_note;
};

// -------------------------------------------------------------------------------------------------
// Running one model

pid_t g_child = 0;

void on_signal(int sig) {
  if (g_child > 0) kill(-g_child, SIGKILL);
  signal(sig, SIG_DFL);
  raise(sig);
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs argv with stdout/stderr into files, in its own process group; kills the group after timeout.
// Returns the exit code, -1 on timeout, 128 + signal if killed by a signal.
int run_with_timeout(const std::vector<std::string>& args, const fs::path& out, const fs::path& err, double timeout_s) {
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    setpgid(0, 0);
    if (!freopen(out.c_str(), "w", stdout) || !freopen(err.c_str(), "w", stderr)) _exit(127);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "bench_pipeline: error: cannot start %s\n", argv[0]);
    _exit(127);
  }
  setpgid(pid, pid);
  g_child = pid;
  volts::core::Stopwatch watch;
  int status = 0;
  bool timed_out = false;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (!timed_out && watch.seconds() > timeout_s) {
      timed_out = true;
      kill(-pid, SIGTERM);
      usleep(500000);
      kill(-pid, SIGKILL);
    }
    usleep(50000);
  }
  kill(-pid, SIGKILL);  // stage processes left behind by a killed driver
  g_child = 0;
  if (timed_out) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string first_error_line(const std::string& err) {
  std::istringstream in(err);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.find(": error: ") != std::string::npos || line.find("internal error") != std::string::npos) return line;
    if (!line.empty() && line.rfind("[", 0) != 0) last = line;
  }
  return last;
}

Result run_model(const Model& m, const fs::path& models_dir, const fs::path& work, const std::string& volts, double timeout_s,
                 bool all_exports) {
  Result r;
  r.model = m.name;
  std::string input;
  if (!m.generate.empty()) {
    r.input = "generated " + m.generate + ", resolution " + std::to_string(m.resolution);
    const auto names = volts::models::model_names();
    if (std::find(names.begin(), names.end(), m.generate) == names.end()) {
      r.status = "not generated yet";
      r.error = "volts-make-model has no '" + m.generate + "' generator";
      return r;
    }
    input = "{generate: " + m.generate + ", resolution: " + std::to_string(m.resolution) + "}";
  } else {
    const fs::path file = models_dir / m.file;
    r.input = m.file;
    if (!fs::exists(file)) {
      r.status = "missing input";
      r.error = file.string() + " not found";
      return r;
    }
    input = "{file: \"" + fs::absolute(file).string() + "\"}";
  }
  const fs::path dir = work / m.name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path config = dir / "bench.yaml";
  std::ofstream(config) << "# bench_pipeline: configs/default.yaml with this input\ninput: " << input << "\n"
                        << (all_exports ? "" : "extract: {exports: [vtu]}\n") << (m.config.empty() ? "" : m.config + "\n");
  if (!m.config.empty()) {
    std::string quoted = m.config;  // one table cell: lines joined by "; "
    for (std::size_t i = quoted.find('\n'); i != std::string::npos; i = quoted.find('\n', i)) quoted.replace(i, 1, "; ");
    r.input += " + " + quoted;
  }
  std::fprintf(stderr, "bench_pipeline: %s ...\n", m.name.c_str());
  volts::core::Stopwatch watch;
  const int rc = run_with_timeout({volts, "run", config.string(), "--workdir", dir.string()}, dir / "volts.stdout.txt",
                                  dir / "volts.stderr.txt", timeout_s);
  r.wall_s = watch.seconds();
  try {
    const Json rep = volts::core::read_report(dir.string());
    if (rep.contains("stages")) r.report = rep["stages"];
  } catch (const std::exception& e) {
    r.error = std::string("report.json: ") + e.what();
  }
  if (rc != 0) {
    if (m.config.find("route: tet") != std::string::npos) r.failed_stage = "tet2hex";
    for (const char* s : kStages)
      if (r.failed_stage.empty() && !r.report.contains(s)) {
        r.failed_stage = s;
        break;
      }
    if (rc < 0) {
      r.status = "timeout";
      r.error = "no result after " + std::to_string(static_cast<int>(timeout_s)) + " s";
    } else {
      r.status = "failed";
      r.error = first_error_line(read_text(dir / "volts.stderr.txt"));
      const std::string prefix = work.string() + "/";  // paths relative to the work directory
      for (std::size_t i = r.error.find(prefix); i != std::string::npos; i = r.error.find(prefix)) r.error.erase(i, prefix.size());
      if (r.error.empty()) r.error = "exit " + std::to_string(rc);
    }
  }
  // Issue 8: bezier.msh loads in Gmsh. Its -check is slow on large meshes (43 s on the torus's
  // 87,648 nodes), so it is not part of the wall time.
  if (rc == 0 && all_exports && std::system("gmsh --version > /dev/null 2>&1") == 0) {
    const int g = run_with_timeout({"gmsh", (dir / "bezier.msh").string(), "-check"}, dir / "gmsh_check.txt", dir / "gmsh_check.err.txt", timeout_s);
    const std::string out = read_text(dir / "gmsh_check.txt") + read_text(dir / "gmsh_check.err.txt");
    const char* stage = r.report.contains("tet2hex") ? "tet2hex" : "extract";
    const auto elements = r.report.contains(stage) ? r.report[stage].value("bezier_elements", -1L) : -1L;
    r.gmsh_ok = g == 0 && out.find("rror") == std::string::npos && out.find(std::to_string(elements) + " elements") != std::string::npos;
    r.gmsh_note = g < 0 ? "timeout" : *r.gmsh_ok ? "ok" : "failed (see gmsh_check.txt)";
  }
  std::fprintf(stderr, "bench_pipeline: %s: %s in %.1f s%s%s\n", m.name.c_str(), r.status.c_str(), r.wall_s,
               r.failed_stage.empty() ? "" : (", stage " + r.failed_stage).c_str(), r.error.empty() ? "" : (": " + r.error).c_str());
  return r;
}

// -------------------------------------------------------------------------------------------------
// Figures and targets

std::optional<double> figure(const Result& r, const char* stage, const char* key) {
  // The tet route's one stage reports extract's figures under "tet2hex" (its time is its own).
  if (std::string(stage) == "extract" && std::string(key) != "time_s" && r.report.contains("tet2hex")) stage = "tet2hex";
  if (!r.report.contains(stage)) return std::nullopt;
  const Json& s = r.report[stage];
  if (!s.contains(key) || !s[key].is_number()) return std::nullopt;
  return s[key].get<double>();
}

std::optional<double> report_total(const Result& r) {
  double t = 0;
  bool any = false;
  for (const char* s : kStages)
    if (auto v = figure(r, s, "time_s")) t += *v, any = true;
  if (auto v = figure(r, "tet2hex", "time_s")) t += *v, any = true;
  return any ? std::optional<double>(t) : std::nullopt;
}

// The reports of two runs agree on everything but times (keys ending in "time_s" or "_s"): the
// pipeline is deterministic, so repeated runs must give the same figures.
bool same_figures(const Json& a, const Json& b) {
  if (a.is_object() != b.is_object() || a.is_array() != b.is_array()) return false;
  if (a.is_object()) {
    if (a.size() != b.size()) return false;
    for (auto it = a.begin(); it != a.end(); ++it) {
      const std::string& k = it.key();
      if (!b.contains(k)) return false;
      if (k.size() >= 2 && k.compare(k.size() - 2, 2, "_s") == 0) continue;  // a time
      if (!same_figures(it.value(), b[k])) return false;
    }
    return true;
  }
  if (a.is_array()) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!same_figures(a[i], b[i])) return false;
    return true;
  }
  return a == b;
}

std::string fmt_count(std::optional<double> v) {
  if (!v) return "-";
  std::string s = std::to_string(static_cast<long long>(std::llround(*v)));
  for (int i = static_cast<int>(s.size()) - 3; i > 0 && s[i - 1] != '-'; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

std::string fmt(std::optional<double> v, const char* f) {
  if (!v) return "-";
  char b[48];
  std::snprintf(b, sizeof b, f, *v);
  return b;
}

void evaluate(Result& r, const Model& m) {
  const bool ran = r.status == "ok";
  auto add = [&](const std::string& name, std::optional<double> v, const char* vf, double limit, const char* lf, bool at_most) {
    Target t{name, fmt(v, vf), std::string(at_most ? "<= " : ">= ") + fmt(limit, lf), false};
    t.pass = ran && v && (at_most ? *v <= limit : *v >= limit);
    r.targets.push_back(t);
  };
  if (m.paper) {
    add("time", r.wall_s > 0 ? std::optional<double>(r.wall_s) : std::nullopt, "%.1f s", m.paper->seconds / 10, "%.2f s", true);
    add("elements", figure(r, "extract", "bezier_elements"), "%.0f", static_cast<double>(m.paper->elements), "%.0f", false);
    r.targets.back().value = fmt_count(figure(r, "extract", "bezier_elements"));
    r.targets.back().limit = ">= " + fmt_count(static_cast<double>(m.paper->elements));
  }
  if (m.sj_target >= -1) add("worst SJ", figure(r, "extract", "min_scaled_jacobian"), "%.3f", m.sj_target, "%.2f", false);
  add("hausdorff", figure(r, "extract", "hausdorff_rel"), "%.2e", 0.005, "%.3f", true);
  add("volume", figure(r, "extract", "volume_rel_error"), "%.2e", 0.005, "%.3f", true);
  const auto valid = figure(r, "extract", "certified_valid"), total = figure(r, "extract", "bezier_elements");
  Target t{"certified", fmt_count(valid) + "/" + fmt_count(total), "all", ran && valid && total && *total > 0 && *valid == *total};
  r.targets.push_back(t);
  if (r.gmsh_ok) r.targets.push_back({"gmsh", r.gmsh_note, "exit 0, no error", *r.gmsh_ok});
}

// One table: header and rows of cells; printed aligned or as Markdown.
using Table = std::vector<std::vector<std::string>>;

// A row shorter than the header is a note (a failed run's message): printed as it is, not aligned.
void print_aligned(const Table& t) {
  std::vector<std::size_t> w(t[0].size(), 0);
  for (const auto& row : t)
    if (row.size() == t[0].size())
      for (std::size_t c = 0; c < row.size(); ++c) w[c] = std::max(w[c], row[c].size());
  for (const auto& row : t) {
    if (row.size() < t[0].size()) {
      std::printf("%-*s  %s\n", static_cast<int>(w[0]), row[0].c_str(), row.size() > 1 ? row[1].c_str() : "");
      continue;
    }
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      const std::string pad(w[c] - row[c].size(), ' ');
      line += c == 0 ? row[c] + pad : "  " + pad + row[c];
    }
    std::printf("%s\n", line.c_str());
  }
}

std::string md_escape(std::string s) {
  for (std::size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
  return s;
}

void print_markdown(const Table& t) {
  for (std::size_t r = 0; r < t.size(); ++r) {
    std::string line = "|";
    for (std::size_t c = 0; c < t[0].size(); ++c) line += " " + (c < t[r].size() ? md_escape(t[r][c]) : "") + " |";
    std::printf("%s\n", line.c_str());
    if (r == 0) {
      line = "|";
      for (std::size_t c = 0; c < t[r].size(); ++c) line += c == 0 ? "---|" : "---:|";
      std::printf("%s\n", line.c_str());
    }
  }
}

Table figures_table(const std::vector<Result>& results, const std::vector<const Model*>& models) {
  Table t = {{"model", "nodes", "functions", "irregular s/i", "elements", "worst SJ", "worst SJ 7^3", "best SJ", "valid/total", "hausdorff_rel", "volume_rel_err",
              "classify s", "split s", "polycube s", "tmesh s", "extract s", "total s", "wall s"}};
  for (std::size_t k = 0; k < results.size(); ++k) {
    const Result& r = results[k];
    if (r.status == "ok" || !r.report.empty()) {
      std::vector<std::string> row = {r.model, fmt_count(figure(r, "tmesh", "nodes")), fmt_count(figure(r, "extract", "global_functions")),
                                      fmt_count(figure(r, "tmesh", "irregular_nodes_surface")) + "/" +
                                          fmt_count(figure(r, "tmesh", "irregular_nodes_interior")),
                                      fmt_count(figure(r, "extract", "bezier_elements")), fmt(figure(r, "extract", "min_scaled_jacobian"), "%.3f"),
                                      fmt(figure(r, "extract", "min_scaled_jacobian_dense"), "%.3f"),
                                      fmt(figure(r, "extract", "max_scaled_jacobian"), "%.3f"),
                                      fmt_count(figure(r, "extract", "certified_valid")) + "/" + fmt_count(figure(r, "extract", "bezier_elements")),
                                      fmt(figure(r, "extract", "hausdorff_rel"), "%.2e"), fmt(figure(r, "extract", "volume_rel_error"), "%.2e")};
      for (const char* s : kStages) row.push_back(fmt(figure(r, s, "time_s"), "%.2f"));
      row.push_back(fmt(report_total(r), "%.2f"));
      row.push_back(fmt(r.wall_s > 0 ? std::optional<double>(r.wall_s) : std::nullopt, "%.1f"));
      t.push_back(row);
    }
    if (r.status != "ok") {
      t.push_back({r.report.empty() ? r.model : "",
                   r.status + (r.failed_stage.empty() ? "" : " at " + r.failed_stage) + (r.error.empty() ? "" : ": " + r.error)});
    }
    if (const Paper* p = models[k]->paper) {
      std::vector<std::string> row(t[0].size(), "");
      row[0] = "  paper " + std::string(p->name);
      row[1] = fmt_count(static_cast<double>(p->nodes));
      row[4] = fmt_count(static_cast<double>(p->elements));
      row[5] = fmt(p->worst_sj, "%.2f");
      row[16] = fmt(p->seconds, "%.1f");
      t.push_back(row);
    }
  }
  return t;
}

Table targets_table(const std::vector<Result>& results) {
  const char* names[] = {"time", "elements", "worst SJ", "hausdorff", "volume", "certified", "gmsh"};
  Table t = {{"model", "time <= paper/10", "elements >= paper", "worst SJ", "hausdorff_rel <= 0.005", "volume_rel_err <= 0.005",
              "all certified valid", "gmsh -check", "all"}};
  for (const Result& r : results) {
    std::vector<std::string> row = {r.model};
    bool all = true;
    for (const char* n : names) {
      auto it = std::find_if(r.targets.begin(), r.targets.end(), [&](const Target& x) { return x.name == n; });
      if (it == r.targets.end()) {
        row.push_back("n/a");
        continue;
      }
      all = all && it->pass;
      std::string cell = std::string(it->pass ? "PASS" : "FAIL") + " " + it->value;
      if (it->name == "time" || it->name == "elements" || it->name == "worst SJ") cell += " (" + it->limit + ")";
      row.push_back(cell);
    }
    row.push_back(all ? "PASS" : "FAIL");
    t.push_back(row);
  }
  return t;
}

Json to_json(const std::vector<Result>& results, const std::vector<const Model*>& models) {
  Json out = Json::array();
  for (std::size_t k = 0; k < results.size(); ++k) {
    const Result& r = results[k];
    Json j = {{"model", r.model}, {"input", r.input}, {"status", r.status}, {"wall_s", r.wall_s}, {"wall_runs_s", r.wall_runs_s}, {"stages", r.report}};
    if (!r.failed_stage.empty()) j["failed_stage"] = r.failed_stage;
    if (!r.error.empty()) j["error"] = r.error;
    if (const Paper* p = models[k]->paper)
      j["paper"] = {{"name", p->name}, {"nodes", p->nodes}, {"elements", p->elements}, {"worst_scaled_jacobian", p->worst_sj}, {"time_s", p->seconds}};
    Json targets = Json::array();
    for (const Target& t : r.targets) targets.push_back({{"target", t.name}, {"value", t.value}, {"limit", t.limit}, {"pass", t.pass}});
    j["targets"] = targets;
    out.push_back(j);
  }
  return out;
}

const char* kUsage =
    "usage: bench_pipeline [--models a,b] [--workdir DIR] [--timeout S] [--json FILE] [--models-dir DIR]\n"
    "                      [--volts PATH] [--all-exports] [--repeat N] [--list]\n"
    "Runs `volts run` on each model and prints Liu et al. 2013 Table 1's columns next to the paper's.\n"
    "  --models a,b     models to run (default: all; --list shows them)\n"
    "  --workdir DIR    run directories DIR/<model> are kept (default: a temporary directory, removed)\n"
    "  --timeout S      per-model limit in seconds (default 600); the run is killed after it\n"
    "  --json FILE      also write the results as JSON\n"
    "  --models-dir DIR shared models (default: $VOLTS_SHARED_MODELS, else ../shared/models next to the sources)\n"
    "  --volts PATH     the volts driver (default: the one built with this benchmark)\n"
    "  --all-exports    keep extract.exports at its default (bext, json, msh, png too; default: vtu only),\n"
    "                   and run `gmsh bezier.msh -check` if gmsh is installed (a target column; not timed)\n"
    "  --repeat N       run every model N times (default 1): wall = the median; the runs' figures must agree\n";

}  // namespace

int main(int argc, char** argv) {
  std::string only, workdir, json_file, volts = VOLTS_DRIVER;
  fs::path models_dir = std::getenv("VOLTS_SHARED_MODELS") ? fs::path(std::getenv("VOLTS_SHARED_MODELS")) : fs::path(VOLTS_SHARED_MODELS);
  double timeout_s = 600;
  bool all_exports = false;
  int repeat = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_pipeline: %s needs a value\n%s", a.c_str(), kUsage);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--models") only = value();
    else if (a == "--workdir") workdir = value();
    else if (a == "--timeout") timeout_s = std::atof(value().c_str());
    else if (a == "--json") json_file = value();
    else if (a == "--models-dir") models_dir = value();
    else if (a == "--volts") volts = value();
    else if (a == "--all-exports") all_exports = true;
    else if (a == "--repeat") repeat = std::atoi(value().c_str());
    else if (a == "--list") {
      for (const Model& m : all_models()) std::printf("%-16s %s\n", m.name.c_str(), m.generate.empty() ? m.file.c_str() : ("generated " + m.generate).c_str());
      return 0;
    } else {
      std::fprintf(stderr, a == "-h" || a == "--help" ? "%s%s" : "bench_pipeline: unknown argument '%s'\n%s", a == "-h" || a == "--help" ? "" : a.c_str(), kUsage);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  if (!(timeout_s > 0)) {
    std::fprintf(stderr, "bench_pipeline: --timeout must be > 0\n");
    return 2;
  }
  if (repeat < 1 || repeat > 100) {
    std::fprintf(stderr, "bench_pipeline: --repeat must be in [1, 100]\n");
    return 2;
  }
  std::vector<const Model*> models;
  if (only.empty()) {
    for (const Model& m : all_models()) models.push_back(&m);
  } else {
    std::stringstream in(only);
    for (std::string name; std::getline(in, name, ',');) {
      auto it = std::find_if(all_models().begin(), all_models().end(), [&](const Model& m) { return m.name == name; });
      if (it == all_models().end()) {
        std::fprintf(stderr, "bench_pipeline: unknown model '%s' (see --list)\n", name.c_str());
        return 2;
      }
      models.push_back(&*it);
    }
  }
  const bool temp = workdir.empty();
  const fs::path work = temp ? fs::temp_directory_path() / ("volts_bench_pipeline_" + std::to_string(::getpid())) : fs::path(workdir);
  fs::create_directories(work);
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);

  std::vector<Result> results;
  for (const Model* m : models) {
    Result r = run_model(*m, models_dir, work, volts, timeout_s, all_exports);
    r.wall_runs_s.push_back(r.wall_s);
    for (int k = 1; k < repeat && r.status == "ok"; ++k) {
      const Result again = run_model(*m, models_dir, work, volts, timeout_s, all_exports);
      r.wall_runs_s.push_back(again.wall_s);
      if (again.status != "ok") {
        r.status = again.status, r.error = "run " + std::to_string(k + 1) + ": " + again.error;
      } else if (!same_figures(r.report, again.report)) {
        r.status = "nondeterministic", r.error = "run " + std::to_string(k + 1) + " gave other figures than run 1";
      }
    }
    std::vector<double> walls = r.wall_runs_s;
    std::sort(walls.begin(), walls.end());
    r.wall_s = walls.size() % 2 ? walls[walls.size() / 2] : 0.5 * (walls[walls.size() / 2 - 1] + walls[walls.size() / 2]);
    results.push_back(std::move(r));
    evaluate(results.back(), *m);
  }
  if (temp) fs::remove_all(work);

  const Table figures = figures_table(results, models), targets = targets_table(results);
  std::printf("Liu et al. 2013 Table 1: volts (this machine) and the paper (2.93 GHz Xeon, 2013)\n\n");
  print_aligned(figures);
  std::printf("\nTargets (issue 8)\n\n");
  print_aligned(targets);
  std::printf("\nMarkdown\n\n");
  print_markdown(figures);
  std::printf("\n");
  print_markdown(targets);
  std::printf("\nnodes: T-mesh nodes (stages.tmesh.nodes, the paper's column); functions: global basis functions (one fewer per\n"
              "T-junction and per clamped extra of the C2 rows of tmesh.continuity c2, the default for cubics); irregular s/i: surface/interior irregular nodes; worst/best SJ: sampled\n"
              "scaled Jacobian (corners + Gauss points, the paper's sample); worst SJ 7^3: on a uniform 7^3 grid per element, faces\n"
              "and edges included (extract.dense_points: the field between those samples); valid: certified det J > 0;\n"
              "hausdorff_rel: sampled, one-sided; stage times\n"
              "from report.json (time_s; with --repeat, the first run's), total = their sum, wall = the whole `volts run`\n"
              "(with --repeat, the median over the runs; targets use wall). Inputs:\n");
  for (const Result& r : results) std::printf("  %s: %s\n", r.model.c_str(), r.input.c_str());
  if (!json_file.empty()) std::ofstream(json_file) << to_json(results, models).dump(2) << "\n";
  return 0;
}
