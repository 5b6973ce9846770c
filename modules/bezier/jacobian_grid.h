// volts::bezier — the partial derivatives of a polynomial Bézier hex on a tensor grid of
// parameter values, by sum factorization: S = Σ_i B_i(u) P_ijk once per (u, j, k), T = Σ_j B_j(v) S
// once per (u, v, k), then Σ_k B_k(w) T per point. Every sum adds its terms in index order from
// zero, so a point's values do not depend on the grid around it (jacobian_samples and the tmesh
// optimizer's x rows rely on getting the same bits). Header-only: V is Eigen::Vector3d (points) or
// double (one coordinate).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstddef>
#include <vector>

namespace volts::bezier {

/// Bernstein values B and derivatives dB of one direction's degree at the grid's coordinates.
struct AxisBases {
  std::vector<Eigen::VectorXd> B, dB;
};

namespace detail {
inline double zero_like(double) { return 0.0; }
inline Eigen::Vector3d zero_like(const Eigen::Vector3d&) { return Eigen::Vector3d::Zero(); }
}  // namespace detail

/// Appends (d/du, d/dv, d/dw) at the grid points (axes[0] coordinates a in [from, to), likewise b
/// and c; a fastest) of the polynomial hex of `degree` with control points `P` in index order
/// i + (p+1)(j + (q+1)k).
template <class V>
void grid_derivatives(const std::array<int, 3>& degree, const V* P, const std::array<AxisBases, 3>& axes, std::size_t from,
                      std::size_t to, std::vector<std::array<V, 3>>& out) {
  const std::size_t ni = static_cast<std::size_t>(degree[0] + 1), nj = static_cast<std::size_t>(degree[1] + 1),
                    nk = static_cast<std::size_t>(degree[2] + 1), G = to - from;
  const V zero = detail::zero_like(P[0]);
  thread_local std::vector<V> S, Su, T, Tu, Tv;
  S.resize(G * nj * nk), Su.resize(S.size());
  for (std::size_t a = 0; a < G; ++a) {
    const Eigen::VectorXd &Bu = axes[0].B[from + a], &dBu = axes[0].dB[from + a];
    for (std::size_t k = 0; k < nk; ++k)
      for (std::size_t j = 0; j < nj; ++j) {
        V s = zero, su = zero;
        const V* row = P + ni * (j + nj * k);
        for (std::size_t i = 0; i < ni; ++i) {
          const Eigen::Index x = static_cast<Eigen::Index>(i);
          s += Bu[x] * row[i], su += dBu[x] * row[i];
        }
        S[a + G * (j + nj * k)] = s, Su[a + G * (j + nj * k)] = su;
      }
  }
  T.resize(G * G * nk), Tu.resize(T.size()), Tv.resize(T.size());
  for (std::size_t b = 0; b < G; ++b) {
    const Eigen::VectorXd &Bv = axes[1].B[from + b], &dBv = axes[1].dB[from + b];
    for (std::size_t a = 0; a < G; ++a)
      for (std::size_t k = 0; k < nk; ++k) {
        V t = zero, tu = zero, tv = zero;
        for (std::size_t j = 0; j < nj; ++j) {
          const Eigen::Index x = static_cast<Eigen::Index>(j);
          const V& s = S[a + G * (j + nj * k)];
          t += Bv[x] * s, tu += Bv[x] * Su[a + G * (j + nj * k)], tv += dBv[x] * s;
        }
        const std::size_t at = a + G * (b + G * k);
        T[at] = t, Tu[at] = tu, Tv[at] = tv;
      }
  }
  for (std::size_t c = 0; c < G; ++c) {
    const Eigen::VectorXd &Bw = axes[2].B[from + c], &dBw = axes[2].dB[from + c];
    for (std::size_t b = 0; b < G; ++b)
      for (std::size_t a = 0; a < G; ++a) {
        V xu = zero, xv = zero, xw = zero;
        for (std::size_t k = 0; k < nk; ++k) {
          const Eigen::Index x = static_cast<Eigen::Index>(k);
          const std::size_t at = a + G * (b + G * k);
          xu += Bw[x] * Tu[at], xv += Bw[x] * Tv[at], xw += dBw[x] * T[at];
        }
        out.push_back({xu, xv, xw});
      }
  }
}

}  // namespace volts::bezier
