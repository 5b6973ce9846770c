// Tests of fit/pillow.h: the pillow partition of the unit cube into the core [1/3,2/3]^3 and six
// frusta, and the seven initial solids whose control points sample the map at Greville points
// (Lin, Huang & Hu 2018, "Construction of the initial TBSs").
#include "fit/pillow.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "core/errors.h"
#include "tmesh/pillow.h"

using namespace volts;
using namespace volts::fit;
using Eigen::Vector3d;

namespace {

using Map = std::function<tmesh::Vec3(const tmesh::Vec3&)>;

Vector3d vec(const tmesh::Vec3& x) { return {x[0], x[1], x[2]}; }
tmesh::Vec3 arr(const Vector3d& x) { return {x[0], x[1], x[2]}; }

// A fixed affine map with a sheared, non-symmetric matrix (det > 0) and an offset.
const Eigen::Matrix3d kA = (Eigen::Matrix3d() << 1.3, 0.2, -0.4, 0.1, 0.9, 0.3, 0.25, -0.35, 1.1).finished();
const Vector3d kB(-0.7, 2.1, 0.4);
tmesh::Vec3 affine(const tmesh::Vec3& uvw) { return arr(kA * vec(uvw) + kB); }

// A smooth injective non-polynomial map: the cube's x wrapped around a cylinder, plus a ripple in z.
tmesh::Vec3 bend(const tmesh::Vec3& u) {
  const double r = 3.0 + u[1], phi = u[0] / 1.5;
  return {r * std::sin(phi), r * std::cos(phi) - 3.0, u[2] + 0.1 * std::sin(3 * u[0])};
}

bezier::TensorBSplineVolume spline(const tmesh::TMesh& t) {
  bezier::TensorBSplineVolume v;
  v.knots = t.knots;
  v.degree = {t.degree, t.degree, t.degree};
  for (const auto& p : t.control_points) v.points.push_back(vec(p));
  return v;
}

Vector3d cube_point(const tmesh::TMesh& t, std::size_t i) { return vec(tmesh::block_point(t.corners, t.parameters[i])); }

}  // namespace

// Linear precision of B-splines sampled at Greville points: Σ_i N_i(t) g_i = t per direction, so a
// tensor product of such splines reproduces every multilinear function of (u, v, w), and
// A·block_point(corners, uvw) + b is one (block_point is trilinear). Every solid is then exactly
// the affine map, whatever the degree.
TEST(InitialSolids, SplinesReproduceAnAffineMapExactly) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const int degree : {2, 3, 5}) {
    PillowParams p;
    p.elements = 3;
    p.degree = degree;
    const auto solids = initial_solids(affine, p);
    ASSERT_EQ(solids.size(), 7u);
    double worst = 0;
    for (const auto& t : solids) {
      EXPECT_EQ(t.degree, degree);
      for (int a = 0; a < 3; ++a) EXPECT_EQ(t.size[a], p.elements + degree);
      const auto v = spline(t);
      for (int s = 0; s < 40; ++s) {
        const tmesh::Vec3 uvw{unit(rng), unit(rng), unit(rng)};
        const Vector3d expected = kA * vec(tmesh::block_point(t.corners, uvw)) + kB;
        worst = std::max(worst, (bezier::evaluate(v, vec(uvw)) - expected).norm());
      }
      // Block corners too (the clamped ends).
      for (int c = 0; c < 8; ++c) {
        const Vector3d uvw(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        worst = std::max(worst, (bezier::evaluate(v, uvw) - (kA * vec(t.corners[c]) + kB)).norm());
      }
    }
    EXPECT_LT(worst, 1e-12) << "degree " << degree;
  }
}

TEST(InitialSolids, KnotsAreUniformWithBezierEndConditions) {
  PillowParams p;
  p.elements = 4;
  p.degree = 3;
  for (const auto& t : initial_solids(bend, p))
    for (int a = 0; a < 3; ++a) {
      const auto& k = t.knots[a];
      ASSERT_EQ(k.size(), static_cast<std::size_t>(p.elements + 2 * p.degree + 1));
      for (int i = 0; i <= p.degree; ++i) {
        EXPECT_EQ(k[static_cast<std::size_t>(i)], 0.0);
        EXPECT_EQ(k[k.size() - 1 - static_cast<std::size_t>(i)], 1.0);
      }
      for (int i = 1; i < p.elements; ++i) EXPECT_NEAR(k[static_cast<std::size_t>(p.degree + i)], double(i) / p.elements, 1e-15);
    }
}

// The initial nets sample the map (they do not interpolate it): the control point with Greville
// point g is map(block_point(corners, g)).
TEST(InitialSolids, ControlPointsAreTheMapAtGrevillePoints) {
  PillowParams p;
  p.elements = 3;
  p.degree = 3;
  double worst = 0, worst_g = 0;
  for (const auto& t : initial_solids(bend, p)) {
    std::array<std::vector<double>, 3> g;
    for (int a = 0; a < 3; ++a) g[a] = bezier::greville_abscissae(t.knots[a], t.degree);
    ASSERT_EQ(t.parameters.size(), t.control_points.size());
    for (int k = 0; k < t.size[2]; ++k)
      for (int j = 0; j < t.size[1]; ++j)
        for (int i = 0; i < t.size[0]; ++i) {
          const std::size_t idx = static_cast<std::size_t>(i + t.size[0] * (j + t.size[1] * k));
          worst_g = std::max(worst_g, (vec(t.parameters[idx]) - Vector3d(g[0][i], g[1][j], g[2][k])).norm());
          worst = std::max(worst, (vec(t.control_points[idx]) - vec(bend(tmesh::block_point(t.corners, t.parameters[idx])))).norm());
        }
  }
  EXPECT_LT(worst_g, 1e-15);
  // A shared point is sampled once, at the first holder's block parameters: other holders' block
  // parameters give the same cube point up to rounding, hence the tolerance.
  EXPECT_LT(worst, 1e-14);
}

TEST(InitialSolids, CoreIsTheMiddleThirdOfTheCube) {
  PillowParams p;
  p.elements = 3;
  const auto solids = initial_solids(affine, p);
  const auto& core = solids.front();
  EXPECT_EQ(core.kind, "core");
  for (int c = 0; c < 8; ++c)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(core.corners[c][a], (c >> a) & 1 ? 2.0 / 3 : 1.0 / 3, 1e-15) << c << " " << a;
  for (int f = 0; f < 6; ++f) EXPECT_EQ(core.boundary[f], 0) << f;
}

// Each frustum: one face on a cube face (flagged as boundary, the whole cube face), the opposite
// face the core's face on that side; the six frusta cover the six cube faces.
TEST(InitialSolids, EachFrustumJoinsACubeFaceToTheCoresFace) {
  PillowParams p;
  p.elements = 2;
  const auto solids = initial_solids(affine, p);
  ASSERT_EQ(solids.size(), 7u);
  const auto& core = solids.front();
  std::set<int> faces;
  for (std::size_t b = 1; b < solids.size(); ++b) {
    const auto& t = solids[b];
    EXPECT_EQ(t.kind, "pillow") << b;
    int flagged = 0, face = -1;
    for (int f = 0; f < 6; ++f)
      if (t.boundary[f]) ++flagged, face = f;
    ASSERT_EQ(flagged, 1) << b;
    faces.insert(face);
    const int a = face / 2, side = face % 2;
    for (int c = 0; c < 8; ++c) {
      const bool outer = ((c >> a) & 1) == side;
      for (int d = 0; d < 3; ++d) {
        const int bit = (c >> d) & 1;
        if (outer) {
          // On the cube face; its other coordinates the face's corners: the whole cube face.
          EXPECT_EQ(t.corners[c][d], d == a ? double(side) : double(bit)) << b << " corner " << c;
        } else {
          // The core's corner with the same bits in the face directions, on the core's face at `side`.
          const int core_corner = (c & ~(1 << a)) | (side << a);
          EXPECT_EQ(t.corners[c][d], core.corners[core_corner][d]) << b << " corner " << c;
        }
      }
    }
  }
  EXPECT_EQ(faces.size(), 6u);
}

// One function id = one point: equal ids have bit-identical positions and the same cube
// parameters; different ids are different cube points (apart by far more than rounding).
TEST(InitialSolids, SharedControlPointsAreOnePoint) {
  PillowParams p;
  p.elements = 3;
  const auto solids = initial_solids(bend, p);
  struct Entry {
    int id;
    Vector3d cube, x;
  };
  std::vector<Entry> all;
  for (const auto& t : solids) {
    ASSERT_EQ(t.function_ids.size(), t.control_points.size());
    for (std::size_t i = 0; i < t.control_points.size(); ++i) all.push_back({t.function_ids[i], cube_point(t, i), vec(t.control_points[i])});
  }
  int shared_pairs = 0, position_mismatch = 0;
  double same_id_cube = 0, distinct_id_cube = 1e300;
  for (std::size_t i = 0; i < all.size(); ++i)
    for (std::size_t j = i + 1; j < all.size(); ++j) {
      const double d = (all[i].cube - all[j].cube).norm();
      if (all[i].id == all[j].id) {
        ++shared_pairs;
        position_mismatch += all[i].x != all[j].x;
        same_id_cube = std::max(same_id_cube, d);
      } else {
        distinct_id_cube = std::min(distinct_id_cube, d);
      }
    }
  std::printf("%d pairs share an id (cube points within %.1e); distinct ids at least %.4f apart\n", shared_pairs, same_id_cube,
              distinct_id_cube);
  EXPECT_GT(shared_pairs, 0);  // the solids do share their common faces
  EXPECT_EQ(position_mismatch, 0);
  EXPECT_LT(same_id_cube, 1e-14);
  // The closest distinct grid points are a block's first Greville step apart: h/3 with h = 1/(3·elements)
  // the core's knot spacing in the cube (1/27 here; the frusta's rows only spread out toward the cube
  // faces). Two ids for one point would make this 0.
  EXPECT_GT(distinct_id_cube, 1e-3);
}

TEST(InitialSolids, OutOfRangeParametersThrow) {
  for (const auto& [elements, degree] : std::vector<std::pair<int, int>>{{0, 3}, {33, 3}, {-1, 3}, {2, 1}, {2, 6}}) {
    PillowParams p;
    p.elements = elements;
    p.degree = degree;
    EXPECT_THROW(initial_solids(affine, p), core::ConfigError) << elements << " " << degree;
  }
  // The ends of the ranges are accepted.
  for (const auto& [elements, degree] : std::vector<std::pair<int, int>>{{1, 2}, {1, 5}}) {
    PillowParams p;
    p.elements = elements;
    p.degree = degree;
    EXPECT_EQ(initial_solids(affine, p).size(), 7u) << elements << " " << degree;
  }
}
