// Determinism (issue 10): the same config run twice gives byte-identical files, so a stage can be
// debugged and a run reproduced. Checked on the generated torus through both routes: polycube
// (all five stages: harmonic fields, TetGen, untangling, optimization) and tet; the box through the
// polycube route is checked in tests/pipeline (Skeleton.SameConfigGivesByteIdenticalFiles).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "common/test_util.h"
#include "core/atomic_file.h"
#include "core/stage_file.h"

namespace fs = std::filesystem;
using namespace volts;

namespace {

std::set<std::string> files_in(const fs::path& d) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(d)) names.insert(e.path().filename().string());
  return names;
}

/// report.json without what legitimately differs between two runs: the times (time_s) and the
/// work directory's own path in "output" and "outputs".
core::Json comparable_report(const fs::path& workdir) {
  core::Json r = core::read_report(workdir.string());
  if (r.contains("summary") && r["summary"].is_object()) r["summary"].erase("time_s");
  for (auto& [stage, figures] : r["stages"].items()) {
    figures.erase("time_s");
    if (figures.contains("output"))
      figures["output"] = fs::path(figures["output"].get<std::string>()).lexically_relative(workdir).string();
    if (figures.contains("outputs"))  // extract: one path per export
      for (auto& [kind, path] : figures["outputs"].items()) path = fs::path(path.get<std::string>()).lexically_relative(workdir).string();
  }
  return r;
}

/// Runs `yaml` twice in fresh work directories and expects the same files, byte for byte, and the
/// same report up to times and paths. Returns the report.
core::Json run_twice(const std::string& name, const std::string& yaml) {
  const fs::path d = test::fresh_dir("hardening", name);
  test::write_text(d / "run.yaml", yaml);
  const fs::path a = d / "a", b = d / "b";
  for (const fs::path& w : {a, b}) {
    const test::Outcome r = test::run(test::bin("volts") + " run " + (d / "run.yaml").string() + " --workdir " + w.string() + " -q");
    EXPECT_EQ(r.code, 0) << r.output;
    if (r.code != 0) return core::Json::object();
  }
  const std::set<std::string> names = files_in(a);
  EXPECT_EQ(names, files_in(b));
  EXPECT_TRUE(names.count("bezier.vtu"));
  EXPECT_TRUE(names.count("config.yaml"));
  for (const std::string& f : names) {
    if (f == "report.json") continue;
    EXPECT_EQ(core::read_text_file((a / f).string()), core::read_text_file((b / f).string())) << f << " differs";
  }
  const core::Json ra = comparable_report(a), rb = comparable_report(b);
  EXPECT_EQ(ra, rb);
  return ra;
}

TEST(Determinism, TorusThroughThePolycubeRouteGivesByteIdenticalFiles) {
  const core::Json r = run_twice("determinism_torus_polycube", "input: {generate: torus, resolution: 12}\n");
  ASSERT_TRUE(r.contains("stages"));
  EXPECT_GT(r["stages"]["extract"]["bezier_elements"].get<int>(), 0);
  EXPECT_GT(r["stages"]["polycube"]["tets"].get<int>(), 0);
}

TEST(Determinism, TorusThroughTheTetRouteGivesByteIdenticalFiles) {
  // Curved boundary and certification on: every part of the route that could depend on order runs.
  const core::Json r = run_twice("determinism_torus", "route: tet\ninput: {generate: torus, resolution: 8}\ntet2hex: {degree: 2}\n");
  ASSERT_TRUE(r.contains("stages"));
  EXPECT_GT(r["stages"]["tet2hex"]["bezier_elements"].get<int>(), 0);
}

}  // namespace
