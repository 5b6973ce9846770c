// volts::surface — surface input, validation and output.
//
// read_surface() turns an OFF, OBJ, STL or PLY file into a Mesh that every later stage can trust:
// one closed, manifold, consistently and outwardly oriented triangle surface without degenerate
// faces. Anything else is refused with an InvalidInputError that names the file, the problem and
// where it is. write_surface() writes a Mesh back, atomically and without losing precision.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <cstddef>
#include <string>
#include <vector>

namespace volts::surface {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
/// Once returned by read_surface: closed, oriented (outward), triangle mesh, one component.
using Mesh = CGAL::Surface_mesh<Point>;

/// What read_surface did, for logs and the report.
struct ReadInfo {
  std::string format;                  ///< "off", "obj", "stl" or "ply"
  std::size_t file_vertices = 0;       ///< vertices as stored in the file (STL: 3 per triangle)
  std::size_t welded_vertices = 0;     ///< duplicates merged (STL stores each triangle's corners separately)
  std::size_t isolated_vertices = 0;   ///< vertices used by no face, dropped
  std::size_t triangulated_faces = 0;  ///< polygons with more than 3 sides split into triangles
  bool flipped = false;                ///< the mesh was globally inverted (inward normals) and was flipped
};

/// Reads OFF (ASCII), OBJ, STL (ASCII and binary) or PLY (ASCII and binary), chosen by the extension
/// (case-insensitive); welds duplicate vertices, drops unused ones, validates (see validate_soup),
/// triangulates polygons and flips a globally inverted surface (info->flipped is then set; the
/// caller logs it).
/// Throws core::InvalidInputError "PATH: <problem> (<where>)" for: a missing or unreadable file, an
/// unknown extension, an empty file, a truncated or malformed file (binary STL size not matching its
/// triangle count, data after the announced faces, ...), every validate_soup problem, a polygon that
/// cannot be triangulated and a surface enclosing no volume. Vertex and face numbers are 0-based, as
/// in the file (STL: vertex k is corner k % 3 of triangle k / 3).
Mesh read_surface(const std::string& path, ReadInfo* info = nullptr);

/// Writes OFF, OBJ (ASCII, 17 significant digits: doubles round-trip exactly), STL (binary, float)
/// or PLY (binary, double), chosen by the extension, atomically (core::write_atomically).
/// Throws core::IoError for an unknown extension or a failed write, std::invalid_argument when a
/// mesh with non-triangle faces is written as STL.
void write_surface(const std::string& path, const Mesh& mesh);

/// Checks that a polygon soup is one closed solid, in this order, so that the message names the
/// root problem: no faces; non-finite coordinates (NaN/Inf); faces with fewer than 3 vertices;
/// vertex indices out of range; a vertex used twice by one face; zero-area faces (exact
/// collinearity); non-manifold edges (used by more than 2 faces); boundary edges (open surface);
/// inconsistent orientation (an edge traversed twice in the same direction); non-manifold vertices
/// (faces around a vertex form more than one fan); more than one connected component.
/// Vertices used by no face are allowed. Orientation may be globally inverted.
/// Throws core::InvalidInputError "SOURCE: <count> <problem>, first ... (<where>)"; vertex and face
/// numbers are 0-based indices into `points` and `faces`.
void validate_soup(const std::vector<Point>& points, const std::vector<std::vector<std::size_t>>& faces,
                   const std::string& source);

/// Length of the diagonal of the axis-aligned bounding box (0 for an empty mesh).
double bbox_diagonal(const Mesh& mesh);

/// Signed enclosed volume, > 0 for outward orientation.
/// Throws std::invalid_argument unless the mesh is a closed triangle mesh.
double signed_volume(const Mesh& mesh);

/// Genus from the Euler characteristic V - E + F = 2 - 2g; the mesh must be one closed component.
int genus(const Mesh& mesh);

}  // namespace volts::surface
