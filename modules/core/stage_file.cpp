#include "core/stage_file.h"

#include <filesystem>
#include <functional>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace volts::core {

std::string producer() { return "volts 0.1.0"; }

void write_stage_file(const std::string& path, const std::string& format, int version, Json payload) {
  Json j = std::move(payload);
  j["format"] = format;
  j["version"] = version;
  j["producer"] = producer();
  // Compact dump: stage files can hold 1e5 points; nlohmann prints doubles round-trip exactly.
  write_text_atomically(path, j.dump() + "\n");
}

Json read_stage_file(const std::string& path, const std::string& format, int max_version) {
  const std::string text = read_text_file(path);
  if (text.empty()) throw InvalidInputError(path + ": file is empty");
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw InvalidInputError(path + ": not a valid " + format + " file (truncated or malformed JSON at byte " +
                            std::to_string(e.byte) + ")");
  } catch (const Json::exception& e) {  // e.g. out_of_range 406: a number such as 1e999 overflows a double
    throw InvalidInputError(path + ": not a valid " + format + " file (malformed JSON: " + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("format") || !j["format"].is_string())
    throw InvalidInputError(path + ": not a volts stage file (no \"format\" header)");
  const std::string got = j["format"].get<std::string>();
  if (got != format) throw InvalidInputError(path + ": is a " + got + " file, expected " + format);
  if (!j.contains("version") || !j["version"].is_number_integer())
    throw InvalidInputError(path + ": " + format + " file has no integer \"version\"");
  int v = 0;
  try {
    v = j["version"].get<int>();
  } catch (const Json::exception&) {  // an integer beyond int (core::Json's checked conversion)
    throw InvalidInputError(path + ": invalid " + format + " version " + j["version"].dump().substr(0, 40));
  }
  if (v > max_version)
    throw InvalidInputError(path + ": " + format + " version " + std::to_string(v) +
                            " is newer than this volts reads (up to " + std::to_string(max_version) +
                            "); rerun the producing stage with this volts");
  if (v < 1) throw InvalidInputError(path + ": invalid " + format + " version " + std::to_string(v));
  return j;
}

const Json& require(const Json& j, const std::string& key, const std::string& file) {
  auto it = j.find(key);
  if (it == j.end()) throw InvalidInputError(file + ": missing \"" + key + "\"");
  return *it;
}

Json read_report(const std::string& workdir) {
  const std::string path = (std::filesystem::path(workdir) / "report.json").string();
  if (!std::filesystem::exists(path)) return Json::object();
  try {
    return Json::parse(read_text_file(path));
  } catch (const Json::exception&) {
    throw InvalidInputError(path + ": report is not valid JSON; delete it to start a fresh report");
  }
}

namespace {
// Read, change and write DIR/report.json back atomically.
void edit_report(const std::string& workdir, const std::function<void(Json&)>& change) {
  Json r = read_report(workdir);
  r["producer"] = producer();
  change(r);
  write_text_atomically((std::filesystem::path(workdir) / "report.json").string(), r.dump(2) + "\n");
}
}  // namespace

void update_report(const std::string& workdir, const std::string& stage, const Json& figures) {
  edit_report(workdir, [&](Json& r) { r["stages"][stage] = figures; });
}

void update_report_entry(const std::string& workdir, const std::string& key, const Json& value) {
  if (key == "stages" || key == "producer") throw InvalidInputError("update_report_entry: '" + key + "' is written by update_report");
  edit_report(workdir, [&](Json& r) { r[key] = value; });
}

}  // namespace volts::core
