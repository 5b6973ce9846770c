// Stage files and atomic writes: round trip, and every broken file is a clear InvalidInputError
// that names the file; a failing writer leaves nothing behind.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stage_file.h"

namespace fs = std::filesystem;
using namespace volts;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("volts_core_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::size_t count() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator())); }
};

void write_raw(const std::string& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

template <class E>
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "<no exception>";
}

}  // namespace

TEST(StageFile, RoundTripKeepsDoublesExactly) {
  TempDir d;
  const std::vector<double> xs = {0.1, 1.0 / 3.0, -2.5e-300, 1e300, 3.141592653589793};
  core::write_stage_file(d.file("a.stage.json"), "volts-test", 2, {{"xs", xs}});
  const auto j = core::read_stage_file(d.file("a.stage.json"), "volts-test", 2);
  EXPECT_EQ(j["xs"].get<std::vector<double>>(), xs);
  EXPECT_EQ(j["version"].get<int>(), 2);
  EXPECT_EQ(d.count(), 1u);  // no temporary left
}

// read_stage_file parses with simdjson and converts to nlohmann's tree (stage_file.cpp): the tree
// must be the one nlohmann's own parser makes, number types included, over texts with every kind
// of value; an integer beyond 64 bits (which simdjson refuses) is a double, as nlohmann reads it.
// The one difference: "-0" is an unsigned 0 here, a signed 0 in nlohmann (equal values).
TEST(StageFile, ReadsTheTreeNlohmannWould) {
  TempDir d;
  const std::vector<std::string> payloads = {
      R"("n": [0, 1, -1, 18446744073709551615, -9223372036854775808, 9223372036854775807, 9223372036854775808])",
      R"("x": [0.0, -0.0, 1.5, 1e5, 1E-300, 2.2250738585072014e-308, 4.9e-324, 1.7976931348623157e308, 0.1, 123456789.123456789])",
      R"("s": ["", "a\"b", "\u00e9t\u00e9 \ud83d\ude00", "cafÃ©", "tab\tnew\nline"], "b": [true, false, null])",
      R"("o": {"a": {"b": [[], {}, [[1]], {"c": {"d": []}}]}, "k": 1, "k": 2})",
      R"("big": 123456789012345678901234567890, "neg": -123456789012345678901234567890)",
  };
  for (const std::string& p : payloads) {
    const std::string text = R"({"format": "volts-test", "version": 1, )" + p + "}";
    write_raw(d.file("a.json"), text);
    const core::Json got = core::read_stage_file(d.file("a.json"), "volts-test", 1);
    const core::Json want = core::Json::parse(text);
    EXPECT_EQ(got, want) << p;
    EXPECT_EQ(got.dump(), want.dump()) << p;  // the same number types too (dump prints 1 and 1.0 apart)
    // nlohmann's == compares numbers across types; the types themselves, value by value:
    std::function<void(const core::Json&, const core::Json&)> same_types = [&](const core::Json& a, const core::Json& b) {
      ASSERT_EQ(a.type(), b.type()) << a.dump() << " in " << p;
      if (a.is_array())
        for (std::size_t i = 0; i < a.size(); ++i) same_types(a[i], b[i]);
      if (a.is_object())
        for (auto it = a.begin(); it != a.end(); ++it) same_types(it.value(), b.at(it.key()));
    };
    same_types(got, want);
  }
  write_raw(d.file("a.json"), R"({"format": "volts-test", "version": 1, "z": -0})");
  EXPECT_EQ(core::read_stage_file(d.file("a.json"), "volts-test", 1)["z"], 0);
}

TEST(StageFile, NewerVersionIsRefused) {
  TempDir d;
  core::write_stage_file(d.file("a.json"), "volts-test", 3, core::Json::object());
  const auto m = message_of<core::InvalidInputError>([&] { core::read_stage_file(d.file("a.json"), "volts-test", 2); });
  EXPECT_NE(m.find(d.file("a.json")), std::string::npos) << m;
  EXPECT_NE(m.find("version 3 is newer"), std::string::npos) << m;
}

TEST(StageFile, WrongFormatIsRefused) {
  TempDir d;
  core::write_stage_file(d.file("a.json"), "volts-split", 1, core::Json::object());
  const auto m = message_of<core::InvalidInputError>([&] { core::read_stage_file(d.file("a.json"), "volts-classify", 1); });
  EXPECT_NE(m.find("is a volts-split file, expected volts-classify"), std::string::npos) << m;
}

TEST(StageFile, TruncatedEmptyMissingAndForeignFilesAreRefused) {
  TempDir d;
  core::write_stage_file(d.file("full.json"), "volts-test", 1, {{"xs", std::vector<int>(100, 7)}});
  const std::string text = core::read_text_file(d.file("full.json"));
  write_raw(d.file("cut.json"), text.substr(0, text.size() / 2));
  write_raw(d.file("empty.json"), "");
  write_raw(d.file("foreign.json"), "{\"hello\": 1}");
  write_raw(d.file("noversion.json"), "{\"format\": \"volts-test\"}");
  struct Case { std::string file, expect; };
  for (const Case& c : {Case{"cut.json", "truncated or malformed"}, Case{"empty.json", "file is empty"},
                        Case{"foreign.json", "not a volts stage file"}, Case{"noversion.json", "no integer \"version\""},
                        Case{"missing.json", "cannot open file"}}) {
    const auto m = message_of<core::InvalidInputError>([&] { core::read_stage_file(d.file(c.file), "volts-test", 1); });
    EXPECT_NE(m.find(d.file(c.file)), std::string::npos) << m;
    EXPECT_NE(m.find(c.expect), std::string::npos) << c.file << ": " << m;
  }
}

TEST(AtomicFile, FailingWriterLeavesNothing) {
  TempDir d;
  EXPECT_THROW(core::write_atomically(d.file("out.txt"),
                                      [](const std::string& tmp) {
                                        std::ofstream(tmp) << "half";
                                        throw core::NumericalError("boom");
                                      }),
               core::NumericalError);
  EXPECT_EQ(d.count(), 0u);
}

TEST(AtomicFile, ReplacesExistingFileWhole) {
  TempDir d;
  core::write_text_atomically(d.file("out.txt"), "first");
  core::write_text_atomically(d.file("out.txt"), "second");
  EXPECT_EQ(core::read_text_file(d.file("out.txt")), "second");
  EXPECT_EQ(d.count(), 1u);
}

TEST(Report, StagesAccumulate) {
  TempDir d;
  core::update_report(d.path.string(), "classify", {{"corners", 8}});
  core::update_report(d.path.string(), "extract", {{"bezier_elements", 512}});
  core::update_report(d.path.string(), "classify", {{"corners", 9}});
  const auto r = core::read_report(d.path.string());
  EXPECT_EQ(r["stages"]["classify"]["corners"].get<int>(), 9);
  EXPECT_EQ(r["stages"]["extract"]["bezier_elements"].get<int>(), 512);
}

TEST(Report, TopLevelEntriesBesideTheStages) {
  TempDir d;
  core::update_report(d.path.string(), "classify", {{"corners", 8}});
  core::update_report_entry(d.path.string(), "summary", {{"tmesh_nodes", 11240}});
  core::update_report(d.path.string(), "extract", {{"bezier_elements", 512}});
  const auto r = core::read_report(d.path.string());
  EXPECT_EQ(r["summary"]["tmesh_nodes"].get<int>(), 11240);
  EXPECT_EQ(r["stages"]["classify"]["corners"].get<int>(), 8);
  EXPECT_THROW(core::update_report_entry(d.path.string(), "stages", core::Json::object()), core::InvalidInputError);
  EXPECT_EQ(core::read_report(d.path.string())["stages"].size(), 2u);
  EXPECT_EQ(d.count(), 1u);  // no temporary left
}

// Integers read from JSON are checked (core/stage_file.h): a number that is not a whole number in
// the type's range is a json type_error, not undefined behaviour (fuzz_stage_polycube: 4.7e126 as
// a triangle index).
TEST(StageFile, IntegerConversionsAreChecked) {
  using core::Json;
  EXPECT_EQ(Json(3.0).get<int>(), 3);
  EXPECT_EQ(Json(-7).get<int>(), -7);
  EXPECT_EQ(Json(4294967295u).get<unsigned>(), 4294967295u);
  EXPECT_EQ(Json::parse("[1, 2, 3]").get<std::vector<int>>(), (std::vector<int>{1, 2, 3}));
  EXPECT_THROW((void)Json(4.72222e126).get<int>(), Json::exception);
  EXPECT_THROW((void)Json(2.5).get<int>(), Json::exception);
  EXPECT_THROW((void)Json(std::nan("")).get<int>(), Json::exception);
  EXPECT_THROW((void)Json(2147483648.0).get<int>(), Json::exception);
  EXPECT_THROW((void)Json(2147483648LL).get<int>(), Json::exception);
  EXPECT_THROW((void)Json(-1).get<unsigned>(), Json::exception);
  EXPECT_THROW((void)Json(9.3e18).get<long long>(), Json::exception);
  EXPECT_THROW((void)Json::parse("[1, 2.5e300]").get<std::vector<int>>(), Json::exception);
  using Pairs = std::vector<std::array<int, 2>>;
  EXPECT_THROW((void)Json::parse("[[0, 1], [2, 1e20]]").get<Pairs>(), Json::exception);
  EXPECT_THROW((void)Json("7").get<int>(), Json::exception);
  EXPECT_EQ(Json(-2147483648.0).get<int>(), -2147483647 - 1);
}
