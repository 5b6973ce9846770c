// libFuzzer target of the .vtu reader of volts-check (bezier::read_bezier_vtu, VTK's XML reader
// underneath): any bytes must give elements or a core::Error.
#include "bezier/vtk_bezier.h"
#include "core/errors.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = volts::fuzz::write_input(data, size, ".vtu");
  try {
    (void)volts::bezier::read_bezier_vtu(path);
  } catch (const volts::core::Error&) {
  }
  return 0;
}
