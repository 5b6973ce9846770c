#include "core/limits.h"

#include <unistd.h>

#include "core/errors.h"

namespace volts::core {

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::size_t(1) << 30;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page);
}

void check_declared_count(const std::string& file, std::size_t count, const std::string& what, std::size_t bytes_each) {
  // Half the memory: the reader, the welded copy and the mesh all hold the data at some point.
  const std::size_t limit = physical_memory_bytes() / 2 / (bytes_each ? bytes_each : 1);
  if (count > limit)
    throw InvalidInputError(file + ": declares " + std::to_string(count) + " " + what +
                            ", more than this machine can hold (limit " + std::to_string(limit) + ")");
}

}  // namespace volts::core
