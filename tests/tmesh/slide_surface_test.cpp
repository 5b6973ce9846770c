// The surface the joint rounds slide nodes along: closest points with their triangle's normal, and
// the distance to the nearest sharp edge (a cube's 12 edges are sharp, its face diagonals are not).
#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.h"
#include "tmesh/slide_surface.h"

using namespace volts;
using tmesh::Vec3;

namespace {

tmesh::SlideSurface unit_cube() {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Two outward triangles per face.
  const std::vector<std::array<int, 3>> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return tmesh::SlideSurface(v, t);
}

}  // namespace

TEST(SlideSurface, ClosestPointsAndNormalsOfACube) {
  const tmesh::SlideSurface s = unit_cube();
  Vec3 n;
  const Vec3 c = s.closest({0.3, 0.6, 1.7}, &n);
  EXPECT_NEAR(c[0], 0.3, 1e-12);
  EXPECT_NEAR(c[1], 0.6, 1e-12);
  EXPECT_NEAR(c[2], 1.0, 1e-12);
  EXPECT_NEAR(std::abs(n[2]), 1.0, 1e-12);
  const Vec3 inside = s.closest({0.5, 0.5, 0.1});
  EXPECT_NEAR(inside[2], 0.0, 1e-12);
}

TEST(SlideSurface, OnlyTheCubesEdgesAreSharp) {
  const tmesh::SlideSurface s = unit_cube();
  EXPECT_EQ(s.sharp_edges(), 12);  // the 6 face diagonals are flat
  EXPECT_NEAR(s.sharp_distance({0.5, 0.5, 1.0}), 0.5, 1e-12);   // a face's centre: half a side from its edges
  EXPECT_NEAR(s.sharp_distance({0.3, 0.3, 1.0}), 0.3, 1e-12);   // on a diagonal, which does not count
  EXPECT_NEAR(s.sharp_distance({1.0, 0.4, 1.0}), 0.0, 1e-12);
}

TEST(SlideSurface, RefusesAnEmptyMeshAndIndicesOutOfRange) {
  EXPECT_THROW(tmesh::SlideSurface({}, {}), core::InvalidInputError);
  EXPECT_THROW(tmesh::SlideSurface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}}), core::InvalidInputError);
}
