// libFuzzer target of one reader (VOLTS_FUZZ_KIND, see readers.h): any bytes must end in a result
// or a core::Error; any other exception escapes, and libFuzzer reports it like a crash.
#include "fuzz_util.h"
#include "readers.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string kind = VOLTS_FUZZ_KIND;
  // The extension picks read_surface's parser; the other readers ignore it.
  const std::string ext = kind == "off" || kind == "obj" || kind == "stl" || kind == "ply" || kind == "vtu" ? "." + kind
                          : kind == "config" ? ".yaml" : ".stage.json";
  const std::string& path = volts::fuzz::write_input(data, size, ext);
  try {
    volts::fuzz::read_input(kind, path);
  } catch (const volts::core::Error&) {
  }
  return 0;
}
