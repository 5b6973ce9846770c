#include "surface/remesh.h"

#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"

namespace volts::surface {

namespace PMP = CGAL::Polygon_mesh_processing;

Remeshed remesh_isotropic(const Mesh& in, const RemeshParams& params) {
  if (!(params.edge_length > 0 && std::isfinite(params.edge_length)))
    throw core::InvalidInputError("remesh_isotropic: edge length " + std::to_string(params.edge_length) + " is not positive");
  if (params.iterations < 1 || params.iterations > 20)
    throw core::InvalidInputError("remesh_isotropic: iterations " + std::to_string(params.iterations) + " outside [1, 20]");
  Remeshed r;
  r.mesh = in;
  Mesh& m = r.mesh;
  auto sharp = m.add_property_map<Mesh::Edge_index, bool>("e:volts_sharp", false).first;
  PMP::detect_sharp_edges(m, params.sharp_angle_deg, sharp);
  std::vector<Mesh::Edge_index> edges;
  for (auto e : m.edges())
    if (sharp[e]) edges.push_back(e);
  // Long sharp edges first, so that protect_constraints (which never splits them) still gets
  // triangles of the target size beside them.
  PMP::split_long_edges(edges, params.edge_length, m, CGAL::parameters::edge_is_constrained_map(sharp));
  PMP::isotropic_remeshing(faces(m), params.edge_length, m,
                           CGAL::parameters::number_of_iterations(static_cast<unsigned>(params.iterations))
                               .edge_is_constrained_map(sharp)
                               .protect_constraints(true));
  // Garbage collection renumbers: read the flags into the pairs afterwards (the map follows).
  m.collect_garbage();
  for (auto e : m.edges())
    if (sharp[e]) {
      const int a = static_cast<int>(m.vertex(e, 0).idx()), b = static_cast<int>(m.vertex(e, 1).idx());
      r.sharp_edge_vertices.push_back(std::min(a, b));
      r.sharp_edge_vertices.push_back(std::max(a, b));
    }
  m.remove_property_map(sharp);
  return r;
}

}  // namespace volts::surface
