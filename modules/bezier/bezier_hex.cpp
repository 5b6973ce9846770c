#include "bezier/bezier_hex.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "bezier/bernstein.h"
#include "bezier/hex_point.h"
#include "core/errors.h"

namespace volts::bezier {

void check(const BezierHex& hex) {
  for (int d = 0; d < 3; ++d)
    if (hex.degree[d] < 1)
      throw core::InvalidInputError("BezierHex: degree " + std::to_string(hex.degree[d]) + " in direction " +
                                    std::to_string(d) + ", must be >= 1");
  const std::size_t n = static_cast<std::size_t>(hex.num_points());
  if (hex.points.size() != n)
    throw core::InvalidInputError("BezierHex: " + std::to_string(hex.points.size()) + " control points, degrees " +
                                  std::to_string(hex.degree[0]) + "," + std::to_string(hex.degree[1]) + "," +
                                  std::to_string(hex.degree[2]) + " need " + std::to_string(n));
  if (!hex.weights.empty()) {
    if (hex.weights.size() != n)
      throw core::InvalidInputError("BezierHex: " + std::to_string(hex.weights.size()) + " weights for " +
                                    std::to_string(n) + " control points");
    for (std::size_t i = 0; i < n; ++i)
      if (!(hex.weights[i] > 0.0) || !std::isfinite(hex.weights[i]))
        throw core::InvalidInputError("BezierHex: weight " + std::to_string(i) + " = " +
                                      std::to_string(hex.weights[i]) + " is not finite and positive");
  }
}

Eigen::Vector3d evaluate(const BezierHex& hex, const Eigen::Vector3d& uvw, Eigen::Matrix3d* jacobian) {
  check(hex);
  std::array<Eigen::VectorXd, 3> B, dB;
  for (int d = 0; d < 3; ++d) B[d] = bernstein_basis(hex.degree[d], uvw[d], &dB[d]);
  // Homogeneous sums: A = sum w B P, W = sum w B and their partial derivatives.
  Eigen::Vector3d A = Eigen::Vector3d::Zero();
  Eigen::Matrix3d dA = Eigen::Matrix3d::Zero();
  double W = 0.0;
  Eigen::RowVector3d dW = Eigen::RowVector3d::Zero();
  const auto& [p, q, r] = hex.degree;
  for (int k = 0; k <= r; ++k)
    for (int j = 0; j <= q; ++j)
      for (int i = 0; i <= p; ++i) {
        const int idx = hex.index(i, j, k);
        const double w = hex.weight(idx);
        const double b = w * B[0][i] * B[1][j] * B[2][k];
        const Eigen::RowVector3d db(w * dB[0][i] * B[1][j] * B[2][k], w * B[0][i] * dB[1][j] * B[2][k],
                                    w * B[0][i] * B[1][j] * dB[2][k]);
        A += b * hex.points[idx];
        W += b;
        dA += hex.points[idx] * db;
        dW += db;
      }
  const Eigen::Vector3d x = A / W;
  if (jacobian) *jacobian = (dA - x * dW) / W;  // quotient rule
  return x;
}

namespace {

// Jacobian of a polynomial hex at (u,v,w) from basis values precomputed per direction, summed one
// direction at a time (the per-point evaluate() allocates its bases and checks the hex: the
// sample below is the inner loop of tmesh optimization).
Eigen::Matrix3d polynomial_jacobian(const BezierHex& hex, const Eigen::VectorXd& Bu, const Eigen::VectorXd& dBu,
                                    const Eigen::VectorXd& Bv, const Eigen::VectorXd& dBv, const Eigen::VectorXd& Bw,
                                    const Eigen::VectorXd& dBw) {
  const auto& [p, q, r] = hex.degree;
  Eigen::Vector3d xu = Eigen::Vector3d::Zero(), xv = xu, xw = xu;
  for (int k = 0; k <= r; ++k) {
    Eigen::Vector3d T = Eigen::Vector3d::Zero(), Tu = T, Tv = T;
    for (int j = 0; j <= q; ++j) {
      Eigen::Vector3d S = Eigen::Vector3d::Zero(), Su = S;
      const Eigen::Vector3d* P = &hex.points[static_cast<std::size_t>(hex.index(0, j, k))];
      for (int i = 0; i <= p; ++i) S += Bu[i] * P[i], Su += dBu[i] * P[i];
      T += Bv[j] * S, Tu += Bv[j] * Su, Tv += dBv[j] * S;
    }
    xu += Bw[k] * Tu, xv += Bw[k] * Tv, xw += dBw[k] * T;
  }
  Eigen::Matrix3d J;
  J << xu, xv, xw;
  return J;
}

// Bernstein values and derivatives at 0, 1 and the Gauss points, per direction.
struct SampleBases {
  int gauss_points = 0;
  std::array<int, 3> degree{};
  std::array<std::vector<Eigen::VectorXd>, 3> B, dB;
};

}  // namespace

std::vector<Eigen::Matrix3d> jacobian_samples(const BezierHex& hex, int gauss_points) {
  check(hex);
  std::vector<Eigen::Matrix3d> out;
  const std::size_t n = static_cast<std::size_t>(std::max(gauss_points, 0));
  out.reserve(8 + n * n * n);
  if (hex.is_rational()) {
    const std::vector<double> g = gauss_legendre_points(gauss_points);
    auto add = [&](const Eigen::Vector3d& uvw) {
      Eigen::Matrix3d J;
      evaluate(hex, uvw, &J);
      out.push_back(J);
    };
    for (int c = 0; c < 8; ++c) add(Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1));
    for (double w : g)
      for (double v : g)
        for (double u : g) add(Eigen::Vector3d(u, v, w));
    return out;
  }
  // Coordinates per direction: 0, 1, then the Gauss points; bases computed once per thread and
  // degrees (tmesh optimization calls this for every element a node supports).
  thread_local SampleBases cache;
  if (cache.gauss_points != gauss_points || cache.degree != hex.degree) {
    std::vector<double> g = gauss_legendre_points(gauss_points);  // throws for n < 1
    g.insert(g.begin(), {0.0, 1.0});
    cache = SampleBases{gauss_points, hex.degree, {}, {}};
    for (int d = 0; d < 3; ++d)
      for (const double t : g) {
        Eigen::VectorXd db;
        cache.B[d].push_back(bernstein_basis(hex.degree[d], t, &db));
        cache.dB[d].push_back(db);
      }
  }
  const auto& B = cache.B;
  const auto& dB = cache.dB;
  const std::size_t ng = B[0].size();
  for (std::size_t c = 0; c < 8; ++c)
    out.push_back(polynomial_jacobian(hex, B[0][c & 1], dB[0][c & 1], B[1][(c >> 1) & 1], dB[1][(c >> 1) & 1], B[2][(c >> 2) & 1],
                                      dB[2][(c >> 2) & 1]));
  // The Gauss grid: polynomial_jacobian's sums, each partial sum formed once for every point
  // that shares it (S, Su per u-point and (j, k); T, Tu, Tv per (u, v)-point and k) instead of
  // once per point. Every sum adds the same terms in the same order, so the matrices are
  // polynomial_jacobian's bit for bit, at a fifth of the operations for cubics.
  const std::size_t G = ng - 2;
  const auto& [p, q, r] = hex.degree;
  const std::size_t nj = static_cast<std::size_t>(q + 1), nk = static_cast<std::size_t>(r + 1);
  thread_local std::vector<Eigen::Vector3d> S, Su, T, Tu, Tv;
  S.resize(G * nj * nk), Su.resize(S.size());
  for (std::size_t a = 0; a < G; ++a) {
    const Eigen::VectorXd &Bu = B[0][2 + a], &dBu = dB[0][2 + a];
    for (std::size_t k = 0; k < nk; ++k)
      for (std::size_t j = 0; j < nj; ++j) {
        Eigen::Vector3d s = Eigen::Vector3d::Zero(), su = s;
        const Eigen::Vector3d* P = &hex.points[static_cast<std::size_t>(hex.index(0, static_cast<int>(j), static_cast<int>(k)))];
        for (int i = 0; i <= p; ++i) s += Bu[i] * P[i], su += dBu[i] * P[i];
        S[a + G * (j + nj * k)] = s, Su[a + G * (j + nj * k)] = su;
      }
  }
  T.resize(G * G * nk), Tu.resize(T.size()), Tv.resize(T.size());
  for (std::size_t b = 0; b < G; ++b) {
    const Eigen::VectorXd &Bv = B[1][2 + b], &dBv = dB[1][2 + b];
    for (std::size_t a = 0; a < G; ++a)
      for (std::size_t k = 0; k < nk; ++k) {
        Eigen::Vector3d t = Eigen::Vector3d::Zero(), tu = t, tv = t;
        for (std::size_t j = 0; j < nj; ++j) {
          const Eigen::Vector3d& s = S[a + G * (j + nj * k)];
          const Eigen::Vector3d& su = Su[a + G * (j + nj * k)];
          t += Bv[static_cast<Eigen::Index>(j)] * s, tu += Bv[static_cast<Eigen::Index>(j)] * su, tv += dBv[static_cast<Eigen::Index>(j)] * s;
        }
        const std::size_t at = a + G * (b + G * k);
        T[at] = t, Tu[at] = tu, Tv[at] = tv;
      }
  }
  for (std::size_t c = 0; c < G; ++c) {
    const Eigen::VectorXd &Bw = B[2][2 + c], &dBw = dB[2][2 + c];
    for (std::size_t b = 0; b < G; ++b)
      for (std::size_t a = 0; a < G; ++a) {
        Eigen::Vector3d xu = Eigen::Vector3d::Zero(), xv = xu, xw = xu;
        for (std::size_t k = 0; k < nk; ++k) {
          const std::size_t at = a + G * (b + G * k);
          xu += Bw[static_cast<Eigen::Index>(k)] * Tu[at], xv += Bw[static_cast<Eigen::Index>(k)] * Tv[at],
              xw += dBw[static_cast<Eigen::Index>(k)] * T[at];
        }
        Eigen::Matrix3d J;
        J << xu, xv, xw;
        out.push_back(J);
      }
  }
  return out;
}

JacobianSample summarize_jacobians(const std::vector<Eigen::Matrix3d>& J) {
  JacobianSample s;
  for (const auto& m : J) {
    const double det = m.determinant(), sj = scaled_jacobian(m);
    s.min_det = std::min(s.min_det, det);
    s.max_det = std::max(s.max_det, det);
    s.min_scaled = std::min(s.min_scaled, sj);
    s.max_scaled = std::max(s.max_scaled, sj);
  }
  return s;
}

JacobianSample sample_jacobian(const BezierHex& hex, int gauss_points) { return summarize_jacobians(jacobian_samples(hex, gauss_points)); }

double volume(const BezierHex& hex, int gauss_points) {
  check(hex);
  const std::vector<double> g = gauss_legendre_points(gauss_points);
  const std::vector<double> gw = gauss_legendre_weights(gauss_points);
  // The Gauss points' bases once per thread, degrees and rule (extract sums every element).
  thread_local std::unique_ptr<HexPoints> points;
  thread_local std::vector<double> rule;
  if (!points || rule != g || !points->has_degree(hex.degree)) {
    std::vector<Eigen::Vector3d> uvw;
    for (int k = 0; k < gauss_points; ++k)
      for (int j = 0; j < gauss_points; ++j)
        for (int i = 0; i < gauss_points; ++i) uvw.emplace_back(g[i], g[j], g[k]);
    points = std::make_unique<HexPoints>(hex.degree, uvw);
    rule = g;
  }
  thread_local std::vector<Eigen::Matrix3d> J;
  points->evaluate(hex, nullptr, &J);
  double vol = 0.0;
  std::size_t n = 0;
  for (int k = 0; k < gauss_points; ++k)
    for (int j = 0; j < gauss_points; ++j)
      for (int i = 0; i < gauss_points; ++i) vol += gw[i] * gw[j] * gw[k] * J[n++].determinant();
  return vol;
}

BezierHex map_coefficients(const BezierHex& hex, const std::array<Eigen::MatrixXd, 3>& M) {
  check(hex);
  std::array<int, 3> in{}, out{};
  for (int d = 0; d < 3; ++d) {
    in[d] = hex.degree[d] + 1;
    out[d] = static_cast<int>(M[d].rows());
    if (M[d].cols() != in[d] || out[d] < 2)
      throw core::InvalidInputError("map_coefficients: map " + std::to_string(d) + " is " +
                                    std::to_string(M[d].rows()) + "x" + std::to_string(M[d].cols()) +
                                    ", expected (m+1)x" + std::to_string(in[d]) + " with m >= 1");
    if (!hex.is_rational())
      for (int a = 0; a < out[d]; ++a)
        if (std::abs(M[d].row(a).sum() - 1.0) > 1e-12)
          throw core::InvalidInputError("map_coefficients: map " + std::to_string(d) +
                                        " is not affine (row sums != 1) for a polynomial hex");
  }
  // Homogeneous coefficients as a 4 x N matrix, contracted one direction at a time (sum
  // factorisation): cost O(N * max(m+1)) instead of O(N^2).
  std::array<int, 3> dims = in;
  std::vector<Eigen::Vector4d> H(hex.points.size());
  for (std::size_t n = 0; n < H.size(); ++n) {
    const double w = hex.weight(static_cast<int>(n));
    H[n] << w * hex.points[n], w;
  }
  for (int d = 0; d < 3; ++d) {
    std::array<int, 3> nd = dims;
    nd[d] = out[d];
    std::vector<Eigen::Vector4d> G(static_cast<std::size_t>(nd[0]) * nd[1] * nd[2], Eigen::Vector4d::Zero());
    for (int k = 0; k < nd[2]; ++k)
      for (int j = 0; j < nd[1]; ++j)
        for (int i = 0; i < nd[0]; ++i) {
          std::array<int, 3> src{i, j, k};
          Eigen::Vector4d sum = Eigen::Vector4d::Zero();
          const int a = src[d];
          for (int b = 0; b < dims[d]; ++b) {
            src[d] = b;
            sum += M[d](a, b) * H[src[0] + dims[0] * (src[1] + dims[1] * src[2])];
          }
          G[i + nd[0] * (j + nd[1] * k)] = sum;
        }
    H = std::move(G);
    dims = nd;
  }
  BezierHex res;
  res.degree = {out[0] - 1, out[1] - 1, out[2] - 1};
  res.points.resize(H.size());
  if (hex.is_rational()) res.weights.resize(H.size());
  for (std::size_t n = 0; n < H.size(); ++n) {
    const double w = H[n][3];
    if (!(w > 0.0))
      throw core::InvalidInputError("map_coefficients: resulting weight " + std::to_string(n) + " = " +
                                    std::to_string(w) + " is not positive");
    res.points[n] = H[n].head<3>() / w;
    if (hex.is_rational()) res.weights[n] = w;
  }
  return res;
}

BezierHex elevate_degree(const BezierHex& hex, const std::array<int, 3>& new_degree) {
  check(hex);
  std::array<Eigen::MatrixXd, 3> E;
  for (int d = 0; d < 3; ++d) E[d] = degree_elevation_matrix(hex.degree[d], new_degree[d]);
  return map_coefficients(hex, E);
}

std::array<BezierHex, 8> subdivide(const BezierHex& hex) {
  check(hex);
  std::array<std::array<Eigen::MatrixXd, 2>, 3> S;
  for (int d = 0; d < 3; ++d)
    for (int half = 0; half < 2; ++half) S[d][half] = subdivision_matrix(hex.degree[d], 0.5 * half, 0.5 * (half + 1));
  std::array<BezierHex, 8> out;
  for (int c = 0; c < 8; ++c) out[c] = map_coefficients(hex, {S[0][c & 1], S[1][(c >> 1) & 1], S[2][(c >> 2) & 1]});
  return out;
}

}  // namespace volts::bezier
