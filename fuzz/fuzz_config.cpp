// libFuzzer target of the YAML config reader (config::parse_config, what load_config runs on the
// file's text): any bytes must give a Config or a core::Error (ConfigError, InvalidInputError).
#include "config/config.h"
#include "core/errors.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const volts::config::Config c = volts::config::parse_config(text, "fuzz.yaml");
    (void)volts::config::to_yaml(c);  // what `volts run` writes back into the work directory
  } catch (const volts::core::Error&) {
  }
  return 0;
}
