#include "tmesh/pillow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "core/errors.h"

namespace volts::tmesh {

Vec3 block_point(const std::array<Vec3, 8>& c, const Vec3& uvw) {
  Vec3 x{0, 0, 0};
  for (int i = 0; i < 8; ++i) {
    const double w = (i & 1 ? uvw[0] : 1 - uvw[0]) * (i & 2 ? uvw[1] : 1 - uvw[1]) * (i & 4 ? uvw[2] : 1 - uvw[2]);
    for (int d = 0; d < 3; ++d) x[d] += w * c[i][d];
  }
  return x;
}

std::vector<Block> rim_pillow(const Block& slab, int layers) {
  if (layers < 1) throw core::ConfigError("tmesh: a rim pillow needs layers >= 1, got " + std::to_string(layers));
  int f = -1, faces = 0;
  for (int i = 0; i < 6; ++i)
    if (slab.boundary[static_cast<std::size_t>(i)]) f = i, ++faces;
  if (faces != 1) throw core::InvalidInputError("tmesh: a rim pillow needs a block with exactly one surface face, got " + std::to_string(faces));
  std::array<int, 6> pillowed{1, 1, 1, 1, 1, 1};
  pillowed[static_cast<std::size_t>(f)] = 0;
  const int a = f / 2, side = f % 2;
  std::vector<Block> out = cube_blocks(pillowed, slab.elements, layers);
  for (Block& b : out) {
    // A new block reaches the surface face iff its four corners on that side lie in its plane.
    bool on_face = true;
    for (std::size_t c = 0; c < 8; ++c)
      if (static_cast<int>((c >> a) & 1) == side) on_face = on_face && b.corners[c][static_cast<std::size_t>(a)] == side;
    b.boundary = {0, 0, 0, 0, 0, 0};
    b.boundary[static_cast<std::size_t>(f)] = on_face ? 1 : 0;
    b.pillow = true;
    for (Vec3& x : b.corners) x = block_point(slab.corners, x);
  }
  return out;
}

namespace {

// Interval ends 0, cuts..., 1 along cube axis d, after checking the cuts.
std::vector<double> cut_ends(int d, const std::vector<double>& cuts) {
  const std::string where = " along cube axis " + std::to_string(d);
  std::vector<double> t{0.0};
  for (const double u : cuts) {
    if (!(u > 0 && u < 1)) throw core::ConfigError("tmesh: cut " + std::to_string(u) + where + " is not in (0, 1)");
    if (!(u > t.back())) throw core::ConfigError("tmesh: cuts" + where + " are not strictly increasing at " + std::to_string(u));
    if (u - t.back() < kMinCutGap) throw core::ConfigError("tmesh: cut " + std::to_string(u) + where + " is too close to the previous one or to 0");
    t.push_back(u);
  }
  if (1 - t.back() < kMinCutGap) throw core::ConfigError("tmesh: cut " + std::to_string(t.back()) + where + " is too close to 1");
  t.push_back(1.0);
  return t;
}

// n elements over the intervals of ends t by length: one each, then one at a time to the interval
// furthest below its share (largest remainder when every share is at least one).
std::vector<int> spread(int n, const std::vector<double>& t) {
  const std::size_t k = t.size() - 1;
  std::vector<int> c(k, 1);
  auto deficit = [&](std::size_t i) { return n * (t[i + 1] - t[i]) - c[i]; };
  for (int left = n - static_cast<int>(k); left > 0; --left) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < k; ++i)
      if (deficit(i) > deficit(best)) best = i;
    ++c[best];
  }
  return c;
}

// lo + u (hi - lo), exactly lo and hi at the ends (so uncut blocks are bitwise today's).
double lerp(double lo, double hi, double u) { return u == 1 ? hi : lo + u * (hi - lo); }

}  // namespace

std::vector<Block> cube_blocks(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers) {
  return cube_blocks(boundary, elements, layers, {});
}

std::vector<Block> cube_blocks(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers,
                               const std::array<std::vector<double>, 3>& cuts) {
  if (layers < 0) throw core::ConfigError("tmesh.pillow_layers must be >= 0, got " + std::to_string(layers));
  for (const int n : elements)
    if (n < 1) throw core::ConfigError("tmesh: a cube needs at least one element per direction");
  std::array<std::vector<double>, 3> t;
  std::array<std::vector<int>, 3> n;
  std::array<int, 3> pieces{};
  for (std::size_t d = 0; d < 3; ++d) {
    t[d] = cut_ends(static_cast<int>(d), cuts[d]);
    n[d] = spread(elements[d], t[d]);
    pieces[d] = static_cast<int>(n[d].size());
  }
  // Core extent: pulled in from every surface face by `layers` elements of the cube's spacing
  // (the whole cube without pillow).
  Vec3 lo{0, 0, 0}, hi{1, 1, 1};
  if (layers > 0)
    for (std::size_t d = 0; d < 3; ++d) {
      const int sides = boundary[2 * d] + boundary[2 * d + 1];
      const double h = 1.0 / (elements[d] + sides * layers);
      if (boundary[2 * d]) lo[d] = layers * h;
      if (boundary[2 * d + 1]) hi[d] = 1 - layers * h;
    }
  std::vector<Block> blocks;
  for (int k = 0; k < pieces[2]; ++k)
    for (int j = 0; j < pieces[1]; ++j)
      for (int i = 0; i < pieces[0]; ++i) {
        const std::array<int, 3> at{i, j, k};
        Block b;
        for (std::size_t c = 0; c < 8; ++c)
          for (std::size_t d = 0; d < 3; ++d) b.corners[c][d] = lerp(lo[d], hi[d], t[d][static_cast<std::size_t>(at[d]) + ((c >> d) & 1)]);
        for (std::size_t d = 0; d < 3; ++d) {
          b.elements[d] = n[d][static_cast<std::size_t>(at[d])];
          if (layers == 0) {
            b.boundary[2 * d] = at[d] == 0 && boundary[2 * d];
            b.boundary[2 * d + 1] = at[d] == pieces[d] - 1 && boundary[2 * d + 1];
          }
        }
        blocks.push_back(b);
      }
  if (layers == 0) return blocks;
  for (std::size_t a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      if (!boundary[2 * a + static_cast<std::size_t>(s)]) continue;
      std::array<int, 3> count = pieces;
      count[a] = 1;  // not cut across its thickness
      for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
          for (int i = 0; i < count[0]; ++i) {
            const std::array<int, 3> at{i, j, k};
            Block slab;
            slab.pillow = true;
            slab.boundary[2 * a + static_cast<std::size_t>(s)] = 1;
            for (std::size_t d = 0; d < 3; ++d) slab.elements[d] = d == a ? layers : n[d][static_cast<std::size_t>(at[d])];
            // Local axes are the cube's (orientation kept); along a, the side toward the face is
            // the cube face, the other the core face. The outer face spans the whole cube face,
            // the inner face the core's, so the slab's sides are diagonal where the next face is a
            // surface face too and flat (on the cube face) where it is not; a cut is the ruled
            // plane between the same relative position on both.
            for (std::size_t c = 0; c < 8; ++c) {
              const bool outer = static_cast<int>((c >> a) & 1) == s;
              for (std::size_t d = 0; d < 3; ++d) {
                if (d == a) {
                  slab.corners[c][d] = outer ? s : (s ? hi[d] : lo[d]);
                } else {
                  const double u = t[d][static_cast<std::size_t>(at[d]) + ((c >> d) & 1)];
                  slab.corners[c][d] = outer ? u : lerp(lo[d], hi[d], u);
                }
              }
            }
            blocks.push_back(slab);
          }
    }
  return blocks;
}

namespace {

// Corners of a block with one face `outer` (on the surface: lo/hi in the two face directions, at
// `at` along `normal`) and the opposite face `inner`; `outer_high` says whether the outer face is
// on the high side of `normal`. Box and frustum alike.
struct Face {
  double at;
  Vec3 lo, hi;  // extent in the two face directions (the normal's entry unused)
};
std::array<Vec3, 8> frustum(int normal, const Face& outer, const Face& inner, bool outer_high) {
  std::array<Vec3, 8> c;
  for (int i = 0; i < 8; ++i) {
    const bool high = (i >> normal) & 1;
    const Face& f = high == outer_high ? outer : inner;
    for (int d = 0; d < 3; ++d) c[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)] = d == normal ? f.at : ((i >> d) & 1 ? f.hi[d] : f.lo[d]);
  }
  return c;
}

}  // namespace

namespace {

// A grid line across the section: its position, its core line (moved by the pillow's thickness
// toward the solid: +1 for the side 0 and hi walls, -1 for the side 1 and lo walls) and a hole
// whose wall it is (-1: a side of the cube), for messages.
struct GridLine {
  double at;
  int toward;
  int hole;
};

std::string hole_name(int h) { return h < 0 ? std::string("the cube's side") : "hole " + std::to_string(h); }

std::string pair_name(int g, int h) {
  if (g >= 0 && h >= 0 && g != h) return "holes " + std::to_string(std::min(g, h)) + " and " + std::to_string(std::max(g, h));
  return hole_name(std::max(g, h)) + " and " + hole_name(std::min(g, h));
}

}  // namespace

std::vector<Block> difference_blocks(int axis, const std::vector<std::array<Vec3, 2>>& holes, const std::array<int, 3>& elements, int layers) {
  if (layers < 0) throw core::ConfigError("tmesh.pillow_layers must be >= 0, got " + std::to_string(layers));
  for (const int e : elements)
    if (e < 1) throw core::ConfigError("tmesh: a cube needs at least one element per direction");
  if (axis < 0 || axis > 2) throw core::TopologyError("tmesh: the holes' axis must be 0, 1 or 2");
  if (holes.empty()) throw core::TopologyError("tmesh: a difference needs at least one hole");
  // Local frame: x, y across the holes, z along them; cube axis of local d is (axis + 1 + d) % 3 (a
  // cyclic permutation keeps the orientation).
  auto cube_axis = [axis](int d) { return (axis + 1 + d) % 3; };
  const int k = static_cast<int>(holes.size());
  auto lo = [&](int i, int d) { return holes[static_cast<std::size_t>(i)][0][static_cast<std::size_t>(cube_axis(d))]; };
  auto hi = [&](int i, int d) { return holes[static_cast<std::size_t>(i)][1][static_cast<std::size_t>(cube_axis(d))]; };
  for (int i = 0; i < k; ++i) {
    const std::array<Vec3, 2>& b = holes[static_cast<std::size_t>(i)];
    const auto a = static_cast<std::size_t>(axis);
    if (b[0][a] != 0 || b[1][a] != 1 || !(0 < lo(i, 0) && lo(i, 0) < hi(i, 0) && hi(i, 0) < 1) || !(0 < lo(i, 1) && lo(i, 1) < hi(i, 1) && hi(i, 1) < 1))
      throw core::TopologyError("tmesh: " + hole_name(i) + " is not a box through the cube along axis " + std::to_string(axis) +
                                " strictly inside it across");
  }
  // Closed boxes: holes that share even a corner leave the solid non-manifold there.
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j)
      if (lo(i, 0) <= hi(j, 0) && lo(j, 0) <= hi(i, 0) && lo(i, 1) <= hi(j, 1) && lo(j, 1) <= hi(i, 1))
        throw core::TopologyError("tmesh: holes " + std::to_string(i) + " and " + std::to_string(j) + " overlap or touch");
  // Per local axis (x, y across, z along): the element size and the pillow's thickness in the
  // cube's parameters (the pillow is `layers` elements of that axis thick).
  std::array<int, 3> per_axis{};
  std::array<double, 3> h{}, th{};
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    per_axis[u] = elements[static_cast<std::size_t>(cube_axis(d))];
    h[u] = 1.0 / (per_axis[u] + 2 * layers), th[u] = layers * h[u];
  }
  // Grid lines along each local cross axis, with the core lines (as the one-hole construction: t,
  // lo - t, hi + t, 1 - t; the core is the solid shrunk by t only while they keep the grid lines'
  // order) and the element counts of their intervals.
  std::array<std::vector<double>, 2> G, C;  // grid and core lines
  std::array<std::vector<int>, 2> n;
  std::vector<std::array<std::array<std::size_t, 2>, 2>> wall(holes.size());  // wall[i][d][side]: the wall's line in G[d]
  for (int d = 0; d < 2; ++d) {
    std::vector<GridLine> lines{{0.0, 1, -1}, {1.0, -1, -1}};
    for (int i = 0; i < k; ++i) lines.push_back({lo(i, d), -1, i}), lines.push_back({hi(i, d), 1, i});
    std::sort(lines.begin(), lines.end(), [](const GridLine& a, const GridLine& b) { return a.at < b.at || (a.at == b.at && a.hole < b.hole); });
    std::vector<GridLine> unique;
    for (const GridLine& l : lines) {
      if (unique.empty() || unique.back().at != l.at) {
        unique.push_back(l);
      } else if (unique.back().toward != l.toward) {
        throw core::TopologyError("tmesh: holes " + std::to_string(unique.back().hole) + " and " + std::to_string(l.hole) +
                                  " meet along a line: the lo wall of one is the hi wall of the other at " + std::to_string(l.at) +
                                  " along cube axis " + std::to_string(cube_axis(d)));
      }
    }
    auto& g = G[static_cast<std::size_t>(d)];
    auto& c = C[static_cast<std::size_t>(d)];
    const double t = th[static_cast<std::size_t>(d)];
    for (const GridLine& l : unique) g.push_back(l.at), c.push_back(l.toward > 0 ? l.at + t : l.at - t);
    for (std::size_t i = 0; i + 1 < c.size(); ++i)
      if (!(c[i] < c[i + 1]))
        throw core::TopologyError("tmesh: " + pair_name(unique[i].hole, unique[i + 1].hole) + " lie too close together along cube axis " +
                                  std::to_string(cube_axis(d)) + " for a pillow of " + std::to_string(layers) + " layer(s) of 1/" +
                                  std::to_string(per_axis[static_cast<std::size_t>(d)] + 2 * layers) + " (lower tmesh.pillow_layers or raise tmesh.level)");
    const std::vector<double>& L = layers ? c : g;  // lines the columns' element counts follow
    for (std::size_t i = 0; i + 1 < L.size(); ++i)
      n[static_cast<std::size_t>(d)].push_back(std::max(1, static_cast<int>(std::lround((L[i + 1] - L[i]) / h[static_cast<std::size_t>(d)]))));
    for (int i = 0; i < k; ++i)
      for (int s = 0; s < 2; ++s) {
        const double w = s ? hi(i, d) : lo(i, d);
        wall[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)][static_cast<std::size_t>(s)] =
            static_cast<std::size_t>(std::lower_bound(g.begin(), g.end(), w) - g.begin());
      }
  }
  const std::vector<double>& X = G[0];
  const std::vector<double>& Y = G[1];
  const std::vector<double>& Xc = C[0];
  const std::vector<double>& Yc = C[1];
  const std::vector<int>& nx = n[0];
  const std::vector<int>& ny = n[1];
  const std::size_t cx = nx.size(), cy = ny.size();
  // solid[i + cx j]: whether cell (i, j) of the section is outside every hole.
  std::vector<bool> solid(cx * cy, true);
  for (const auto& w : wall)
    for (std::size_t j = w[1][0]; j < w[1][1]; ++j)
      for (std::size_t i = w[0][0]; i < w[0][1]; ++i) solid[i + cx * j] = false;
  auto is_solid = [&](std::size_t i, std::size_t j) { return i < cx && j < cy && solid[i + cx * j]; };  // false off the grid (wraps)

  std::vector<Block> out;
  auto add = [&](const std::array<Vec3, 8>& local, std::array<int, 3> count, std::array<int, 6> boundary, bool pillow) {
    Block b;
    for (int i = 0; i < 8; ++i)
      for (int d = 0; d < 3; ++d) b.corners[static_cast<std::size_t>(i)][static_cast<std::size_t>(cube_axis(d))] = local[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)];
    b.elements = count;
    b.boundary = boundary;
    b.pillow = pillow;
    out.push_back(b);
  };
  const std::vector<double>& XL = layers ? Xc : X;
  const std::vector<double>& YL = layers ? Yc : Y;
  const double t = th[2];  // along the holes
  const int nz = per_axis[2];
  const double z0 = layers ? t : 0, z1 = layers ? 1 - t : 1;
  // Columns (the core's, or the solid's without pillow).
  for (std::size_t j = 0; j < cy; ++j)
    for (std::size_t i = 0; i < cx; ++i) {
      if (!is_solid(i, j)) continue;
      const Face lo_face{z0, {XL[i], YL[j], 0}, {XL[i + 1], YL[j + 1], 0}}, hi_face{z1, {XL[i], YL[j], 0}, {XL[i + 1], YL[j + 1], 0}};
      std::array<int, 6> boundary{0, 0, 0, 0, 0, 0};
      if (!layers)  // is_solid is false off the grid: i - 1 wraps past cx
        boundary = {!is_solid(i - 1, j), !is_solid(i + 1, j), !is_solid(i, j - 1), !is_solid(i, j + 1), 1, 1};
      add(frustum(2, hi_face, lo_face, true), {nx[i], ny[j], nz}, boundary, false);
    }
  if (!layers) return out;
  // Under the cube's four sides: a frustum per grid interval, between the side and the core's side
  // (x and y sides interleaved, as the one-hole construction ordered them).
  for (int s = 0; s < 2; ++s)
    for (std::size_t m = 0; m < std::max(cx, cy); ++m) {
      std::array<int, 6> bx{0, 0, 0, 0, 0, 0}, by{0, 0, 0, 0, 0, 0};
      bx[static_cast<std::size_t>(s)] = 1, by[static_cast<std::size_t>(2 + s)] = 1;
      if (m < cy)
        add(frustum(0, {double(s), {0, Y[m], 0}, {0, Y[m + 1], 1}}, {Xc[s ? cx : 0], {0, Yc[m], t}, {0, Yc[m + 1], 1 - t}}, s == 1),
            {layers, ny[m], nz}, bx, true);
      if (m < cx)
        add(frustum(1, {double(s), {X[m], 0, 0}, {X[m + 1], 0, 1}}, {Yc[s ? cy : 0], {Xc[m], 0, t}, {Xc[m + 1], 0, 1 - t}}, s == 1),
            {nx[m], layers, nz}, by, true);
    }
  // Under the two holed faces: a frustum per column, between its cell and the core's.
  for (int s = 0; s < 2; ++s)
    for (std::size_t j = 0; j < cy; ++j)
      for (std::size_t i = 0; i < cx; ++i) {
        if (!is_solid(i, j)) continue;
        std::array<int, 6> b{0, 0, 0, 0, 0, 0};
        b[static_cast<std::size_t>(4 + s)] = 1;
        add(frustum(2, {double(s), {X[i], Y[j], 0}, {X[i + 1], Y[j + 1], 0}}, {s ? 1 - t : t, {Xc[i], Yc[j], 0}, {Xc[i + 1], Yc[j + 1], 0}}, s == 1),
            {nx[i], ny[j], layers}, b, true);
      }
  // Under each hole's walls (the circumferential pillow), a frustum per grid interval: the solid
  // lies on the wall's far side from the hole, so a lo wall is the slab's high face and a hi wall
  // its low one.
  for (const auto& w : wall)
    for (int s = 0; s < 2; ++s) {
      std::array<int, 6> bx{0, 0, 0, 0, 0, 0}, by{0, 0, 0, 0, 0, 0};
      bx[static_cast<std::size_t>(1 - s)] = 1, by[static_cast<std::size_t>(3 - s)] = 1;
      const std::size_t wx = w[0][static_cast<std::size_t>(s)], wy = w[1][static_cast<std::size_t>(s)];
      for (std::size_t j = w[1][0]; j < w[1][1]; ++j)
        add(frustum(0, {X[wx], {0, Y[j], 0}, {0, Y[j + 1], 1}}, {Xc[wx], {0, Yc[j], t}, {0, Yc[j + 1], 1 - t}}, s == 0),
            {layers, ny[j], nz}, bx, true);
      for (std::size_t i = w[0][0]; i < w[0][1]; ++i)
        add(frustum(1, {Y[wy], {X[i], 0, 0}, {X[i + 1], 0, 1}}, {Yc[wy], {Xc[i], 0, t}, {Xc[i + 1], 0, 1 - t}}, s == 0),
            {nx[i], layers, nz}, by, true);
    }
  return out;
}

std::vector<Block> difference_blocks(int axis, const std::vector<std::array<Vec3, 2>>& holes, int elements, int layers) {
  return difference_blocks(axis, holes, {elements, elements, elements}, layers);
}

std::vector<Block> difference_blocks(int axis, const Vec3& hole_lo, const Vec3& hole_hi, int elements, int layers) {
  return difference_blocks(axis, std::vector<std::array<Vec3, 2>>{{hole_lo, hole_hi}}, elements, layers);
}

namespace {

// A block face lying on a cube face: its corners in the cube face's two coordinates (the cube axes
// other than the face's, in increasing order; corner k: bit 0 along the first, bit 1 along the
// second) and the block's element counts along them.
struct FacePiece {
  std::array<std::array<double, 2>, 4> x;
  std::array<int, 2> n;
};

constexpr double kProfileTol = 1e-12;

// The faces of `blocks` (whose axes are the cube's) lying on the cube face x_axis = side.
std::vector<FacePiece> face_tiling(const std::vector<Block>& blocks, std::size_t axis, int side) {
  const std::size_t u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
  std::vector<FacePiece> out;
  for (const Block& b : blocks)
    for (std::size_t s = 0; s < 2; ++s) {
      FacePiece f;
      bool on = true;
      for (std::size_t k = 0; k < 4; ++k) {
        const Vec3& p = b.corners[(s << axis) | ((k & 1) << u) | ((k >> 1) << v)];
        on = on && std::abs(p[axis] - side) < kProfileTol;
        f.x[k] = {p[u], p[v]};
      }
      if (!on) continue;
      f.n = {b.elements[u], b.elements[v]};
      out.push_back(f);
    }
  return out;
}

// Whether two tilings have the same pieces (corners to kProfileTol, element counts), in any order.
bool same_tiling(const std::vector<FacePiece>& f, const std::vector<FacePiece>& g) {
  if (f.size() != g.size()) return false;
  auto same = [](const FacePiece& p, const FacePiece& q) {
    if (p.n != q.n) return false;
    for (std::size_t k = 0; k < 4; ++k)
      for (std::size_t d = 0; d < 2; ++d)
        if (!(std::abs(p.x[k][d] - q.x[k][d]) < kProfileTol)) return false;
    return true;
  };
  std::vector<bool> used(g.size(), false);
  for (const FacePiece& p : f) {
    std::size_t m = 0;
    while (m < g.size() && (used[m] || !same(p, g[m]))) ++m;
    if (m == g.size()) return false;
    used[m] = true;
  }
  return true;
}

// The intervals a tiling's pieces cover along face coordinate w, in order: their ends and element counts.
struct Intervals {
  std::vector<double> ends;
  std::vector<int> n;
};
Intervals intervals(const std::vector<FacePiece>& pieces, std::size_t w) {
  std::vector<std::pair<std::array<double, 2>, int>> iv;  // ([lo, hi], elements)
  for (const FacePiece& p : pieces) {
    const double lo = std::min({p.x[0][w], p.x[1][w], p.x[2][w], p.x[3][w]}), hi = std::max({p.x[0][w], p.x[1][w], p.x[2][w], p.x[3][w]});
    if (std::none_of(iv.begin(), iv.end(), [&](const auto& x) { return std::abs(x.first[0] - lo) < kProfileTol && std::abs(x.first[1] - hi) < kProfileTol; }))
      iv.push_back({{lo, hi}, p.n[w]});
  }
  std::sort(iv.begin(), iv.end());
  Intervals out;
  for (const auto& [range, n] : iv) {
    if (out.ends.empty()) out.ends.push_back(range[0]);
    out.ends.push_back(range[1]);
    out.n.push_back(n);
  }
  return out;
}

bool same_intervals(const Intervals& x, const Intervals& y) {
  if (x.n != y.n || x.ends.size() != y.ends.size()) return false;
  for (std::size_t i = 0; i < x.ends.size(); ++i)
    if (!(std::abs(x.ends[i] - y.ends[i]) < kProfileTol)) return false;
  return true;
}

std::string cell_name(const std::array<int, 2>& c) { return "(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + ")"; }

const char* const kAxisName[3] = {"a", "b", "c"};

}  // namespace

std::vector<std::vector<Block>> profile_blocks(const std::vector<std::array<int, 2>>& cells, int elements, int layers) {
  if (layers < 0) throw core::ConfigError("tmesh.pillow_layers must be >= 0, got " + std::to_string(layers));
  if (elements < 1) throw core::ConfigError("tmesh: a cube needs at least one element per direction");
  if (cells.empty()) throw core::InvalidInputError("tmesh: the profile has no cells");
  std::map<std::array<int, 2>, std::size_t> index;
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (!index.emplace(cells[i], i).second) throw core::InvalidInputError("tmesh: profile cell " + cell_name(cells[i]) + " is listed twice");
  const std::size_t count = cells.size();
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  // nb[i][2 * axis + side]: the cell across cube face (axis, side) of cell i, kNone on the surface
  // (and always for the a faces, which the ring glues to the same cell).
  std::vector<std::array<std::size_t, 6>> nb(count);
  for (std::size_t i = 0; i < count; ++i) {
    nb[i].fill(kNone);
    for (std::size_t axis = 1; axis < 3; ++axis)
      for (std::size_t side = 0; side < 2; ++side) {
        std::array<long long, 2> q{cells[i][0], cells[i][1]};
        q[axis - 1] += side ? 1 : -1;
        if (q[axis - 1] < std::numeric_limits<int>::min() || q[axis - 1] > std::numeric_limits<int>::max()) continue;
        const auto it = index.find({static_cast<int>(q[0]), static_cast<int>(q[1])});
        if (it != index.end()) nb[i][2 * axis + side] = it->second;
      }
  }
  std::vector<bool> seen(count, false);
  std::vector<std::size_t> stack{0};
  seen[0] = true;
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    for (const std::size_t m : nb[i])
      if (m != kNone && !seen[m]) seen[m] = true, stack.push_back(m);
  }
  for (std::size_t i = 0; i < count; ++i)
    if (!seen[i])
      throw core::InvalidInputError("tmesh: profile cell " + cell_name(cells[i]) + " is not edge-connected to cell " + cell_name(cells[0]));

  std::vector<std::array<int, 6>> boundary(count);
  std::vector<bool> surface(count, false);
  for (std::size_t i = 0; i < count; ++i) {
    boundary[i] = {0, 0, 0, 0, 0, 0};
    for (std::size_t f = 2; f < 6; ++f) {
      boundary[i][f] = nb[i][f] == kNone;
      surface[i] = surface[i] || boundary[i][f];
    }
  }
  // The cell across from cell i by (db, dc) on the grid, kNone if there is none.
  auto cell_at = [&](std::size_t i, int db, int dc) {
    const long long x = static_cast<long long>(cells[i][0]) + db, y = static_cast<long long>(cells[i][1]) + dc;
    if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max() || y < std::numeric_limits<int>::min() ||
        y > std::numeric_limits<int>::max())
      return kNone;
    const auto it = index.find({static_cast<int>(x), static_cast<int>(y)});
    return it == index.end() ? kNone : it->second;
  };
  // Conformity: the faces two cells share, and each cell's a = 0 and a = 1 faces (the ring). An
  // empty string if they conform, else why not.
  auto nonconforming = [&](const std::vector<std::vector<Block>>& out) -> std::string {
    for (std::size_t i = 0; i < count; ++i) {
      if (!same_tiling(face_tiling(out[i], 0, 0), face_tiling(out[i], 0, 1)))
        return "tmesh: profile cell " + cell_name(cells[i]) + ": its blocks tile its faces a = 0 and a = 1 differently, so the ring does not close";
      for (std::size_t axis = 1; axis < 3; ++axis) {
        const std::size_t m = nb[i][2 * axis + 1];
        if (m == kNone) continue;
        if (!same_tiling(face_tiling(out[i], axis, 1), face_tiling(out[m], axis, 0)))
          return "tmesh: profile cells " + cell_name(cells[i]) + " and " + cell_name(cells[m]) + " do not conform with " +
                 std::to_string(layers) + " pillow layer(s): their blocks tile the shared face (" + kAxisName[axis] +
                 " = 1 of the first) differently; this pillow rule cannot take the profile (0 layers can)";
      }
    }
    return {};
  };

  std::vector<std::vector<Block>> out(count);
  if (layers == 0) {
    for (std::size_t i = 0; i < count; ++i) out[i] = cube_blocks(boundary[i], {elements, elements, elements}, 0);
    const std::string why = nonconforming(out);
    if (!why.empty()) throw core::TopologyError(why);
    return out;
  }

  // Rule 1 (per cell): a cell with a surface face is its pillowed cube; a cell without one is cut
  // along d in {b, c} where the slabs of the neighbours across the faces perpendicular to the
  // other cross axis e end on the shared face, with their counts. Neighbours without a surface
  // face have no slabs and ask for nothing. Fails (false) if two neighbours disagree.
  auto per_cell = [&]() {
    for (std::size_t i = 0; i < count; ++i)
      if (surface[i]) out[i] = cube_blocks(boundary[i], {elements, elements, elements}, layers);
    for (std::size_t i = 0; i < count; ++i) {
      if (surface[i]) continue;
      std::array<std::vector<double>, 3> cuts;
      std::array<int, 3> counts{elements, elements, elements};
      for (std::size_t d = 1; d < 3; ++d) {
        const std::size_t e = 3 - d;
        std::size_t from = kNone;
        Intervals want;
        for (int side = 0; side < 2; ++side) {
          const std::size_t m = nb[i][2 * e + static_cast<std::size_t>(side)];
          if (!surface[m]) continue;
          // N's face toward cell i, in the coordinates (a, d): d is the second.
          const Intervals got = intervals(face_tiling(out[m], e, 1 - side), 1);
          if (from == kNone) {
            from = m, want = got;
          } else if (!same_intervals(got, want)) {
            return false;
          }
        }
        if (from == kNone) continue;
        cuts[d].assign(want.ends.begin() + 1, want.ends.end() - 1);
        counts[d] = 0;
        for (const int n : want.n) counts[d] += n;
      }
      out[i] = cube_blocks({0, 0, 0, 0, 0, 0}, counts, 0, cuts);
    }
    return true;
  };
  if (per_cell() && nonconforming(out).empty()) return out;

  // Rule 2 (one sheet): every slab of the profile has the thickness p = layers h, h = 1 / (elements
  // + 2 layers), and the cube's spacing along b and c is h everywhere (elements + (2 - surface
  // faces along d) layers elements along d), so a slab has `layers` elements across and the part
  // between two slab ends `elements`. Along d, cell i has a line at p (x_d = 1 - p) if its face
  // (d, 0) (resp. (d, 1)) is on the surface (the slab's inner face) or a concave edge of the
  // section runs along that side (the p x p column where the slabs of the two neighbours meet);
  // since a cut crosses the whole cell, the lines along d are shared by the cells in a row along
  // the other cross axis. A line where the cell's face is not on the surface is a cut (absolute
  // position, converted to the core's parameter).
  const double h = 1.0 / (elements + 2 * layers), p = layers * h;
  std::vector<std::array<std::array<bool, 2>, 3>> line(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t d = 1; d < 3; ++d)
      for (std::size_t s = 0; s < 2; ++s) line[i][d][s] = boundary[i][2 * d + s];
    for (int s = 0; s < 2; ++s)
      for (int t = 0; t < 2; ++t)
        if (nb[i][2 + static_cast<std::size_t>(s)] != kNone && nb[i][4 + static_cast<std::size_t>(t)] != kNone &&
            cell_at(i, s ? 1 : -1, t ? 1 : -1) == kNone)
          line[i][1][static_cast<std::size_t>(s)] = line[i][2][static_cast<std::size_t>(t)] = true;
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t d = 1; d < 3; ++d)
        for (std::size_t side = 0; side < 2; ++side) {
          const std::size_t m = nb[i][2 * (3 - d) + side];
          if (m == kNone) continue;
          for (std::size_t s = 0; s < 2; ++s)
            if (line[i][d][s] != line[m][d][s]) line[i][d][s] = line[m][d][s] = true, changed = true;
        }
  }
  for (std::size_t i = 0; i < count; ++i) {
    std::array<int, 3> n{elements, elements, elements};
    std::array<std::vector<double>, 3> cuts;
    for (std::size_t d = 1; d < 3; ++d) {
      const int sides = boundary[i][2 * d] + boundary[i][2 * d + 1];
      n[d] = elements + (2 - sides) * layers;
      const double lo = boundary[i][2 * d] ? p : 0, hi = boundary[i][2 * d + 1] ? 1 - p : 1;
      for (std::size_t s = 0; s < 2; ++s)
        if (line[i][d][s] && !boundary[i][2 * d + s]) cuts[d].push_back(((s ? 1 - p : p) - lo) / (hi - lo));
    }
    out[i] = cube_blocks(boundary[i], n, layers, cuts);
  }
  const std::string why = nonconforming(out);
  if (!why.empty()) throw core::TopologyError(why);
  return out;
}

}  // namespace volts::tmesh
