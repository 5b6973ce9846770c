#include "tet2hex/convert.h"

#include <map>
#include <vector>

#include "bezier/bernstein.h"
#include "bezier/bernstein_poly.h"
#include "core/errors.h"

namespace volts::tet2hex {
namespace {

using bezier::BezierHex;
using bezier::BezierTet;

// Homogeneous control net (w·P, w) of a tet, for bezier::blossom and exact rational conversion.
std::vector<Eigen::Vector4d> homogeneous_net(const BezierTet& tet) {
  std::vector<Eigen::Vector4d> net(tet.points.size());
  for (std::size_t i = 0; i < net.size(); ++i) {
    const double w = tet.weight(static_cast<int>(i));
    net[i] << w * tet.points[i], w;
  }
  return net;
}

// A hex of degree n from homogeneous coefficients; stays polynomial if the tet was.
BezierHex hex_from_homogeneous(int n, const std::vector<Eigen::Vector4d>& h, bool rational) {
  BezierHex hex;
  hex.degree = {n, n, n};
  hex.points.resize(h.size());
  if (rational) hex.weights.resize(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    hex.points[i] = h[i].head<3>() / h[i][3];
    if (rational) hex.weights[i] = h[i][3];
  }
  return hex;
}


}  // namespace

BezierHex degenerate_hex(const BezierTet& tet) {
  bezier::check(tet);
  const int n = tet.degree;
  const std::vector<Eigen::Vector4d> net = homogeneous_net(tet);
  // Eq. (10): T∘ψ⁻¹ = Σ T_{ijk} B_i^n(r) B_j^{n-i}(s) B_k^{n-i-j}(t). Raise t from degree n-i-j and
  // then s from n-i to n: the products A_n..A_{m+1} of eq. (7) are degree_elevation_matrix(m, n).
  std::vector<Eigen::Vector4d> h((n + 1) * (n + 1) * (n + 1), Eigen::Vector4d::Zero());
  auto at = [&](int i, int j, int k) -> Eigen::Vector4d& { return h[i + (n + 1) * (j + (n + 1) * k)]; };
  for (int i = 0; i <= n; ++i) {
    // Q_{i,j,k} (eq. (6)): rows j = 0..n-i, columns k = 0..n.
    std::vector<std::vector<Eigen::Vector4d>> q(n - i + 1, std::vector<Eigen::Vector4d>(n + 1, Eigen::Vector4d::Zero()));
    for (int j = 0; j <= n - i; ++j) {
      const Eigen::MatrixXd A = bezier::degree_elevation_matrix(n - i - j, n);
      for (int k = 0; k <= n; ++k)
        for (int m = 0; m <= n - i - j; ++m) q[j][k] += A(k, m) * net[bezier::simplex_index(3, n, i, j, m)];
    }
    // P_{i,j,k} (eq. (5)).
    const Eigen::MatrixXd A = bezier::degree_elevation_matrix(n - i, n);
    for (int k = 0; k <= n; ++k)
      for (int j = 0; j <= n; ++j)
        for (int m = 0; m <= n - i; ++m) at(i, j, k) += A(j, m) * q[m][k];
  }
  return hex_from_homogeneous(n, h, tet.is_rational());
}

std::array<Eigen::Vector4d, 8> subdomain_corners(int c) {
  if (c < 0 || c > 3) throw core::InvalidInputError("tet2hex::subdomain_corners: corner " + std::to_string(c) + " is not in 0..3");
  // Even permutations (c, a, b, d) of (0,1,2,3): the edges c→a, c→b, c→d are a positive frame.
  static const int other[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  const Eigen::Vector4d e[4] = {Eigen::Vector4d::Unit(0), Eigen::Vector4d::Unit(1), Eigen::Vector4d::Unit(2), Eigen::Vector4d::Unit(3)};
  const Eigen::Vector4d& v = e[c];
  const Eigen::Vector4d& a = e[other[c][0]];
  const Eigen::Vector4d& b = e[other[c][1]];
  const Eigen::Vector4d& d = e[other[c][2]];
  return {v,
          (v + a) / 2,
          (v + b) / 2,
          (v + a + b) / 3,
          (v + d) / 2,
          (v + a + d) / 3,
          (v + b + d) / 3,
          Eigen::Vector4d::Constant(0.25)};
}

BezierHex compose_trilinear(const BezierTet& tet, const std::array<Eigen::Vector4d, 8>& corners) {
  bezier::check(tet);
  const int n = tet.degree;
  const std::vector<Eigen::Vector4d> net = homogeneous_net(tet);
  // Blossom values at multisets of the 8 corners (the Q of eq. (13)), memoized by their counts.
  std::map<std::array<int, 8>, Eigen::Vector4d> memo;
  auto q = [&](const std::array<int, 8>& counts) -> const Eigen::Vector4d& {
    auto it = memo.find(counts);
    if (it != memo.end()) return it->second;
    std::vector<Eigen::Vector4d> args;
    for (int c = 0; c < 8; ++c) args.insert(args.end(), counts[c], corners[c]);
    return memo.emplace(counts, bezier::blossom(3, n, net, args)).first->second;
  };
  // Eq. (12): P_ijk is the mean of the blossom over the ways of pairing the n arguments' r-, s- and
  // t-values (i, j, k of them equal to 1): x1 (x2) of the j s-ones fall on r = 1 (r = 0), then
  // y1, z1, y2, z2 of the k t-ones on the groups (r,s) = (1,1), (1,0), (0,1), (0,0) — hypergeometric
  // weights that sum to 1. Corner index r + 2s + 4t.
  std::vector<Eigen::Vector4d> h((n + 1) * (n + 1) * (n + 1), Eigen::Vector4d::Zero());
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Eigen::Vector4d p = Eigen::Vector4d::Zero();
        for (int x1 = 0; x1 <= std::min(i, j); ++x1) {
          const int x2 = j - x1;
          if (x2 > n - i) continue;
          const double ws = bezier::binomial(i, x1) * bezier::binomial(n - i, x2) / bezier::binomial(n, j);
          const int g[4] = {x1, i - x1, x2, n - i - x2};  // group sizes (r,s) = (1,1), (1,0), (0,1), (0,0)
          for (int y1 = 0; y1 <= g[0]; ++y1)
            for (int z1 = 0; z1 <= g[1]; ++z1)
              for (int y2 = 0; y2 <= g[2]; ++y2) {
                const int z2 = k - y1 - z1 - y2;
                if (z2 < 0 || z2 > g[3]) continue;
                const double wt = bezier::binomial(g[0], y1) * bezier::binomial(g[1], z1) * bezier::binomial(g[2], y2) * bezier::binomial(g[3], z2) / bezier::binomial(n, k);
                std::array<int, 8> counts{};
                counts[1 + 2 + 4] = y1, counts[1 + 2] = g[0] - y1;
                counts[1 + 4] = z1, counts[1] = g[1] - z1;
                counts[2 + 4] = y2, counts[2] = g[2] - y2;
                counts[4] = z2, counts[0] = g[3] - z2;
                p += ws * wt * q(counts);
              }
        }
        h[i + (n + 1) * (j + (n + 1) * k)] = p;
      }
  return hex_from_homogeneous(n, h, tet.is_rational());
}

std::array<BezierHex, 4> four_hexes(const BezierTet& tet) {
  return {compose_trilinear(tet, subdomain_corners(0)), compose_trilinear(tet, subdomain_corners(1)),
          compose_trilinear(tet, subdomain_corners(2)), compose_trilinear(tet, subdomain_corners(3))};
}

}  // namespace volts::tet2hex
