// Shared by the polycube tests (header-only): locating parameter points in a volume map, and the
// checks that make a torus volume map one-to-one onto its round ring (Liu et al. §4.3).
#pragma once

#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <random>

#include "polycube/embedding.h"
#include "split/split.h"
#include "volmap/volmap.h"

namespace volts::test {

/// Points of parameter space checked against a volume map: how many lie in other than exactly one
/// mapped tet, have no physical image, or map outside the solid.
struct LocateCounts {
  int not_one = 0, missing = 0, outside = 0;
};

inline void locate_point(const volmap::Locator& locate, const CGAL::Side_of_triangle_mesh<surface::Mesh, surface::Kernel>& inside,
                         const std::array<double, 3>& x, LocateCounts& c) {
  c.not_one += locate.tets_containing(x, 1e-12).size() != 1;
  const auto p = locate.physical(x);
  if (!p) {
    ++c.missing;
    return;
  }
  c.outside += inside(surface::Point((*p)[0], (*p)[1], (*p)[2])) == CGAL::ON_UNBOUNDED_SIDE;
}

inline void expect_all_located(const LocateCounts& c) {
  EXPECT_EQ(c.not_one, 0);
  EXPECT_EQ(c.missing, 0);
  EXPECT_EQ(c.outside, 0);
}

/// No flipped tet, a positive smallest volume ratio, the tets' volume that of the solid, the round ring's volume up to its chords, and
/// one-to-one: 2,000 random points of the `cubes` cubes' sectors (kept off the chords of the round ring)
/// lie in exactly one mapped tet and map inside the solid `rd` bounds (fills included).
inline void expect_ring_map_one_to_one(const split::Decomposition& rd, const polycube::Embedding& e, const volmap::VolumeMap& vm,
                                       unsigned seed, int cubes = 4) {
  EXPECT_EQ(vm.flipped_tets, 0) << vm.flipped_tets_before_untangling << " before untangling";
  EXPECT_GT(vm.min_volume_ratio, 0);
  // The domain is the round ring (radius 1 to 2, height 1: volume 3π, area 12π) up to its chords.
  EXPECT_LE(vm.parameter_volume, 3 * M_PI);
  EXPECT_GE(vm.parameter_volume, 3 * M_PI - 12 * M_PI * e.boundary_gap);

  Eigen::Vector3d lo = vm.parameter.at(0), hi = lo;
  for (const auto& p : vm.parameter) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const volmap::Locator locate(vm, 2 * e.boundary_gap / (hi - lo).norm());
  const surface::Mesh solid = split::layout_mesh(rd.layout, true);
  // The tets fill the solid exactly once (no fold or overlap from collapses and flips).
  double tets_volume = 0;
  for (const auto& t : vm.tets) tets_volume += tetmesh::signed_volume6(vm.physical[t[0]], vm.physical[t[1]], vm.physical[t[2]], vm.physical[t[3]]) / 6;
  const double solid_volume = CGAL::to_double(CGAL::Polygon_mesh_processing::volume(solid));
  EXPECT_NEAR(tets_volume, solid_volume, 1e-9 * solid_volume);
  CGAL::Side_of_triangle_mesh<surface::Mesh, surface::Kernel> inside(solid);
  const double margin = std::max(0.01, 2 * e.boundary_gap);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), w(margin, 1 - margin);
  LocateCounts c;
  for (int k = 0; k < 2000; ++k) locate_point(locate, inside, polycube::cell_point(e, k % cubes, {u(rng), w(rng), w(rng)}), c);
  expect_all_located(c);
}

}  // namespace volts::test
