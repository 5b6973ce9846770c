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
#include <string>
#include <vector>

#include "polycube/embedding.h"
#include "split/split.h"
#include "volmap/volmap.h"

namespace volts::test {

/// The embedding's inner circle (b = 0, radius 1) carries the physically shortest side of the
/// ring: summed over the sectors, the chords along the ring at b = 0 are shorter than on any other
/// side of the cross section. (Split's corner order is arbitrary; before the embedding chose its
/// frame, the generated torus had its outer side on the inner circle, and its volume map's worst
/// tet was 4x flatter.)
inline void expect_inner_side_shortest(const std::vector<std::array<double, 3>>& pts, const polycube::Embedding& e, const std::string& name) {
  // side 0: b = 0, 1: b = 1, 2: c = 0, 3: c = 1; a corner index is a + 2b + 4c
  std::array<double, 4> len{};
  for (const auto& cv : e.corner_vertex)
    for (int bc = 0; bc < 4; ++bc) {
      const auto& x = pts.at(static_cast<std::size_t>(cv[static_cast<std::size_t>(2 * bc)]));
      const auto& y = pts.at(static_cast<std::size_t>(cv[static_cast<std::size_t>(2 * bc + 1)]));
      const double l = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
      const int b = bc & 1, c = bc >> 1;
      len[static_cast<std::size_t>(b)] += l;
      len[static_cast<std::size_t>(2 + c)] += l;
    }
  for (int side = 1; side < 4; ++side) EXPECT_LT(len[0], len[static_cast<std::size_t>(side)]) << name << ": side " << side;
}

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
/// one-to-one: 2,000 random points of the `cubes` cubes' sectors (of their profile cells if the
/// embedding has a profile; kept off the chords of the round ring) lie in exactly one mapped tet
/// and map inside the solid `rd` bounds (fills included).
inline void expect_ring_map_one_to_one(const split::Decomposition& rd, const polycube::Embedding& e, const volmap::VolumeMap& vm,
                                       unsigned seed, int cubes = 4) {
  EXPECT_EQ(vm.flipped_tets, 0) << vm.flipped_tets_before_untangling << " before untangling";
  EXPECT_GT(vm.min_volume_ratio, 0);
  // The domain is the round ring of the cross section (radius 1 + b, height c; the square: volume
  // 3π, area 12π) up to its chords. Volume and area by Pappus: 2π times the moments about the axis.
  std::vector<std::array<double, 2>> polygon = e.profile.empty() ? std::vector<std::array<double, 2>>{{0, 0}, {1, 0}, {1, 1}, {0, 1}} : e.profile.polygon;
  double volume = 0, area = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto &p = polygon[i], &q = polygon[(i + 1) % polygon.size()];
    const double rp = 1 + p[0], rq = 1 + q[0];
    volume += M_PI * (rp * rp + rp * rq + rq * rq) / 3 * (q[1] - p[1]);  // 2π ∮ r²/2 dz (Green)
    area += M_PI * (rp + rq) * std::hypot(q[0] - p[0], q[1] - p[1]);
  }
  volume = std::abs(volume);
  EXPECT_LE(vm.parameter_volume, volume * (1 + 1e-12));
  EXPECT_GE(vm.parameter_volume, volume - area * e.boundary_gap);

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
  const int cells = e.profile.empty() ? 1 : static_cast<int>(e.profile.cells.size());
  for (int k = 0; k < 2000; ++k) {
    std::array<double, 3> x{u(rng), w(rng), w(rng)};
    // With a profile: a point of a random cell at least `margin` from the polygon's sides (its chords).
    for (bool near = !e.profile.empty(); near;) {
      const auto [i, j] = e.profile.cells[static_cast<std::size_t>(k / cubes % cells)];
      const auto &b = e.profile.b, &cc = e.profile.c;
      x[1] = b[static_cast<std::size_t>(i)] + u(rng) * (b[static_cast<std::size_t>(i) + 1] - b[static_cast<std::size_t>(i)]);
      x[2] = cc[static_cast<std::size_t>(j)] + u(rng) * (cc[static_cast<std::size_t>(j) + 1] - cc[static_cast<std::size_t>(j)]);
      near = false;
      for (std::size_t s = 0; s < polygon.size(); ++s) {
        const auto &p = polygon[s], &q = polygon[(s + 1) % polygon.size()];  // axis-parallel sides
        near = near || (std::abs(x[1] - std::clamp(x[1], std::min(p[0], q[0]), std::max(p[0], q[0]))) < margin &&
                        std::abs(x[2] - std::clamp(x[2], std::min(p[1], q[1]), std::max(p[1], q[1]))) < margin);
      }
    }
    locate_point(locate, inside, polycube::cell_point(e, k % cubes, x), c);
  }
  expect_all_located(c);
}

}  // namespace volts::test
