// volts::core — atomic output files: everything is written to a temporary name in the target's
// directory and renamed only when complete, so a crash or an error never leaves a half file.
#pragma once

#include <functional>
#include <string>

namespace volts::core {

/// Calls write(tmp_path) to produce the file at a temporary path next to `path`, then renames it
/// to `path`. If write throws, the temporary file is removed and the exception propagates.
/// Throws IoError if the directory is not writable or the rename fails.
void write_atomically(const std::string& path, const std::function<void(const std::string& tmp_path)>& write);

/// Writes `content` to `path` atomically.
void write_text_atomically(const std::string& path, const std::string& content);

/// Reads a whole file; throws InvalidInputError naming the file if it cannot be opened.
std::string read_text_file(const std::string& path);

}  // namespace volts::core
