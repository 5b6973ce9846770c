#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_mesh_to_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/exceptions.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <new>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "surface/formats.h"
#include "surface/soup_checks.h"
#include "surface/surface.h"

namespace volts::surface {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using detail::Polygon;

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw core::InvalidInputError(path + ": " + problem);
}

detail::RawSoup parse(const std::string& path, const std::string& format, const std::string& text) {
  try {
    if (format == "off") return detail::parse_off(path, text);
    if (format == "obj") return detail::parse_obj(path, text);
    if (format == "stl") return detail::parse_stl(path, text);
    return detail::parse_ply(path, text);
  } catch (const std::bad_alloc&) {  // e.g. a PLY list length read from garbage
    fail(path, "malformed " + format + " file: implausible sizes (out of memory while reading)");
  } catch (const std::length_error&) {
    fail(path, "malformed " + format + " file: implausible sizes");
  } catch (const CGAL::Failure_exception& e) {  // CGAL assertions, in builds that keep them
    fail(path, "malformed " + format + " file (CGAL: " + e.message() + ")");
  }
}

/// For STL, file vertex k is a triangle corner; say which, since STL has no vertex numbers.
std::string name_file_vertex(const detail::RawSoup& raw, std::size_t file_index, const Point& p) {
  std::string name = "vertex " + std::to_string(file_index);
  if (raw.points_are_corners)
    name += " (corner " + std::to_string(file_index % 3) + " of triangle " + std::to_string(file_index / 3) + ")";
  return name + " " + detail::format_point(p);
}

}  // namespace

Mesh read_surface(const std::string& path, ReadInfo* info_out) {
  ReadInfo info;
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".off" && ext != ".obj" && ext != ".stl" && ext != ".ply")
    fail(path, "unknown extension '" + ext + "' (expected .off, .obj, .stl or .ply)");
  info.format = ext.substr(1);

  const std::string text = core::read_text_file(path);  // throws InvalidInputError naming the file
  if (text.find_first_not_of(" \t\r\n\f\v") == std::string::npos) fail(path, "empty file");

  const detail::RawSoup raw = parse(path, info.format, text);
  info.file_vertices = raw.points.size();

  // Checks welding depends on (finite coordinates, valid indices), vertices numbered as in the file.
  detail::check_soup_indices(raw.points, raw.faces, path,
                             [&](std::size_t i) { return name_file_vertex(raw, i, raw.points[i]); });

  // Weld. CGAL keeps the first occurrence of each position and the order of the faces.
  std::vector<Point> points = raw.points;
  std::vector<Polygon> faces = raw.faces;
  info.welded_vertices = PMP::merge_duplicate_points_in_polygon_soup(points, faces);
  std::vector<std::size_t> file_index(points.size(), static_cast<std::size_t>(-1));
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t c = 0; c < faces[f].size(); ++c)
      file_index[faces[f][c]] = std::min(file_index[faces[f][c]], raw.faces[f][c]);
  detail::check_soup_surface(points, faces, path,
                             [&](std::size_t i) { return name_file_vertex(raw, file_index[i], points[i]); });

  info.isolated_vertices = PMP::remove_isolated_points_in_polygon_soup(points, faces);
  // The checks above imply this; CGAL's own test guards polygon_soup_to_polygon_mesh's precondition.
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
    fail(path, "not a valid polygon mesh (CGAL's is_polygon_soup_a_polygon_mesh refused it)");
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);

  // Mesh face f is soup face f, so messages can keep the file's face numbers.
  std::vector<Mesh::Face_index> polygons;
  for (const Mesh::Face_index f : mesh.faces())
    if (mesh.degree(f) > 3) polygons.push_back(f);
  for (const Mesh::Face_index f : polygons) {
    const std::size_t degree = mesh.degree(f);
    if (!PMP::triangulate_face(f, mesh))
      fail(path, "cannot triangulate face " + std::to_string(static_cast<std::size_t>(f)) + " (" +
                     std::to_string(degree) + " vertices): it has no well-defined normal");
  }
  info.triangulated_faces = polygons.size();
  if (!polygons.empty()) {
    // Triangulating may create a zero-area triangle, or split a quad along a diagonal that is
    // already an edge elsewhere (CGAL does not check); numbers in such messages are of the welded mesh.
    std::vector<Point> tri_points;
    std::vector<Polygon> tri_faces;
    PMP::polygon_mesh_to_polygon_soup(mesh, tri_points, tri_faces);
    validate_soup(tri_points, tri_faces,
                  path + ": after triangulating " + detail::count_of(polygons.size(), "polygon", "polygons"));
  }

  const double volume = PMP::volume(mesh);
  const double diagonal = bbox_diagonal(mesh);
  // A closed, consistently oriented surface can still be flat (e.g. two triangles back to back).
  if (!(std::abs(volume) > 1e-12 * diagonal * diagonal * diagonal)) {
    std::ostringstream m;
    m << "the surface encloses no volume (signed volume " << volume << ", bounding-box diagonal " << diagonal << ")";
    fail(path, m.str());
  }
  if (volume < 0) {
    PMP::reverse_face_orientations(mesh);
    info.flipped = true;
  }
  if (info_out) *info_out = info;
  return mesh;
}

}  // namespace volts::surface
