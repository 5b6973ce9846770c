#include "bezier/hex_point.h"

#include <string>

#include "bezier/bernstein.h"
#include "core/errors.h"

namespace volts::bezier {

HexPoint::HexPoint(const std::array<int, 3>& degree, const Eigen::Vector3d& uvw) : degree_(degree), uvw_(uvw) {
  for (int d = 0; d < 3; ++d)
    if (degree[d] < 1) throw core::InvalidInputError("HexPoint: degree " + std::to_string(degree[d]) + " in direction " + std::to_string(d) + ", must be >= 1");
  std::array<Eigen::VectorXd, 3> B, dB;
  for (int d = 0; d < 3; ++d) B[d] = bernstein_basis(degree[d], uvw[d], &dB[d]);
  // The products as evaluate() forms them with weight 1 (1 * x = x exactly): ((B_i B_j) B_k).
  for (int k = 0; k <= degree[2]; ++k)
    for (int j = 0; j <= degree[1]; ++j)
      for (int i = 0; i <= degree[0]; ++i) {
        b_.push_back(B[0][i] * B[1][j] * B[2][k]);
        db_.emplace_back(dB[0][i] * B[1][j] * B[2][k], B[0][i] * dB[1][j] * B[2][k], B[0][i] * B[1][j] * dB[2][k]);
      }
}

Eigen::Vector3d HexPoint::evaluate(const BezierHex& hex, Eigen::Matrix3d* jacobian) const {
  check(hex);
  if (hex.degree != degree_)
    throw core::InvalidInputError("HexPoint: a hex of degrees " + std::to_string(hex.degree[0]) + "," + std::to_string(hex.degree[1]) + "," +
                                  std::to_string(hex.degree[2]) + " at a point made for " + std::to_string(degree_[0]) + "," +
                                  std::to_string(degree_[1]) + "," + std::to_string(degree_[2]));
  if (hex.is_rational()) return bezier::evaluate(hex, uvw_, jacobian);
  // evaluate()'s homogeneous sums in its order; the derivative sums only when asked for (x does
  // not depend on them).
  Eigen::Vector3d A = Eigen::Vector3d::Zero();
  double W = 0.0;
  const std::size_t n = b_.size();
  if (!jacobian) {
    for (std::size_t idx = 0; idx < n; ++idx) {
      A += b_[idx] * hex.points[idx];
      W += b_[idx];
    }
    return A / W;
  }
  Eigen::Matrix3d dA = Eigen::Matrix3d::Zero();
  Eigen::RowVector3d dW = Eigen::RowVector3d::Zero();
  for (std::size_t idx = 0; idx < n; ++idx) {
    const double b = b_[idx];
    const Eigen::RowVector3d& db = db_[idx];
    A += b * hex.points[idx];
    W += b;
    dA += hex.points[idx] * db;
    dW += db;
  }
  const Eigen::Vector3d x = A / W;
  *jacobian = (dA - x * dW) / W;  // quotient rule
  return x;
}

HexPoints::HexPoints(const std::array<int, 3>& degree, const std::vector<Eigen::Vector3d>& uvw) : degree_(degree), uvw_(uvw) {
  const std::size_t n = uvw.size(), terms = static_cast<std::size_t>((degree[0] + 1) * (degree[1] + 1) * (degree[2] + 1));
  b_.resize(terms * n);
  for (auto& d : db_) d.resize(terms * n);
  for (std::size_t pt = 0; pt < n; ++pt) {
    const HexPoint one(degree, uvw[pt]);  // checks the degrees
    for (std::size_t idx = 0; idx < terms; ++idx) {
      b_[idx * n + pt] = one.b_[idx];
      for (int d = 0; d < 3; ++d) db_[static_cast<std::size_t>(d)][idx * n + pt] = one.db_[idx][d];
    }
  }
  // W and dW of a polynomial hex (every weight 1) do not depend on its points: summed here once,
  // term by term in index order as evaluate() sums them.
  w_.assign(n, 0.0);
  for (auto& d : dw_) d.assign(n, 0.0);
  for (std::size_t idx = 0; idx < terms; ++idx)
    for (std::size_t pt = 0; pt < n; ++pt) {
      w_[pt] += b_[idx * n + pt];
      for (std::size_t d = 0; d < 3; ++d) dw_[d][pt] += db_[d][idx * n + pt];
    }
}

void HexPoints::evaluate(const BezierHex& hex, std::vector<Eigen::Vector3d>* x, std::vector<Eigen::Matrix3d>* jacobians) const {
  check(hex);
  if (hex.degree != degree_)
    throw core::InvalidInputError("HexPoints: a hex of degrees " + std::to_string(hex.degree[0]) + "," + std::to_string(hex.degree[1]) + "," +
                                  std::to_string(hex.degree[2]) + " at points made for " + std::to_string(degree_[0]) + "," +
                                  std::to_string(degree_[1]) + "," + std::to_string(degree_[2]));
  const std::size_t n = uvw_.size();
  if (x) x->resize(n);
  if (jacobians) jacobians->resize(n);
  if (hex.is_rational()) {
    for (std::size_t pt = 0; pt < n; ++pt) {
      const Eigen::Vector3d y = bezier::evaluate(hex, uvw_[pt], jacobians ? &(*jacobians)[pt] : nullptr);
      if (x) (*x)[pt] = y;
    }
    return;
  }
  // HexPoint::evaluate's sums, one array per sum: A (3) and with the Jacobian dA (row r, column
  // c at 3 + 3r + c); W and dW are the constructor's. Per point the terms are added in index order.
  const bool with_j = jacobians != nullptr;
  thread_local std::vector<double> acc;
  acc.assign((with_j ? 12 : 3) * n, 0.0);
  double* A0 = acc.data();
  double *A1 = A0 + n, *A2 = A1 + n;
  const std::size_t terms = hex.points.size();
  for (std::size_t idx = 0; idx < terms; ++idx) {
    const double P0 = hex.points[idx][0], P1 = hex.points[idx][1], P2 = hex.points[idx][2];
    const double* __restrict b = &b_[idx * n];
    for (std::size_t pt = 0; pt < n; ++pt) A0[pt] += b[pt] * P0, A1[pt] += b[pt] * P1, A2[pt] += b[pt] * P2;
    if (!with_j) continue;
    const double P[3] = {P0, P1, P2};
    for (int c = 0; c < 3; ++c) {
      const double* __restrict db = &db_[static_cast<std::size_t>(c)][idx * n];
      for (int r = 0; r < 3; ++r) {
        double* __restrict dA = acc.data() + (3 + 3 * r + c) * n;
        const double Pr = P[r];
        for (std::size_t pt = 0; pt < n; ++pt) dA[pt] += Pr * db[pt];
      }
    }
  }
  for (std::size_t pt = 0; pt < n; ++pt) {
    const Eigen::Vector3d A(A0[pt], A1[pt], A2[pt]);
    const Eigen::Vector3d y = A / w_[pt];
    if (x) (*x)[pt] = y;
    if (!with_j) continue;
    Eigen::Matrix3d dA;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) dA(r, c) = acc[(3 + 3 * r + c) * n + pt];
    const Eigen::RowVector3d dW(dw_[0][pt], dw_[1][pt], dw_[2][pt]);
    (*jacobians)[pt] = (dA - y * dW) / w_[pt];  // quotient rule
  }
}

}  // namespace volts::bezier
