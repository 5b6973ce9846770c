#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Polygon_mesh_processing/polygon_mesh_to_polygon_soup.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "surface/surface.h"

namespace volts::surface {

void write_surface(const std::string& path, const Mesh& mesh) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".off" && ext != ".obj" && ext != ".stl" && ext != ".ply")
    throw core::IoError(path + ": unknown extension '" + ext + "' (expected .off, .obj, .stl or .ply)");

  // Written from a soup so that extra property maps a caller attached to the mesh never leak into
  // the file (CGAL's Surface_mesh PLY writer writes them all) and removed elements are skipped.
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> faces;
  CGAL::Polygon_mesh_processing::polygon_mesh_to_polygon_soup(mesh, points, faces);
  if (ext == ".stl" && std::any_of(faces.begin(), faces.end(), [](const auto& f) { return f.size() != 3; }))
    throw std::invalid_argument(path + ": STL can only store triangles, the mesh has larger faces");

  core::write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw core::IoError(path + ": cannot open for writing");
    // 17 significant digits make every double read back bit-identical.
    const auto exact = CGAL::parameters::stream_precision(17);
    bool ok = false;
    if (ext == ".off") {
      ok = CGAL::IO::write_OFF(out, points, faces, exact);
    } else if (ext == ".obj") {
      ok = CGAL::IO::write_OBJ(out, points, faces, exact);
    } else if (ext == ".stl") {
      CGAL::IO::set_mode(out, CGAL::IO::BINARY);  // binary STL: compact; coordinates become floats either way
      ok = CGAL::IO::write_STL(out, points, faces);
    } else {
      CGAL::IO::set_mode(out, CGAL::IO::BINARY);  // binary PLY stores the doubles themselves
      ok = CGAL::IO::write_PLY(out, points, faces);
    }
    out.close();
    if (!ok || !out) throw core::IoError(path + ": write failed (disk full?)");
  });
}

}  // namespace volts::surface
