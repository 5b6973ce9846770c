#include "tet2hex/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "bezier/vtk_bezier.h"
#include "core/errors.h"
#include "core/log.h"

namespace volts::tet2hex {
using tetmesh::signed_volume6;

std::vector<bezier::BezierTet> linear_tets(const tetmesh::TetMesh& mesh) {
  std::vector<bezier::BezierTet> r;
  r.reserve(mesh.tets.size());
  for (const auto& t : mesh.tets) {
    bezier::BezierTet b;
    b.degree = 1;
    // simplex_index order for n = 1: a = 0 (vertex 0), u (1), v (2), w (3).
    b.points = {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]};
    r.push_back(std::move(b));
  }
  return r;
}

std::vector<bezier::BezierTet> read_tet_vtu(const std::string& path) {
  // The reading is bezier::read_bezier_vtu's; this adds what the tet route needs: only linear and
  // Bézier tets, one degree, finite points, positive orientation.
  bezier::VtuElements in = bezier::read_bezier_vtu(path);
  if (in.vtk_type.empty()) throw core::InvalidInputError(path + ": no cells");
  std::vector<bezier::BezierTet> tets;
  tets.reserve(in.tets.size());
  int degree = -1;
  for (int c = 0; c < static_cast<int>(in.vtk_type.size()); ++c) {
    const int type = in.vtk_type[c];
    if (type != 10 && type != 78)  // VTK_TETRA, VTK_BEZIER_TETRAHEDRON
      throw core::InvalidInputError(path + ": cell " + std::to_string(c) + " has VTK type " + std::to_string(type) +
                                    "; only tetrahedra (10) and Bézier tetrahedra (78) are read");
    bezier::BezierTet t = std::move(in.tets[in.element[c]]);
    if (degree >= 0 && t.degree != degree) throw core::InvalidInputError(path + ": cells of different degrees (" + std::to_string(degree) + " and " + std::to_string(t.degree) + ")");
    degree = t.degree;
    for (const auto& x : t.points)
      if (!x.allFinite()) throw core::InvalidInputError(path + ": cell " + std::to_string(c) + ": a point is not finite");
    // Negative orientation (corner frame): swap the roles of v and w.
    const int n = t.degree;
    if (signed_volume6(t.points[0], t.points[bezier::simplex_index(3, n, n, 0, 0)], t.points[bezier::simplex_index(3, n, 0, n, 0)],
                       t.points[bezier::simplex_index(3, n, 0, 0, n)]) < 0) {
      bezier::BezierTet s = t;
      for (const auto& a : bezier::simplex_multi_indices(3, n)) {
        const int from = bezier::simplex_index(3, n, a[1], a[2], a[3]), to = bezier::simplex_index(3, n, a[1], a[3], a[2]);
        s.points[to] = t.points[from];
        if (!t.weights.empty()) s.weights[to] = t.weights[from];
      }
      t = std::move(s);
    }
    tets.push_back(std::move(t));
  }
  return tets;
}

}  // namespace volts::tet2hex
