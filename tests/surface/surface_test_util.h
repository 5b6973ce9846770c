// Shared helpers of the volts::surface tests: a private temporary directory per test, small
// known meshes as file text, and an expectation on InvalidInputError messages.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/errors.h"
#include "surface/surface.h"

namespace volts::surface::test {

namespace fs = std::filesystem;

/// An empty directory of its own for the running test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("volts-surface-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const fs::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Writes `content` byte for byte and returns the file's path.
  std::string write(const std::string& name, const std::string& content) const {
    std::ofstream out(file(name), std::ios::binary);
    out << content;
    return file(name);
  }

 private:
  fs::path path_;
};

/// Expects `f` to throw core::InvalidInputError whose message starts with "PATH: " and contains `text`.
template <class F>
void expect_invalid_input(F&& f, const std::string& path, const std::string& text) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning: " << text;
  } catch (const core::InvalidInputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << "message does not start with the path: " << message;
    EXPECT_NE(message.find(text), std::string::npos) << "expected '" << text << "' in: " << message;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type, message: " << e.what();
  }
}

// Tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1), outward faces; volume 1/6.
inline const std::string kTetrahedronOff =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

}  // namespace volts::surface::test
