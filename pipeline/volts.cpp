// volts: the driver. `volts run CONFIG` runs the stage executables in order through their files
// in a work directory, or resumes at any stage from the files already there.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <vector>

#include "config/config.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/log.h"
#include "core/stage_file.h"
#include "run_summary.h"
#include "stage_main.h"

extern char** environ;
namespace fs = std::filesystem;
using namespace volts;

namespace {

const char* kUsage =
    "usage: volts run CONFIG [--workdir DIR] [--from STAGE] [--to STAGE] [-v|-q]\n"
    "       volts stages\n"
    "       volts --help | --version\n\n"
    "Runs the stages classify, split, polycube, tmesh, extract (one executable each, volts-STAGE)\n"
    "on the run described by CONFIG (YAML; see configs/default.yaml). Each stage reads the previous\n"
    "stage's file in DIR and writes its own, so --from STAGE resumes from the files on disk.\n"
    "With 'route: tet' in CONFIG the route is the single stage tet2hex (volts-tet2hex); with 'route: fit'\n"
    "it is classify, then fit (volts-fit: seven pillowed B-spline solids, Lin, Huang & Hu 2018).\n\n"
    "  --workdir DIR   work directory (default: runs/<CONFIG name without extension>)\n"
    "  --from STAGE    first stage to run (default: classify)\n"
    "  --to STAGE      last stage to run (default: extract)\n\n"
    "DIR gets <stage>.stage.json, one ParaView file per stage, bezier.vtu, report.json and the\n"
    "effective config (config.yaml).\n";

// The stages of a route, in order.
std::vector<std::string> route_stages(const std::string& route) {
  if (route == "tet") return {"tet2hex"};
  if (route == "fit") return {"classify", "fit"};
  return std::vector<std::string>(std::begin(pipeline::kStages), std::end(pipeline::kStages));
}

int stage_index(const std::vector<std::string>& stages, const std::string& name) {
  std::string list;
  for (int i = 0; i < static_cast<int>(stages.size()); ++i) {
    if (name == stages[i]) return i;
    list += (i ? ", " : "") + stages[i];
  }
  throw core::UsageError("unknown stage '" + name + "'; the stages of this route are " + list);
}

int spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  static const std::vector<std::string> env = pipeline::stage_environment(environ);
  std::vector<char*> envp;
  for (const auto& e : env) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  pid_t pid;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), envp.data()) != 0)
    throw core::IoError("cannot start " + args[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return static_cast<int>(core::ExitCode::internal);
}

std::string fmt(const core::Json& v) {
  if (v.is_number_float()) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v.get<double>());
    return b;
  }
  return v.dump();
}

void print_summary(const std::string& workdir, const std::vector<std::string>& stages, int from, int to) {
  const core::Json r = core::read_report(workdir);
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"classify", {"corners", "curves", "feature_curves", "difference_curves", "patches", "genus"}},
      {"split", {"genus", "components", "tori", "quad_patches", "filled_triangles"}},
      {"polycube", {"cubes", "flipped_surface_triangles", "max_angle_distortion_deg"}},
      {"tmesh", {"nodes", "elements", "max_level", "min_scaled_jacobian_after"}},
      {"extract", {"bezier_elements", "degree", "certified_valid", "undecided", "min_scaled_jacobian", "max_scaled_jacobian",
                   "hausdorff_rel", "volume_rel_error"}},
      {"tet2hex", {"tets", "bezier_elements", "degree", "certified_valid", "min_scaled_jacobian", "hausdorff_rel", "volume_rel_error",
                   "boundary_faces_reverted"}},
      {"fit", {"patch_source", "bezier_elements", "certified_valid", "min_scaled_jacobian", "volume_frac_scaled_jacobian_above_0_5",
               "hausdorff_rel", "volume_rel_error", "g1_max_angle_deg_after"}}};
  std::cout << "\nvolts summary (" << workdir << "/report.json)\n";
  std::printf("  %-9s %9s  %s\n", "stage", "time [s]", "figures");
  double total = 0;
  for (int i = from; i <= to; ++i) {
    const auto it = r.find("stages");
    if (it == r.end() || !it->contains(stages[i])) continue;
    const core::Json& s = (*it)[stages[i]];
    std::string figs;
    for (const auto& k : keys.at(stages[i]))
      if (s.contains(k)) figs += k + "=" + (k == "components" ? std::to_string(s[k].size()) : fmt(s[k])) + "  ";
    const double t = s.value("time_s", 0.0);
    total += t;
    std::printf("  %-9s %9.3f  %s\n", stages[i].c_str(), t, figs.c_str());
  }
  std::printf("  %-9s %9.3f\n", "total", total);
}

int run(int argc, char** argv) {
  std::string config_path, workdir, log_flag, from_name, to_name;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw core::UsageError(a + " needs a value");
      return argv[++i];
    };
    if (a == "--workdir") workdir = value();
    else if (a == "--from") from_name = value();
    else if (a == "--to") to_name = value();
    else if (a == "-v" || a == "-q") log_flag = a;
    else if (a == "-h" || a == "--help") { std::cout << kUsage; return 0; }
    else if (!a.empty() && a[0] == '-') throw core::UsageError("unknown option '" + a + "'");
    else if (config_path.empty()) config_path = a;
    else throw core::UsageError("more than one CONFIG given ('" + config_path + "', '" + a + "')");
  }
  if (config_path.empty()) throw core::UsageError("volts run needs a CONFIG file (see configs/default.yaml)");
  const config::Config cfg = config::load_config(config_path);  // fail early, before any stage runs
  const std::vector<std::string> stages = route_stages(cfg.route);
  const int from = from_name.empty() ? 0 : stage_index(stages, from_name);
  const int to = to_name.empty() ? static_cast<int>(stages.size()) - 1 : stage_index(stages, to_name);
  if (from > to) throw core::UsageError("--from comes after --to");
  if (workdir.empty()) workdir = (fs::path("runs") / fs::path(config_path).stem()).string();
  fs::create_directories(workdir);
  if (from > 0) {
    const std::string needed = pipeline::stage_file(workdir, stages[from - 1]);
    if (!fs::exists(needed))
      throw core::InvalidInputError(needed + ": missing; run the earlier stages first (volts run " + config_path +
                                    " --workdir " + workdir + " --to " + stages[from - 1] + ")");
  }
  core::write_text_atomically((fs::path(workdir) / "config.yaml").string(), config::to_yaml(cfg));
  const fs::path bindir = fs::canonical("/proc/self/exe").parent_path();
  for (int i = from; i <= to; ++i) {
    const std::string& stage = stages[i];
    std::vector<std::string> args = {(bindir / ("volts-" + stage)).string(), "--config", config_path, "--workdir", workdir};
    if (!log_flag.empty()) args.push_back(log_flag);
    core::log("stage " + stage);
    const int rc = spawn(args);
    if (rc != 0) {
      std::cerr << "volts: stage " << stage << " failed (exit " << rc << "); after fixing, resume with: volts run "
                << config_path << " --workdir " << workdir << " --from " << stage << "\n";
      return rc;
    }
  }
  // Table 1's columns once the route's last stage ran (report key `summary`, docs/formats.md);
  // null when an earlier stage has no entry (its stage file copied in, not run here).
  if (to == static_cast<int>(stages.size()) - 1) {
    core::Json summary = nullptr;
    try {
      summary = pipeline::run_summary(core::read_report(workdir), stages);
    } catch (const core::InvalidInputError& e) {
      core::log_warning(std::string("report.json gets no summary: ") + e.what());
    }
    core::update_report_entry(workdir, "summary", summary);
  }
  print_summary(workdir, stages, from, to);
  const fs::path vtu = fs::path(workdir) / "bezier.vtu";
  if (to == static_cast<int>(stages.size()) - 1 && fs::exists(vtu)) std::cout << "\nopen in ParaView: " << fs::absolute(vtu).string() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  core::set_log_tool("volts");
  try {
    if (argc < 2) throw core::UsageError("no command given\n" + std::string(kUsage));
    const std::string cmd = argv[1];
    if (cmd == "-h" || cmd == "--help" || cmd == "help") { std::cout << kUsage; return 0; }
    if (cmd == "--version") { std::cout << core::producer() << "\n"; return 0; }
    if (cmd == "stages") {
      for (const char* s : pipeline::kStages) std::cout << s << "\n";
      return 0;
    }
    if (cmd == "run") return run(argc, argv);
    throw core::UsageError("unknown command '" + cmd + "' (see volts --help)");
  } catch (const core::Error& e) {
    std::cerr << "volts: error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << "volts: internal error (please report): " << e.what() << "\n";
    return 1;
  }
}
