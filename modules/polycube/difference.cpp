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

constexpr double kPi = 3.14159265358979323846;

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

// Fixes, around each corner of the foot's rectangle, the free vertices of the triangles outside
// the foot at that corner: on a circle about the corner (half its shorter rim edge in the image),
// spread over the 270° outside the rectangle in the order the surface has them around the corner
// (their angles there scaled to it). The rim is smooth at the corner and its image turns 90°: a
// harmonic map left those vertices inside the rectangle at resolution 24 (a fan whose link has
// no kernel). `tris` are the holed face's triangles, `fixed` holds the rectangle's points.
void fix_foot_corner_fans(const split::Layout& L, const std::vector<int>& tris, const split::Patch& foot,
                          std::map<int, std::array<double, 2>>& fixed) {
  const std::set<int> inside(foot.triangles.begin(), foot.triangles.end());
  auto point = [&](int v) { return Eigen::Vector3d(L.points[v][0], L.points[v][1], L.points[v][2]); };
  for (const int c : foot.corners) {
    std::set<int> around;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (int t : tris) {
      const auto& tr = L.triangles[static_cast<std::size_t>(t)];
      if (inside.count(t) || std::find(tr.begin(), tr.end(), c) == tr.end()) continue;
      normal += (point(tr[1]) - point(tr[0])).cross(point(tr[2]) - point(tr[0]));
      for (int v : tr)
        if (v != c) around.insert(v);
    }
    std::vector<int> rim, free;
    for (int v : around) (fixed.count(v) ? rim : free).push_back(v);
    if (rim.size() != 2 || free.empty() || !(normal.norm() > 0)) continue;  // not a corner with an outside fan
    const std::array<double, 2> pc = fixed.at(c), pa = fixed.at(rim[0]), pb = fixed.at(rim[1]);
    const double la = std::hypot(pa[0] - pc[0], pa[1] - pc[1]), lb = std::hypot(pb[0] - pc[0], pb[1] - pc[1]);
    if (!(la > 0 && lb > 0)) continue;
    // Physical angles about the corner from rim[0], in the face's plane.
    const Eigen::Vector3d n = normal.normalized(), e1 = ((point(rim[0]) - point(c)) - (point(rim[0]) - point(c)).dot(n) * n).normalized(), e2 = n.cross(e1);
    auto phi = [&](int v) {
      const Eigen::Vector3d d = point(v) - point(c);
      const double a = std::atan2(d.dot(e2), d.dot(e1));
      return a < 0 ? a + 2 * kPi : a;
    };
    // The fan runs from rim[0] to rim[1] one way round: the way that holds every free vertex.
    double end = phi(rim[1]);
    bool forward = true;
    for (int v : free) forward = forward && phi(v) < end;
    if (!forward) end = 2 * kPi - end;
    // In the image: from rim[0]'s direction to rim[1]'s the long way (outside the rectangle).
    const double alpha = std::atan2(pa[1] - pc[1], pa[0] - pc[0]);
    const double turn = (pa[0] - pc[0]) * (pb[1] - pc[1]) - (pa[1] - pc[1]) * (pb[0] - pc[0]) > 0 ? -1.0 : 1.0;  // away from the inside quarter
    const double r = 0.5 * std::min(la, lb);
    for (int v : free) {
      const double t = (forward ? phi(v) : 2 * kPi - phi(v)) / end;
      const double a = alpha + turn * t * 1.5 * kPi;
      fixed[v] = {pc[0] + r * std::cos(a), pc[1] + r * std::sin(a)};
    }
  }
}

}  // namespace

DifferenceMap map_difference_surface(const split::Decomposition& input, const PatchMapParams& params, int foot_patch) {
  const split::Decomposition d = merge_face_patches(input);
  const split::Layout& L = d.layout;
  DifferenceMap m;
  m.cube = -1;
  bool other = false;
  for (std::size_t c = 0; c < d.components.size(); ++c) {
    const auto type = d.components[c].type;
    if (type == split::ComponentType::cube && m.cube < 0) m.cube = static_cast<int>(c);
    else if (type == split::ComponentType::virtual_component) m.holes.push_back(HoleBox{static_cast<int>(c), {0, 0, 0}, {1, 1, 1}});
    else other = true;
  }
  if (other || m.cube < 0 || m.holes.empty())
    throw core::TopologyError("polycube: a difference is one cube minus virtual components (through holes); the components are " + describe(d));
  const std::size_t nh = m.holes.size();
  // Hole h: "hole h (virtual component c)" in messages.
  auto hole_name = [&](std::size_t h) {
    return nh == 1 ? "the virtual component " + std::to_string(m.holes[h].virtual_component)
                   : "hole " + std::to_string(h) + " (virtual component " + std::to_string(m.holes[h].virtual_component) + ")";
  };
  std::map<int, std::size_t> hole_of;  // virtual component -> hole
  for (std::size_t h = 0; h < nh; ++h) hole_of[m.holes[h].virtual_component] = h;
  std::vector<std::vector<int>> fills(nh);  // per hole: its fill patches, in contact order
  for (const auto& c : d.contacts) {
    const int lo = std::min(c.a, c.b), hi = std::max(c.a, c.b);
    const int v = lo == m.cube ? hi : hi == m.cube ? lo : -1;
    const auto h = hole_of.find(v);
    if (c.via != "filled_patch" || h == hole_of.end() || c.index < 0 || c.index >= static_cast<int>(L.patches.size())) {
      const int named = hole_of.count(c.a) ? c.a : hole_of.count(c.b) ? c.b : -1;
      throw core::TopologyError("polycube: components " + std::to_string(c.a) + " and " + std::to_string(c.b) + " meet via " + c.via + " " +
                                std::to_string(c.index) + "; in a difference " +
                                (named >= 0 ? "the virtual component " + std::to_string(named) : std::string("each virtual component")) +
                                " meets the cube " + std::to_string(m.cube) + " only on filled patches");
    }
    fills[h->second].push_back(c.index);
  }
  for (std::size_t h = 0; h < nh; ++h)
    if (fills[h].size() != 2)
      throw core::TopologyError("polycube: " + hole_name(h) + " meets the cube " + std::to_string(m.cube) + " on " + std::to_string(fills[h].size()) +
                                " filled patches; a through hole meets it on two (blind holes are not supported)");

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
  if (cube.faces.size() != 6) throw core::TopologyError("polycube: the cube " + std::to_string(m.cube) + " of a difference has not six faces");
  for (std::size_t h = 0; h < nh; ++h)
    if (d.components[static_cast<std::size_t>(m.holes[h].virtual_component)].faces.size() != 6)
      throw core::TopologyError("polycube: " + hole_name(h) + " of a difference has not six faces");
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
                                ") that is neither a corner of the cube nor of a hole");
    return it->second;
  };

  // The holed faces: the cube faces that hold a hole's fills; every hole runs between the same two.
  std::vector<std::array<int, 2>> holed(nh, {-1, -1});
  std::vector<std::array<Vec3, 2>> side(nh);
  m.axis = -1;
  for (std::size_t h = 0; h < nh; ++h) {
    int axis = -1;
    for (int i = 0; i < 2; ++i) {
      const int t = L.patches[static_cast<std::size_t>(fills[h][i])].triangles.front();
      for (std::size_t f = 0; f < cube.faces.size(); ++f)
        for (int p : cube.faces[f].patches) {
          const auto& tris = L.patches[static_cast<std::size_t>(p)].triangles;
          if (std::find(tris.begin(), tris.end(), t) != tris.end()) holed[h][i] = p;
        }
      if (holed[h][i] < 0) throw core::TopologyError("polycube: fill patch " + std::to_string(fills[h][i]) + " lies in no face of the cube");
    }
    for (int i = 0; i < 2; ++i) {
      std::array<Vec3, 4> x;
      for (int k = 0; k < 4; ++k) x[k] = corner_point(L.patches[static_cast<std::size_t>(holed[h][i])].corners[k], holed[h][i]);
      const int f = face_of(x);
      if (f < 0) throw core::TopologyError("polycube: patch " + std::to_string(holed[h][i]) + " does not lie on one face of the cube");
      if (axis >= 0 && axis != f / 2)
        throw core::TopologyError("polycube: the two rims of " + hole_name(h) + " lie on faces of the cube that are not opposite (patches " +
                                  std::to_string(holed[h][0]) + " and " + std::to_string(holed[h][1]) + ")");
      axis = f / 2;
      side[h][i] = x[0];
    }
    if (side[h][0][axis] == side[h][1][axis])
      throw core::TopologyError("polycube: both rims of " + hole_name(h) + " lie on the same face of the cube (patch " + std::to_string(holed[h][0]) + ")");
    if (h > 0 && axis != m.axis)
      throw core::TopologyError("polycube: " + hole_name(h) + " runs along cube axis " + std::to_string(axis) + ", " + hole_name(0) + " along axis " +
                                std::to_string(m.axis) + "; the holes of a difference must run along one axis (their fills on the same two opposite faces)");
    if (h > 0 && std::set<int>(holed[h].begin(), holed[h].end()) != std::set<int>(holed[0].begin(), holed[0].end()))
      throw core::TopologyError("polycube: the rims of " + hole_name(h) + " lie in patches " + std::to_string(holed[h][0]) + " and " +
                                std::to_string(holed[h][1]) + ", those of " + hole_name(0) + " in " + std::to_string(holed[0][0]) + " and " +
                                std::to_string(holed[0][1]));
    m.axis = axis;
  }

  // The holes' boxes. A rim vertex's place in its face: its bilinear coordinates in the quad of the
  // face's four corners (closest point, Gauss-Newton; exact for a planar face), taken to cube
  // parameters; `rim_extent` gives the min and max of those over a rim, across the hole (a1, a2).
  // (A harmonic map of the face was tried first: on the 48-vertex tube it moved the box across
  // both axes for a hole moved across one.)
  const int a1 = (m.axis + 1) % 3, a2 = (m.axis + 2) % 3;
  auto rim_extent = [&](int holed_patch, int fill, std::array<double, 2>& lo, std::array<double, 2>& hi, double* length = nullptr) {
    const auto& P = L.patches[static_cast<std::size_t>(holed_patch)];
    const auto& F = L.patches[static_cast<std::size_t>(fill)];
    std::array<Eigen::Vector3d, 4> X;  // physical corners
    std::array<Vec3, 4> C;             // their cube points
    for (int k = 0; k < 4; ++k) {
      const auto& q = L.points[P.corners[k]];
      X[k] = Eigen::Vector3d(q[0], q[1], q[2]);
      C[k] = corner_point(P.corners[k], holed_patch);
    }
    lo = {1, 1}, hi = {0, 0};
    if (length) *length = 0;
    for (const auto& rim_side : F.sides) {
      std::array<double, 2> previous{};
      bool first = true;
      for (int v : rim_side) {
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
        std::array<double, 2> here{};
        for (int b = 0; b < 2; ++b) {
          const int ax = b == 0 ? a1 : a2;
          const double x = (1 - s0) * (1 - t0) * C[0][ax] + s0 * (1 - t0) * C[1][ax] + s0 * t0 * C[2][ax] + (1 - s0) * t0 * C[3][ax];
          lo[b] = std::min(lo[b], x), hi[b] = std::max(hi[b], x);
          here[static_cast<std::size_t>(b)] = x;
        }
        if (length && !first) *length += std::hypot(here[0] - previous[0], here[1] - previous[1]);
        previous = here, first = false;
      }
    }
  };
  // A rim's bounding box shrunk about its centre to the rim's length (a square of the rim's
  // perimeter; see the several-holes case below).
  auto shrink_to_rim = [](std::array<double, 2>& lo, std::array<double, 2>& hi, double length) {
    const double box = 2 * ((hi[0] - lo[0]) + (hi[1] - lo[1]));
    const double shrink = std::clamp(box > 0 ? length / box : 1.0, 0.5, 1.0);
    for (int b = 0; b < 2; ++b) {
      const double c = (lo[b] + hi[b]) / 2;
      lo[b] = c - shrink * (c - lo[b]), hi[b] = c + shrink * (hi[b] - c);
    }
  };
  if (nh == 1) {
    // One hole: its mean width (relative to the cube) is the ratio of the rims' length to the
    // faces' (at most 0.5: the T-mesh's pillow, one element of 1/10 at the default level, needs
    // room beside it); its centre and aspect follow the rims' extents in their faces, the two faces'
    // averaged. The box keeps 0.25 from the cube's sides (measured in session 5: a column 0.225
    // wide left the pillow's frusta 0.025 wide and the worst elements there).
    HoleBox& H = m.holes[0];
    double rim = 0, outer = 0;
    std::array<double, 2> centre{0, 0}, extent{0, 0};
    for (int i = 0; i < 2; ++i) {
      const auto& P = L.patches[static_cast<std::size_t>(holed[0][i])];
      const auto& F = L.patches[static_cast<std::size_t>(fills[0][i])];
      for (int k = 0; k < 4; ++k) {
        rim += chain_length(L, F.sides[k]);
        outer += chain_length(L, P.sides[k]);
      }
      std::array<double, 2> lo{1, 1}, hi{0, 0};
      rim_extent(holed[0][i], fills[0][i], lo, hi);
      for (int b = 0; b < 2; ++b) centre[b] += (lo[b] + hi[b]) / 4, extent[b] += (hi[b] - lo[b]) / 2;
    }
    const double width = std::clamp(outer > 0 ? rim / outer : 0.5, 0.1, 0.5);
    const double mean_extent = (extent[0] + extent[1]) / 2;
    H.lo[m.axis] = 0.0, H.hi[m.axis] = 1.0;
    for (int b = 0; b < 2; ++b) {
      const int a = b == 0 ? a1 : a2;
      const double w = std::clamp(mean_extent > 0 ? width * extent[b] / mean_extent : width, 0.1, 0.5);
      const double c = std::clamp(centre[b], 0.25 + w / 2, 0.75 - w / 2);
      H.lo[a] = c - w / 2, H.hi[a] = c + w / 2;
    }
  } else {
    // Several holes: each box is its rims' extent, the two faces' averaged (no margin: the holes'
    // sizes and spacing are the shape's), shrunk about its centre to the rims' length: a round
    // rim's bounding square puts the rim's diagonal points 1.41 radii out where the surface around
    // has no room (the plate: 10 flipped triangles at the boxes' corners, 52 flipped tets after
    // untangling); the square of the rim's perimeter moves them 1.11 radii out and its sides in.
    // Coordinates within 1e-6 of each other across an axis become equal (their mean): aligned
    // holes share the T-mesh's grid lines, and the structure refuses coordinates that almost
    // coincide.
    for (std::size_t h = 0; h < nh; ++h) {
      HoleBox& H = m.holes[h];
      std::array<double, 2> lo{0, 0}, hi{0, 0};
      double length = 0;
      for (int i = 0; i < 2; ++i) {
        std::array<double, 2> l{1, 1}, u{0, 0};
        double rim = 0;
        rim_extent(holed[h][i], fills[h][i], l, u, &rim);
        for (int b = 0; b < 2; ++b) lo[b] += l[b] / 2, hi[b] += u[b] / 2;
        length += rim / 2;
      }
      shrink_to_rim(lo, hi, length);
      H.lo[m.axis] = 0.0, H.hi[m.axis] = 1.0;
      H.lo[a1] = lo[0], H.hi[a1] = hi[0], H.lo[a2] = lo[1], H.hi[a2] = hi[1];
    }
    for (const int a : {a1, a2}) {
      std::vector<double*> xs;
      for (auto& H : m.holes) xs.push_back(&H.lo[a]), xs.push_back(&H.hi[a]);
      std::stable_sort(xs.begin(), xs.end(), [](const double* x, const double* y) { return *x < *y; });
      for (std::size_t i = 0; i < xs.size();) {
        std::size_t j = i + 1;
        while (j < xs.size() && *xs[j] - *xs[j - 1] <= 1e-6) ++j;
        if (j - i > 1) {
          double mean = 0;
          for (std::size_t k = i; k < j; ++k) mean += *xs[k];
          mean /= static_cast<double>(j - i);
          for (std::size_t k = i; k < j; ++k) *xs[k] = mean;
        }
        i = j;
      }
    }
    auto box_text = [&](std::size_t h) {
      const HoleBox& H = m.holes[h];
      return "[" + std::to_string(H.lo[a1]) + ", " + std::to_string(H.hi[a1]) + "] x [" + std::to_string(H.lo[a2]) + ", " +
             std::to_string(H.hi[a2]) + "] across the holes' axis";
    };
    for (std::size_t h = 0; h < nh; ++h) {
      const HoleBox& H = m.holes[h];
      for (const int a : {a1, a2})
        if (!(H.lo[a] >= 1e-3 && H.hi[a] <= 1 - 1e-3 && H.lo[a] < H.hi[a]))
          throw core::TopologyError("polycube: the box of " + hole_name(h) + ", " + box_text(h) + ", is empty or within 1e-3 of the cube's sides");
    }
    for (std::size_t h = 0; h < nh; ++h)
      for (std::size_t g = h + 1; g < nh; ++g) {
        bool apart = false;
        for (const int a : {a1, a2}) apart = apart || m.holes[h].hi[a] < m.holes[g].lo[a] || m.holes[g].hi[a] < m.holes[h].lo[a];
        if (!apart)
          throw core::TopologyError("polycube: the boxes of " + hole_name(h) + ", " + box_text(h) + ", and " + hole_name(g) + ", " + box_text(g) +
                                    ", overlap or touch");
      }
  }
  // The foot: a rectangle of the holed face its triangles lie in, sized as a hole's box.
  int foot_face = -1;  // i of holed[0][i]
  if (foot_patch >= 0) {
    if (foot_patch >= static_cast<int>(L.patches.size()) || L.patches[static_cast<std::size_t>(foot_patch)].triangles.empty())
      throw core::TopologyError("polycube: the foot patch " + std::to_string(foot_patch) + " is not a patch of the difference");
    const int t0 = L.patches[static_cast<std::size_t>(foot_patch)].triangles.front();
    for (int i = 0; i < 2; ++i) {
      const auto& tris = L.patches[static_cast<std::size_t>(holed[0][i])].triangles;
      if (std::find(tris.begin(), tris.end(), t0) != tris.end()) foot_face = i;
    }
    if (foot_face < 0)
      throw core::TopologyError("polycube: the foot (patch " + std::to_string(foot_patch) +
                                ") lies in neither face the holes run through; a component can stand only on a holed face");
    std::array<double, 2> lo{1, 1}, hi{0, 0};
    double length = 0;
    rim_extent(holed[0][foot_face], foot_patch, lo, hi, &length);
    shrink_to_rim(lo, hi, length);
    FootRect F;
    F.patch = foot_patch;
    F.lo[m.axis] = F.hi[m.axis] = side[0][foot_face][m.axis];
    F.lo[a1] = lo[0], F.hi[a1] = hi[0], F.lo[a2] = lo[1], F.hi[a2] = hi[1];
    const std::string text = "[" + std::to_string(lo[0]) + ", " + std::to_string(hi[0]) + "] x [" + std::to_string(lo[1]) + ", " + std::to_string(hi[1]) + "]";
    for (const int a : {a1, a2})
      if (!(F.lo[a] >= 1e-3 && F.hi[a] <= 1 - 1e-3 && F.lo[a] < F.hi[a]))
        throw core::TopologyError("polycube: the foot's rectangle " + text + " is empty or within 1e-3 of the cube's sides");
    for (std::size_t h = 0; h < nh; ++h) {
      bool apart = false;
      for (const int a : {a1, a2}) apart = apart || m.holes[h].hi[a] < F.lo[a] || F.hi[a] < m.holes[h].lo[a];
      if (!apart) throw core::TopologyError("polycube: the foot's rectangle " + text + " overlaps or touches the box of " + hole_name(h));
    }
    // Its corners: beside the face corner nearest by the cyclic correspondence, either way round.
    const auto& O = L.patches[static_cast<std::size_t>(holed[0][foot_face])].corners;
    const auto& R = L.patches[static_cast<std::size_t>(foot_patch)].corners;
    double best = std::numeric_limits<double>::infinity();
    std::array<int, 4> match{};
    for (const int turn : {1, 3})
      for (int shift = 0; shift < 4; ++shift) {
        double cost = 0;
        std::array<int, 4> s{};
        for (int k = 0; k < 4; ++k) {
          s[k] = (shift + turn * k) % 4;
          const double e = dist(L.points[R[k]], L.points[O[s[k]]]);
          cost += e * e;
        }
        if (cost < best) best = cost, match = s;
      }
    for (int k = 0; k < 4; ++k) {
      Vec3 p = corner_point(O[match[k]], holed[0][foot_face]);
      for (const int a : {a1, a2}) p[a] = p[a] > 0.5 ? F.hi[a] : F.lo[a];
      if (!corner_at.emplace(R[k], p).second)
        throw core::TopologyError("polycube: foot corner " + std::to_string(R[k]) + " is also a corner of the cube or of a rim");
    }
    m.foot = F;
  }
  // Rim corners: matched to the holed face's corners by the cyclic correspondence nearest in space
  // (translation-invariant: an off-centre hole matches alike), then put at the corner of their
  // hole's box beside their face corner.
  for (std::size_t h = 0; h < nh; ++h)
    for (int i = 0; i < 2; ++i) {
      const auto& O = L.patches[static_cast<std::size_t>(holed[h][i])].corners;
      const auto& R = L.patches[static_cast<std::size_t>(fills[h][i])].corners;
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
        Vec3 p = corner_point(O[match[k]], holed[h][i]);
        for (int a = 0; a < 3; ++a)
          if (a != m.axis) p[a] = p[a] > 0.5 ? m.holes[h].hi[a] : m.holes[h].lo[a];
        if (!corner_at.emplace(R[k], p).second)
          throw core::TopologyError("polycube: rim corner " + std::to_string(R[k]) + " of " + hole_name(h) +
                                    " is also a corner of the cube or of another rim");
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
  std::set<int> skip(holed[0].begin(), holed[0].end());
  for (const auto& f : fills) skip.insert(f.begin(), f.end());
  std::vector<int> placed;
  for (int p : cube.patches)
    if (!skip.count(p)) placed.push_back(p);
  for (const auto& H : m.holes)
    for (int p : d.components[static_cast<std::size_t>(H.virtual_component)].patches)
      if (!skip.count(p)) placed.push_back(p);
  if (m.foot) placed.push_back(m.foot->patch);  // then fixed in its holed face's map below
  // Several holes: a patch's points on its face's plane exactly (the bilinear sum can miss it by
  // an ulp: 1 + 2e-16 on the plate). One hole keeps the plain sum, so that its maps stay bitwise
  // what they were.
  const bool exact_planes = nh > 1;
  for (int p : placed) {
    const auto& P = L.patches[static_cast<std::size_t>(p)];
    std::array<Vec3, 4> X;
    for (int k = 0; k < 4; ++k) X[k] = corner_point(P.corners[k], p);
    if (face_of(X) < 0)
      throw core::TopologyError("polycube: the corners of patch " + std::to_string(p) +
                                " are not those of one face of the cube or of a hole (the hole's walls do not join the rims straight through)");
    const PatchMap& pm = maps[static_cast<std::size_t>(p)];
    for (std::size_t i = 0; i < pm.vertices.size(); ++i) {
      const double s = pm.st[i][0], t = pm.st[i][1];
      Vec3 y{};
      for (int a = 0; a < 3; ++a)
        y[a] = exact_planes && X[0][a] == X[1][a] && X[0][a] == X[2][a] && X[0][a] == X[3][a]
                   ? X[0][a]
                   : (1 - s) * (1 - t) * X[0][a] + s * (1 - t) * X[1][a] + s * t * X[2][a] + (1 - s) * t * X[3][a];
      put(pm.vertices[i], y);
    }
    m.flipped_surface_triangles += pm.flipped_triangles;
    m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, pm.max_angle_distortion_deg);
  }
  // The holed faces: each face minus its fills, between the face's sides and its k rims, all
  // placed above.
  for (int i = 0; i < 2; ++i) {
    std::vector<int> tris;
    for (int t : L.patches[static_cast<std::size_t>(holed[0][i])].triangles)
      if (!L.filled[static_cast<std::size_t>(t)]) tris.push_back(t);
    std::map<int, std::array<double, 2>> fixed;
    for (int t : tris)
      for (int v : L.triangles[static_cast<std::size_t>(t)]) {
        const Vec3& x = pts[static_cast<std::size_t>(v)];  // v < solid_vertices: a triangle that is not a fill
        if (!std::isnan(x[0])) fixed[v] = {x[a1], x[a2]};
      }
    const std::string what = "holed patch " + std::to_string(holed[0][i]);
    auto at = harmonic_positions(L, tris, fixed, params, what);
    // A harmonic map of a face with holes can flip triangles beside the holes' image corners: those
    // are unfolded (nothing moves where none flips); beside the foot's corners, where that leaves
    // flips, the corners' fans are fixed first, if that leaves fewer.
    if (unfold_free_vertices(L, tris, fixed, at, 20) > 0 && m.foot && i == foot_face) {
      std::map<int, std::array<double, 2>> fans = fixed;
      fix_foot_corner_fans(L, tris, L.patches[static_cast<std::size_t>(m.foot->patch)], fans);
      auto other = harmonic_positions(L, tris, fans, params, what);
      if (unfold_free_vertices(L, tris, fans, other, 20) < map_quality(L, tris, at).flipped_triangles) at = std::move(other);
    }
    for (const auto& [v, x] : at) {
      if (!std::isnan(pts[static_cast<std::size_t>(v)][0])) continue;  // placed above (the fans' are not yet)
      Vec3 y{};
      y[m.axis] = side[0][i][m.axis], y[a1] = x[0], y[a2] = x[1];
      put(v, y);
    }
    const MapQuality q = map_quality(L, tris, at);
    m.flipped_surface_triangles += q.flipped_triangles;
    m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, q.max_angle_distortion_deg);
  }
  for (std::size_t v = 0; v < pts.size(); ++v)
    if (std::isnan(pts[v][0])) throw core::TopologyError("polycube: vertex " + std::to_string(v) + " of the solid lies on no patch of the difference");

  // Mirror (swap the two axes across the holes) if the frame came out left-handed.
  if (layout_volume(L, pts, Fills::skip) < 0) {
    m.mirrored = true;
    for (auto& p : pts) std::swap(p[a1], p[a2]);
    for (auto& H : m.holes) std::swap(H.lo[a1], H.lo[a2]), std::swap(H.hi[a1], H.hi[a2]);
    if (m.foot) std::swap(m.foot->lo[a1], m.foot->lo[a2]), std::swap(m.foot->hi[a1], m.foot->hi[a2]);
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
  core::Json j{{"kind", "difference"},
               {"cube", m.cube},
               {"axis", m.axis},
               {"mirrored", m.mirrored},
               {"solid_vertices", m.solid_vertices},
               {"points", pts},
               {"flipped_surface_triangles", m.flipped_surface_triangles},
               {"max_angle_distortion_deg", m.max_angle_distortion_deg},
               {"max_mismatch", m.max_mismatch}};
  if (m.holes.size() == 1) {  // the one-hole format, as before several holes were mapped
    j["virtual_component"] = m.holes[0].virtual_component;
    j["hole_lo"] = m.holes[0].lo;
    j["hole_hi"] = m.holes[0].hi;
  } else {
    core::Json holes = core::Json::array();
    for (const auto& h : m.holes) holes.push_back({{"virtual_component", h.virtual_component}, {"hole_lo", h.lo}, {"hole_hi", h.hi}});
    j["holes"] = std::move(holes);
  }
  if (m.foot) j["foot"] = {{"patch", m.foot->patch}, {"lo", m.foot->lo}, {"hi", m.foot->hi}};
  return j;
}

DifferenceMap difference_from_json(const core::Json& j, const std::string& file) {
  DifferenceMap m;
  try {
    m.cube = core::require(j, "cube", file).get<int>();
    m.axis = core::require(j, "axis", file).get<int>();
    auto hole = [&](const core::Json& h) {
      HoleBox b;
      b.virtual_component = core::require(h, "virtual_component", file).get<int>();
      b.lo = core::require(h, "hole_lo", file).get<std::array<double, 3>>();
      b.hi = core::require(h, "hole_hi", file).get<std::array<double, 3>>();
      return b;
    };
    if (j.contains("holes")) {
      if (j.contains("virtual_component") || j.contains("hole_lo") || j.contains("hole_hi"))
        throw core::InvalidInputError(file + ": polycube has both holes and the one-hole virtual_component/hole_lo/hole_hi; give one form");
      const core::Json& hs = j["holes"];
      if (!hs.is_array() || hs.empty()) throw core::InvalidInputError(file + ": polycube.holes must be a non-empty array");
      for (const auto& h : hs) {
        if (!h.is_object()) throw core::InvalidInputError(file + ": polycube.holes holds a member that is not an object");
        m.holes.push_back(hole(h));
      }
    } else {
      m.holes.push_back(hole(j));
    }
    m.mirrored = core::require(j, "mirrored", file).get<bool>();
    m.solid_vertices = core::require(j, "solid_vertices", file).get<int>();
    const auto pts = core::require(j, "points", file).get<std::vector<double>>();
    if (m.solid_vertices < 4 || pts.size() != 3 * static_cast<std::size_t>(m.solid_vertices))
      throw core::InvalidInputError(file + ": polycube.points needs 3 numbers per solid vertex (solid_vertices " + std::to_string(m.solid_vertices) + ")");
    for (std::size_t i = 0; i < pts.size(); i += 3) m.points.push_back({pts[i], pts[i + 1], pts[i + 2]});
    m.flipped_surface_triangles = j.value("flipped_surface_triangles", 0);
    m.max_angle_distortion_deg = j.value("max_angle_distortion_deg", 0.0);
    m.max_mismatch = j.value("max_mismatch", 0.0);
    if (j.contains("foot")) {
      const core::Json& f = j["foot"];
      FootRect F;
      F.patch = core::require(f, "patch", file).get<int>();
      F.lo = core::require(f, "lo", file).get<std::array<double, 3>>();
      F.hi = core::require(f, "hi", file).get<std::array<double, 3>>();
      m.foot = F;
    }
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(file + ": malformed difference polycube: " + x.what());
  }
  if (m.axis < 0 || m.axis > 2) throw core::InvalidInputError(file + ": polycube.axis must be 0, 1 or 2");
  const bool one = m.holes.size() == 1;
  for (std::size_t h = 0; h < m.holes.size(); ++h) {
    const HoleBox& H = m.holes[h];
    const std::string name = one ? "polycube.hole_lo/hole_hi" : "polycube.holes[" + std::to_string(h) + "]";
    for (int a = 0; a < 3; ++a)
      if (!(H.lo[a] >= 0 && H.lo[a] < H.hi[a] && H.hi[a] <= 1) || (a == m.axis && (H.lo[a] != 0 || H.hi[a] != 1)) ||
          (a != m.axis && (H.lo[a] <= 0 || H.hi[a] >= 1)))
        throw core::InvalidInputError(file + ": " + name + " is not a box through the unit cube along its axis");
    for (std::size_t g = 0; g < h; ++g) {
      const HoleBox& G = m.holes[g];
      if (G.virtual_component == H.virtual_component)
        throw core::InvalidInputError(file + ": polycube.holes[" + std::to_string(g) + "] and [" + std::to_string(h) + "] are the same virtual component " +
                                      std::to_string(H.virtual_component));
      bool apart = false;
      for (int a = 0; a < 3; ++a) apart = apart || (a != m.axis && (H.hi[a] < G.lo[a] || G.hi[a] < H.lo[a]));
      if (!apart)
        throw core::InvalidInputError(file + ": the boxes polycube.holes[" + std::to_string(g) + "] and [" + std::to_string(h) + "] overlap or touch");
    }
  }
  for (const auto& p : m.points)
    for (double x : p)
      if (!std::isfinite(x)) throw core::InvalidInputError(file + ": polycube.points holds a non-finite value");
  if (m.foot) {
    const FootRect& F = *m.foot;
    bool ok = F.patch >= 0 && (F.lo[m.axis] == 0 || F.lo[m.axis] == 1) && F.hi[m.axis] == F.lo[m.axis];
    for (int a = 0; a < 3; ++a)
      if (a != m.axis) ok = ok && F.lo[a] > 0 && F.lo[a] < F.hi[a] && F.hi[a] < 1;
    if (!ok) throw core::InvalidInputError(file + ": polycube.foot is not a rectangle inside a face the holes run through");
    for (const HoleBox& H : m.holes) {
      bool apart = false;
      for (int a = 0; a < 3; ++a) apart = apart || (a != m.axis && (H.hi[a] < F.lo[a] || F.hi[a] < H.lo[a]));
      if (!apart) throw core::InvalidInputError(file + ": polycube.foot overlaps or touches the box of virtual component " + std::to_string(H.virtual_component));
    }
  }
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
