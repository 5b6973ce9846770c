#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <cmath>
#include <stdexcept>

#include "surface/surface.h"

namespace volts::surface {

namespace PMP = CGAL::Polygon_mesh_processing;

double bbox_diagonal(const Mesh& mesh) {
  if (mesh.number_of_vertices() == 0) return 0.0;
  const CGAL::Bbox_3 b = PMP::bbox(mesh);
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) +
                   CGAL::square(b.zmax() - b.zmin()));
}

double signed_volume(const Mesh& mesh) {
  // PMP::volume only asserts these in debug builds and returns garbage otherwise.
  if (!CGAL::is_triangle_mesh(mesh) || !CGAL::is_closed(mesh))
    throw std::invalid_argument("signed_volume: the mesh must be a closed triangle mesh");
  return PMP::volume(mesh);  // sum of signed tetrahedra against the origin: > 0 when outward
}

int genus(const Mesh& mesh) {
  const long long chi = static_cast<long long>(mesh.number_of_vertices()) -
                        static_cast<long long>(mesh.number_of_edges()) +
                        static_cast<long long>(mesh.number_of_faces());
  return static_cast<int>((2 - chi) / 2);
}

}  // namespace volts::surface
