// Tests of the foldover-free energy (volmap/foldover_energy.h): the vertex form's value, gradient
// and closed-form Hessian against the matrix form and against differences, over random tets
// (positive, and inverted with eps > 0).
#include "volmap/foldover_energy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace volts::volmap;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

struct Case {
  Matrix3d A;  // J = A + p gᵀ
  Vector3d g, p;
  double eps;
};

// Random cases: J near a rotation-free stretch (det > 0) or mirrored (det < 0, then eps > 0).
std::vector<Case> cases(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Case> out;
  while (static_cast<int>(out.size()) < n) {
    Case c;
    Matrix3d J = Matrix3d::Identity() * 1.5;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J(i, j) += 0.6 * u(rng);
    const bool inverted = out.size() % 3 == 2;
    if (inverted) J.col(0) = -J.col(0);
    c.g = Vector3d(u(rng), u(rng), u(rng));
    c.p = Vector3d(u(rng), u(rng), u(rng));
    c.A = J - c.p * c.g.transpose();
    c.eps = inverted ? 0.3 + 0.5 * std::abs(u(rng)) : (out.size() % 3 == 1 ? 0.05 : 0.0);
    if (!inverted && !(J.determinant() > 0.05)) continue;
    out.push_back(c);
  }
  return out;
}

double energy_at(const Case& c, const Vector3d& p) {
  double D = 0;
  return vertex_energy(c.A + p * c.g.transpose(), c.g, c.eps, &D, nullptr, nullptr);
}

Vector3d gradient_at(const Case& c, const Vector3d& p) {
  double D = 0;
  Vector3d g;
  vertex_energy(c.A + p * c.g.transpose(), c.g, c.eps, &D, &g, nullptr);
  return g;
}

}  // namespace

TEST(FoldoverEnergy, VertexFormAgreesWithTheMatrixForm) {
  for (const Case& c : cases(300, 7)) {
    const Matrix3d J = c.A + c.p * c.g.transpose();
    double D1 = 0, D2 = 0;
    Matrix3d dJ;
    Vector3d g;
    const double e1 = tet_energy(J, c.eps, &D1, &dJ);
    const double e2 = vertex_energy(J, c.g, c.eps, &D2, &g, nullptr);
    EXPECT_EQ(D1, D2);
    EXPECT_NEAR(e2, e1, 1e-13 * std::abs(e1));
    // The chain rule: ∂E/∂p = (∂E/∂J) g.
    EXPECT_LT((g - dJ * c.g).norm(), 1e-12 * (1 + g.norm()));
  }
}

TEST(FoldoverEnergy, GradientAndHessianMatchDifferences) {
  double worst_g = 0, worst_h = 0;
  for (const Case& c : cases(300, 11)) {
    double D = 0;
    Vector3d g;
    Matrix3d H;
    vertex_energy(c.A + c.p * c.g.transpose(), c.g, c.eps, &D, &g, &H);
    const double h = 1e-6;
    Vector3d gd;
    Matrix3d Hd;
    for (int k = 0; k < 3; ++k) {
      const Vector3d dp = h * Vector3d::Unit(k);
      gd[k] = (energy_at(c, c.p + dp) - energy_at(c, c.p - dp)) / (2 * h);
      Hd.col(k) = (gradient_at(c, c.p + dp) - gradient_at(c, c.p - dp)) / (2 * h);
    }
    worst_g = std::max(worst_g, (g - gd).norm() / (1 + g.norm()));
    worst_h = std::max(worst_h, (H - Hd).norm() / (1 + H.norm()));
    EXPECT_LT((H - H.transpose()).norm(), 1e-12 * (1 + H.norm()));
  }
  // Central differences at h = 1e-6: truncation ~h², rounding ~1e-16/h.
  EXPECT_LT(worst_g, 1e-7);
  EXPECT_LT(worst_h, 1e-6);
}

TEST(FoldoverEnergy, TheUnregularizedEnergyIsABarrier) {
  Matrix3d J = Matrix3d::Identity();
  double D = 0;
  EXPECT_TRUE(std::isfinite(tet_energy(J, 0.0, &D, nullptr)));
  // The identity is the minimum over the scaled maps s I of the energy at eps = 0 (det J = 1).
  const double e1 = tet_energy(J, 0.0, &D, nullptr);
  for (double s : {0.8, 0.95, 1.05, 1.25}) EXPECT_GT(tet_energy(s * J, 0.0, &D, nullptr), e1);
  J(0, 0) = -1;
  const double e = vertex_energy(J, Vector3d(1, 0, 0), 0.0, &D, nullptr, nullptr);
  EXPECT_LT(D, 0);
  EXPECT_FALSE(std::isfinite(e));
}
