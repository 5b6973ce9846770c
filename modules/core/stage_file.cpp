#include "core/stage_file.h"

#include <simdjson.h>

#include <filesystem>
#include <functional>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace volts::core {

std::string producer() { return "volts 0.1.0"; }

namespace {

// e's value as an X; e.type() has said that it is one (value_unsafe() on the temporary result
// would dangle, so get() fills x in place).
template <class X>
X value_of(simdjson::dom::element e) {
  X x{};
  if (e.get(x) != simdjson::SUCCESS) throw NumericalError("stage file: simdjson element of an unexpected type");
  return x;
}

// simdjson's document as nlohmann's tree, with nlohmann's number types: an integer without a sign
// is number_unsigned, with one number_integer (as nlohmann's own parser stores them).
Json to_json(simdjson::dom::element e) {
  using T = simdjson::dom::element_type;
  switch (e.type()) {
    case T::ARRAY: {
      const auto list = value_of<simdjson::dom::array>(e);
      Json a = Json::array();
      auto& v = a.get_ref<Json::array_t&>();
      v.reserve(list.size());  // a hint: size() saturates for very long arrays
      for (const simdjson::dom::element x : list) v.push_back(to_json(x));
      return a;
    }
    case T::OBJECT: {
      const auto object = value_of<simdjson::dom::object>(e);
      Json o = Json::object();
      for (const simdjson::dom::key_value_pair kv : object) o[std::string(kv.key)] = to_json(kv.value);  // the last of equal keys wins, as in nlohmann
      return o;
    }
    case T::INT64: {
      const auto i = value_of<std::int64_t>(e);
      return i >= 0 ? Json(static_cast<std::uint64_t>(i)) : Json(i);
    }
    case T::UINT64: return Json(value_of<std::uint64_t>(e));
    case T::DOUBLE: return Json(value_of<double>(e));
    case T::STRING: return Json(std::string(value_of<std::string_view>(e)));
    case T::BOOL: return Json(value_of<bool>(e));
    case T::NULL_VALUE: return Json(nullptr);
  }
  return Json();
}

// The stage file's text as a tree. simdjson parses it (stage files reach 35 MB: the assembly's
// extract read it in 0.39 s with nlohmann's parser, 0.22 s this way); what it
// refuses goes to nlohmann's parser, whose errors name the byte (and which reads integers beyond
// 64 bits as doubles, where simdjson stops).
Json parse_text(const std::string& text) {
  simdjson::dom::parser parser;  // its buffers go with it
  simdjson::dom::element root;
  if (parser.parse(text).get(root) == simdjson::SUCCESS) return to_json(root);
  return Json::parse(text);
}

}  // namespace

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
    j = parse_text(text);
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
