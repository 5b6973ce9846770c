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

}  // namespace volts::bezier
