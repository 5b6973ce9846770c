#include "bezier/bezier_hex.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "bezier/bernstein.h"
#include "bezier/jacobian_grid.h"
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

// Bernstein values and derivatives at the grid's coordinates, then the Gauss points, per direction.
struct SampleBases {
  int gauss_points = 0, grid_points = 0;
  std::array<int, 3> degree{};
  std::array<AxisBases, 3> axes;
};

std::vector<double> uniform_points(int n) {
  if (n < 2) throw core::InvalidInputError("Jacobian samples: at least 2 grid points per direction (the corners), got " + std::to_string(n));
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back(i / (n - 1.0));
  return t;
}

}  // namespace

std::vector<Eigen::Matrix3d> jacobian_samples(const BezierHex& hex, int gauss_points, int grid_points) {
  check(hex);
  std::vector<Eigen::Matrix3d> out;
  const std::size_t n = static_cast<std::size_t>(std::max(gauss_points, 0)), m = static_cast<std::size_t>(std::max(grid_points, 0));
  out.reserve(m * m * m + n * n * n);
  if (hex.is_rational()) {
    const std::vector<double> g = gauss_legendre_points(gauss_points), t = uniform_points(grid_points);
    auto add = [&](const Eigen::Vector3d& uvw) {
      Eigen::Matrix3d J;
      evaluate(hex, uvw, &J);
      out.push_back(J);
    };
    for (double w : t)
      for (double v : t)
        for (double u : t) add(Eigen::Vector3d(u, v, w));
    for (double w : g)
      for (double v : g)
        for (double u : g) add(Eigen::Vector3d(u, v, w));
    return out;
  }
  // Coordinates per direction: the grid's (0, 1 for the corners), then the Gauss points; bases
  // computed once per thread and degrees (tmesh optimization calls this for every element a node
  // supports).
  thread_local SampleBases cache;
  if (cache.gauss_points != gauss_points || cache.grid_points != grid_points || cache.degree != hex.degree) {
    std::vector<double> g = gauss_legendre_points(gauss_points);  // throws for n < 1
    const std::vector<double> t = uniform_points(grid_points);
    g.insert(g.begin(), t.begin(), t.end());
    cache = SampleBases{gauss_points, grid_points, hex.degree, {}};
    for (int d = 0; d < 3; ++d)
      for (const double x : g) {
        Eigen::VectorXd db;
        cache.axes[d].B.push_back(bernstein_basis(hex.degree[d], x, &db));
        cache.axes[d].dB.push_back(db);
      }
  }
  // The grid, then the Gauss points, each by sum factorization (the per-point sums of the tmesh
  // optimizer's inner loop, a fifth of the operations for cubics).
  thread_local std::vector<std::array<Eigen::Vector3d, 3>> columns;
  columns.clear();
  grid_derivatives(hex.degree, hex.points.data(), cache.axes, 0, m, columns);
  grid_derivatives(hex.degree, hex.points.data(), cache.axes, m, cache.axes[0].B.size(), columns);
  for (const auto& [xu, xv, xw] : columns) {
    Eigen::Matrix3d J;
    J << xu, xv, xw;
    out.push_back(J);
  }
  return out;
}

std::vector<Eigen::Matrix3d> jacobian_grid(const BezierHex& hex, int n) {
  return jacobian_tensor_grid(hex, uniform_points(n));
}

std::vector<Eigen::Matrix3d> jacobian_tensor_grid(const BezierHex& hex, const std::vector<double>& t) {
  check(hex);
  std::vector<Eigen::Matrix3d> out;
  out.reserve(t.size() * t.size() * t.size());
  if (hex.is_rational()) {
    for (const double w : t)
      for (const double v : t)
        for (const double u : t) {
          Eigen::Matrix3d J;
          evaluate(hex, Eigen::Vector3d(u, v, w), &J);
          out.push_back(J);
        }
    return out;
  }
  // The bases once per thread, degrees and points (extract calls this for every element).
  thread_local std::pair<std::array<int, 3>, std::vector<double>> key{{-1, -1, -1}, {}};
  thread_local std::array<AxisBases, 3> axes;
  if (key.first != hex.degree || key.second != t) {
    key = {hex.degree, t};
    for (int d = 0; d < 3; ++d) {
      axes[static_cast<std::size_t>(d)] = {};
      for (const double x : t) {
        Eigen::VectorXd db;
        axes[static_cast<std::size_t>(d)].B.push_back(bernstein_basis(hex.degree[d], x, &db));
        axes[static_cast<std::size_t>(d)].dB.push_back(db);
      }
    }
  }
  thread_local std::vector<std::array<Eigen::Vector3d, 3>> columns;
  columns.clear();
  grid_derivatives(hex.degree, hex.points.data(), axes, 0, t.size(), columns);
  for (const auto& [xu, xv, xw] : columns) {
    Eigen::Matrix3d J;
    J << xu, xv, xw;
    out.push_back(J);
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

JacobianSample sample_jacobian(const BezierHex& hex, int gauss_points, int grid_points) {
  return summarize_jacobians(jacobian_samples(hex, gauss_points, grid_points));
}

double volume(const BezierHex& hex, int gauss_points) {
  const std::vector<double> g = gauss_legendre_points(gauss_points);
  const std::vector<double> gw = gauss_legendre_weights(gauss_points);
  const std::vector<Eigen::Matrix3d> J = jacobian_tensor_grid(hex, g);
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
