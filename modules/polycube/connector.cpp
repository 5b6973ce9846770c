#include "polycube/connector.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <limits>
#include <set>

#include "core/errors.h"

namespace volts::polycube {

namespace {
using Vec3 = std::array<double, 3>;
using Mark = std::function<std::optional<Vec3>(int)>;

// A lens's tip: at fraction `at` of the cube edge from corner vertex `from` to corner vertex `to`.
struct Tip {
  int from = -1, to = -1;
  double at = 0;
};

// The tips of the lensed end face `lensed` on the two sides of that face crossing its strips, at
// the strips' lines: the mean arc-length fraction of the lower and the upper tips along both
// sides (so the lines are straight). Sets m's strip figures. Throws core::TopologyError if the
// face's patches do not have two tips on each of two opposite sides of the face.
std::map<int, Tip> strip_tips(const split::Layout& L, const std::vector<split::CubeFace>& faces, std::size_t lensed, const std::array<int, 2>& end,
                              const std::string& who, const Mark& corner, ConnectorMap& m) {
  std::set<int> tip;
  for (const int p : faces[lensed].patches)
    for (const int v : L.patches.at(static_cast<std::size_t>(p)).corners)
      if (!corner(v)) tip.insert(v);
  const double a_end = static_cast<int>(lensed) == end[1] ? 1.0 : 0.0;
  struct Side {
    std::vector<int> chain;
    std::vector<std::size_t> tips;  // indices into chain
  };
  std::vector<Side> sides;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (static_cast<int>(f) == end[0] || static_cast<int>(f) == end[1]) continue;
    for (const auto& chain : L.patches.at(static_cast<std::size_t>(faces[f].patches.at(0))).sides) {
      const auto u = corner(chain.front()), w = corner(chain.back());
      if (!u || !w || (*u)[0] != a_end || (*w)[0] != a_end) continue;
      Side sd{chain, {}};
      for (std::size_t i = 1; i + 1 < chain.size(); ++i)
        if (tip.count(chain[i])) sd.tips.push_back(i);
      if (!sd.tips.empty()) sides.push_back(std::move(sd));
    }
  }
  if (tip.size() != 4 || sides.size() != 2 || sides[0].tips.size() != 2 || sides[1].tips.size() != 2)
    throw core::TopologyError(who + ": its end face of three patches does not have its lenses' four tips two on each of two sides (" +
                              std::to_string(tip.size()) + " tips on " + std::to_string(sides.size()) + " sides)");
  // Both sides run along the same cube axis; orient them from its 0 to its 1.
  std::array<double, 2> mean{0, 0};
  int axis = -1;
  for (Side& sd : sides) {
    const Vec3 u = *corner(sd.chain.front()), w = *corner(sd.chain.back());
    int d = -1;
    for (int q = 1; q < 3; ++q)
      if (u[q] != w[q]) d = q;
    if (d < 0 || (axis >= 0 && d != axis)) throw core::TopologyError(who + ": the sides through its lenses' tips are not opposite sides of its end face");
    axis = d;
    if (u[d] > w[d]) {
      std::reverse(sd.chain.begin(), sd.chain.end());
      for (std::size_t& i : sd.tips) i = sd.chain.size() - 1 - i;
      std::sort(sd.tips.begin(), sd.tips.end());
    }
    const std::vector<double> frac = arc_length_fractions(L, sd.chain);
    for (int k = 0; k < 2; ++k) mean[static_cast<std::size_t>(k)] += frac[sd.tips[static_cast<std::size_t>(k)]] / 2;
  }
  std::map<int, Tip> out;
  for (const Side& sd : sides) {
    const int o = static_cast<int>((*corner(sd.chain.front()))[static_cast<std::size_t>(3 - axis)]);
    for (int k = 0; k < 2; ++k) {
      const int v = sd.chain[sd.tips[static_cast<std::size_t>(k)]];
      out[v] = Tip{sd.chain.front(), sd.chain.back(), mean[static_cast<std::size_t>(k)]};
      m.strip_vertex[static_cast<std::size_t>(o + 2 * k)] = v;
    }
  }
  if (out.size() != 4 || std::set<int>(m.strip_vertex.begin(), m.strip_vertex.end()).size() != 4)
    throw core::TopologyError(who + ": the tips of its lenses are not two on each side of its end face");
  m.strip_end = static_cast<int>(a_end);
  m.strip_axis = axis;
  m.strip = mean;
  return out;
}

// The patch's map with each side piecewise by arc length between the marked vertices on it (its
// corners and any interior vertex `mark` places, at the fraction of its cube edge that place
// gives); nullopt if no side has an interior mark (then map_patches' map is this map).
std::optional<PatchMap> remap_through_marks(const split::Layout& L, const split::Patch& P, const Mark& mark, const PatchMapParams& params, int index) {
  static const std::array<std::array<double, 2>, 4> corner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  std::map<int, std::array<double, 2>> fixed;
  bool marked = false;
  for (int k = 0; k < 4; ++k) {
    const auto& chain = P.sides[static_cast<std::size_t>(k)];
    const Vec3 x0 = *mark(chain.front()), x1 = *mark(chain.back());
    double len2 = 0;
    for (int q = 0; q < 3; ++q) len2 += (x1[q] - x0[q]) * (x1[q] - x0[q]);
    // Marks along the chain (index, fraction of the edge), both ends included.
    std::vector<std::pair<std::size_t, double>> at{{0, 0.0}};
    for (std::size_t i = 1; i + 1 < chain.size(); ++i)
      if (const auto x = mark(chain[i])) {
        double g = 0;
        for (int q = 0; q < 3; ++q) g += ((*x)[q] - x0[q]) * (x1[q] - x0[q]) / len2;
        at.emplace_back(i, g);
      }
    at.emplace_back(chain.size() - 1, 1.0);
    marked = marked || at.size() > 2;
    std::vector<double> s(chain.size(), 0.0);
    for (std::size_t i = 1; i < chain.size(); ++i) s[i] = s[i - 1] + chain_length(L, {chain[i - 1], chain[i]});
    const auto& a = corner[static_cast<std::size_t>(k)];
    const auto& b = corner[static_cast<std::size_t>((k + 1) % 4)];
    for (std::size_t j = 0; j + 1 < at.size(); ++j)
      for (std::size_t i = at[j].first; i <= at[j + 1].first; ++i) {
        const double span = s[at[j + 1].first] - s[at[j].first];
        const double g = at[j].second + (span > 0 ? (s[i] - s[at[j].first]) / span : 0.0) * (at[j + 1].second - at[j].second);
        fixed[chain[i]] = {a[0] + g * (b[0] - a[0]), a[1] + g * (b[1] - a[1])};
      }
  }
  if (!marked) return std::nullopt;
  return solve_patch_map(L, P.triangles, fixed, params, "patch " + std::to_string(index));
}

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
  int lensed = -1;  // the end face of three patches (split.connector_end: shoulder), if any
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::size_t np = faces[f].patches.size();
    if (np != 1 && np != 3) throw core::TopologyError(who + " has a face of " + std::to_string(np) + " patches");
    int disk = -1, disks = 0;
    for (const int p : faces[f].patches) {
      const auto& tris = L.patches.at(static_cast<std::size_t>(p)).triangles;
      if (!tris.empty() && L.filled.at(static_cast<std::size_t>(tris[0]))) disk = p, ++disks;
    }
    if (np == 3 && disks != 1)
      throw core::TopologyError(who + " has a face of three patches that is not a disk between the two faces of a shoulder (" +
                                std::to_string(disks) + " of them fill an opening)");
    if (disk < 0) continue;
    const auto& tris = L.patches.at(static_cast<std::size_t>(disk)).triangles;
    const bool first = ring0_triangles.count(piece.layout_triangle.at(static_cast<std::size_t>(tris[0]))) > 0;
    if (end[first ? 0 : 1] >= 0) throw core::TopologyError(who + " has two faces on the disk of one ring");
    end[first ? 0 : 1] = static_cast<int>(f);
    if (np == 3) {
      if (lensed >= 0) throw core::TopologyError(who + " has two ends of three patches; one shoulder end is supported");
      lensed = static_cast<int>(f);
    }
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
  std::vector<PatchMap> maps = map_patches(d, params);
  auto cube_point = [&](int v, bool swap) {
    const auto it = std::find(m.corner_vertex.begin(), m.corner_vertex.end(), v);
    if (it == m.corner_vertex.end()) return std::optional<Vec3>{};
    const int i = static_cast<int>(it - m.corner_vertex.begin());
    Vec3 x{double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)};
    if (swap) std::swap(x[1], x[2]);
    return std::optional<Vec3>{x};
  };
  // A lensed end (Liu et al. Fig. 13, the rod's small eye): its face is stacked in three strips
  // across the eye's thickness, lens | disk | lens, so that the disk's strip is a rectangle that
  // ring 1's face covers exactly. The lenses' tips (corners of the face's patches, not of the
  // cube) lie on the face's two sides that cross the strips; they sit at the strips' lines.
  std::map<int, Tip> tips;
  if (lensed >= 0) tips = strip_tips(L, faces, static_cast<std::size_t>(lensed), end, who, [&](int v) { return cube_point(v, false); }, m);
  auto mark = [&](int v, bool swap) -> std::optional<Vec3> {
    if (auto x = cube_point(v, swap)) return x;
    const auto t = tips.find(v);
    if (t == tips.end()) return std::nullopt;
    const Vec3 u = *cube_point(t->second.from, swap), w = *cube_point(t->second.to, swap);
    Vec3 x{};
    for (int q = 0; q < 3; ++q) x[q] = u[q] + t->second.at * (w[q] - u[q]);
    return x;
  };
  // Patches whose sides pass through tips: those sides piecewise by arc length between the marks.
  for (std::size_t p = 0; p < L.patches.size() && !tips.empty(); ++p)
    if (auto pm = remap_through_marks(L, L.patches[p], [&](int v) { return mark(v, false); }, params, static_cast<int>(p))) maps[p] = std::move(*pm);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto place = [&](bool swap) {
    std::vector<Vec3> pts(L.points.size(), Vec3{nan, nan, nan});
    m.max_mismatch = 0;
    for (std::size_t p = 0; p < L.patches.size(); ++p) {
      std::array<Vec3, 4> X;
      for (int k = 0; k < 4; ++k) {
        const auto x = mark(L.patches[p].corners[static_cast<std::size_t>(k)], swap);
        if (!x) throw core::TopologyError(who + ": a patch corner is no corner of the cube");
        X[static_cast<std::size_t>(k)] = *x;
      }
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
    if (m.strip_axis > 0) m.strip_axis = 3 - m.strip_axis;
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
  core::Json j{{"component", piece.component.at(0)},
                    {"layout_vertex", piece.layout_vertex},
                    {"layout_triangle", piece.layout_triangle},
                    {"corner_vertex", m.corner_vertex},
                    {"mirrored", m.mirrored},
                    {"points", pts},
                    {"flipped_surface_triangles", m.flipped_surface_triangles},
                    {"max_angle_distortion_deg", m.max_angle_distortion_deg},
                    {"max_mismatch", m.max_mismatch},
                    {"volume_map", volmap::to_json(vm)}};
  if (m.strip_axis > 0) j["end_strip"] = core::Json{{"end", m.strip_end}, {"axis", m.strip_axis}, {"lo", m.strip[0]}, {"hi", m.strip[1]}, {"corner_vertex", m.strip_vertex}};
  return j;
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
