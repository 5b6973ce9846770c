// Theorem 3 and Proposition 4 (Xu et al. 2018): the four hexes of a Bézier tet are the tet over the
// sub-domains D1..D4 (1,000 random points), their volumes add up to the tet's, they are certified
// valid when the tet is, and the hexes of neighbouring tets (and of one tet) meet without gaps.
#include <gtest/gtest.h>

#include <map>

#include "bezier/certify.h"
#include "bezier/quadrature.h"
#include "tet2hex/convert.h"
#include "test_util.h"

using namespace volts;
using namespace volts::tet2hex;

namespace {

// The trilinear map of the sub-domain corners (barycentric → u, v, w).
Eigen::Vector3d phi(const std::array<Eigen::Vector4d, 8>& c, const Eigen::Vector3d& rst) {
  Eigen::Vector4d l = Eigen::Vector4d::Zero();
  for (int k = 0; k < 8; ++k)
    l += ((k & 1) ? rst[0] : 1 - rst[0]) * ((k & 2) ? rst[1] : 1 - rst[1]) * ((k & 4) ? rst[2] : 1 - rst[2]) * c[k];
  return l.tail<3>();
}

// ∫_tet det J by the collapsed (Duffy) Gauss rule on the tet itself — independent of the conversion.
double tet_volume(const bezier::BezierTet& tet) {
  const int m = 2 * tet.degree + 2;  // det J: degree 3n-3 in (u,v,w), times (1-r)^2 (1-s)
  const std::vector<double> x = bezier::gauss_legendre_points(m), w = bezier::gauss_legendre_weights(m);
  double v = 0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int c = 0; c < m; ++c) {
        const double r = x[a], s = x[b], t = x[c];
        Eigen::Matrix3d J;
        bezier::evaluate(tet, Eigen::Vector3d(r, (1 - r) * s, (1 - r) * (1 - s) * t), &J);
        v += w[a] * w[b] * w[c] * J.determinant() * (1 - r) * (1 - r) * (1 - s);
      }
  return v;
}

}  // namespace

class FourHexes : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(FourHexes, AgreeWithTheTetAtRandomPoints) {
  const auto [n, rational] = GetParam();
  std::mt19937 rng(200 + n + 10 * rational);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const bezier::BezierTet tet = test::random_tet(rng, n, 0.1, rational);
    const auto hexes = four_hexes(tet);
    double worst = 0;
    for (int i = 0; i < 1000; ++i) {
      const int c = i % 4;
      const Eigen::Vector3d rst(u(rng), u(rng), u(rng));
      worst = std::max(worst, (bezier::evaluate(hexes[c], rst) - bezier::evaluate(tet, phi(subdomain_corners(c), rst))).norm());
    }
    EXPECT_LE(worst, 1e-12 * test::size(tet)) << "degree " << n << " trial " << trial;
  }
}

// Proposition 4: a tet certified valid gives four hexes certified valid.
TEST_P(FourHexes, HexesOfAValidTetAreCertifiedValid) {
  const auto [n, rational] = GetParam();
  std::mt19937 rng(400 + n + 10 * rational);
  int valid_tets = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const bezier::BezierTet tet = test::random_tet(rng, n, n == 1 ? 0.0 : 0.12, rational);
    if (bezier::certify(tet).status != bezier::Validity::valid) continue;
    ++valid_tets;
    for (const auto& h : four_hexes(tet)) EXPECT_EQ(bezier::certify(h).status, bezier::Validity::valid) << "degree " << n;
  }
  EXPECT_GE(valid_tets, 10) << "too few valid random tets to test Proposition 4";
}

// The sub-domains tile the tet, so the hexes' volumes add up to the tet's (polynomial tets: Gauss
// quadrature of det J is exact for them).
TEST(FourHexesVolume, VolumesAddUpToTheTet) {
  for (int n = 1; n <= 4; ++n) {
    std::mt19937 rng(300 + n);
    for (int trial = 0; trial < 5; ++trial) {
      const bezier::BezierTet tet = test::random_tet(rng, n, 0.05);
      double sum = 0;
      for (const auto& h : four_hexes(tet)) sum += bezier::volume(h, 2 * n + 1);
      const double v = tet_volume(tet);
      EXPECT_GT(v, 0);
      EXPECT_NEAR(sum, v, 1e-12 * std::abs(v)) << "degree " << n;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Degrees, FourHexes, ::testing::Combine(::testing::Values(1, 2, 3, 4), ::testing::Bool()));

// Two random curved tets sharing a face (shared control points identical, as in a conforming
// mesh): every hex face meets its neighbour's — 6 inner faces per tet plus 3 on the shared
// triangle — with the same control points up to the square's symmetry.
TEST(FourHexesMesh, NeighbouringHexesMeetWithoutGaps) {
  for (int n = 1; n <= 4; ++n) {
    std::mt19937 rng(500 + n);
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    const Eigen::Vector3d X[5] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.9, 0.9, 0.9}};
    const std::array<int, 4> tv[2] = {{0, 1, 2, 3}, {1, 4, 2, 3}};  // share face (1,2,3); both positive
    std::map<std::vector<std::pair<int, int>>, Eigen::Vector3d> wobble;  // per global control point
    std::vector<bezier::BezierHex> hexes;
    double size = 0;
    for (const auto& g : tv) {
      bezier::BezierTet t;
      t.degree = n;
      for (const auto& a : bezier::simplex_multi_indices(3, n)) {
        std::vector<std::pair<int, int>> key;
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for (int v = 0; v < 4; ++v)
          if (a[v] > 0) key.push_back({g[v], a[v]}), x += a[v] * X[g[v]];
        std::sort(key.begin(), key.end());
        if (n > 1 && key.size() > 1 && !wobble.count(key)) wobble[key] = Eigen::Vector3d(u(rng), u(rng), u(rng));
        t.points.push_back(key.size() > 1 && n > 1 ? Eigen::Vector3d(x / n + wobble[key]) : Eigen::Vector3d(x / n));
      }
      size = std::max(size, test::size(t));
      for (const auto& h : four_hexes(t)) hexes.push_back(h);
    }
    // Faces as (n+1)^2 grids; match by corner positions.
    struct Face { int hex; std::vector<Eigen::Vector3d> grid; };
    std::vector<Face> faces;
    for (int e = 0; e < static_cast<int>(hexes.size()); ++e)
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side <= n; side += n) {
          Face f{e, {}};
          for (int b = 0; b <= n; ++b)
            for (int a = 0; a <= n; ++a) {
              int ijk[3];
              ijk[axis] = side, ijk[(axis + 1) % 3] = a, ijk[(axis + 2) % 3] = b;
              f.grid.push_back(hexes[e].points[hexes[e].index(ijk[0], ijk[1], ijk[2])]);
            }
          faces.push_back(f);
        }
    auto at = [&](const Face& f, int a, int b) { return f.grid[a + (n + 1) * b]; };
    int pairs = 0;
    double worst = 0;
    for (std::size_t i = 0; i < faces.size(); ++i)
      for (std::size_t j = i + 1; j < faces.size(); ++j) {
        // Try the 8 symmetries of the square; a match needs the four corners within 1e-9.
        for (int sym = 0; sym < 8; ++sym) {
          auto map = [&](int a, int b) {
            int x = (sym & 1) ? n - a : a, y = (sym & 2) ? n - b : b;
            if (sym & 4) std::swap(x, y);
            return at(faces[j], x, y);
          };
          bool corners = true;
          for (int a = 0; a <= n; a += n)
            for (int b = 0; b <= n; b += n) corners = corners && (at(faces[i], a, b) - map(a, b)).norm() < 1e-9;
          if (!corners) continue;
          ++pairs;
          for (int a = 0; a <= n; ++a)
            for (int b = 0; b <= n; ++b) worst = std::max(worst, (at(faces[i], a, b) - map(a, b)).norm());
          break;
        }
      }
    EXPECT_EQ(pairs, 15) << "degree " << n;
    EXPECT_LE(worst, 1e-12 * size) << "degree " << n;
  }
}
