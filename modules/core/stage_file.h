// volts::core — versioned stage files and the run report.
//
// Every stage writes one JSON stage file (docs/formats.md):
//   { "format": "volts-<stage>", "version": N, "producer": "volts 0.1.0", ... payload ... }
// Readers check the format name and refuse newer versions, so a file from a future volts or from
// another stage is a clear error rather than garbage.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

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

/// Reads DIR/report.json, or an empty object if there is none.
Json read_report(const std::string& workdir);

/// The producer string written in every file ("volts 0.1.0").
std::string producer();

}  // namespace volts::core
