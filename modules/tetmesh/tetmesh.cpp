#include "tetmesh/tetmesh.h"

#define TETLIBRARY
#include <tetgen.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "core/log.h"

namespace volts::tetmesh {
namespace {

std::string tetgen_reason(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "the surface intersects itself";
    case 4: return "an input feature is smaller than TetGen's tolerance";
    case 5: return "two input facets are too close";
    case 10: return "invalid input";
    default: return "error code " + std::to_string(code);
  }
}

}  // namespace

TetMesh tetrahedralize(const surface::Mesh& surface, const TetgenParams& p) {
  if (!(p.max_radius_edge_ratio == 0.0 || (p.max_radius_edge_ratio >= 1.1 && p.max_radius_edge_ratio <= 10.0)))
    throw core::ConfigError("TetGen max_radius_edge_ratio must be 0 or in [1.1, 10]");
  if (!(p.min_dihedral_deg >= 0.0 && p.min_dihedral_deg <= 30.0)) throw core::ConfigError("TetGen min_dihedral_deg must be in [0, 30]");
  if (!(p.max_volume_rel >= 0.0 && p.max_volume_rel <= 1.0)) throw core::ConfigError("TetGen max_volume_rel must be in [0, 1]");

  // TetGen 1.5 can crash (not throw) on some self-intersecting PLCs (seen: a ring's surface closed
  // by a disk that crosses it), so the exact test comes first.
  if (CGAL::Polygon_mesh_processing::does_self_intersect(surface))
    throw core::NumericalError("TetGen not run: the surface to tetrahedralize intersects itself");
  tetgenio in, out;
  in.firstnumber = 0;
  std::map<surface::Mesh::Vertex_index, int> id;
  in.numberofpoints = static_cast<int>(surface.number_of_vertices());
  in.pointlist = new REAL[3 * in.numberofpoints];
  int k = 0;
  for (auto v : surface.vertices()) {
    const auto& q = surface.point(v);
    in.pointlist[3 * k] = q.x(), in.pointlist[3 * k + 1] = q.y(), in.pointlist[3 * k + 2] = q.z();
    id[v] = k++;
  }
  in.numberoffacets = static_cast<int>(surface.number_of_faces());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  k = 0;
  for (auto f : surface.faces()) {
    tetgenio::facet& fc = in.facetlist[k++];
    tetgenio::init(&fc);
    fc.numberofpolygons = 1;
    fc.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&fc.polygonlist[0]);
    std::vector<int> vs;
    for (auto v : vertices_around_face(surface.halfedge(f), surface)) vs.push_back(id[v]);
    fc.polygonlist[0].numberofvertices = static_cast<int>(vs.size());
    fc.polygonlist[0].vertexlist = new int[vs.size()];
    std::copy(vs.begin(), vs.end(), fc.polygonlist[0].vertexlist);
  }

  std::ostringstream sw;
  sw << "pzQ";  // PLC, 0-based, quiet (TetGen prints to stdout otherwise)
  if (p.max_radius_edge_ratio > 0) {
    sw << "q" << p.max_radius_edge_ratio;
    if (p.min_dihedral_deg > 0) sw << "/" << p.min_dihedral_deg;
  }
  if (p.max_volume_rel > 0) sw << "a" << p.max_volume_rel * std::abs(surface::signed_volume(surface));
  if (p.keep_boundary) sw << "Y";
  std::string switches = sw.str();
  core::log_verbose("tetgen -" + switches);
  try {
    // TetGen's exact predicates set global state on every call (exactinit): one call at a time.
    static std::mutex tetgen;
    const std::lock_guard<std::mutex> lock(tetgen);
    ::tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw core::NumericalError("TetGen failed: " + tetgen_reason(code) + " (switches -" + switches + ")");
  }
  if (out.numberoftetrahedra <= 0 || out.numberofcorners < 4)
    throw core::NumericalError("TetGen returned no tetrahedra (switches -" + switches + ")");

  TetMesh m;
  m.points.resize(out.numberofpoints);
  for (int i = 0; i < out.numberofpoints; ++i)
    m.points[i] = Eigen::Vector3d(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
  // Callers give data per surface vertex (volmap's boundary condition): TetGen keeps the input points
  // first, in order; check it rather than trust it (it would drop duplicate or unused points).
  bool same = out.numberofpoints >= in.numberofpoints;
  for (int i = 0; same && i < in.numberofpoints; ++i)
    same = out.pointlist[3 * i] == in.pointlist[3 * i] && out.pointlist[3 * i + 1] == in.pointlist[3 * i + 1] &&
           out.pointlist[3 * i + 2] == in.pointlist[3 * i + 2];
  if (!same)
    throw core::NumericalError("TetGen did not keep the " + std::to_string(in.numberofpoints) +
                               " surface vertices as its first points (duplicate or unused vertices?)");
  m.tets.resize(out.numberoftetrahedra);
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    std::array<int, 4> c;
    for (int j = 0; j < 4; ++j) c[j] = out.tetrahedronlist[t * out.numberofcorners + j];
    const double v = signed_volume6(m.points[c[0]], m.points[c[1]], m.points[c[2]], m.points[c[3]]);
    if (v < 0) std::swap(c[2], c[3]);
    if (v == 0) throw core::NumericalError("TetGen returned a flat tetrahedron (" + std::to_string(t) + ")");
    m.tets[t] = c;
  }
  return m;
}

std::vector<std::array<int, 2>> boundary_faces(const TetMesh& mesh) {
  std::map<std::array<int, 3>, std::vector<std::array<int, 2>>> faces;
  for (int t = 0; t < static_cast<int>(mesh.tets.size()); ++t)
    for (int x = 0; x < 4; ++x) {
      std::array<int, 3> f;
      for (int j = 0, m = 0; j < 4; ++j)
        if (j != x) f[m++] = mesh.tets[t][j];
      std::sort(f.begin(), f.end());
      faces[f].push_back({t, x});
    }
  std::vector<std::array<int, 2>> b;
  for (const auto& kv : faces)
    if (kv.second.size() == 1) b.push_back(kv.second[0]);
  return b;
}

}  // namespace volts::tetmesh
