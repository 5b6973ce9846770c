// Helpers shared by the tests of every module (header-only): running a command as a user would,
// fresh temporary directories, small text files, generated models.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "models/models.h"
#include "surface/surface.h"

namespace volts::test {

/// What a command did: its exit code (-1 if it did not exit normally or could not start) and its
/// stdout and stderr, interleaved.
struct Outcome {
  int code = -1;
  std::string output;
};

/// Runs `cmd` through the shell with stderr joined to stdout.
inline Outcome run(const std::string& cmd) {
  Outcome r;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p)) r.output += buf.data();
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

#ifdef VOLTS_BIN_DIR
/// Path of an executable of this build (VOLTS_BIN_DIR is set by the test's CMakeLists).
inline std::string bin(const std::string& tool) { return std::string(VOLTS_BIN_DIR) + "/" + tool; }
#endif

namespace detail {
/// The directories fresh_dir made in this process, removed when it exits: the pipeline tests write
/// hundreds of MB each, and a test run that left them behind filled the CI machine's disk. They are
/// kept if a test failed (to look at) or if VOLTS_KEEP_TEST_DIRS is set.
struct DirsToRemove {
  std::vector<std::filesystem::path> dirs;
  ~DirsToRemove() {
    if (std::getenv("VOLTS_KEEP_TEST_DIRS") != nullptr) return;
    if (::testing::UnitTest::GetInstance()->Failed()) {
      for (const auto& d : dirs) std::cerr << "kept for inspection: " << d.string() << "\n";
      return;
    }
    for (const auto& d : dirs) {
      std::error_code ec;  // a directory a test removed itself is no error
      std::filesystem::remove_all(d, ec);
    }
  }
};
inline DirsToRemove& dirs_to_remove() {
  static DirsToRemove dirs;
  return dirs;
}
}  // namespace detail

/// An empty directory <tmp>/volts_<prefix>_<pid>_<name>, removed first if it exists (the pid keeps
/// concurrent test runs apart), and removed again when the test process exits unless a test failed.
inline std::filesystem::path fresh_dir(const std::string& prefix, const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("volts_" + prefix + "_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  detail::dirs_to_remove().dirs.push_back(d);
  return d;
}

/// Writes `text` to `path` as is (binary mode: no newline translation).
inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// The generated model `name` (models::model_names()) at `resolution`, other parameters default.
inline surface::Mesh generated_model(const std::string& name, int resolution) {
  models::ModelParams p;
  p.name = name;
  p.resolution = resolution;
  return models::make_model(p);
}

}  // namespace volts::test
