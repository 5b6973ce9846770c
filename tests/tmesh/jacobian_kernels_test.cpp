// The joint rounds' kernels (tmesh/jacobian_kernels.h): Jacobians on sample grids equal the hex's
// own evaluation, the pull-back is their exact transpose, the gradient is the scaled Jacobian's,
// and every result has the bits of the scalar Eigen code the kernels replaced (kept here as the
// reference), so runs do not depend on which version (AVX2 or not) the machine picks. This file
// is built twice: against the library (the version the loader picks) and with the kernels
// compiled without target clones (test_jacobian_kernels_default).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "bezier/bernstein.h"
#include "bezier/bezier_hex.h"
#include "bezier/quadrature.h"
#include "tmesh/jacobian_kernels.h"

using namespace volts;
using namespace volts::tmesh::kernels;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

// The reference: the optimizer's scalar Eigen code before the kernels (session 36), verbatim in
// its arithmetic.
void reference_jacobians(const std::vector<Vector3d>& Q, const Grid3& g, std::vector<Matrix3d>& J) {
  const std::size_t n = static_cast<std::size_t>(g.u.n), mu = g.u.t.size(), mv = g.v.t.size(), mw = g.w.t.size();
  std::vector<Vector3d> W0(n * n * mw, Vector3d::Zero()), W1(W0.size(), Vector3d::Zero());
  for (std::size_t k = 0; k < mw; ++k)
    for (std::size_t c = 0; c < n; ++c) {
      const double bc = g.w.B[k * n + c], dc = g.w.dB[k * n + c];
      for (std::size_t ab = 0; ab < n * n; ++ab) W0[ab + n * n * k] += bc * Q[ab + n * n * c], W1[ab + n * n * k] += dc * Q[ab + n * n * c];
    }
  std::vector<Vector3d> V00(n * mv * mw, Vector3d::Zero()), V10(V00.size(), Vector3d::Zero()), V01(V00.size(), Vector3d::Zero());
  for (std::size_t k = 0; k < mw; ++k)
    for (std::size_t j = 0; j < mv; ++j)
      for (std::size_t b = 0; b < n; ++b) {
        const double bb = g.v.B[j * n + b], db = g.v.dB[j * n + b];
        for (std::size_t a = 0; a < n; ++a) {
          const std::size_t in = a + n * (b + n * k), out = a + n * (j + mv * k);
          V00[out] += bb * W0[in], V10[out] += db * W0[in], V01[out] += bb * W1[in];
        }
      }
  for (std::size_t k = 0; k < mw; ++k)
    for (std::size_t j = 0; j < mv; ++j)
      for (std::size_t i = 0; i < mu; ++i) {
        Matrix3d M = Matrix3d::Zero();
        for (std::size_t a = 0; a < n; ++a) {
          const std::size_t in = a + n * (j + mv * k);
          M.col(0) += g.u.dB[i * n + a] * V00[in], M.col(1) += g.u.B[i * n + a] * V10[in], M.col(2) += g.u.B[i * n + a] * V01[in];
        }
        J.push_back(M);
      }
}

void reference_pull_back(const std::vector<Matrix3d>& G, const Grid3& g, std::vector<Vector3d>& dQ) {
  const std::size_t n = static_cast<std::size_t>(g.u.n), mu = g.u.t.size(), mv = g.v.t.size(), mw = g.w.t.size();
  std::vector<Vector3d> V00(n * mv * mw, Vector3d::Zero()), V10(V00.size(), Vector3d::Zero()), V01(V00.size(), Vector3d::Zero());
  for (std::size_t k = 0; k < mw; ++k)
    for (std::size_t j = 0; j < mv; ++j)
      for (std::size_t i = 0; i < mu; ++i) {
        const Matrix3d& M = G[i + mu * (j + mv * k)];
        for (std::size_t a = 0; a < n; ++a) {
          const std::size_t out = a + n * (j + mv * k);
          V00[out] += g.u.dB[i * n + a] * M.col(0), V10[out] += g.u.B[i * n + a] * M.col(1), V01[out] += g.u.B[i * n + a] * M.col(2);
        }
      }
  std::vector<Vector3d> W0(n * n * mw, Vector3d::Zero()), W1(W0.size(), Vector3d::Zero());
  for (std::size_t k = 0; k < mw; ++k)
    for (std::size_t j = 0; j < mv; ++j)
      for (std::size_t b = 0; b < n; ++b) {
        const double bb = g.v.B[j * n + b], db = g.v.dB[j * n + b];
        for (std::size_t a = 0; a < n; ++a) {
          const std::size_t in = a + n * (j + mv * k), out = a + n * (b + n * k);
          W0[out] += bb * V00[in] + db * V10[in], W1[out] += bb * V01[in];
        }
      }
  for (std::size_t k = 0; k < mw; ++k)
    for (std::size_t c = 0; c < n; ++c) {
      const double bc = g.w.B[k * n + c], dc = g.w.dB[k * n + c];
      for (std::size_t ab = 0; ab < n * n; ++ab) dQ[ab + n * n * c] += bc * W0[ab + n * n * k] + dc * W1[ab + n * n * k];
    }
}

std::vector<double> uniform(int m) {
  std::vector<double> t;
  for (int i = 0; i < m; ++i) t.push_back(m == 1 ? 0.5 : i / (m - 1.0));
  return t;
}

// The grids the optimizer uses (uniform with the corners, Gauss points, the dense check grid, a
// fold's 3 points per axis around a witness: one axis different from the others) for degree p.
std::vector<Grid3> grids(int p) {
  auto iso = [](const GridAxis& a) { return Grid3{a, a, a}; };
  return {iso(grid_axis(p, uniform(5))), iso(grid_axis(p, bezier::gauss_legendre_points(4))), iso(grid_axis(p, uniform(7))),
          Grid3{grid_axis(p, {0.1, 0.2, 0.3}), grid_axis(p, {0.0, 0.5}), grid_axis(p, {0.7, 0.8, 0.9, 1.0})}};
}

// A distorted hex of degree p (its points off the unit lattice by up to `noise`), some inverted.
bezier::BezierHex random_hex(int p, std::mt19937& rng, double noise) {
  std::uniform_real_distribution<double> d(-noise, noise);
  bezier::BezierHex h;
  h.degree = {p, p, p};
  for (int k = 0; k <= p; ++k)
    for (int j = 0; j <= p; ++j)
      for (int i = 0; i <= p; ++i) h.points.push_back(Vector3d(i, 1.5 * j, 0.7 * k) / p + Vector3d(d(rng), d(rng), d(rng)));
  return h;
}

Matrix3d random_matrix(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1, 1);
  Matrix3d m;
  for (int i = 0; i < 9; ++i) m(i % 3, i / 3) = d(rng);
  return m;
}

}  // namespace

TEST(JacobianKernels, JacobiansAreTheHexsOwnAndHaveTheReferenceBits) {
  std::mt19937 rng(7);
  for (int p = 1; p <= 4; ++p)
    for (int trial = 0; trial < 6; ++trial) {
      const bezier::BezierHex h = random_hex(p, rng, trial < 3 ? 0.05 : 0.6);
      for (const Grid3& g : grids(p)) {
        SampleMatrices J;
        J.resize(g.size() + 3);
        grid_jacobians(h.points.data(), g, J, 3);  // at an offset, as the optimizer appends grids
        std::vector<Matrix3d> ref;
        reference_jacobians(h.points, g, ref);
        ASSERT_EQ(ref.size(), g.size());
        for (std::size_t s = 0; s < g.size(); ++s) {
          const Matrix3d m = J.matrix(3 + s);
          for (int e = 0; e < 9; ++e) ASSERT_EQ(m(e % 3, e / 3), ref[s](e % 3, e / 3)) << "degree " << p << " sample " << s;
          const std::size_t i = s % g.u.t.size(), j = (s / g.u.t.size()) % g.v.t.size(), k = s / (g.u.t.size() * g.v.t.size());
          Matrix3d direct;
          bezier::evaluate(h, Vector3d(g.u.t[i], g.v.t[j], g.w.t[k]), &direct);
          EXPECT_LT((m - direct).norm(), 1e-12 * (1 + direct.norm())) << "degree " << p << " sample " << s;
        }
      }
    }
}

TEST(JacobianKernels, ScaledJacobiansHaveTheBitsOfBezierScaledJacobian) {
  std::mt19937 rng(11);
  std::vector<Matrix3d> ms;
  for (int i = 0; i < 997; ++i) ms.push_back(random_matrix(rng));  // not a multiple of any vector width
  Matrix3d degenerate = random_matrix(rng);
  degenerate.col(1).setZero();
  ms.push_back(degenerate);
  Matrix3d flat = random_matrix(rng);
  flat.col(2) = 2.0 * flat.col(0);
  ms.push_back(flat);
  ms.push_back(-Matrix3d::Identity());
  SampleMatrices J;
  J.resize(ms.size());
  for (std::size_t s = 0; s < ms.size(); ++s) J.set(s, ms[s]);
  std::vector<double> out(ms.size());
  scaled_jacobians(J, out.data());
  int negative = 0;
  for (std::size_t s = 0; s < ms.size(); ++s) {
    ASSERT_EQ(out[s], bezier::scaled_jacobian(ms[s])) << "sample " << s;
    negative += out[s] < 0 ? 1 : 0;
  }
  EXPECT_EQ(out[997], 0.0);   // a vanishing column
  EXPECT_EQ(out[999], -1.0);  // an inverted frame
  EXPECT_GT(negative, 300);    // both signs were exercised
}

TEST(JacobianKernels, WeightedGradientsAreTheScaledJacobiansDerivativeWithTheReferenceBits) {
  std::mt19937 rng(13);
  std::vector<Matrix3d> ms;
  std::vector<double> w;
  std::uniform_real_distribution<double> d(0, 1);
  for (int i = 0; i < 203; ++i) {
    ms.push_back(random_matrix(rng));
    w.push_back(i % 16 < 8 && i % 5 ? d(rng) : 0.0);  // whole blocks of 8 without weight, and single zeros
  }
  ms[17].col(0).setZero();
  SampleMatrices J;
  J.resize(ms.size());
  for (std::size_t s = 0; s < ms.size(); ++s) J.set(s, ms[s]);
  weighted_gradients(J, w.data());
  for (std::size_t s = 0; s < ms.size(); ++s) {
    Matrix3d G;
    scaled_jacobian_gradient(ms[s], G);
    const Matrix3d expected = w[s] == 0.0 ? Matrix3d::Zero() : Matrix3d(G * w[s]);
    const Matrix3d got = J.matrix(s);
    for (int e = 0; e < 9; ++e) ASSERT_EQ(got(e % 3, e / 3), expected(e % 3, e / 3)) << "sample " << s;
    if (w[s] == 0.0 || s == 17) continue;
    // Central differences of bezier::scaled_jacobian (away from the clamp at ±1).
    if (std::abs(bezier::scaled_jacobian(ms[s])) > 0.99) continue;
    for (int e = 0; e < 9; ++e) {
      const double h = 1e-6;
      Matrix3d a = ms[s], b = ms[s];
      a(e % 3, e / 3) += h, b(e % 3, e / 3) -= h;
      const double fd = (bezier::scaled_jacobian(a) - bezier::scaled_jacobian(b)) / (2 * h);
      EXPECT_NEAR(got(e % 3, e / 3), w[s] * fd, 1e-6 * (1 + std::abs(fd))) << "sample " << s << " entry " << e;
    }
  }
  EXPECT_EQ(J.matrix(17), Matrix3d::Zero());  // a vanishing column: no direction to move
}

TEST(JacobianKernels, PullBackIsTheTransposeAndHasTheReferenceBits) {
  std::mt19937 rng(17);
  for (int p = 1; p <= 4; ++p)
    for (const Grid3& g : grids(p)) {
      const bezier::BezierHex h = random_hex(p, rng, 0.3);
      const std::size_t np = h.points.size();
      std::vector<Matrix3d> G;
      for (std::size_t s = 0; s < g.size(); ++s) G.push_back(random_matrix(rng));
      SampleMatrices Gs;
      Gs.resize(g.size() + 2);
      for (std::size_t s = 0; s < g.size(); ++s) Gs.set(2 + s, G[s]);
      std::vector<Vector3d> start(np);
      for (Vector3d& x : start) x = random_matrix(rng).col(0);
      std::vector<Vector3d> dQ = start, ref = start;  // both add to what is there
      grid_pull_back(Gs, 2, g, dQ.data());
      reference_pull_back(G, g, ref);
      for (std::size_t i = 0; i < np; ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(dQ[i][c], ref[i][c]) << "degree " << p << " point " << i;
      // <G, J(Q)> = <pull_back(G), Q>: J is linear in Q.
      SampleMatrices J;
      J.resize(g.size());
      grid_jacobians(h.points.data(), g, J, 0);
      double lhs = 0, rhs = 0, scale = 0;
      for (std::size_t s = 0; s < g.size(); ++s) lhs += (G[s].array() * J.matrix(s).array()).sum(), scale += G[s].norm() * J.matrix(s).norm();
      for (std::size_t i = 0; i < np; ++i) rhs += (dQ[i] - start[i]).dot(h.points[i]);
      EXPECT_NEAR(lhs, rhs, 1e-13 * scale) << "degree " << p;
    }
}

namespace {

// The reference: Spline::hex_points' and Spline::pull_back's scalar Eigen code before the kernels.
void reference_extract(int n, const std::array<Eigen::MatrixXd, 3>& C, std::vector<Vector3d> P, std::vector<Vector3d>& Q) {
  Q.assign(P.size(), Vector3d::Zero());
  auto apply = [&](const Eigen::MatrixXd& M, int stride, std::vector<Vector3d>& in, std::vector<Vector3d>& out) {
    for (std::size_t idx = 0; idx < in.size(); ++idx) {
      const int along = (static_cast<int>(idx) / stride) % n;
      const std::size_t base = idx - static_cast<std::size_t>(along * stride);
      Vector3d s = Vector3d::Zero();
      for (int a = 0; a < n; ++a) s += M(a, along) * in[base + static_cast<std::size_t>(a * stride)];
      out[idx] = s;
    }
  };
  apply(C[0], 1, P, Q);
  apply(C[1], n, Q, P);
  apply(C[2], n * n, P, Q);
}

void reference_extract_transpose(int n, const std::array<Eigen::MatrixXd, 3>& C, std::vector<Vector3d>& g) {
  std::vector<Vector3d> tmp(g.size(), Vector3d::Zero());
  auto apply_t = [&](const Eigen::MatrixXd& M, int stride, const std::vector<Vector3d>& out, std::vector<Vector3d>& in) {
    std::fill(in.begin(), in.end(), Vector3d::Zero());
    for (std::size_t idx = 0; idx < out.size(); ++idx) {
      const int along = (static_cast<int>(idx) / stride) % n;
      const std::size_t base = idx - static_cast<std::size_t>(along * stride);
      for (int a = 0; a < n; ++a) in[base + static_cast<std::size_t>(a * stride)] += M(a, along) * out[idx];
    }
  };
  apply_t(C[2], n * n, g, tmp);
  apply_t(C[1], n, tmp, g);
  apply_t(C[0], 1, g, tmp);
  g.swap(tmp);
}

}  // namespace

TEST(JacobianKernels, TensorExtractionAndItsTransposeHaveTheReferenceBits) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> d(-1, 1);
  for (int p = 1; p <= 4; ++p) {
    const int n = p + 1;
    for (int trial = 0; trial < 5; ++trial) {
      std::array<Eigen::MatrixXd, 3> C;
      for (auto& M : C) M = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return d(rng); });
      std::vector<Vector3d> P(static_cast<std::size_t>(n * n * n)), G(P.size());
      for (auto& x : P) x = Vector3d(d(rng), d(rng), d(rng));
      for (auto& x : G) x = Vector3d(d(rng), d(rng), d(rng));
      std::vector<Vector3d> Q(P.size()), ref;
      tensor_extract(n, C[0].data(), C[1].data(), C[2].data(), P.data(), Q.data());
      reference_extract(n, C, P, ref);
      for (std::size_t i = 0; i < P.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(Q[i][c], ref[i][c]) << "degree " << p << " point " << i;
      std::vector<Vector3d> T = G, refT = G;
      tensor_extract_transpose(n, C[0].data(), C[1].data(), C[2].data(), T.data());
      reference_extract_transpose(n, C, refT);
      for (std::size_t i = 0; i < P.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(T[i][c], refT[i][c]) << "degree " << p << " point " << i;
      // <G, extract(P)> = <transpose(G), P>
      double lhs = 0, rhs = 0, scale = 0;
      for (std::size_t i = 0; i < P.size(); ++i) lhs += G[i].dot(Q[i]), rhs += T[i].dot(P[i]), scale += G[i].norm() * Q[i].norm();
      EXPECT_NEAR(lhs, rhs, 1e-13 * scale) << "degree " << p;
      // Identity matrices: the points themselves.
      const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
      tensor_extract(n, I.data(), I.data(), I.data(), P.data(), Q.data());
      for (std::size_t i = 0; i < P.size(); ++i) EXPECT_EQ(Q[i], P[i]);
    }
  }
}
