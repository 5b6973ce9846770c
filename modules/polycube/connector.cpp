#include "polycube/connector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/errors.h"

namespace volts::polycube {

namespace {
using Vec3 = std::array<double, 3>;
}  // namespace

ConnectorMap map_connector(const Ring& piece, const Ring& ring0, const PatchMapParams& params) {
  const split::Decomposition& d = piece.decomposition;
  const split::Layout& L = d.layout;
  const std::string who = "polycube: the connector (component " + std::to_string(piece.component.at(0)) + ")";
  if (d.components.size() != 1 || d.components[0].faces.size() != 6) throw core::TopologyError(who + " is not one cube of six faces");
  const auto& faces = d.components[0].faces;
  // Its two ends: the faces whose patch holds fill triangles; a = 0 the one closing ring 0.
  const std::set<int> ring0_triangles(ring0.layout_triangle.begin(), ring0.layout_triangle.end());
  std::array<int, 2> end{-1, -1};
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (faces[f].patches.size() == 3)
      throw core::TopologyError(who + " ends on a shoulder with a face of three patches (its disk and the shoulder's two faces, "
                                "split.connector_end: shoulder): mapping that face as three strips is not implemented yet "
                                "(docs/status.md, Session 21); use split.connector_end: level");
    if (faces[f].patches.size() != 1) throw core::TopologyError(who + " has a face of " + std::to_string(faces[f].patches.size()) + " patches");
    const auto& tris = L.patches.at(static_cast<std::size_t>(faces[f].patches[0])).triangles;
    if (tris.empty() || !L.filled.at(static_cast<std::size_t>(tris[0]))) continue;
    const bool first = ring0_triangles.count(piece.layout_triangle.at(static_cast<std::size_t>(tris[0]))) > 0;
    if (end[first ? 0 : 1] >= 0) throw core::TopologyError(who + " has two faces on the disk of one ring");
    end[first ? 0 : 1] = static_cast<int>(f);
  }
  if (end[0] < 0 || end[1] < 0) throw core::TopologyError(who + " does not end on a disk of each ring");
  ConnectorMap m;
  // Corners: the a = 0 end's in order, each one's partner across a side patch at a = 1.
  const auto& c0 = faces[static_cast<std::size_t>(end[0])].corners;
  const auto& c1 = faces[static_cast<std::size_t>(end[1])].corners;
  static const int bc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    m.corner_vertex[static_cast<std::size_t>(bc[k][0] * 2 + bc[k][1] * 4)] = c0[static_cast<std::size_t>(k)];
    int partner = -1;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (static_cast<int>(f) == end[0] || static_cast<int>(f) == end[1]) continue;
      const auto& q = faces[f].corners;
      for (int i = 0; i < 4; ++i) {
        if (q[static_cast<std::size_t>(i)] != c0[static_cast<std::size_t>(k)]) continue;
        for (const int j : {(i + 1) % 4, (i + 3) % 4}) {
          const int v = q[static_cast<std::size_t>(j)];
          if (std::find(c1.begin(), c1.end(), v) == c1.end()) continue;
          if (partner >= 0 && partner != v) throw core::TopologyError(who + ": its side patches join a corner of one disk to two of the other");
          partner = v;
        }
      }
    }
    if (partner < 0) throw core::TopologyError(who + ": no side patch joins corner " + std::to_string(k) + " of one disk to the other");
    m.corner_vertex[static_cast<std::size_t>(1 + bc[k][0] * 2 + bc[k][1] * 4)] = partner;
  }
  // Each patch onto its face of the cube: its corners are cube corners, the map affine in (s, t).
  const std::vector<PatchMap> maps = map_patches(d, params);
  auto corner_point = [&](int v, bool swap) {
    const auto it = std::find(m.corner_vertex.begin(), m.corner_vertex.end(), v);
    if (it == m.corner_vertex.end()) throw core::TopologyError(who + ": a patch corner is no corner of the cube");
    const int i = static_cast<int>(it - m.corner_vertex.begin());
    Vec3 x{double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)};
    if (swap) std::swap(x[1], x[2]);
    return x;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto place = [&](bool swap) {
    std::vector<Vec3> pts(L.points.size(), Vec3{nan, nan, nan});
    m.max_mismatch = 0;
    for (std::size_t p = 0; p < L.patches.size(); ++p) {
      std::array<Vec3, 4> X;
      for (int k = 0; k < 4; ++k) X[static_cast<std::size_t>(k)] = corner_point(L.patches[p].corners[static_cast<std::size_t>(k)], swap);
      const PatchMap& pm = maps[p];
      for (std::size_t v = 0; v < pm.vertices.size(); ++v) {
        const double s = pm.st[v][0], t = pm.st[v][1];
        Vec3 y{};
        for (int q = 0; q < 3; ++q) y[q] = (1 - s) * (1 - t) * X[0][q] + s * (1 - t) * X[1][q] + s * t * X[2][q] + (1 - s) * t * X[3][q];
        Vec3& slot = pts[static_cast<std::size_t>(pm.vertices[v])];
        if (!std::isnan(slot[0]))
          m.max_mismatch = std::max(m.max_mismatch, std::sqrt((slot[0] - y[0]) * (slot[0] - y[0]) + (slot[1] - y[1]) * (slot[1] - y[1]) +
                                                              (slot[2] - y[2]) * (slot[2] - y[2])));
        slot = y;
      }
    }
    return pts;
  };
  m.points = place(false);
  if (layout_volume(L, m.points, Fills::include) < 0) {
    m.mirrored = true;
    m.points = place(true);
    std::array<int, 8> swapped{};
    for (int i = 0; i < 8; ++i) swapped[static_cast<std::size_t>((i & 1) | ((i >> 2) & 1) << 1 | ((i >> 1) & 1) << 2)] = m.corner_vertex[static_cast<std::size_t>(i)];
    m.corner_vertex = swapped;
  }
  for (const auto& p : m.points)
    if (std::isnan(p[0])) throw core::TopologyError(who + " has a vertex in none of its patches");
  for (const PatchMap& pm : maps) {
    m.flipped_surface_triangles += pm.flipped_triangles;
    m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, pm.max_angle_distortion_deg);
  }
  return m;
}

volmap::VolumeMap connector_volume_map(const Ring& piece, const ConnectorMap& m, const Params& params) {
  volmap::Params vp;
  vp.tetgen.max_volume_rel = params.tet_max_volume_rel;
  vp.smooth_sweeps = params.smooth_sweeps;
  vp.smooth_below_ratio = params.smooth_below_ratio;
  return volmap::harmonic_volume_map(split::layout_mesh(piece.decomposition.layout, true), m.points, vp);
}

core::Json to_json(const Ring& piece, const ConnectorMap& m, const volmap::VolumeMap& vm) {
  std::vector<double> pts;
  for (const auto& p : m.points) pts.insert(pts.end(), p.begin(), p.end());
  return core::Json{{"component", piece.component.at(0)},
                    {"layout_vertex", piece.layout_vertex},
                    {"layout_triangle", piece.layout_triangle},
                    {"corner_vertex", m.corner_vertex},
                    {"mirrored", m.mirrored},
                    {"points", pts},
                    {"flipped_surface_triangles", m.flipped_surface_triangles},
                    {"max_angle_distortion_deg", m.max_angle_distortion_deg},
                    {"max_mismatch", m.max_mismatch},
                    {"volume_map", volmap::to_json(vm)}};
}

std::array<int, 8> connector_corners(const core::Json& j, const std::string& file) {
  std::vector<int> layout_vertex;
  std::array<int, 8> corner{};
  try {
    layout_vertex = core::require(j, "layout_vertex", file).get<std::vector<int>>();
    corner = core::require(j, "corner_vertex", file).get<std::array<int, 8>>();
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(file + ": malformed connector layout_vertex or corner_vertex: " + x.what());
  }
  for (int& v : corner) {
    if (v < 0 || v >= static_cast<int>(layout_vertex.size())) throw core::InvalidInputError(file + ": connector corner_vertex is out of range");
    v = layout_vertex[static_cast<std::size_t>(v)];
  }
  if (std::set<int>(corner.begin(), corner.end()).size() != 8) throw core::InvalidInputError(file + ": connector corner_vertex repeats a vertex");
  return corner;
}

}  // namespace volts::polycube
