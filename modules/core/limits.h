// volts::core — limits of what an input may ask for: sizes a file declares are checked against the
// machine's memory before anything is allocated, so a corrupt or hostile header is a clear error
// instead of an out-of-memory kill.
#pragma once

#include <cstddef>
#include <string>

namespace volts::core {

/// Physical memory of this machine in bytes (sysconf; 1 GiB if it cannot be read).
std::size_t physical_memory_bytes();

/// Throws InvalidInputError "FILE: declares COUNT WHAT, more than this machine can hold (limit N)"
/// if COUNT items of BYTES_EACH bytes (what holding one costs, roughly) exceed half the physical
/// memory.
void check_declared_count(const std::string& file, std::size_t count, const std::string& what, std::size_t bytes_each);

}  // namespace volts::core
