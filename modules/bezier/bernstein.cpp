#include "bezier/bernstein.h"

#include <string>

#include "core/errors.h"

namespace volts::bezier {

Eigen::VectorXd bernstein_basis(int degree, double x, Eigen::VectorXd* derivatives) {
  if (degree < 0) throw core::InvalidInputError("bernstein_basis: negative degree " + std::to_string(degree));
  const int p = degree;
  Eigen::VectorXd B = Eigen::VectorXd::Zero(p + 1);
  B[0] = 1.0;
  for (int k = 1; k <= p; ++k) {
    // B now holds degree k-1: the derivative of degree p is p (B^{p-1}_{i-1} - B^{p-1}_i).
    if (k == p && derivatives) {
      derivatives->resize(p + 1);
      for (int i = 0; i <= p; ++i) (*derivatives)[i] = p * ((i > 0 ? B[i - 1] : 0.0) - (i < p ? B[i] : 0.0));
    }
    for (int i = k; i >= 0; --i) B[i] = (i < k ? (1.0 - x) * B[i] : 0.0) + (i > 0 ? x * B[i - 1] : 0.0);
  }
  if (p == 0 && derivatives) *derivatives = Eigen::VectorXd::Zero(1);
  return B;
}

Eigen::MatrixXd degree_elevation_matrix(int from, int to) {
  if (from < 0 || to < from)
    throw core::InvalidInputError("degree_elevation_matrix: cannot elevate degree " + std::to_string(from) +
                                  " to " + std::to_string(to));
  Eigen::MatrixXd E = Eigen::MatrixXd::Identity(from + 1, from + 1);
  for (int p = from; p < to; ++p) {
    // One step p -> p+1: c'_i = i/(p+1) c_{i-1} + (1 - i/(p+1)) c_i.
    Eigen::MatrixXd step = Eigen::MatrixXd::Zero(p + 2, p + 1);
    for (int i = 0; i <= p + 1; ++i) {
      const double a = static_cast<double>(i) / (p + 1);
      if (i > 0) step(i, i - 1) = a;
      if (i <= p) step(i, i) = 1.0 - a;
    }
    E = step * E;
  }
  return E;
}

Eigen::MatrixXd subdivision_matrix(int degree, double a, double b) {
  if (degree < 0) throw core::InvalidInputError("subdivision_matrix: negative degree " + std::to_string(degree));
  // Row i is the blossom P(a^(p-i), b^i) as a functional of the coefficients: apply p-i de
  // Casteljau steps at a and i at b to the identity.
  const int p = degree;
  Eigen::MatrixXd S(p + 1, p + 1);
  for (int i = 0; i <= p; ++i) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Identity(p + 1, p + 1);  // rows = current coefficients
    for (int m = p; m > 0; --m) {
      const double t = (p - m) < (p - i) ? a : b;
      for (int r = 0; r < m; ++r) c.row(r) = (1.0 - t) * c.row(r) + t * c.row(r + 1);
    }
    S.row(i) = c.row(0);
  }
  return S;
}

}  // namespace volts::bezier
