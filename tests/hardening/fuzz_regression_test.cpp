// The fuzzers' finds, kept: every file in tests/hardening/fuzz_regressions/<kind>/ is an input that
// once crashed, hung or threw an untyped exception in the reader of that kind (fuzz/readers.h); each
// must now be refused with a volts error (core::Error) naming the file. The seed corpora
// (fuzz/corpus/<kind>/, small valid files) must still read without error.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "readers.h"

namespace fs = std::filesystem;
using namespace volts;

namespace {

/// (kind, file) for every file under `root`/<kind>/.
std::vector<std::pair<std::string, fs::path>> inputs(const fs::path& root) {
  std::vector<std::pair<std::string, fs::path>> out;
  if (!fs::is_directory(root)) return out;
  for (const auto& kind : fs::directory_iterator(root))
    if (kind.is_directory())
      for (const auto& f : fs::directory_iterator(kind.path()))
        if (f.is_regular_file()) out.emplace_back(kind.path().filename().string(), f.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(FuzzRegressions, EveryFoundInputIsRefusedWithAVoltsError) {
  for (const auto& [kind, file] : inputs(fs::path(VOLTS_SOURCE_DIR) / "tests/hardening/fuzz_regressions")) {
    SCOPED_TRACE(kind + ": " + file.string());
    try {
      fuzz::read_input(kind, file.string());
      ADD_FAILURE() << "read without error";
    } catch (const core::Error& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
  }
}

TEST(FuzzRegressions, EverySeedReads) {
  const auto seeds = inputs(fs::path(VOLTS_SOURCE_DIR) / "fuzz/corpus");
  EXPECT_GE(seeds.size(), 20u);
  for (const auto& [kind, file] : seeds) {
    SCOPED_TRACE(kind + ": " + file.string());
    EXPECT_NO_THROW(fuzz::read_input(kind, file.string()));
  }
}

}  // namespace
