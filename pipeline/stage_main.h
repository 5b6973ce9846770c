// Shared command line and error handling of the stage executables (volts-classify ... volts-extract).
// Each executable is a thin main() that calls run_stage() with its body.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "classify/classify.h"
#include "config/config.h"
#include "core/stage_file.h"
#include "surface/surface.h"

namespace volts::pipeline {

/// Stage names, in order; these are contracts (config sections, --from/--to, report keys).
inline const char* const kStages[] = {"classify", "split", "polycube", "tmesh", "extract"};

/// File names inside the work directory: DIR/<stage>.stage.json. Inline so that the driver `volts`
/// links nothing of stage_main.cpp: that would pull in the surface readers and VTK, whose dynamic
/// loading was most of the driver's start (34 → 8 ms CPU).
inline std::string stage_file(const std::string& workdir, const std::string& stage) {
  return (std::filesystem::path(workdir) / (stage + ".stage.json")).string();
}

struct StageContext {
  std::string stage;
  std::string workdir = ".";
  std::string input;   ///< --input: overrides the default input file
  std::string output;  ///< --output: overrides DIR/<stage>.stage.json
  config::Config config;
  std::string path(const std::string& name) const;  ///< DIR/name
  std::string input_file(const std::string& previous_stage) const;
  std::string output_file() const;
};

/// The input surface of a run: --input FILE, else config input.file, else the generated model of
/// input.generate. Logs what it did (a flipped or welded surface) and returns the report's "input"
/// figures in `info`. Throws core::ConfigError if there is no input, as read_surface/make_model else.
surface::Mesh load_input_surface(const StageContext& ctx, core::Json* info);

/// Checks that every integer member of the payloads of a stage file (classification,
/// decomposition, polycube, tmesh; those present) is an integer in int's range: the payload
/// readers convert with nlohmann's get<int>, and a float such as 1e30 cast to int is undefined.
/// Throws core::InvalidInputError naming `file` and the member.
void check_integer_members(const std::string& file, const core::Json& stage_file);

/// Cross-checks of the payloads of one stage file: a file edited by hand, or assembled from
/// mismatched runs, is refused here with core::InvalidInputError naming `file` and the first
/// inconsistency, rather than reaching an algorithm that trusts its indices.
void check_classification(const std::string& file, const surface::Mesh& mesh, const classify::Classification& c);
void check_decomposition(const std::string& file, const classify::Classification& c, const split::Decomposition& d);
void check_polycube(const std::string& file, const surface::Mesh& mesh, const classify::Classification& c,
                    const polycube::Polycube& p);

/// classify.stage.json as the stages after classify read it (split, fit): the file's JSON (its
/// payloads are passed on unchanged), the surface and the classification, cross-checked.
struct ClassifyInput {
  std::string file;
  core::Json json;
  surface::Mesh mesh;
  classify::Classification classification;
};
/// Throws what read_stage_file, check_integer_members and check_classification throw.
ClassifyInput read_classify_input(const StageContext& ctx);

/// Parses `--config FILE --workdir DIR --input FILE --output FILE -v -q --help`, runs `body`, records
/// time_s and the body's figures in DIR/report.json, and turns every volts error into
/// "volts-STAGE: error: ..." on stderr with its exit code. `help` is the stage's one-paragraph
/// description for --help.
int run_stage(int argc, char** argv, const std::string& stage, const std::string& help,
              const std::function<core::Json(StageContext&)>& body);

/// The environment the driver starts the stages with: `vars` (null-terminated "NAME=value"
/// strings) plus glibc.malloc.hugetlb=1 in GLIBC_TUNABLES (appended to the tunables given, or a
/// new GLIBC_TUNABLES) unless that tunable is set already, which then stands. malloc then asks for
/// transparent huge pages (madvise; nothing changes where THP is "never"). Why: on the VMs volts is
/// benchmarked on, a 4 KiB page touched the first time costs ~13 us (the eight's extract took
/// 14,700 such faults); with huge pages the eight's run is ~10 % shorter and the rod's tmesh
/// 11.4 -> 10.3 s (docs/benchmarks.md "Session 46"). GLIBC_TUNABLES is read when a process
/// starts, so only a parent can set it.
std::vector<std::string> stage_environment(char** vars);

}  // namespace volts::pipeline
