// profile_blocks: a ring of cubes whose cross section is a union of grid cells (a washer with a
// plus-shaped section). Cells with a surface face are pillowed cubes, a cell without one is cut
// where its neighbours' slabs end so the pillow wraps around the section's concave edges (Liu et
// al. §5.2, Fig. 9); profiles whose surface cells would need cuts (an L, T, U) get one sheet of
// uniform thickness instead (pillow.h, rule 2); every face two cells share, and each cell's faces a = 0 and a = 1 (glued
// around the ring), carry the same block faces with the same element counts on both sides.
// Conformity is checked here independently of the function's own check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/errors.h"
#include "tmesh/pillow.h"

using namespace volts;
using tmesh::Block;
using tmesh::Vec3;
using Cell = std::array<int, 2>;

namespace {

// The plus: the centre (no surface face) first, then the four arms.
const std::vector<Cell> kPlus = {{1, 1}, {0, 1}, {2, 1}, {1, 0}, {1, 2}};

long long key(double x) { return std::llround(x * 1e9); }

// A block face on the cube face x_axis = side as a quad in the face's two coordinates (the other
// axes, increasing): its corners (corner k: bit 0 along the first block direction, bit 1 along
// the second; 1e-9 units), then the block's element counts along them. Sorted, so two tilings
// compare with ==. Faces between cells are axis-aligned rectangles (`rectangles`); the faces
// a = 0 and a = 1 of a pillowed cube have the slabs' trapezoids.
using Quad = std::array<long long, 10>;
std::vector<Quad> face_quads(const std::vector<Block>& blocks, std::size_t axis, int side, bool rectangles) {
  const std::size_t u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
  std::vector<Quad> out;
  for (const Block& b : blocks)
    for (std::size_t s = 0; s < 2; ++s) {
      std::array<Vec3, 4> x;
      for (std::size_t k = 0; k < 4; ++k) x[k] = b.corners[(s << axis) | ((k & 1) << u) | ((k >> 1) << v)];
      if (!std::all_of(x.begin(), x.end(), [&](const Vec3& p) { return std::abs(p[axis] - side) < 1e-12; })) continue;
      if (rectangles) {  // corner k is (lo or hi by bit 0, lo or hi by bit 1)
        EXPECT_EQ(key(x[0][u]), key(x[2][u]));
        EXPECT_EQ(key(x[1][u]), key(x[3][u]));
        EXPECT_EQ(key(x[0][v]), key(x[1][v]));
        EXPECT_EQ(key(x[2][v]), key(x[3][v]));
      }
      Quad q;
      for (std::size_t k = 0; k < 4; ++k) q[2 * k] = key(x[k][u]), q[2 * k + 1] = key(x[k][v]);
      q[8] = b.elements[u], q[9] = b.elements[v];
      out.push_back(q);
    }
  std::sort(out.begin(), out.end());
  return out;
}

// Total area of the quads (shoelace over corners 0, 1, 3, 2).
double area(const std::vector<Quad>& quads) {
  double a = 0;
  for (const Quad& q : quads) {
    const std::array<std::size_t, 4> ring = {0, 1, 3, 2};
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t k = ring[i], l = ring[(i + 1) % 4];
      a += 0.5 * (q[2 * k] * 1e-9 * q[2 * l + 1] * 1e-9 - q[2 * l] * 1e-9 * q[2 * k + 1] * 1e-9);
    }
  }
  return a;
}

// Every pair of cells sharing a b or c face tiles it identically, and each cell's a = 0 face is
// tiled like its a = 1 face; every such face is covered. Returns the number of shared faces.
int expect_conforming(const std::vector<Cell>& cells, const std::vector<std::vector<Block>>& blocks) {
  EXPECT_EQ(blocks.size(), cells.size());
  int shared = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const auto a0 = face_quads(blocks[i], 0, 0, false), a1 = face_quads(blocks[i], 0, 1, false);
    EXPECT_EQ(a0, a1) << "cell " << cells[i][0] << "," << cells[i][1] << ": faces a = 0 and a = 1";
    EXPECT_NEAR(area(a0), 1.0, 1e-9);
    for (std::size_t m = 0; m < cells.size(); ++m)
      for (std::size_t axis = 1; axis < 3; ++axis) {
        Cell next = cells[i];
        ++next[axis - 1];
        if (cells[m] != next) continue;
        ++shared;
        const auto mine = face_quads(blocks[i], axis, 1, true), theirs = face_quads(blocks[m], axis, 0, true);
        EXPECT_EQ(mine, theirs) << "cells " << cells[i][0] << "," << cells[i][1] << " and " << cells[m][0] << "," << cells[m][1];
        EXPECT_NEAR(area(mine), 1.0, 1e-9);
      }
  }
  return shared;
}

void expect_same_blocks(const std::vector<Block>& got, const std::vector<Block>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].corners, want[i].corners) << "block " << i;
    EXPECT_EQ(got[i].elements, want[i].elements) << "block " << i;
    EXPECT_EQ(got[i].boundary, want[i].boundary) << "block " << i;
    EXPECT_EQ(got[i].pillow, want[i].pillow) << "block " << i;
  }
}

struct Box {
  Vec3 lo, hi;
};

// The block as an axis-aligned box (expects its corners to be one).
Box as_box(const Block& b) {
  Box x{b.corners[0], b.corners[7]};
  for (std::size_t c = 0; c < 8; ++c)
    for (std::size_t d = 0; d < 3; ++d) EXPECT_EQ(b.corners[c][d], (c >> d) & 1 ? x.hi[d] : x.lo[d]) << "not an axis-aligned box";
  return x;
}

// The distinct intervals blocks cover along axis d with their element counts, in order.
std::vector<std::pair<std::pair<double, double>, int>> intervals(const std::vector<Block>& blocks, std::size_t d) {
  std::map<std::pair<long long, long long>, std::pair<std::pair<double, double>, int>> at;
  for (const Block& b : blocks) {
    const double lo = std::min(b.corners[0][d], b.corners[7][d]), hi = std::max(b.corners[0][d], b.corners[7][d]);
    const auto [it, fresh] = at.emplace(std::pair{key(lo), key(hi)}, std::pair{std::pair{lo, hi}, b.elements[d]});
    EXPECT_TRUE(fresh || it->second.second == b.elements[d]) << "one interval, two element counts";
  }
  std::vector<std::pair<std::pair<double, double>, int>> out;
  for (const auto& [k, x] : at) out.push_back(x);
  return out;
}

// The trilinear Jacobian determinant of a block at its parameters x.
double jacobian(const Block& b, const Vec3& x) {
  std::array<Vec3, 3> col{};
  for (std::size_t c = 0; c < 8; ++c)
    for (std::size_t d = 0; d < 3; ++d) {
      double w = 1;
      for (std::size_t e = 0; e < 3; ++e) {
        const bool hi = (c >> e) & 1;
        w *= e == d ? (hi ? 1.0 : -1.0) : (hi ? x[e] : 1 - x[e]);
      }
      for (std::size_t k = 0; k < 3; ++k) col[d][k] += w * b.corners[c][k];
    }
  return col[0][0] * (col[1][1] * col[2][2] - col[1][2] * col[2][1]) - col[0][1] * (col[1][0] * col[2][2] - col[1][2] * col[2][0]) +
         col[0][2] * (col[1][0] * col[2][1] - col[1][1] * col[2][0]);
}

// The block's volume (2-point Gauss per direction, exact for a trilinear map's Jacobian).
double volume(const Block& b) {
  const double g = 0.5 / std::sqrt(3.0);
  double v = 0;
  for (int c = 0; c < 8; ++c) v += jacobian(b, {c & 1 ? 0.5 + g : 0.5 - g, c & 2 ? 0.5 + g : 0.5 - g, c & 4 ? 0.5 + g : 0.5 - g}) / 8;
  return v;
}

// Whether x lies strictly inside the block (Newton on the trilinear map from the block's centre).
bool contains(const Block& b, const Vec3& x) {
  Vec3 u{0.5, 0.5, 0.5};
  for (int it = 0; it < 40; ++it) {
    const Vec3 y = tmesh::block_point(b.corners, u);
    // Columns of the Jacobian by differences of the trilinear map (exact: it is linear along each direction).
    std::array<Vec3, 3> col;
    for (std::size_t d = 0; d < 3; ++d) {
      Vec3 lo = u, hi = u;
      lo[d] = 0, hi[d] = 1;
      const Vec3 a = tmesh::block_point(b.corners, lo), z = tmesh::block_point(b.corners, hi);
      for (std::size_t k = 0; k < 3; ++k) col[d][k] = z[k] - a[k];
    }
    const Vec3 r{x[0] - y[0], x[1] - y[1], x[2] - y[2]};
    auto det = [](const Vec3& p, const Vec3& q, const Vec3& w) {
      return p[0] * (q[1] * w[2] - q[2] * w[1]) - p[1] * (q[0] * w[2] - q[2] * w[0]) + p[2] * (q[0] * w[1] - q[1] * w[0]);
    };
    const double D = det(col[0], col[1], col[2]);
    if (!(std::abs(D) > 1e-300)) return false;
    u[0] += det(r, col[1], col[2]) / D, u[1] += det(col[0], r, col[2]) / D, u[2] += det(col[0], col[1], r) / D;
    if (!(std::abs(u[0]) < 10 && std::abs(u[1]) < 10 && std::abs(u[2]) < 10)) return false;
  }
  const Vec3 y = tmesh::block_point(b.corners, u);
  if (std::abs(y[0] - x[0]) + std::abs(y[1] - x[1]) + std::abs(y[2] - x[2]) > 1e-12) return false;
  return u[0] > 1e-9 && u[0] < 1 - 1e-9 && u[1] > 1e-9 && u[1] < 1 - 1e-9 && u[2] > 1e-9 && u[2] < 1 - 1e-9;
}

// A block face (axis, side) as its four corners (in the block's corner order), keyed, without
// their coordinate along `axis` (the face's, 0 or 1 in the cube, which the neighbour across sees
// as 1 or 0).
std::array<long long, 12> face_key(const Block& b, std::size_t axis, std::size_t side) {
  std::array<long long, 12> k{};
  std::size_t n = 0;
  for (std::size_t c = 0; c < 8; ++c)
    if (((c >> axis) & 1) == side)
      for (std::size_t d = 0; d < 3; ++d) k[n++] = d == axis ? 0 : key(b.corners[c][d]);
  return k;
}

// The concave corners of a profile: (cell, side along b, side along c) whose two neighbours
// across those faces are cells and the cell diagonally across is not.
std::vector<std::array<std::size_t, 3>> concave_corners(const std::vector<Cell>& cells) {
  const std::set<Cell> in(cells.begin(), cells.end());
  std::vector<std::array<std::size_t, 3>> out;
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (std::size_t s = 0; s < 2; ++s)
      for (std::size_t t = 0; t < 2; ++t) {
        const int db = s ? 1 : -1, dc = t ? 1 : -1;
        const Cell x = cells[i];
        if (in.count({x[0] + db, x[1]}) && in.count({x[0], x[1] + dc}) && !in.count({x[0] + db, x[1] + dc})) out.push_back({i, s, t});
      }
  return out;
}

// Everything a profile's blocks must be, checked independently of profile_blocks: shared faces
// conform (expect_conforming), every block is positively oriented (Jacobian > 0 at its corners)
// with `e` elements along a, each cell's blocks tile its cube (volumes sum to 1, every sample point
// in exactly one block), block faces on a surface face of the cell are flagged (pillow slabs with
// `layers` elements across when layers > 0) and cover it, no other face is flagged, and at every
// concave corner the pillow wraps: the cell has a p x p column (p = the slabs' thickness on the
// faces it shares) whose faces toward the two neighbours are whole faces of their surface slabs.
// uniform_p: also every slab of the profile has thickness layers / (e + 2 layers). Returns the
// number of shared faces.
int expect_valid_profile(const std::vector<Cell>& cells, const std::vector<std::vector<Block>>& blocks, int e, int layers, int samples,
                         bool uniform_p) {
  const int shared = expect_conforming(cells, blocks);
  const std::set<Cell> in(cells.begin(), cells.end());
  const double p = static_cast<double>(layers) / (e + 2 * layers);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    SCOPED_TRACE("cell " + std::to_string(cells[i][0]) + "," + std::to_string(cells[i][1]));
    std::array<bool, 6> surface{};
    for (std::size_t f = 2; f < 6; ++f) {
      Cell x = cells[i];
      x[f / 2 - 1] += f % 2 ? 1 : -1;
      surface[f] = !in.count(x);
    }
    double vol = 0;
    for (std::size_t k = 0; k < blocks[i].size(); ++k) {
      const Block& b = blocks[i][k];
      SCOPED_TRACE("block " + std::to_string(k));
      EXPECT_EQ(b.elements[0], e);
      for (int c = 0; c < 8; ++c) EXPECT_GT(jacobian(b, {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}), 1e-9) << "corner " << c;
      vol += volume(b);
      for (std::size_t ax = 0; ax < 3; ++ax)
        for (std::size_t side = 0; side < 2; ++side) {
          // The cube face the block face lies on, if any.
          int on = -1;
          for (std::size_t A = 0; A < 3; ++A)
            for (std::size_t S = 0; S < 2; ++S) {
              bool all = true;
              for (std::size_t c = 0; c < 8; ++c)
                if (((c >> ax) & 1) == side) all = all && std::abs(b.corners[c][A] - double(S)) < 1e-12;
              if (all) on = static_cast<int>(2 * A + S);
            }
          const bool flagged = b.boundary[2 * ax + side] != 0;
          if (on >= 0 && surface[static_cast<std::size_t>(on)]) {
            EXPECT_TRUE(flagged) << "face " << ax << "," << side << " on the surface unflagged";
            EXPECT_EQ(static_cast<int>(2 * ax + side), on);
            if (layers > 0) {
              EXPECT_TRUE(b.pillow);
              EXPECT_EQ(b.elements[ax], layers);
              if (uniform_p)
                for (std::size_t c = 0; c < 8; ++c)
                  if (((c >> ax) & 1) != side) {
                    EXPECT_NEAR(b.corners[c][ax], side ? 1 - p : p, 1e-12) << "slab thickness";
                  }
            }
          } else {
            EXPECT_FALSE(flagged) << "interior face " << ax << "," << side << " flagged";
          }
        }
    }
    EXPECT_NEAR(vol, 1.0, 1e-12);
    for (std::size_t f = 2; f < 6; ++f)
      if (surface[f]) {
        EXPECT_NEAR(area(face_quads(blocks[i], f / 2, f % 2, false)), 1.0, 1e-9) << "surface face " << f;
      }
    for (int x = 0; x < samples; ++x)
      for (int y = 0; y < samples; ++y)
        for (int z = 0; z < samples; ++z) {
          const Vec3 q{(x + 0.5) / samples, (y + 0.37) / samples, (z + 0.61) / samples};
          int inside = 0;
          for (const Block& b : blocks[i]) inside += contains(b, q);
          EXPECT_EQ(inside, 1) << q[0] << " " << q[1] << " " << q[2];
        }
  }
  for (const auto& [i, s, t] : concave_corners(cells)) {
    SCOPED_TRACE("concave corner of cell " + std::to_string(cells[i][0]) + "," + std::to_string(cells[i][1]) + " at b side " +
                 std::to_string(s) + ", c side " + std::to_string(t));
    Block col;
    for (std::size_t c = 0; c < 8; ++c) {
      col.corners[c][0] = double(c & 1);
      col.corners[c][1] = ((c >> 1) & 1) == s ? double(s) : (s ? 1 - p : p);
      col.corners[c][2] = ((c >> 2) & 1) == t ? double(t) : (t ? 1 - p : p);
    }
    const Block* column = nullptr;
    for (const Block& b : blocks[i])
      if (face_key(b, 0, 0) == face_key(col, 0, 0) && face_key(b, 0, 1) == face_key(col, 0, 1)) column = &b;
    EXPECT_NE(column, nullptr) << "no p x p column";
    if (!column) continue;
    EXPECT_EQ(column->elements, (std::array<int, 3>{e, layers, layers}));
    EXPECT_FALSE(column->pillow) << "a core piece of the cell, continuing the neighbours' slabs";
    // Its face toward each neighbour is the whole face of that neighbour's slab under the surface
    // face on the column's other side.
    for (std::size_t d = 1; d < 3; ++d) {
      const std::size_t side = d == 1 ? s : t, other = d == 1 ? t : s;
      Cell n = cells[i];
      n[d - 1] += side ? 1 : -1;
      const std::size_t j = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), n) - cells.begin());
      EXPECT_LT(j, cells.size());
      if (j >= cells.size()) continue;
      int found = 0;
      for (const Block& b : blocks[j])
        if (face_key(b, d, 1 - side) == face_key(*column, d, side) && key(b.corners[side ? 0 : 7][d]) == key(side ? 0.0 : 1.0)) {
          ++found;
          EXPECT_TRUE(b.pillow);
          EXPECT_EQ(b.boundary[2 * (3 - d) + other], 1) << "the neighbour's slab under its surface face";
          EXPECT_EQ(b.elements[3 - d], layers);
        }
      EXPECT_EQ(found, 1) << "neighbour across axis " << d;
    }
  }
  return shared;
}

}  // namespace

TEST(ProfileBlocks, PlusCentreIsCutWhereTheArmsSlabsEndAndEverySharedFaceConforms) {
  const int e = 8, layers = 1;
  std::vector<std::vector<Block>> blocks;
  ASSERT_NO_THROW(blocks = tmesh::profile_blocks(kPlus, e, layers));
  ASSERT_EQ(blocks.size(), kPlus.size());

  // The arms: their three surface faces pillowed, the face toward the centre not.
  const std::array<std::array<int, 6>, 4> arm_boundary = {{{0, 0, 1, 0, 1, 1}, {0, 0, 0, 1, 1, 1}, {0, 0, 1, 1, 1, 0}, {0, 0, 1, 1, 0, 1}}};
  for (std::size_t i = 1; i < kPlus.size(); ++i) {
    SCOPED_TRACE("arm " + std::to_string(i));
    expect_same_blocks(blocks[i], tmesh::cube_blocks(arm_boundary[i - 1], {e, e, e}, layers));
    EXPECT_EQ(blocks[i].size(), 4u) << "core and three slabs";
  }

  // The arms' slab thickness across the centre's faces, read from the arm (1,0)'s core: the slabs
  // under its b faces end at the core's b extent.
  const auto& arm = blocks[3];
  ASSERT_FALSE(arm[0].pillow);
  const double p = arm[0].corners[0][1], q = arm[0].corners[7][1];
  EXPECT_NEAR(p, 1.0 / (e + 2 * layers), 1e-15);
  EXPECT_NEAR(q, 1 - 1.0 / (e + 2 * layers), 1e-15);
  EXPECT_NEAR(arm[0].corners[0][2], 1.0 / (e + layers), 1e-15) << "its one slab along c is thicker (not on a face it shares)";

  // The centre: 3 x 3 columns, no pillow of its own, cut at p and q along b and c.
  const auto& centre = blocks[0];
  ASSERT_EQ(centre.size(), 9u);
  for (const Block& b : centre) {
    EXPECT_FALSE(b.pillow);
    EXPECT_EQ(b.boundary, (std::array<int, 6>{0, 0, 0, 0, 0, 0}));
    EXPECT_EQ(b.elements[0], e);
  }
  for (std::size_t d = 1; d < 3; ++d) {
    const auto iv = intervals(centre, d);
    ASSERT_EQ(iv.size(), 3u) << "axis " << d;
    EXPECT_EQ(iv[0].first.first, 0.0);
    EXPECT_EQ(iv[0].first.second, p) << "cut at the arms' slab thickness";
    EXPECT_EQ(iv[1].first.second, q);
    EXPECT_EQ(iv[2].first.second, 1.0);
    EXPECT_EQ(iv[0].second, 1);
    EXPECT_EQ(iv[1].second, 8);
    EXPECT_EQ(iv[2].second, 1);
  }
  // The pillow wraps around each concave edge: the corner column b, c in [0, p] is one element by
  // one, the continuation of the slabs of arms (0,1) and (1,0).
  int corner_columns = 0;
  for (const Block& b : centre)
    if (b.elements[1] == 1 && b.elements[2] == 1) ++corner_columns;
  EXPECT_EQ(corner_columns, 4);

  // The centre's blocks tile [0,1]^3: axis-aligned boxes, volumes summing to 1, no overlaps, and
  // every sample point (none on a cut) in exactly one box.
  std::vector<Box> boxes;
  double volume = 0;
  for (const Block& b : centre) {
    boxes.push_back(as_box(b));
    const Box& x = boxes.back();
    volume += (x.hi[0] - x.lo[0]) * (x.hi[1] - x.lo[1]) * (x.hi[2] - x.lo[2]);
  }
  EXPECT_NEAR(volume, 1.0, 1e-12);
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      double overlap = 1;
      for (std::size_t d = 0; d < 3; ++d) overlap *= std::max(0.0, std::min(boxes[i].hi[d], boxes[j].hi[d]) - std::max(boxes[i].lo[d], boxes[j].lo[d]));
      EXPECT_EQ(overlap, 0.0) << "blocks " << i << " and " << j << " overlap";
    }
  for (int i = 0; i < 13; ++i)
    for (int j = 0; j < 13; ++j)
      for (int k = 0; k < 13; ++k) {
        const Vec3 x{(i + 0.5) / 13, (j + 0.37) / 13, (k + 0.61) / 13};
        int inside = 0;
        for (const Box& b : boxes)
          inside += x[0] > b.lo[0] && x[0] < b.hi[0] && x[1] > b.lo[1] && x[1] < b.hi[1] && x[2] > b.lo[2] && x[2] < b.hi[2];
        EXPECT_EQ(inside, 1) << x[0] << " " << x[1] << " " << x[2];
      }

  // Every shared face (the four arms against the centre) tiles identically, checked here by rectangles.
  EXPECT_EQ(expect_conforming(kPlus, blocks), 4);
  // Concretely: the centre's face b = 0 against arm (0,1)'s face b = 1: three rectangles along c.
  const auto face = face_quads(centre, 1, 0, true);
  ASSERT_EQ(face.size(), 3u);
  EXPECT_EQ(face, face_quads(blocks[1], 1, 1, true));
  EXPECT_EQ(face[0][5], key(p));
  EXPECT_EQ(face[1][5], key(q));
  EXPECT_EQ(face[0][9], 1);
  EXPECT_EQ(face[1][9], 8);
  EXPECT_EQ(face[2][9], 1);
}

TEST(ProfileBlocks, OneCellIsTheTorusCube) {
  for (int layers = 0; layers <= 2; ++layers) {
    SCOPED_TRACE("layers " + std::to_string(layers));
    const auto blocks = tmesh::profile_blocks({{0, 0}}, 6, layers);
    ASSERT_EQ(blocks.size(), 1u);
    expect_same_blocks(blocks[0], tmesh::cube_blocks({0, 0, 1, 1, 1, 1}, {6, 6, 6}, layers));
    EXPECT_EQ(blocks[0].size(), layers ? 5u : 1u);
  }
}

TEST(ProfileBlocks, LShapeIsOnePillowSheetAndConformsWithoutLayersToo) {
  const std::vector<Cell> ell = {{0, 0}, {1, 0}, {0, 1}};
  // With layers: the corner cell (0,0) has surface faces and needs cuts (its neighbours' slabs
  // end on its faces), so the whole profile takes the one-sheet rule (see LTAndUShapes... below).
  for (int layers = 1; layers <= 2; ++layers) {
    SCOPED_TRACE("layers " + std::to_string(layers));
    std::vector<std::vector<Block>> blocks;
    ASSERT_NO_THROW(blocks = tmesh::profile_blocks(ell, 8, layers));
    EXPECT_EQ(expect_conforming(ell, blocks), 2);
  }
  std::vector<std::vector<Block>> blocks;
  ASSERT_NO_THROW(blocks = tmesh::profile_blocks(ell, 8, 0));
  EXPECT_EQ(expect_conforming(ell, blocks), 2);
  expect_same_blocks(blocks[0], tmesh::cube_blocks({0, 0, 1, 0, 1, 0}, {8, 8, 8}, 0));
  expect_same_blocks(blocks[1], tmesh::cube_blocks({0, 0, 0, 1, 1, 1}, {8, 8, 8}, 0));
  expect_same_blocks(blocks[2], tmesh::cube_blocks({0, 0, 1, 1, 0, 1}, {8, 8, 8}, 0));
  for (const auto& cell : blocks) EXPECT_EQ(cell.size(), 1u);
}

TEST(ProfileBlocks, ThreeInARowConformsWithMatchingSlabsAlongC) {
  const std::vector<Cell> row = {{0, 0}, {1, 0}, {2, 0}};
  const int e = 6, layers = 2;
  const auto blocks = tmesh::profile_blocks(row, e, layers);
  ASSERT_EQ(blocks.size(), 3u);
  // The middle cell is a surface cell (its c faces), the ends have three surface faces.
  expect_same_blocks(blocks[1], tmesh::cube_blocks({0, 0, 0, 0, 1, 1}, {e, e, e}, layers));
  expect_same_blocks(blocks[0], tmesh::cube_blocks({0, 0, 1, 0, 1, 1}, {e, e, e}, layers));
  expect_same_blocks(blocks[2], tmesh::cube_blocks({0, 0, 0, 1, 1, 1}, {e, e, e}, layers));
  EXPECT_EQ(expect_conforming(row, blocks), 2);
  // On the face between (0,0) and (1,0), along c: slabs of 2 elements and thickness 2/(6+4) at
  // both ends, the core's 6 between (rectangles sorted by a, then c).
  const auto face = face_quads(blocks[1], 1, 0, true);
  ASSERT_EQ(face.size(), 3u);
  EXPECT_EQ(face[0][1], 0);
  EXPECT_EQ(face[0][5], key(0.2));
  EXPECT_EQ(face[1][5], key(0.8));
  EXPECT_EQ(face[2][5], key(1.0));
  EXPECT_EQ(face[0][9], layers);
  EXPECT_EQ(face[1][9], e);
  EXPECT_EQ(face[2][9], layers);
  for (const Quad& r : face) EXPECT_EQ(r[8], e) << "along a";
}

TEST(ProfileBlocks, OtherProfilesConform) {
  // A 3 x 3 square (the centre needs no cuts) and a plus with two-cell vertical arms and a double
  // centre (each centre cell is cut along b by the arm beyond it, along c by the side arms) conform.
  const std::vector<std::vector<Cell>> good = {
      {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {0, 2}, {1, 2}, {2, 2}},
      {{1, 0}, {1, 1}, {1, 2}, {1, 3}, {0, 1}, {2, 1}, {0, 2}, {2, 2}},
  };
  const std::array<int, 2> shared = {12, 9};
  for (std::size_t g = 0; g < good.size(); ++g)
    for (int layers = 0; layers <= 2; ++layers) {
      SCOPED_TRACE("profile " + std::to_string(g) + ", layers " + std::to_string(layers));
      std::vector<std::vector<Block>> blocks;
      ASSERT_NO_THROW(blocks = tmesh::profile_blocks(good[g], 5, layers));
      EXPECT_EQ(expect_conforming(good[g], blocks), shared[g]);
    }
  EXPECT_EQ(tmesh::profile_blocks(good[0], 5, 1)[4].size(), 1u) << "the square's centre is one uncut block";
  EXPECT_EQ(tmesh::profile_blocks(good[1], 5, 1)[1].size(), 6u) << "cut at two places along b, one along c";
  // A centre whose arm (1,0) has slabs along b on its face and whose other side (1,2) has none:
  // the per-cell rule cannot cut the centre to match both, the one-sheet rule takes it (the
  // centre's cuts along b at the concave edges run on through (1,2)).
  const std::vector<Cell> mismatched = {{1, 0}, {0, 1}, {1, 1}, {2, 1}, {0, 2}, {1, 2}, {2, 2}};
  for (int layers = 0; layers <= 2; ++layers) {
    SCOPED_TRACE("mismatched centre, layers " + std::to_string(layers));
    std::vector<std::vector<Block>> blocks;
    ASSERT_NO_THROW(blocks = tmesh::profile_blocks(mismatched, 8, layers));
    EXPECT_EQ(expect_conforming(mismatched, blocks), 8);
  }
}

TEST(ProfileBlocks, BadInputIsRefused) {
  EXPECT_THROW(tmesh::profile_blocks({}, 8, 1), core::InvalidInputError);
  EXPECT_THROW(tmesh::profile_blocks({{0, 0}, {1, 0}, {0, 0}}, 8, 1), core::InvalidInputError);
  EXPECT_THROW(tmesh::profile_blocks({{0, 0}, {2, 0}}, 8, 1), core::InvalidInputError);
  EXPECT_THROW(tmesh::profile_blocks({{0, 0}, {1, 1}}, 8, 0), core::InvalidInputError) << "a corner is not an edge";
  EXPECT_THROW(tmesh::profile_blocks(kPlus, 0, 1), core::ConfigError);
  EXPECT_THROW(tmesh::profile_blocks(kPlus, 8, -1), core::ConfigError);
  try {
    tmesh::profile_blocks({{0, 0}, {1, 0}, {5, 5}}, 8, 1);
    ADD_FAILURE() << "no InvalidInputError";
  } catch (const core::InvalidInputError& err) {
    EXPECT_NE(std::string(err.what()).find("(5,5)"), std::string::npos) << err.what();
  }
}

TEST(ProfileBlocks, LTAndUShapesArePillowedAsOneSheetThatWrapsTheirConcaveEdges) {
  // Their cells with surface faces need cuts (the corner cell of the L, the stem's foot of the T,
  // the U's bottom corners): one sheet of uniform thickness p = layers / (e + 2 layers) under the
  // whole surface, a p x p column at every concave edge.
  struct Shape {
    std::string name;
    std::vector<Cell> cells;
    int shared, concave;
  };
  const std::vector<Shape> shapes = {
      {"L", {{0, 0}, {1, 0}, {0, 1}}, 2, 1},
      {"T", {{0, 0}, {1, 0}, {2, 0}, {1, 1}}, 3, 2},
      {"U", {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {2, 1}}, 4, 2},
  };
  for (const Shape& shape : shapes)
    for (const int e : {8, 4})
      for (int layers = 1; layers <= 2; ++layers) {
        SCOPED_TRACE(shape.name + ", elements " + std::to_string(e) + ", layers " + std::to_string(layers));
        EXPECT_EQ(static_cast<int>(concave_corners(shape.cells).size()), shape.concave);
        std::vector<std::vector<Block>> blocks;
        ASSERT_NO_THROW(blocks = tmesh::profile_blocks(shape.cells, e, layers));
        ASSERT_EQ(blocks.size(), shape.cells.size());
        EXPECT_EQ(expect_valid_profile(shape.cells, blocks, e, layers, 7, true), shape.shared);
      }
  // The L concretely: the corner cell (0,0) is its pillowed cube (slabs under b = 0 and c = 0)
  // with its core cut at 1 - p along b and c; (1,0)'s c = 1 slab and (0,1)'s b = 1 slab meet its
  // column [1 - p, 1]^2 (checked above), and its face toward (1,0) carries c-intervals [0, p],
  // [p, 1 - p], [1 - p, 1] with 1, 8, 1 elements.
  const std::vector<Cell> ell = shapes[0].cells;
  const auto blocks = tmesh::profile_blocks(ell, 8, 1);
  const double p = 0.1;
  const auto face = face_quads(blocks[0], 1, 1, true);
  ASSERT_EQ(face.size(), 3u);
  EXPECT_EQ(face[0][5], key(p));
  EXPECT_EQ(face[1][5], key(1 - p));
  EXPECT_EQ(face[2][5], key(1.0));
  EXPECT_EQ(face[0][9], 1);
  EXPECT_EQ(face[1][9], 8);
  EXPECT_EQ(face[2][9], 1);
  EXPECT_EQ(face, face_quads(blocks[1], 1, 0, true));
  // Pillowed cube (two slabs, each cut once) + core cut into 2 x 2.
  EXPECT_EQ(blocks[0].size(), 8u);
  EXPECT_EQ(std::count_if(blocks[0].begin(), blocks[0].end(), [](const Block& b) { return b.pillow; }), 4);
}

TEST(ProfileBlocks, EveryConnectedProfileInAThreeByThreeGridIsPillowedConformingly) {
  // No profile remains impossible: every edge-connected set of cells of a 3 x 3 grid (bars, Ls,
  // Ts, Us, Zs, the ring around an empty centre, cells touching only at a corner through others)
  // gives valid, conforming blocks with 1 and 2 layers; the profiles the per-cell rule takes keep
  // its blocks (the tests above), the others get the one sheet.
  int profiles = 0;
  for (int mask = 1; mask < 512; ++mask) {
    std::vector<Cell> cells;
    for (int k = 0; k < 9; ++k)
      if (mask >> k & 1) cells.push_back({k % 3, k / 3});
    std::set<Cell> seen{cells[0]};
    std::vector<Cell> stack{cells[0]};
    const std::set<Cell> in(cells.begin(), cells.end());
    while (!stack.empty()) {
      const Cell c = stack.back();
      stack.pop_back();
      for (const Cell& n : {Cell{c[0] + 1, c[1]}, Cell{c[0] - 1, c[1]}, Cell{c[0], c[1] + 1}, Cell{c[0], c[1] - 1}})
        if (in.count(n) && seen.insert(n).second) stack.push_back(n);
    }
    if (seen.size() != cells.size()) continue;
    ++profiles;
    for (int layers = 1; layers <= 2; ++layers) {
      SCOPED_TRACE("mask " + std::to_string(mask) + ", layers " + std::to_string(layers));
      std::vector<std::vector<Block>> blocks;
      ASSERT_NO_THROW(blocks = tmesh::profile_blocks(cells, 4, layers));
      expect_valid_profile(cells, blocks, 4, layers, 3, false);
    }
  }
  EXPECT_EQ(profiles, 218);
}
