#include "surface/mesh_json.h"

#include <cmath>

#include "core/errors.h"

namespace volts::surface {

std::vector<std::array<double, 3>> vertex_array(const Mesh& mesh) {
  std::vector<std::array<double, 3>> xyz;
  xyz.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    xyz.push_back({p.x(), p.y(), p.z()});
  }
  return xyz;
}

std::vector<std::vector<int>> triangle_array(const Mesh& mesh) {
  std::vector<std::vector<int>> tris;
  tris.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    std::vector<int> t;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t.push_back(static_cast<int>(v));
    tris.push_back(std::move(t));
  }
  return tris;
}

std::vector<std::array<int, 3>> triangle_triples(const Mesh& mesh) {
  std::vector<std::array<int, 3>> tris;
  tris.reserve(mesh.number_of_faces());
  for (const auto& t : triangle_array(mesh)) tris.push_back({t.at(0), t.at(1), t.at(2)});
  return tris;
}

core::Json mesh_to_json(const Mesh& mesh) {
  std::vector<double> xyz;
  xyz.reserve(3 * mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  }
  std::vector<std::size_t> tri;
  tri.reserve(3 * mesh.number_of_faces());
  for (auto f : mesh.faces())
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) tri.push_back(std::size_t(v));
  return core::Json{{"vertices", xyz}, {"faces", tri}};
}

Mesh mesh_from_json(const core::Json& j, const std::string& file) {
  const auto& jv = core::require(j, "vertices", file);
  const auto& jf = core::require(j, "faces", file);
  if (!jv.is_array() || jv.size() % 3 != 0 || !jf.is_array() || jf.size() % 3 != 0 || jf.empty())
    throw core::InvalidInputError(file + ": surface arrays are malformed (need 3 values per vertex and face)");
  Mesh mesh;
  const std::size_t nv = jv.size() / 3;
  for (std::size_t i = 0; i < nv; ++i) {
    double c[3];
    for (int k = 0; k < 3; ++k) {
      if (!jv[3 * i + k].is_number()) throw core::InvalidInputError(file + ": vertex " + std::to_string(i) + " is not numeric");
      c[k] = jv[3 * i + k].get<double>();
      if (!std::isfinite(c[k])) throw core::InvalidInputError(file + ": vertex " + std::to_string(i) + " is not finite");
    }
    mesh.add_vertex(Point(c[0], c[1], c[2]));
  }
  for (std::size_t f = 0; f < jf.size() / 3; ++f) {
    Mesh::Vertex_index vs[3];
    for (int k = 0; k < 3; ++k) {
      if (!jf[3 * f + k].is_number_unsigned() || jf[3 * f + k].get<std::size_t>() >= nv)
        throw core::InvalidInputError(file + ": face " + std::to_string(f) + " has an invalid vertex index");
      vs[k] = Mesh::Vertex_index(static_cast<Mesh::size_type>(jf[3 * f + k].get<std::size_t>()));
    }
    if (mesh.add_face(vs[0], vs[1], vs[2]) == Mesh::null_face())
      throw core::InvalidInputError(file + ": face " + std::to_string(f) + " breaks manifoldness");
  }
  // Stage files carry a validated surface; a hand-edited one that is no longer closed is refused
  // before algorithms that assume it.
  if (!CGAL::is_closed(mesh)) throw core::InvalidInputError(file + ": the surface in the stage file is not closed");
  return mesh;
}

}  // namespace volts::surface
