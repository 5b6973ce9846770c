// volts::core — versioned stage files and the run report.
//
// Every stage writes one JSON stage file (docs/formats.md):
//   { "format": "volts-<stage>", "version": N, "producer": "volts 0.1.0", ... payload ... }
// Readers check the format name and refuse newer versions, so a file from a future volts or from
// another stage is a clear error rather than garbage.
#pragma once

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>

// Every conversion of a JSON number to an integer type checks that it is a whole number the type
// holds. nlohmann's own conversion is a static_cast, undefined behaviour for 4.7e126 -> int
// (fuzz_stage_polycube, a layout triangle index); this specialization is seen by every user of
// core::Json (this is the only place nlohmann/json.hpp is included) and covers get<int>() as
// well as vectors and arrays of ints. Out of range is a json type_error, which the readers
// already turn into InvalidInputError naming the file.
namespace nlohmann {
template <typename T>
struct adl_serializer<T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>>> {
  template <typename J>
  static void to_json(J& j, T v) noexcept {
    ::nlohmann::to_json(j, v);
  }
  template <typename J>
  static void from_json(const J& j, T& v) {
    using I = typename J::number_integer_t;
    using U = typename J::number_unsigned_t;
    using F = typename J::number_float_t;
    constexpr auto lo = std::numeric_limits<T>::min();
    constexpr auto hi = std::numeric_limits<T>::max();
    bool ok = false;
    if (const U* u = j.template get_ptr<const U*>()) {
      ok = *u <= static_cast<std::make_unsigned_t<T>>(hi);
      if (ok) v = static_cast<T>(*u);
    } else if (const I* i = j.template get_ptr<const I*>()) {
      ok = std::is_signed_v<T> ? *i >= static_cast<I>(lo) && (sizeof(T) >= sizeof(I) || *i <= static_cast<I>(hi))
                               : *i >= 0 && static_cast<std::make_unsigned_t<I>>(*i) <= hi;
      if (ok) v = static_cast<T>(*i);
    } else if (const F* f = j.template get_ptr<const F*>()) {
      ok = std::isfinite(*f) && std::trunc(*f) == *f && *f >= static_cast<F>(lo) && *f < static_cast<F>(hi) + 1;  // hi + 1: 2^63 for int64
      if (ok) v = static_cast<T>(*f);
    } else if (const bool* b = j.template get_ptr<const bool*>()) {
      ok = true;  // as nlohmann converts booleans
      v = static_cast<T>(*b);
    } else {
      throw detail::type_error::create(302, "type must be number, but is " + std::string(j.type_name()), &j);
    }
    if (!ok) throw detail::type_error::create(302, "number " + j.dump().substr(0, 40) + " is not an integer in range", &j);
  }
};
}  // namespace nlohmann

namespace volts::core {

using Json = nlohmann::json;

/// Writes `payload` (an object) with the format header to `path`, atomically.
void write_stage_file(const std::string& path, const std::string& format, int version, Json payload);

/// Reads a stage file and checks its header. Throws InvalidInputError naming the file if it is
/// missing, not JSON, truncated, of another format, or of a version outside [1, max_version].
Json read_stage_file(const std::string& path, const std::string& format, int max_version);

/// Typed access to a required member of a stage file; throws InvalidInputError naming file and key.
const Json& require(const Json& j, const std::string& key, const std::string& file);

/// Merges `figures` as stages.<stage> into DIR/report.json (created if missing), atomically.
void update_report(const std::string& workdir, const std::string& stage, const Json& figures);

/// Sets the top-level `key` (not "stages" or "producer") of DIR/report.json to `value`, atomically.
void update_report_entry(const std::string& workdir, const std::string& key, const Json& value);

/// Reads DIR/report.json, or an empty object if there is none.
Json read_report(const std::string& workdir);

/// The producer string written in every file ("volts 0.1.0").
std::string producer();

}  // namespace volts::core
