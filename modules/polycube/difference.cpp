#include "polycube/difference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "core/errors.h"
#include "polycube/cube_frame.h"
#include "polycube/embedding.h"

namespace volts::polycube {

namespace {

using Vec3 = std::array<double, 3>;

double dist(const Vec3& a, const Vec3& b) { return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2])); }

std::string describe(const split::Decomposition& d) {
  std::string s;
  for (std::size_t c = 0; c < d.components.size(); ++c)
    s += (c ? ", " : "") + std::to_string(c) + " (" + split::to_string(d.components[c].type) + ")";
  return s.empty() ? "none" : s;
}

// The one coordinate shared by the four corners of a face (2*axis + value), or -1.
int face_of(const std::array<Vec3, 4>& x) {
  int face = -1, shared = 0;
  for (int a = 0; a < 3; ++a)
    if (x[0][a] == x[1][a] && x[0][a] == x[2][a] && x[0][a] == x[3][a]) ++shared, face = 2 * a;
  return shared == 1 ? face : -1;
}

}  // namespace

DifferenceMap map_difference_surface(const split::Decomposition& input, const PatchMapParams& params) {
  const split::Decomposition d = merge_face_patches(input);
  const split::Layout& L = d.layout;
  DifferenceMap m;
  m.cube = m.virtual_component = -1;
  bool other = d.components.size() != 2;
  for (std::size_t c = 0; c < d.components.size(); ++c) {
    const auto type = d.components[c].type;
    if (type == split::ComponentType::cube && m.cube < 0) m.cube = static_cast<int>(c);
    else if (type == split::ComponentType::virtual_component && m.virtual_component < 0) m.virtual_component = static_cast<int>(c);
    else other = true;
  }
  if (other || m.cube < 0 || m.virtual_component < 0)
    throw core::TopologyError("polycube: a difference is one cube minus one virtual component; the components are " + describe(d));
  m.axis = -1;
  std::vector<int> fills;
  for (const auto& c : d.contacts) {
    if (c.via != "filled_patch" || std::min(c.a, c.b) != std::min(m.cube, m.virtual_component) ||
        std::max(c.a, c.b) != std::max(m.cube, m.virtual_component) || c.index < 0 || c.index >= static_cast<int>(L.patches.size()))
      throw core::TopologyError("polycube: components " + std::to_string(c.a) + " and " + std::to_string(c.b) + " meet via " + c.via + " " +
                                std::to_string(c.index) + "; in a difference the virtual component " + std::to_string(m.virtual_component) +
                                " meets the cube " + std::to_string(m.cube) + " only on filled patches");
    fills.push_back(c.index);
  }
  if (fills.size() != 2)
    throw core::TopologyError("polycube: the virtual component " + std::to_string(m.virtual_component) + " meets the cube " + std::to_string(m.cube) +
                              " on " + std::to_string(fills.size()) + " filled patches; a through hole meets it on two (blind holes are not supported)");

  // The solid's vertices come first in the layout (split appends the fills' vertices last).
  std::vector<char> used;
  for (std::size_t t = 0; t < L.triangles.size(); ++t)
    if (!L.filled[t])
      for (int v : L.triangles[t]) {
        if (v >= static_cast<int>(used.size())) used.resize(static_cast<std::size_t>(v) + 1, 0);
        used[static_cast<std::size_t>(v)] = 1;
      }
  m.solid_vertices = static_cast<int>(used.size());
  for (std::size_t v = 0; v < used.size(); ++v)
    if (!used[v])
      throw core::TopologyError("polycube: layout vertex " + std::to_string(v) + " lies only on a fill but before the last vertex of the solid");

  const std::vector<PatchMap> maps = map_patches(d, params);
  // The cube's frame: each corner's corner of the unit cube, from the faces' corner cycles.
  const auto& cube = d.components[static_cast<std::size_t>(m.cube)];
  const auto& hole = d.components[static_cast<std::size_t>(m.virtual_component)];
  if (cube.faces.size() != 6 || hole.faces.size() != 6)
    throw core::TopologyError("polycube: the cube or the virtual component of a difference has not six faces");
  std::map<int, int> corner_index;
  for (const auto& f : cube.faces)
    for (int v : f.corners) corner_index.emplace(v, static_cast<int>(corner_index.size()));
  std::vector<std::set<int>> adjacency(corner_index.size());
  for (const auto& f : cube.faces)
    for (int k = 0; k < 4; ++k) {
      const int a = corner_index.at(f.corners[k]), b = corner_index.at(f.corners[(k + 1) % 4]);
      adjacency[a].insert(b), adjacency[b].insert(a);
    }
  const std::vector<int> code = detail::cube_codes(adjacency);
  std::map<int, Vec3> corner_at;
  for (const auto& [v, i] : corner_index) corner_at[v] = {double(code[i] & 1), double((code[i] >> 1) & 1), double((code[i] >> 2) & 1)};
  auto corner_point = [&](int v, int patch) {
    const auto it = corner_at.find(v);
    if (it == corner_at.end())
      throw core::TopologyError("polycube: patch " + std::to_string(patch) + " has a corner (vertex " + std::to_string(v) +
                                ") that is neither a corner of the cube nor of the hole");
    return it->second;
  };

  // The holed faces: the cube faces that hold a fill; the hole runs between them.
  std::array<int, 2> holed{-1, -1};
  for (int i = 0; i < 2; ++i) {
    const int t = L.patches[static_cast<std::size_t>(fills[i])].triangles.front();
    for (std::size_t f = 0; f < cube.faces.size(); ++f)
      for (int p : cube.faces[f].patches) {
        const auto& tris = L.patches[static_cast<std::size_t>(p)].triangles;
        if (std::find(tris.begin(), tris.end(), t) != tris.end()) holed[i] = p;
      }
    if (holed[i] < 0) throw core::TopologyError("polycube: fill patch " + std::to_string(fills[i]) + " lies in no face of the cube");
  }
  std::array<Vec3, 2> side;
  for (int i = 0; i < 2; ++i) {
    std::array<Vec3, 4> x;
    for (int k = 0; k < 4; ++k) x[k] = corner_point(L.patches[static_cast<std::size_t>(holed[i])].corners[k], holed[i]);
    const int f = face_of(x);
    if (f < 0) throw core::TopologyError("polycube: patch " + std::to_string(holed[i]) + " does not lie on one face of the cube");
    if (m.axis >= 0 && m.axis != f / 2)
      throw core::TopologyError("polycube: the hole's two rims lie on faces of the cube that are not opposite (patches " +
                                std::to_string(holed[0]) + " and " + std::to_string(holed[1]) + ")");
    m.axis = f / 2;
    side[i] = x[0];
  }
  if (side[0][m.axis] == side[1][m.axis])
    throw core::TopologyError("polycube: both rims of the hole lie on the same face of the cube (patch " + std::to_string(holed[0]) + ")");

  // The hole's box. Its mean width (relative to the cube) is the ratio of the rims' length to the
  // faces' (at most 0.5: the T-mesh's pillow, one element of 1/10 at the default level, needs room
  // beside it). Its centre and aspect follow where the rim lies in its face: each rim vertex's
  // bilinear coordinates in the quad of the face's four corners (closest point, Gauss-Newton; exact
  // for a planar face) give a box per face, and the two faces' boxes are averaged. (A harmonic map
  // of the face was tried first: on the 48-vertex tube it moved the box across both axes for a hole
  // moved across one.) The box keeps 0.25 from the cube's sides (measured in session 5: a column
  // 0.225 wide left the pillow's frusta 0.025 wide and the worst elements there).
  const int a1 = (m.axis + 1) % 3, a2 = (m.axis + 2) % 3;
  double rim = 0, outer = 0;
  std::array<double, 2> centre{0, 0}, extent{0, 0};
  for (int i = 0; i < 2; ++i) {
    const auto& P = L.patches[static_cast<std::size_t>(holed[i])];
    const auto& F = L.patches[static_cast<std::size_t>(fills[i])];
    std::array<Eigen::Vector3d, 4> X;  // physical corners
    std::array<Vec3, 4> C;             // their cube points
    for (int k = 0; k < 4; ++k) {
      rim += chain_length(L, F.sides[k]);
      outer += chain_length(L, P.sides[k]);
      const auto& q = L.points[P.corners[k]];
      X[k] = Eigen::Vector3d(q[0], q[1], q[2]);
      C[k] = corner_point(P.corners[k], holed[i]);
    }
    std::array<double, 2> lo{1, 1}, hi{0, 0};
    for (const auto& side : F.sides)
      for (int v : side) {
        const auto& q = L.points[v];
        const Eigen::Vector3d r(q[0], q[1], q[2]);
        double st[2] = {0.5, 0.5};
        for (int it = 0; it < 30; ++it) {
          const double s0 = st[0], t0 = st[1];
          const Eigen::Vector3d B = (1 - s0) * (1 - t0) * X[0] + s0 * (1 - t0) * X[1] + s0 * t0 * X[2] + (1 - s0) * t0 * X[3];
          Eigen::Matrix<double, 3, 2> J;
          J.col(0) = (1 - t0) * (X[1] - X[0]) + t0 * (X[2] - X[3]);
          J.col(1) = (1 - s0) * (X[3] - X[0]) + s0 * (X[2] - X[1]);
          const Eigen::Vector2d step = (J.transpose() * J).ldlt().solve(J.transpose() * (r - B));
          if (!step.allFinite()) break;
          st[0] += step[0], st[1] += step[1];
          if (step.norm() < 1e-12) break;
        }
        const double s0 = std::clamp(st[0], 0.0, 1.0), t0 = std::clamp(st[1], 0.0, 1.0);
        for (int b = 0; b < 2; ++b) {
          const int ax = b == 0 ? a1 : a2;
          const double x = (1 - s0) * (1 - t0) * C[0][ax] + s0 * (1 - t0) * C[1][ax] + s0 * t0 * C[2][ax] + (1 - s0) * t0 * C[3][ax];
          lo[b] = std::min(lo[b], x), hi[b] = std::max(hi[b], x);
        }
      }
    for (int b = 0; b < 2; ++b) centre[b] += (lo[b] + hi[b]) / 4, extent[b] += (hi[b] - lo[b]) / 2;
  }
  const double width = std::clamp(outer > 0 ? rim / outer : 0.5, 0.1, 0.5);
  const double mean_extent = (extent[0] + extent[1]) / 2;
  m.hole_lo[m.axis] = 0.0, m.hole_hi[m.axis] = 1.0;
  for (int b = 0; b < 2; ++b) {
    const int a = b == 0 ? a1 : a2;
    const double w = std::clamp(mean_extent > 0 ? width * extent[b] / mean_extent : width, 0.1, 0.5);
    const double c = std::clamp(centre[b], 0.25 + w / 2, 0.75 - w / 2);
    m.hole_lo[a] = c - w / 2, m.hole_hi[a] = c + w / 2;
  }
  // Rim corners: matched to the holed face's corners by the cyclic correspondence nearest in space,
  // then put at the hole box's corner beside their face corner.
  for (int i = 0; i < 2; ++i) {
    const auto& O = L.patches[static_cast<std::size_t>(holed[i])].corners;
    const auto& R = L.patches[static_cast<std::size_t>(fills[i])].corners;
    double best = std::numeric_limits<double>::infinity();
    std::array<int, 4> match{};
    // The fill and the holed face hold the fill triangles alike, so their corners turn the same
    // way: only the cyclic shift is free.
    for (int shift = 0; shift < 4; ++shift) {
      double cost = 0;
      std::array<int, 4> s{};
      for (int k = 0; k < 4; ++k) {
        s[k] = (shift + k) % 4;
        const double e = dist(L.points[R[k]], L.points[O[s[k]]]);
        cost += e * e;
      }
      if (cost < best) best = cost, match = s;
    }
    for (int k = 0; k < 4; ++k) {
      Vec3 p = corner_point(O[match[k]], holed[i]);
      for (int a = 0; a < 3; ++a)
        if (a != m.axis) p[a] = p[a] > 0.5 ? m.hole_hi[a] : m.hole_lo[a];
      if (!corner_at.emplace(R[k], p).second)
        throw core::TopologyError("polycube: rim corner " + std::to_string(R[k]) + " is also a corner of the cube");
    }
  }

  // Every patch but the holed faces and the fills: its square, bilinearly onto its face.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec3> pts(static_cast<std::size_t>(m.solid_vertices), Vec3{nan, nan, nan});
  auto put = [&](int v, const Vec3& y) {
    if (v < 0 || v >= m.solid_vertices)
      throw core::TopologyError("polycube: vertex " + std::to_string(v) + " of a mapped patch lies only on a fill");
    Vec3& slot = pts[static_cast<std::size_t>(v)];
    if (!std::isnan(slot[0])) m.max_mismatch = std::max(m.max_mismatch, dist(slot, y));
    slot = y;
  };
  std::vector<int> placed;
  for (const auto* comp : {&cube, &hole})
    for (int p : comp->patches)
      if (p != holed[0] && p != holed[1] && p != fills[0] && p != fills[1]) placed.push_back(p);
  for (int p : placed) {
    const auto& P = L.patches[static_cast<std::size_t>(p)];
    std::array<Vec3, 4> X;
    for (int k = 0; k < 4; ++k) X[k] = corner_point(P.corners[k], p);
    if (face_of(X) < 0)
      throw core::TopologyError("polycube: the corners of patch " + std::to_string(p) +
                                " are not those of one face of the cube or of the hole (the hole's walls do not join the rims straight through)");
    const PatchMap& pm = maps[static_cast<std::size_t>(p)];
    for (std::size_t i = 0; i < pm.vertices.size(); ++i) {
      const double s = pm.st[i][0], t = pm.st[i][1];
      Vec3 y{};
      for (int a = 0; a < 3; ++a) y[a] = (1 - s) * (1 - t) * X[0][a] + s * (1 - t) * X[1][a] + s * t * X[2][a] + (1 - s) * t * X[3][a];
      put(pm.vertices[i], y);
    }
    m.flipped_surface_triangles += pm.flipped_triangles;
    m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, pm.max_angle_distortion_deg);
  }
  // The holed faces: annuli between the face's sides and the rim, both placed above.
  for (int i = 0; i < 2; ++i) {
    std::vector<int> tris;
    for (int t : L.patches[static_cast<std::size_t>(holed[i])].triangles)
      if (!L.filled[static_cast<std::size_t>(t)]) tris.push_back(t);
    std::map<int, std::array<double, 2>> fixed;
    for (int t : tris)
      for (int v : L.triangles[static_cast<std::size_t>(t)]) {
        const Vec3& x = pts[static_cast<std::size_t>(v)];  // v < solid_vertices: a triangle that is not a fill
        if (!std::isnan(x[0])) fixed[v] = {x[a1], x[a2]};
      }
    const auto at = harmonic_positions(L, tris, fixed, params, "holed patch " + std::to_string(holed[i]));
    for (const auto& [v, x] : at) {
      if (fixed.count(v)) continue;
      Vec3 y{};
      y[m.axis] = side[i][m.axis], y[a1] = x[0], y[a2] = x[1];
      put(v, y);
    }
    const MapQuality q = map_quality(L, tris, at);
    m.flipped_surface_triangles += q.flipped_triangles;
    m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, q.max_angle_distortion_deg);
  }
  for (std::size_t v = 0; v < pts.size(); ++v)
    if (std::isnan(pts[v][0])) throw core::TopologyError("polycube: vertex " + std::to_string(v) + " of the solid lies on no patch of the difference");

  // Mirror (swap the two axes across the hole) if the frame came out left-handed.
  if (layout_volume(L, pts, Fills::skip) < 0) {
    m.mirrored = true;
    for (auto& p : pts) std::swap(p[a1], p[a2]);
    std::swap(m.hole_lo[a1], m.hole_lo[a2]);
    std::swap(m.hole_hi[a1], m.hole_hi[a2]);
  }
  m.points = std::move(pts);
  return m;
}

surface::Mesh difference_solid(const split::Decomposition& d, const DifferenceMap& m) {
  surface::Mesh mesh;
  for (int v = 0; v < m.solid_vertices; ++v) {
    const auto& p = d.layout.points.at(static_cast<std::size_t>(v));
    mesh.add_vertex(surface::Point(p[0], p[1], p[2]));
  }
  using VI = surface::Mesh::Vertex_index;
  for (std::size_t t = 0; t < d.layout.triangles.size(); ++t) {
    if (d.layout.filled[t]) continue;
    const auto& tr = d.layout.triangles[t];
    for (int v : tr)
      if (v < 0 || v >= m.solid_vertices) throw core::TopologyError("polycube: triangle " + std::to_string(t) + " of the solid uses a fill vertex");
    if (mesh.add_face(VI(tr[0]), VI(tr[1]), VI(tr[2])) == surface::Mesh::null_face())
      throw core::TopologyError("polycube: triangle " + std::to_string(t) + " of the solid is not manifold");
  }
  return mesh;
}

volmap::VolumeMap difference_volume_map(const split::Decomposition& d, const DifferenceMap& m, const Params& params) {
  volmap::Params vp;
  vp.tetgen.max_volume_rel = params.tet_max_volume_rel;
  vp.smooth_sweeps = params.smooth_sweeps;
  vp.smooth_below_ratio = params.smooth_below_ratio;
  return volmap::harmonic_volume_map(difference_solid(d, m), m.points, vp);
}

core::Json to_json(const DifferenceMap& m) {
  std::vector<double> pts;
  for (const auto& p : m.points) pts.insert(pts.end(), p.begin(), p.end());
  return core::Json{{"kind", "difference"},
                    {"cube", m.cube},
                    {"virtual_component", m.virtual_component},
                    {"axis", m.axis},
                    {"hole_lo", m.hole_lo},
                    {"hole_hi", m.hole_hi},
                    {"mirrored", m.mirrored},
                    {"solid_vertices", m.solid_vertices},
                    {"points", pts},
                    {"flipped_surface_triangles", m.flipped_surface_triangles},
                    {"max_angle_distortion_deg", m.max_angle_distortion_deg},
                    {"max_mismatch", m.max_mismatch}};
}

DifferenceMap difference_from_json(const core::Json& j, const std::string& file) {
  DifferenceMap m;
  try {
    m.cube = core::require(j, "cube", file).get<int>();
    m.virtual_component = core::require(j, "virtual_component", file).get<int>();
    m.axis = core::require(j, "axis", file).get<int>();
    m.hole_lo = core::require(j, "hole_lo", file).get<std::array<double, 3>>();
    m.hole_hi = core::require(j, "hole_hi", file).get<std::array<double, 3>>();
    m.mirrored = core::require(j, "mirrored", file).get<bool>();
    m.solid_vertices = core::require(j, "solid_vertices", file).get<int>();
    const auto pts = core::require(j, "points", file).get<std::vector<double>>();
    if (m.solid_vertices < 4 || pts.size() != 3 * static_cast<std::size_t>(m.solid_vertices))
      throw core::InvalidInputError(file + ": polycube.points needs 3 numbers per solid vertex (solid_vertices " + std::to_string(m.solid_vertices) + ")");
    for (std::size_t i = 0; i < pts.size(); i += 3) m.points.push_back({pts[i], pts[i + 1], pts[i + 2]});
    m.flipped_surface_triangles = j.value("flipped_surface_triangles", 0);
    m.max_angle_distortion_deg = j.value("max_angle_distortion_deg", 0.0);
    m.max_mismatch = j.value("max_mismatch", 0.0);
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(file + ": malformed difference polycube: " + x.what());
  }
  if (m.axis < 0 || m.axis > 2) throw core::InvalidInputError(file + ": polycube.axis must be 0, 1 or 2");
  for (int a = 0; a < 3; ++a)
    if (!(m.hole_lo[a] >= 0 && m.hole_lo[a] < m.hole_hi[a] && m.hole_hi[a] <= 1) || (a == m.axis && (m.hole_lo[a] != 0 || m.hole_hi[a] != 1)) ||
        (a != m.axis && (m.hole_lo[a] <= 0 || m.hole_hi[a] >= 1)))
      throw core::InvalidInputError(file + ": polycube.hole_lo/hole_hi is not a box through the unit cube along its axis");
  for (const auto& p : m.points)
    for (double x : p)
      if (!std::isfinite(x)) throw core::InvalidInputError(file + ": polycube.points holds a non-finite value");
  return m;
}

void write_difference_vtp(const std::string& path, const split::Decomposition& d, const DifferenceMap& m, bool mapped) {
  const split::Layout& L = d.layout;
  std::vector<int> comp(L.triangles.size(), -1);
  for (std::size_t c = 0; c < d.components.size(); ++c)
    for (int p : d.components[c].patches)
      for (int t : L.patches[static_cast<std::size_t>(p)].triangles) comp[static_cast<std::size_t>(t)] = static_cast<int>(c);
  viz::PolyData v;
  const std::vector<Vec3> physical(L.points.begin(), L.points.begin() + m.solid_vertices);
  v.points = mapped ? m.points : physical;
  viz::Field other{mapped ? "xyz" : "uvw", 3, {}}, cf{"component_id", 1, {}};
  for (const auto& p : mapped ? physical : m.points) other.values.insert(other.values.end(), p.begin(), p.end());
  for (std::size_t t = 0; t < L.triangles.size(); ++t) {
    if (L.filled[t]) continue;
    v.polys.push_back({L.triangles[t][0], L.triangles[t][1], L.triangles[t][2]});
    cf.values.push_back(comp[t]);
  }
  v.point_fields = {other};
  v.cell_fields = {cf};
  viz::write_vtp(path, v);
}

}  // namespace volts::polycube
