// Shared by the libFuzzer targets: the readers read files, so each input is written to a
// per-process temporary file first. A volts error (core::Error) is the expected answer to bad
// bytes; any other exception escapes and libFuzzer reports it, like a crash, leak or timeout.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace volts::fuzz {

/// Writes the input to /tmp/volts_fuzz_<pid><ext> (the pid keeps parallel fuzzers apart; the
/// extension picks the reader) and returns its path.
inline const std::string& write_input(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  static const std::string path = "/tmp/volts_fuzz_" + std::to_string(::getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();  // the harness itself failed, not the reader
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

}  // namespace volts::fuzz
