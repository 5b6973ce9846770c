// volts::quality on elements whose figures are known exactly: axis-aligned boxes (scaled Jacobian
// 1, no deviation from the box surface), a box with one face pushed out by d, a mirrored box.
#include <gtest/gtest.h>

#include <cmath>

#include "bezier/certify.h"
#include "core/errors.h"
#include "models/models.h"
#include "quality/quality.h"

namespace volts::quality {
namespace {

// The generated box [-1,1] x [-0.75,0.75] x [-0.5,0.5].
surface::Mesh box_surface() {
  models::ModelParams p;
  p.name = "box";
  p.resolution = 8;
  return models::make_model(p);
}

// Degree-2 hex filling [lo, hi] (axis-aligned), control points on the uniform grid.
bezier::BezierHex box_hex(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  bezier::BezierHex h;
  h.degree = {2, 2, 2};
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [i, j, k] = h.ijk(n);
    const Eigen::Vector3d t(i / 2.0, j / 2.0, k / 2.0);
    h.points.push_back(lo + (hi - lo).cwiseProduct(t));
  }
  return h;
}

const Eigen::Vector3d kLo(-1, -0.75, -0.5), kHi(1, 0.75, 0.5);
const double kDiagonal = std::sqrt(4 + 2.25 + 1);

std::vector<BoundaryFace> all_faces(int element) {
  std::vector<BoundaryFace> f;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) f.push_back({element, axis, side});
  return f;
}

// Degree-2 affine hex x = origin + A (u, v, w): J = A everywhere.
bezier::BezierHex affine_hex(const Eigen::Matrix3d& A, const Eigen::Vector3d& origin) {
  bezier::BezierHex h;
  h.degree = {2, 2, 2};
  for (int n = 0; n < h.num_points(); ++n) {
    const auto [i, j, k] = h.ijk(n);
    h.points.push_back(origin + A * Eigen::Vector3d(i / 2.0, j / 2.0, k / 2.0));
  }
  return h;
}

// u and v at angle theta, w perpendicular to both: scaled Jacobian sin(theta) everywhere.
Eigen::Matrix3d sheared(double theta) {
  Eigen::Matrix3d A;
  A.col(0) = Eigen::Vector3d(1, 0, 0);
  A.col(1) = Eigen::Vector3d(std::cos(theta), std::sin(theta), 0);
  A.col(2) = Eigen::Vector3d(0, 0, 0.5);
  return A;
}

// worst_samples over a family of sheared hexes: the lowest `count` in order, at their first
// sample (all equal: corner 0), and the surface bound of a boundary face spanned by the sheared
// pair equals the scaled Jacobian (that face's tangents are the limit), 1 for a face spanned by
// a perpendicular pair.
TEST(Quality, WorstSamplesAreTheLowestElementsAndNameTheSurfaceLimit) {
  const std::vector<double> theta{1.2, 0.5, 1.5707963267948966, 0.9, 0.3};
  std::vector<bezier::BezierHex> hexes;
  for (std::size_t e = 0; e < theta.size(); ++e) hexes.push_back(affine_hex(sheared(theta[e]), Eigen::Vector3d(3.0 * e, 0, 0)));
  // Element 4 has its w = 0 face (tangents u, v) on the surface, element 1 its u = 0 face (v, w).
  const std::vector<BoundaryFace> faces{{4, 2, 0}, {1, 0, 0}};
  const ScaledJacobian sj = scaled_jacobian(hexes, 3);
  const std::vector<WorstSample> w = worst_samples(hexes, sj, faces, 3, 3);
  ASSERT_EQ(w.size(), 3u);
  const int expected[3] = {4, 1, 3};  // theta 0.3, 0.5, 0.9
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(w[i].element, expected[i]);
    EXPECT_NEAR(w[i].scaled_jacobian, std::sin(theta[static_cast<std::size_t>(expected[i])]), 1e-12);
    EXPECT_DOUBLE_EQ(w[i].scaled_jacobian, sj.min_per_element[static_cast<std::size_t>(expected[i])]);
    EXPECT_TRUE(w[i].at_corner);
    EXPECT_EQ(w[i].uvw, Eigen::Vector3d::Zero());
    EXPECT_NEAR((w[i].position - Eigen::Vector3d(3.0 * expected[i], 0, 0)).norm(), 0.0, 1e-12);
  }
  EXPECT_EQ(w[0].boundary_faces, 1);
  EXPECT_NEAR(w[0].surface_bound, std::sin(0.3), 1e-12);
  EXPECT_EQ(w[1].boundary_faces, 1);
  EXPECT_NEAR(w[1].surface_bound, 1.0, 1e-12);
  EXPECT_EQ(w[2].boundary_faces, 0);
  EXPECT_EQ(w[2].surface_bound, 1.0);
  EXPECT_EQ(worst_samples(hexes, sj, faces, 3, 99).size(), hexes.size());
  EXPECT_THROW(worst_samples(hexes, scaled_jacobian({hexes[0]}, 3), faces, 3, 3), core::InvalidInputError);
}

// A hex whose worst point is inside: one corner control point of a cubic box pulled inward
// lowers the Jacobian near that corner; the worst sample is that corner, not a Gauss point, and
// it is the only element reported with count 1.
TEST(Quality, WorstSampleOfAPulledCornerIsThatCorner) {
  bezier::BezierHex h = box_hex(kLo, kHi);
  const int corner = h.index(2, 2, 2);
  h.points[static_cast<std::size_t>(corner)] -= Eigen::Vector3d(0.3, 0.2, 0.1);
  const std::vector<bezier::BezierHex> hexes{box_hex(kLo, kHi), h};
  const ScaledJacobian sj = scaled_jacobian(hexes, 3);
  const std::vector<WorstSample> w = worst_samples(hexes, sj, all_faces(1), 3, 1);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].element, 1);
  EXPECT_LT(w[0].scaled_jacobian, 0.99);
  EXPECT_TRUE(w[0].at_corner);
  EXPECT_EQ(w[0].uvw, Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(w[0].boundary_faces, 3);  // a corner of the box lies on three of its faces
  EXPECT_EQ(w[0].surface_bound, 1.0);   // no single surface face there
}

TEST(Quality, BoxHexHasScaledJacobianOneEverywhere) {
  const auto sj = scaled_jacobian({box_hex(kLo, kHi), box_hex({0, 0, 0}, {3, 1, 0.2})}, 4);
  ASSERT_EQ(sj.min_per_element.size(), 2u);
  ASSERT_EQ(sj.max_per_element.size(), 2u);
  for (int e = 0; e < 2; ++e) {
    EXPECT_NEAR(sj.min_per_element[e], 1.0, 1e-12);
    EXPECT_NEAR(sj.max_per_element[e], 1.0, 1e-12);
  }
  EXPECT_NEAR(sj.min, 1.0, 1e-12);
  EXPECT_NEAR(sj.max, 1.0, 1e-12);
}

// The uniform grid sees the field on faces: a box hex whose face-centre control point slides
// along the face tilts the derivative across the face most at its centre, which the corners do
// not see (their derivatives do not involve that point) and the interior Gauss points see less
// of; nested grids (2 = the corners, 3, 5) can only find lower minima; an affine hex has its one
// value everywhere.
TEST(Quality, ScaledJacobianOnAGridSeesBetweenTheSamples) {
  bezier::BezierHex h = box_hex(kLo, kHi);
  h.points[static_cast<std::size_t>(h.index(1, 1, 0))] += Eigen::Vector3d(0.8, 0.0, 0.0);
  const std::vector<bezier::BezierHex> hexes{box_hex(kLo, kHi), h};
  const ScaledJacobian sampled = scaled_jacobian(hexes, 3);
  const ScaledJacobian g2 = scaled_jacobian_on_grid(hexes, 2), g3 = scaled_jacobian_on_grid(hexes, 3), g5 = scaled_jacobian_on_grid(hexes, 5);
  ASSERT_EQ(g3.min_per_element.size(), 2u);
  EXPECT_NEAR(g5.min_per_element[0], 1.0, 1e-12);
  EXPECT_LT(g3.min_per_element[1], sampled.min_per_element[1] - 0.05) << "the grid misses the dip at the pulled edge";
  EXPECT_LE(g3.min, g2.min);
  EXPECT_LE(g5.min, g3.min);
  EXPECT_EQ(g3.min, g3.min_per_element[1]);
  const auto affine = scaled_jacobian_on_grid({affine_hex(sheared(0.7), Eigen::Vector3d(1, 2, 3))}, 6);
  EXPECT_NEAR(affine.min, std::sin(0.7), 1e-12);
  EXPECT_NEAR(affine.max, std::sin(0.7), 1e-12);
  EXPECT_THROW(scaled_jacobian_on_grid(hexes, 1), core::InvalidInputError);
}

// worst_grid_samples: the element with the dip first, at the grid point where the field is lowest
// (checked against every point of the grid by evaluate()), named as a grid point with its
// boundary faces; an undistorted element after it, at its first grid point (all equal).
TEST(Quality, WorstGridSampleIsTheLowestGridPoint) {
  bezier::BezierHex h = box_hex(kLo, kHi);
  h.points[static_cast<std::size_t>(h.index(1, 1, 0))] += Eigen::Vector3d(0.8, 0.0, 0.0);
  const std::vector<bezier::BezierHex> hexes{box_hex(kLo, kHi), h};
  const std::vector<BoundaryFace> faces{{1, 2, 0}};  // element 1's w = 0 face, where the dip is
  for (const int n : {5, 7}) {
    const ScaledJacobian g = scaled_jacobian_on_grid(hexes, n);
    const std::vector<WorstSample> w = worst_grid_samples(hexes, g, faces, n, 2);
    ASSERT_EQ(w.size(), 2u);
    EXPECT_EQ(w[0].element, 1);
    EXPECT_TRUE(w[0].on_grid);
    EXPECT_DOUBLE_EQ(w[0].scaled_jacobian, g.min_per_element[1]);
    double lowest = 2;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          Eigen::Matrix3d J;
          bezier::evaluate(h, Eigen::Vector3d(i, j, k) / (n - 1.0), &J);
          lowest = std::min(lowest, bezier::scaled_jacobian(J));
        }
    EXPECT_NEAR(w[0].scaled_jacobian, lowest, 1e-12);
    Eigen::Matrix3d J;
    EXPECT_NEAR((bezier::evaluate(h, w[0].uvw, &J) - w[0].position).norm(), 0.0, 1e-15);
    EXPECT_NEAR(bezier::scaled_jacobian(J), lowest, 1e-12);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(w[0].uvw[d] * (n - 1), std::round(w[0].uvw[d] * (n - 1)), 1e-12) << "not a grid point";
    EXPECT_EQ(w[0].boundary_faces, w[0].uvw[2] == 0.0 ? 1 : 0);
    EXPECT_EQ(w[1].element, 0);
    EXPECT_TRUE(w[1].at_corner && w[1].on_grid);
    EXPECT_EQ(w[1].uvw, Eigen::Vector3d::Zero());
    EXPECT_NEAR(w[1].scaled_jacobian, 1.0, 1e-12);
  }
  EXPECT_THROW(worst_grid_samples(hexes, scaled_jacobian_on_grid(hexes, 3), faces, 1, 2), core::InvalidInputError);
  EXPECT_THROW(worst_grid_samples(hexes, scaled_jacobian_on_grid({hexes[0]}, 3), faces, 3, 2), core::InvalidInputError);
}

TEST(Quality, BoxHexDoesNotDeviateFromTheSurfaceThroughItsBoundary) {
  const surface::Mesh s = box_surface();
  const auto dev = boundary_deviation({box_hex(kLo, kHi)}, all_faces(0), s, 8);
  ASSERT_EQ(dev.per_element.size(), 1u);
  EXPECT_NEAR(dev.per_element[0], 0.0, 1e-12);
  EXPECT_NEAR(dev.max, 0.0, 1e-12);
  EXPECT_NEAR(dev.rel, 0.0, 1e-12);
  EXPECT_NEAR(dev.diagonal, kDiagonal, 1e-12);
  const auto v = volume({box_hex(kLo, kHi)}, s, 4);
  EXPECT_NEAR(v.elements, 3.0, 1e-12);
  EXPECT_NEAR(v.surface, 3.0, 1e-12);
  EXPECT_NEAR(v.rel_error, 0.0, 1e-12);
}

TEST(Quality, FaceOffsetByDFromAPlaneGivesDOverTheDiagonal) {
  const surface::Mesh s = box_surface();
  const double d = 0.125;
  // Element 1 reaches d above the box's top plane z = 0.5; only that face is on the boundary.
  const std::vector<bezier::BezierHex> hexes = {box_hex(kLo, kHi), box_hex(kLo, {1, 0.75, 0.5 + d})};
  const auto dev = boundary_deviation(hexes, {{1, 2, 1}}, s, 5);
  ASSERT_EQ(dev.per_element.size(), 2u);
  EXPECT_EQ(dev.per_element[0], 0.0);  // not on the boundary: not measured
  EXPECT_NEAR(dev.per_element[1], d, 1e-12);
  EXPECT_NEAR(dev.max, d, 1e-12);
  EXPECT_NEAR(dev.rel, d / kDiagonal, 1e-12);
  // The same element's bottom face lies on the surface.
  EXPECT_NEAR(boundary_deviation(hexes, {{1, 2, 0}}, s, 5).max, 0.0, 1e-12);
  const auto v = volume({hexes[1]}, s, 4);
  EXPECT_NEAR(v.elements, 3.0 + 3.0 * d, 1e-12);
  EXPECT_NEAR(v.rel_error, d, 1e-12);
}

TEST(Quality, BoundaryDeviationRefusesBadInput) {
  const surface::Mesh s = box_surface();
  EXPECT_THROW(boundary_deviation({box_hex(kLo, kHi)}, all_faces(0), s, 1), core::InvalidInputError);
  EXPECT_THROW(boundary_deviation({box_hex(kLo, kHi)}, {{1, 0, 0}}, s, 4), core::InvalidInputError);
  EXPECT_THROW(boundary_deviation({box_hex(kLo, kHi)}, {{0, 3, 0}}, s, 4), core::InvalidInputError);
}

TEST(Quality, ValidityCountsAddUp) {
  // A box is certified valid; its mirror image has det J < 0 everywhere.
  bezier::BezierHex mirrored = box_hex(kLo, kHi);
  for (auto& p : mirrored.points) p.x() = -p.x();
  std::vector<int> status;
  for (const auto& h : {box_hex(kLo, kHi), mirrored, box_hex({0, 0, 0}, {1, 2, 3})})
    status.push_back(static_cast<int>(bezier::certify(h, {}).status));
  status.push_back(static_cast<int>(bezier::Validity::undecided));
  const ValidityCounts c = count_validity(status);
  EXPECT_EQ(c.valid, 2);
  EXPECT_EQ(c.invalid, 1);
  EXPECT_EQ(c.undecided, 1);
  EXPECT_EQ(c.valid + c.invalid + c.undecided, static_cast<int>(status.size()));
  const ValidityCounts none = count_validity({});
  EXPECT_EQ(none.valid + none.invalid + none.undecided, 0);
  const auto sj = scaled_jacobian({mirrored}, 3);
  EXPECT_NEAR(sj.max, -1.0, 1e-12);
}

TEST(Quality, FiguresDoNotDependOnTheThreadCount) {
  // 300 cubic hexes tiling the box in slabs, interior points jiggled: every figure is computed
  // per element in parallel and reduced in element order, so it must be bit-identical.
  const surface::Mesh s = box_surface();
  std::vector<bezier::BezierHex> hexes;
  std::vector<BoundaryFace> faces;
  for (int e = 0; e < 300; ++e) {
    const double x0 = -1 + 2.0 * e / 300, x1 = -1 + 2.0 * (e + 1) / 300;
    bezier::BezierHex h = box_hex({x0, -0.75, -0.5}, {x1, 0.75, 0.5});
    h = bezier::elevate_degree(h, {3, 3, 3});
    for (int n = 0; n < h.num_points(); ++n) {
      const auto [i, j, k] = h.ijk(n);
      if (j > 0 && j < 3 && k > 0 && k < 3) h.points[n].y() += 0.05 * std::sin(7.0 * e + n);
      else h.points[n].z() += 0.01 * std::cos(3.0 * e + n) * (k == 0 || k == 3 ? 0 : 1);
    }
    hexes.push_back(h);
    faces.push_back({e, 1, 0}), faces.push_back({e, 2, 1});
  }
  auto figures = [&](const char* threads) {
    setenv("VOLTS_THREADS", threads, 1);
    const ScaledJacobian sj = scaled_jacobian(hexes, 4);
    const BoundaryDeviation d = boundary_deviation(hexes, faces, s, 5);
    const Volume v = volume(hexes, s, 5);
    std::vector<double> all = sj.min_per_element;
    all.insert(all.end(), sj.max_per_element.begin(), sj.max_per_element.end());
    all.insert(all.end(), d.per_element.begin(), d.per_element.end());
    all.insert(all.end(), {sj.min, sj.max, d.max, d.rel, v.elements, v.rel_error, volume_fraction_scaled_jacobian_above(hexes, 4, 0.9)});
    unsetenv("VOLTS_THREADS");
    return all;
  };
  const std::vector<double> one = figures("1");
  EXPECT_EQ(figures("2"), one);
  EXPECT_EQ(figures("3"), one);
}

}  // namespace
}  // namespace volts::quality
