// Garanzha et al. 2021's foldover-free energy of one tet, and its derivatives in one vertex.
#include "volmap/foldover_energy.h"

#include <cmath>

namespace volts::volmap {
namespace {

constexpr double kTheta = 0.5;

Eigen::Matrix3d cofactors(const Eigen::Matrix3d& J) {  // d det / d J
  Eigen::Matrix3d C;
  C.col(0) = J.col(1).cross(J.col(2)), C.col(1) = J.col(2).cross(J.col(0)), C.col(2) = J.col(0).cross(J.col(1));
  return C;
}

}  // namespace

double tet_energy(const Eigen::Matrix3d& J, double eps, double* det, Eigen::Matrix3d* dJ) {
  const double theta = kTheta;
  const Eigen::Matrix3d C = cofactors(J);
  const double D = J.col(0).dot(C.col(0)), F = J.squaredNorm();
  *det = D;
  const double root = std::sqrt(eps * eps + D * D), chi = (D + root) / 2, dchi = chi / root;
  const double c23 = std::cbrt(chi * chi);
  if (dJ)
    *dJ = (1 - theta) * (2 * J / (3 * c23) - (2.0 / 9) * F / (c23 * chi) * dchi * C) +
          theta * (D / chi - (D * D + 1) / (2 * chi * chi) * dchi) * C;
  return (1 - theta) * F / (3 * c23) + theta * (D * D + 1) / (2 * chi);
}

double vertex_energy(const Eigen::Matrix3d& J, const Eigen::Vector3d& g, double eps, double* det, Eigen::Vector3d* grad,
                     Eigen::Matrix3d* hess) {
  // E = a F u + b h with F = |J|², u = χ^{-2/3}, h = (D² + 1) / χ; along p, ∇F = 2 J g,
  // ∇²F = 2 |g|² I, ∇D = C g (constant: D is affine in p), so every second derivative in D is
  // a chain rule in one variable.
  const double a = (1 - kTheta) / 3, b = kTheta / 2;
  const Eigen::Matrix3d C = cofactors(J);
  const double D = J.col(0).dot(C.col(0)), F = J.squaredNorm();
  *det = D;
  const double root = std::sqrt(eps * eps + D * D), chi = (D + root) / 2;
  const double u = 1 / std::cbrt(chi * chi), w = 1 / chi;
  const double e = a * F * u + b * (D * D + 1) * w;
  if (!grad) return e;
  const double dchi = chi / root, ddchi = chi * (root - D) / (root * root * root);
  const double du = -(2.0 / 3) * u * w * dchi;
  const double dw = -w * w * dchi;
  const double dh = 2 * D * w + (D * D + 1) * dw;
  const Eigen::Vector3d gF = 2 * J * g, gD = C * g;
  *grad = a * (u * gF + F * du * gD) + b * dh * gD;
  if (hess) {
    const double ddu = (10.0 / 9) * u * w * w * dchi * dchi - (2.0 / 3) * u * w * ddchi;
    const double ddw = 2 * w * w * w * dchi * dchi - w * w * ddchi;
    const double ddh = 2 * w + 4 * D * dw + (D * D + 1) * ddw;
    const Eigen::Matrix3d cross = gF * gD.transpose();
    *hess = a * (2 * u * g.squaredNorm() * Eigen::Matrix3d::Identity() + du * (cross + cross.transpose()) + F * ddu * gD * gD.transpose()) +
            b * ddh * gD * gD.transpose();
  }
  return e;
}

}  // namespace volts::volmap
