#include "tmesh/pillow.h"

#include <algorithm>
#include <cmath>
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

std::vector<Block> cube_blocks(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers) {
  if (layers < 0) throw core::ConfigError("tmesh.pillow_layers must be >= 0, got " + std::to_string(layers));
  for (const int n : elements)
    if (n < 1) throw core::ConfigError("tmesh: a cube needs at least one element per direction");
  auto box = [](const Vec3& lo, const Vec3& hi) {
    std::array<Vec3, 8> c;
    for (int i = 0; i < 8; ++i)
      for (int d = 0; d < 3; ++d) c[i][d] = (i >> d) & 1 ? hi[d] : lo[d];
    return c;
  };
  if (layers == 0) {
    Block b;
    b.corners = box({0, 0, 0}, {1, 1, 1});
    b.elements = elements;
    b.boundary = boundary;
    return {b};
  }
  // Core extent: pulled in from every surface face by `layers` elements of the cube's spacing.
  Vec3 lo{0, 0, 0}, hi{1, 1, 1};
  for (int d = 0; d < 3; ++d) {
    const int sides = boundary[2 * d] + boundary[2 * d + 1];
    const double h = 1.0 / (elements[d] + sides * layers);
    if (boundary[2 * d]) lo[d] = layers * h;
    if (boundary[2 * d + 1]) hi[d] = 1 - layers * h;
  }
  std::vector<Block> blocks;
  Block core;
  core.corners = box(lo, hi);
  core.elements = elements;
  blocks.push_back(core);
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      if (!boundary[2 * a + s]) continue;
      Block slab;
      slab.pillow = true;
      slab.elements = elements;
      slab.elements[a] = layers;
      slab.boundary[2 * a + s] = 1;
      // Local axes are the cube's (orientation kept); along a, the side toward the face is the
      // cube face, the other the core face. The outer face spans the whole cube face, the inner
      // face the core's, so the slab's sides are diagonal where the next face is a surface face
      // too and flat (on the cube face) where it is not.
      for (int i = 0; i < 8; ++i) {
        const bool outer = ((i >> a) & 1) == s;
        Vec3 x;
        for (int d = 0; d < 3; ++d) {
          const int bit = (i >> d) & 1;
          if (d == a) x[d] = outer ? s : (s ? hi[d] : lo[d]);
          else x[d] = outer ? bit : (bit ? hi[d] : lo[d]);
        }
        slab.corners[i] = x;
      }
      blocks.push_back(slab);
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

std::vector<Block> difference_blocks(int axis, const Vec3& hole_lo, const Vec3& hole_hi, int elements, int layers) {
  if (layers < 0) throw core::ConfigError("tmesh.pillow_layers must be >= 0, got " + std::to_string(layers));
  if (elements < 1) throw core::ConfigError("tmesh: a cube needs at least one element per direction");
  if (axis < 0 || axis > 2) throw core::TopologyError("tmesh: the hole's axis must be 0, 1 or 2");
  // Local frame: x, y across the hole, z along it; cube axis of local d is (axis + 1 + d) % 3 (a
  // cyclic permutation keeps the orientation).
  auto cube_axis = [axis](int d) { return (axis + 1 + d) % 3; };
  std::array<double, 4> X{0, hole_lo[cube_axis(0)], hole_hi[cube_axis(0)], 1}, Y{0, hole_lo[cube_axis(1)], hole_hi[cube_axis(1)], 1};
  if (hole_lo[axis] != 0 || hole_hi[axis] != 1 || !(X[0] < X[1] && X[1] < X[2] && X[2] < X[3]) || !(Y[0] < Y[1] && Y[1] < Y[2] && Y[2] < Y[3]))
    throw core::TopologyError("tmesh: the hole is not a box through the cube along axis " + std::to_string(axis));
  const double h = 1.0 / (elements + 2 * layers), t = layers * h;
  // Core lines: the solid's faces moved inward by t (outer faces in, hole walls out).
  const std::array<double, 4> Xc{t, X[1] - t, X[2] + t, 1 - t}, Yc{t, Y[1] - t, Y[2] + t, 1 - t};
  for (int i = 0; i < 3; ++i)
    if (!(Xc[i] < Xc[i + 1]) || !(Yc[i] < Yc[i + 1]))
      throw core::TopologyError("tmesh: the hole lies too close to the cube's side for a pillow of " + std::to_string(layers) +
                                " layer(s) of 1/" + std::to_string(elements + 2 * layers) + " (lower tmesh.pillow_layers or raise tmesh.level)");
  const std::array<double, 4>& XL = layers ? Xc : X;  // lines the columns' element counts follow
  const std::array<double, 4>& YL = layers ? Yc : Y;
  std::array<int, 3> nx{}, ny{};
  for (int i = 0; i < 3; ++i) {
    nx[static_cast<std::size_t>(i)] = std::max(1, static_cast<int>(std::lround((XL[i + 1] - XL[i]) / h)));
    ny[static_cast<std::size_t>(i)] = std::max(1, static_cast<int>(std::lround((YL[i + 1] - YL[i]) / h)));
  }
  std::vector<Block> out;
  auto add = [&](const std::array<Vec3, 8>& local, std::array<int, 3> n, std::array<int, 6> boundary, bool pillow) {
    Block b;
    for (int i = 0; i < 8; ++i)
      for (int d = 0; d < 3; ++d) b.corners[static_cast<std::size_t>(i)][static_cast<std::size_t>(cube_axis(d))] = local[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)];
    b.elements = n;
    b.boundary = boundary;
    b.pillow = pillow;
    out.push_back(b);
  };
  const double z0 = layers ? t : 0, z1 = layers ? 1 - t : 1;
  // Columns (the core's, or the solid's without pillow).
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      const Face lo{z0, {XL[i], YL[j], 0}, {}}, hi{z1, {XL[i], YL[j], 0}, {}};
      Face l = lo, u = hi;
      l.hi = u.hi = {XL[i + 1], YL[j + 1], 0};
      std::array<int, 6> boundary{0, 0, 0, 0, 0, 0};
      if (!layers) boundary = {i == 0 || (i == 2 && j == 1), i == 2 || (i == 0 && j == 1), j == 0 || (j == 2 && i == 1), j == 2 || (j == 0 && i == 1), 1, 1};
      add(frustum(2, u, l, true), {nx[static_cast<std::size_t>(i)], ny[static_cast<std::size_t>(j)], elements}, boundary, false);
    }
  if (!layers) return out;
  // Under the cube's four sides: three frusta each, between the side and the core's side.
  for (int s = 0; s < 2; ++s)
    for (int k = 0; k < 3; ++k) {
      std::array<int, 6> bx{0, 0, 0, 0, 0, 0}, by{0, 0, 0, 0, 0, 0};
      bx[static_cast<std::size_t>(s)] = 1, by[static_cast<std::size_t>(2 + s)] = 1;
      add(frustum(0, {double(s), {0, Y[k], 0}, {0, Y[k + 1], 1}}, {Xc[s ? 3 : 0], {0, Yc[k], t}, {0, Yc[k + 1], 1 - t}}, s == 1),
          {layers, ny[static_cast<std::size_t>(k)], elements}, bx, true);
      add(frustum(1, {double(s), {X[k], 0, 0}, {X[k + 1], 0, 1}}, {Yc[s ? 3 : 0], {Xc[k], 0, t}, {Xc[k + 1], 0, 1 - t}}, s == 1),
          {nx[static_cast<std::size_t>(k)], layers, elements}, by, true);
    }
  // Under the two holed faces: eight frusta each, between the annulus and the core's.
  for (int s = 0; s < 2; ++s)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        if (i == 1 && j == 1) continue;
        std::array<int, 6> b{0, 0, 0, 0, 0, 0};
        b[static_cast<std::size_t>(4 + s)] = 1;
        add(frustum(2, {double(s), {X[i], Y[j], 0}, {X[i + 1], Y[j + 1], 0}}, {s ? 1 - t : t, {Xc[i], Yc[j], 0}, {Xc[i + 1], Yc[j + 1], 0}}, s == 1),
            {nx[static_cast<std::size_t>(i)], ny[static_cast<std::size_t>(j)], layers}, b, true);
      }
  // Under the hole's four walls (the circumferential pillow): the solid lies on the wall's far side
  // from the hole, so the wall at X[1] is the slab's high x face and the one at X[2] its low one.
  for (int s = 0; s < 2; ++s) {
    std::array<int, 6> bx{0, 0, 0, 0, 0, 0}, by{0, 0, 0, 0, 0, 0};
    bx[static_cast<std::size_t>(1 - s)] = 1, by[static_cast<std::size_t>(3 - s)] = 1;
    add(frustum(0, {X[1 + s], {0, Y[1], 0}, {0, Y[2], 1}}, {Xc[1 + s], {0, Yc[1], t}, {0, Yc[2], 1 - t}}, s == 0),
        {layers, ny[1], elements}, bx, true);
    add(frustum(1, {Y[1 + s], {X[1], 0, 0}, {X[2], 0, 1}}, {Yc[1 + s], {Xc[1], 0, t}, {Xc[2], 0, 1 - t}}, s == 0),
        {nx[1], layers, elements}, by, true);
  }
  return out;
}

}  // namespace volts::tmesh
