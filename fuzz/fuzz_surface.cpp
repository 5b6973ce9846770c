// libFuzzer target of read_surface for one format (VOLTS_FUZZ_EXT: ".off", ".obj", ".stl", ".ply"):
// parsing, welding and validation of arbitrary bytes must end in a core::Error or a valid mesh.
#include "core/errors.h"
#include "fuzz_util.h"
#include "surface/surface.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = volts::fuzz::write_input(data, size, VOLTS_FUZZ_EXT);
  try {
    const volts::surface::Mesh mesh = volts::surface::read_surface(path);
    // What read_surface promises every later stage: a closed triangle mesh.
    if (mesh.is_empty() || !CGAL::is_closed(mesh) || !CGAL::is_triangle_mesh(mesh)) std::abort();
  } catch (const volts::core::Error&) {
  }
  return 0;
}
