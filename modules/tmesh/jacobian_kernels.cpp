#include "tmesh/jacobian_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "bezier/bernstein.h"

// Every kernel also in an AVX2 version, chosen when the program loads (no FMA: see the header).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(VOLTS_NO_TARGET_CLONES)
#define VOLTS_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define VOLTS_KERNEL
#endif
// The kernels' helpers are inlined into every version (a helper called out of line would run the
// default version's code).
#define VOLTS_INLINE inline __attribute__((always_inline))

namespace volts::tmesh::kernels {

static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "arrays of Vector3d are read as arrays of doubles");

GridAxis grid_axis(int degree, const std::vector<double>& t) {
  GridAxis g;
  g.n = degree + 1, g.t = t;
  for (const double x : t) {
    Eigen::VectorXd d;
    const Eigen::VectorXd b = bezier::bernstein_basis(degree, x, &d);
    for (int a = 0; a < g.n; ++a) g.B.push_back(b[a]), g.dB.push_back(d[a]);
  }
  const std::size_t n = static_cast<std::size_t>(g.n), m = t.size();
  g.BT.resize(n * m), g.dBT.resize(n * m);
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t a = 0; a < n; ++a) g.BT[a * m + i] = g.B[i * n + a], g.dBT[a * m + i] = g.dB[i * n + a];
  return g;
}

Eigen::Matrix3d SampleMatrices::matrix(std::size_t s) const {
  Eigen::Matrix3d m;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m(r, c) = entry(r, c)[s];
  return m;
}

void SampleMatrices::set(std::size_t s, const Eigen::Matrix3d& m) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) entry(r, c)[s] = m(r, c);
}

namespace {

constexpr std::size_t kMaxFunctions = 16;  // Bernstein functions per direction (degree 15)

// The sums below keep their partial sums in registers, up to 16 outputs at a time: accumulating in
// the output array itself reloads what the previous term stored, and those stalls took most of
// the time (the loops are short: 4–48 values).

// Four doubles as one value (GCC/Clang vector extension: one AVX register, two SSE2 ones): written
// out so that the compiler does not vectorize the sums' loops over their terms instead, which it
// did with shuffles and in-order scalar adds.
typedef double Double4 __attribute__((vector_size(32)));

// (By reference: a vector passed by value would change the ABI of the default version.)
VOLTS_INLINE void load4(Double4& v, const double* p) { std::memcpy(&v, p, sizeof v); }
VOLTS_INLINE void store4(double* p, const Double4& v) { std::memcpy(p, &v, sizeof v); }

// out[t] = Σ_{i<m} coef[i] in[i stride + t] for t < len (i in order, from zero).
template <std::size_t W>
VOLTS_INLINE void sum_chunk(std::size_t m, const double* __restrict coef, const double* __restrict in, std::size_t stride, double* __restrict out) {
  if constexpr (W % 4 == 0) {
    Double4 acc[W / 4];
    for (std::size_t v = 0; v < W / 4; ++v) acc[v] = Double4{0.0, 0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < m; ++i) {
      const double c = coef[i];
      const double* __restrict x = in + i * stride;
      for (std::size_t v = 0; v < W / 4; ++v) {
        Double4 xv;
        load4(xv, x + 4 * v);
        acc[v] += c * xv;
      }
    }
    for (std::size_t v = 0; v < W / 4; ++v) store4(out + 4 * v, acc[v]);
  } else {
    double acc[W];
    for (std::size_t t = 0; t < W; ++t) acc[t] = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      const double c = coef[i];
      const double* __restrict x = in + i * stride;
      for (std::size_t t = 0; t < W; ++t) acc[t] += c * x[t];
    }
    for (std::size_t t = 0; t < W; ++t) out[t] = acc[t];
  }
}

template <std::size_t Len = 0>
VOLTS_INLINE void sum(std::size_t m, const double* coef, const double* in, std::size_t stride, std::size_t len, double* out) {
  if constexpr (Len > 0 && Len <= 16) return sum_chunk<Len>(m, coef, in, stride, out);
  if constexpr (Len > 16 && Len % 16 == 0) {  // more would not stay in registers
    for (std::size_t t = 0; t < Len; t += 16) sum_chunk<16>(m, coef, in + t, stride, out + t);
    return;
  }
  std::size_t t = 0;
  for (; t + 8 <= len; t += 8) sum_chunk<8>(m, coef, in + t, stride, out + t);
  for (; t < len; ++t) sum_chunk<1>(m, coef, in + t, stride, out + t);
}

// out[t] = init[t] + Σ_{i<m} (ca[i] x[i stride + t] + cb[i] y[i stride + t]) (init null: from zero).
template <std::size_t W>
VOLTS_INLINE void pair_sum_chunk(std::size_t m, const double* __restrict ca, const double* __restrict x, const double* __restrict cb,
                                 const double* __restrict y, std::size_t stride, const double* init, double* out) {
  if constexpr (W % 4 == 0) {
    Double4 acc[W / 4];
    for (std::size_t v = 0; v < W / 4; ++v) {
      acc[v] = Double4{0.0, 0.0, 0.0, 0.0};
      if (init) load4(acc[v], init + 4 * v);
    }
    for (std::size_t i = 0; i < m; ++i) {
      const double a = ca[i], b = cb[i];
      const double* __restrict xi = x + i * stride;
      const double* __restrict yi = y + i * stride;
      for (std::size_t v = 0; v < W / 4; ++v) {
        Double4 xv, yv;
        load4(xv, xi + 4 * v), load4(yv, yi + 4 * v);
        acc[v] += a * xv + b * yv;
      }
    }
    for (std::size_t v = 0; v < W / 4; ++v) store4(out + 4 * v, acc[v]);
  } else {
    double acc[W];
    for (std::size_t t = 0; t < W; ++t) acc[t] = init ? init[t] : 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      const double a = ca[i], b = cb[i];
      const double* __restrict xi = x + i * stride;
      const double* __restrict yi = y + i * stride;
      for (std::size_t t = 0; t < W; ++t) acc[t] += a * xi[t] + b * yi[t];
    }
    for (std::size_t t = 0; t < W; ++t) out[t] = acc[t];
  }
}

template <std::size_t Len = 0>
VOLTS_INLINE void pair_sum(std::size_t m, const double* ca, const double* x, const double* cb, const double* y, std::size_t stride, std::size_t len,
                     const double* init, double* out) {
  if constexpr (Len > 0 && Len <= 16) return pair_sum_chunk<Len>(m, ca, x, cb, y, stride, init, out);
  if constexpr (Len > 16 && Len % 16 == 0) {
    for (std::size_t t = 0; t < Len; t += 16) pair_sum_chunk<16>(m, ca, x + t, cb, y + t, stride, init ? init + t : nullptr, out + t);
    return;
  }
  std::size_t t = 0;
  for (; t + 8 <= len; t += 8) pair_sum_chunk<8>(m, ca, x + t, cb, y + t, stride, init ? init + t : nullptr, out + t);
  for (; t < len; ++t) pair_sum_chunk<1>(m, ca, x + t, cb, y + t, stride, init ? init + t : nullptr, out + t);
}

// o[i] = Σ_a T[a m + i] x[a] (a in order, from zero) for i < m; N functions (0: n of them).
template <std::size_t N>
VOLTS_INLINE void contract(std::size_t n, std::size_t m, const double* __restrict T, const double* __restrict x, double* __restrict o) {
  const std::size_t count = N > 0 ? N : n;
  for (std::size_t i = 0; i < m; ++i) {
    double acc = 0.0;
    for (std::size_t a = 0; a < count; ++a) acc += T[a * m + i] * x[a];
    o[i] = acc;
  }
}

}  // namespace

// Layouts (doubles): Q and W per w-layer k: [b][a][xyz] (L = 3n² doubles); V per (k, j): [a][xyz]
// (R = 3n doubles). Sums run over the contracted index in order from zero, as the Eigen code did.
namespace {
// N > 0: the number of Bernstein functions per direction known at compile time (the loops then
// have fixed lengths); 0: g.u.n.
template <std::size_t N>
VOLTS_INLINE void grid_jacobians_impl(const Eigen::Vector3d* Q, const Grid3& g, SampleMatrices& J, std::size_t first) {
  constexpr std::size_t L_ = 3 * N * N, R_ = 3 * N;
  const std::size_t n = N > 0 ? N : static_cast<std::size_t>(g.u.n), mu = g.u.t.size(), mv = g.v.t.size(), mw = g.w.t.size();
  const std::size_t L = 3 * n * n, R = 3 * n;
  const double* q = Q->data();
  thread_local std::vector<double> W0, W1, V00, V10, V01;
  W0.resize(L * mw), W1.resize(L * mw);
  for (std::size_t k = 0; k < mw; ++k) {  // w
    sum<L_>(n, g.w.B.data() + k * n, q, L, L, W0.data() + L * k);
    sum<L_>(n, g.w.dB.data() + k * n, q, L, L, W1.data() + L * k);
  }
  V00.resize(R * mv * mw), V10.resize(V00.size()), V01.resize(V00.size());
  for (std::size_t k = 0; k < mw; ++k)  // v
    for (std::size_t j = 0; j < mv; ++j) {
      const std::size_t at = R * (j + mv * k);
      sum<R_>(n, g.v.B.data() + j * n, W0.data() + L * k, R, R, V00.data() + at);
      sum<R_>(n, g.v.dB.data() + j * n, W0.data() + L * k, R, R, V10.data() + at);
      sum<R_>(n, g.v.B.data() + j * n, W1.data() + L * k, R, R, V01.data() + at);
    }
  const double* coef[3] = {g.u.dBT.data(), g.u.BT.data(), g.u.BT.data()};  // column c of J: d/du, d/dv, d/dw
  const std::vector<double>* V[3] = {&V00, &V10, &V01};
  for (std::size_t k = 0; k < mw; ++k)  // u
    for (std::size_t j = 0; j < mv; ++j) {
      const std::size_t s0 = first + mu * (j + mv * k);
      for (int c = 0; c < 3; ++c) {
        const double* v = V[c]->data() + R * (j + mv * k);
        for (int r = 0; r < 3; ++r) {
          double x[kMaxFunctions];
          for (std::size_t a = 0; a < n; ++a) x[a] = v[3 * a + static_cast<std::size_t>(r)];
          contract<N>(n, mu, coef[c], x, J.entry(r, c) + s0);
        }
      }
    }
}
}  // namespace

VOLTS_KERNEL void grid_jacobians(const Eigen::Vector3d* Q, const Grid3& g, SampleMatrices& J, std::size_t first) {
  if (g.u.n == 4) return grid_jacobians_impl<4>(Q, g, J, first);  // cubic: the pipeline's degree
  grid_jacobians_impl<0>(Q, g, J, first);
}

double scaled_jacobian_gradient(const Eigen::Matrix3d& J, Eigen::Matrix3d& G) {
  const Eigen::Vector3d n2(J.col(0).squaredNorm(), J.col(1).squaredNorm(), J.col(2).squaredNorm());
  const double D = std::sqrt(n2[0] * n2[1] * n2[2]);
  if (!(D > 0)) {
    G.setZero();
    return 0;
  }
  Eigen::Matrix3d cof;
  cof.col(0) = J.col(1).cross(J.col(2));
  cof.col(1) = J.col(2).cross(J.col(0));
  cof.col(2) = J.col(0).cross(J.col(1));
  const double sj = J.col(0).dot(cof.col(0)) / D;
  for (int c = 0; c < 3; ++c) G.col(c) = cof.col(c) / D - sj * J.col(c) / n2[c];
  return sj;
}

// bezier::scaled_jacobian per sample, written without branches (both sides computed, then chosen)
// so that the loop vectorizes; the arithmetic is Eigen's: norms (x² + y²) + z², the determinant by
// its first-row expansion, the product (n0 n1) n2.
VOLTS_KERNEL void scaled_jacobians(const SampleMatrices& J, double* out) {
  const std::size_t m = J.size();
  const double *__restrict m00 = J.entry(0, 0), *__restrict m10 = J.entry(1, 0), *__restrict m20 = J.entry(2, 0);
  const double *__restrict m01 = J.entry(0, 1), *__restrict m11 = J.entry(1, 1), *__restrict m21 = J.entry(2, 1);
  const double *__restrict m02 = J.entry(0, 2), *__restrict m12 = J.entry(1, 2), *__restrict m22 = J.entry(2, 2);
  for (std::size_t s = 0; s < m; ++s) {
    const double n0 = std::sqrt(m00[s] * m00[s] + m10[s] * m10[s] + m20[s] * m20[s]);
    const double n1 = std::sqrt(m01[s] * m01[s] + m11[s] * m11[s] + m21[s] * m21[s]);
    const double n2 = std::sqrt(m02[s] * m02[s] + m12[s] * m12[s] + m22[s] * m22[s]);
    const double det = m00[s] * (m11[s] * m22[s] - m12[s] * m21[s]) - m01[s] * (m10[s] * m22[s] - m12[s] * m20[s]) +
                       m02[s] * (m10[s] * m21[s] - m11[s] * m20[s]);
    const double v = det / (n0 * n1 * n2);
    const double clamped = v < -1.0 ? -1.0 : (1.0 < v ? 1.0 : v);
    out[s] = ((n0 == 0.0) | (n1 == 0.0) | (n2 == 0.0)) ? 0.0 : clamped;  // | not ||: no branch
  }
}

namespace {

typedef long long Long4 __attribute__((vector_size(32)));

// Samples [s, s + 4) of weighted_gradients in Double4 lanes (the compiler does not vectorize the
// loop over samples by itself); per lane the arithmetic of scaled_jacobian_gradient.
VOLTS_INLINE void weighted_gradients_4(double* const* e, const double* weight, std::size_t s) {
  Double4 x0, y0, z0, x1, y1, z1, x2, y2, z2, w;
  load4(x0, e[0] + s), load4(y0, e[1] + s), load4(z0, e[2] + s);
  load4(x1, e[3] + s), load4(y1, e[4] + s), load4(z1, e[5] + s);
  load4(x2, e[6] + s), load4(y2, e[7] + s), load4(z2, e[8] + s);
  load4(w, weight + s);
  const Double4 q0 = x0 * x0 + y0 * y0 + z0 * z0, q1 = x1 * x1 + y1 * y1 + z1 * z1, q2 = x2 * x2 + y2 * y2 + z2 * z2;
  const Double4 P = q0 * q1 * q2;
  Double4 D;
  for (int l = 0; l < 4; ++l) D[l] = std::sqrt(P[l]);
  const Double4 a0 = y1 * z2 - z1 * y2, b0 = z1 * x2 - x1 * z2, c0 = x1 * y2 - y1 * x2;
  const Double4 a1 = y2 * z0 - z2 * y0, b1 = z2 * x0 - x2 * z0, c1 = x2 * y0 - y2 * x0;
  const Double4 a2 = y0 * z1 - z0 * y1, b2 = z0 * x1 - x0 * z1, c2 = x0 * y1 - y0 * x1;
  const Double4 sj = (x0 * a0 + y0 * b0 + z0 * c0) / D;
  const Long4 keep = (D > 0) & (w != 0);  // all ones where kept: the bits pass unchanged, else +0
  auto put = [&](double* p, const Double4& g) {
    const Double4 kept = reinterpret_cast<Double4>(reinterpret_cast<Long4>(g) & keep);
    store4(p + s, kept);
  };
  put(e[0], (a0 / D - sj * x0 / q0) * w), put(e[1], (b0 / D - sj * y0 / q0) * w), put(e[2], (c0 / D - sj * z0 / q0) * w);
  put(e[3], (a1 / D - sj * x1 / q1) * w), put(e[4], (b1 / D - sj * y1 / q1) * w), put(e[5], (c1 / D - sj * z1 / q1) * w);
  put(e[6], (a2 / D - sj * x2 / q2) * w), put(e[7], (b2 / D - sj * y2 / q2) * w), put(e[8], (c2 / D - sj * z2 / q2) * w);
}

}  // namespace

// ∂(det J / (|J0||J1||J2|))/∂J = cof/D - sj J_c/|J_c|², ∂det/∂J_c the cross product of the other
// two columns; per entry as the Eigen code computed it: (cof / D - (sj J) / |J_c|²) · weight.
VOLTS_KERNEL void weighted_gradients(SampleMatrices& J, const double* weight) {
  const std::size_t m = J.size();
  double* e[9] = {J.entry(0, 0), J.entry(1, 0), J.entry(2, 0), J.entry(0, 1), J.entry(1, 1), J.entry(2, 1), J.entry(0, 2), J.entry(1, 2), J.entry(2, 2)};
  // Blocks of 4 samples; a block whose weights are all 0 (many: the soft minimum's weights fall
  // off fast) is only zeroed.
  for (std::size_t s0 = 0; s0 < m; s0 += 4) {
    const std::size_t end = std::min(m, s0 + 4);
    bool any = false;
    for (std::size_t s = s0; s < end; ++s) any = any || weight[s] != 0.0;
    if (!any)
      for (double* p : e) std::fill(p + s0, p + end, 0.0);
    else if (end == s0 + 4)
      weighted_gradients_4(e, weight, s0);
    else {  // the last samples, padded with weight 0
      double buffer[9][4] = {}, w[4] = {};
      double* b[9];
      for (int c = 0; c < 9; ++c) b[c] = buffer[c], std::copy(e[c] + s0, e[c] + end, buffer[c]);
      std::copy(weight + s0, weight + end, w);
      weighted_gradients_4(b, w, 0);
      for (int c = 0; c < 9; ++c) std::copy(buffer[c], buffer[c] + (end - s0), e[c] + s0);
    }
  }
}

namespace {

// Layouts (doubles) as in grid_jacobians: V per (k, j): [a][xyz]; W per w-layer k: [b][a][xyz] (that
// of dQ). Each sum in the order of the Eigen code (i, then j, then k, from zero; dQ from its value).
template <std::size_t N>
VOLTS_INLINE void grid_pull_back_impl(const SampleMatrices& G, std::size_t first, const Grid3& g, Eigen::Vector3d* dQ) {
  constexpr std::size_t L_ = 3 * N * N, R_ = 3 * N;
  const std::size_t n = N > 0 ? N : static_cast<std::size_t>(g.u.n), mu = g.u.t.size(), mv = g.v.t.size(), mw = g.w.t.size();
  const std::size_t L = 3 * n * n, R = 3 * n;
  thread_local std::vector<double> W0, W1, V00, V10, V01;
  V00.resize(R * mv * mw), V10.resize(V00.size()), V01.resize(V00.size());
  for (std::size_t k = 0; k < mw; ++k)  // u: V[a][r] = Σ_i G(r, c)[s] B_a(t_i)
    for (std::size_t j = 0; j < mv; ++j) {
      const std::size_t s0 = first + mu * (j + mv * k), at = R * (j + mv * k);
      for (std::size_t r = 0; r < 3; ++r) {
        double t0[kMaxFunctions], t1[kMaxFunctions], t2[kMaxFunctions];
        sum<N>(mu, G.entry(static_cast<int>(r), 0) + s0, g.u.dB.data(), n, n, t0);
        sum<N>(mu, G.entry(static_cast<int>(r), 1) + s0, g.u.B.data(), n, n, t1);
        sum<N>(mu, G.entry(static_cast<int>(r), 2) + s0, g.u.B.data(), n, n, t2);
        for (std::size_t a = 0; a < n; ++a) V00[at + 3 * a + r] = t0[a], V10[at + 3 * a + r] = t1[a], V01[at + 3 * a + r] = t2[a];
      }
    }
  W0.resize(L * mw), W1.resize(W0.size());
  for (std::size_t k = 0; k < mw; ++k)  // v
    for (std::size_t b = 0; b < n; ++b) {
      const double* bv = g.v.BT.data() + b * mv;
      const double* dbv = g.v.dBT.data() + b * mv;
      pair_sum<R_>(mv, bv, V00.data() + R * mv * k, dbv, V10.data() + R * mv * k, R, R, nullptr, W0.data() + L * k + R * b);
      sum<R_>(mv, bv, V01.data() + R * mv * k, R, R, W1.data() + L * k + R * b);
    }
  double* dq = dQ->data();
  for (std::size_t c = 0; c < n; ++c)  // w
    pair_sum<L_>(mw, g.w.BT.data() + c * mw, W0.data(), g.w.dBT.data() + c * mw, W1.data(), L, L, dq + L * c, dq + L * c);
}
}  // namespace

VOLTS_KERNEL void grid_pull_back(const SampleMatrices& G, std::size_t first, const Grid3& g, Eigen::Vector3d* dQ) {
  if (g.u.n == 4) return grid_pull_back_impl<4>(G, first, g, dQ);
  grid_pull_back_impl<0>(G, first, g, dQ);
}

namespace {

// u: per row of n points (3 doubles each), out[i] = Σ_a C(a, i) in[a] — or with `transpose`
// Σ_a C(i, a) in[a] — per coordinate.
template <std::size_t N>
VOLTS_INLINE void rows_u(std::size_t n, const double* C, bool transpose, const double* in, double* out) {
  const std::size_t count = N > 0 ? N : n, R = 3 * count;
  for (std::size_t row = 0; row < count * count; ++row) {
    const double* __restrict p = in + R * row;
    double* __restrict o = out + R * row;
    for (std::size_t i = 0; i < count; ++i) {
      double s0 = 0.0, s1 = 0.0, s2 = 0.0;
      for (std::size_t a = 0; a < count; ++a) {
        const double c = transpose ? C[i + count * a] : C[a + count * i];
        s0 += c * p[3 * a], s1 += c * p[3 * a + 1], s2 += c * p[3 * a + 2];
      }
      o[3 * i] = s0, o[3 * i + 1] = s1, o[3 * i + 2] = s2;
    }
  }
}

template <std::size_t N>
VOLTS_INLINE void tensor_extract_impl(std::size_t n, const double* Cu, const double* Cv, const double* Cw, const double* P, double* Q) {
  constexpr std::size_t L_ = 3 * N * N, R_ = 3 * N;
  const std::size_t L = 3 * n * n, R = 3 * n;
  thread_local std::vector<double> T1, T2;
  T1.resize(L * n), T2.resize(L * n);
  rows_u<N>(n, Cu, false, P, T1.data());
  for (std::size_t k = 0; k < n; ++k)  // v: column j of Cv over the rows b of layer k
    for (std::size_t j = 0; j < n; ++j) sum<R_>(n, Cv + n * j, T1.data() + L * k, R, R, T2.data() + L * k + R * j);
  for (std::size_t c = 0; c < n; ++c) sum<L_>(n, Cw + n * c, T2.data(), L, L, Q + L * c);  // w
}

template <std::size_t N>
VOLTS_INLINE void tensor_extract_transpose_impl(std::size_t n, const double* Cu, const double* Cv, const double* Cw, double* G) {
  constexpr std::size_t L_ = 3 * N * N, R_ = 3 * N;
  const std::size_t L = 3 * n * n, R = 3 * n;
  thread_local std::vector<double> T;
  T.resize(L * n);
  double row[kMaxFunctions];
  for (std::size_t a = 0; a < n; ++a) {  // w: row a of Cw over the layers
    for (std::size_t i = 0; i < n; ++i) row[i] = Cw[a + n * i];
    sum<L_>(n, row, G, L, L, T.data() + L * a);
  }
  for (std::size_t b = 0; b < n; ++b) {  // v
    for (std::size_t i = 0; i < n; ++i) row[i] = Cv[b + n * i];
    for (std::size_t k = 0; k < n; ++k) sum<R_>(n, row, T.data() + L * k, R, R, G + L * k + R * b);
  }
  std::copy(G, G + L * n, T.data());
  rows_u<N>(n, Cu, true, T.data(), G);  // u
}

}  // namespace

VOLTS_KERNEL void tensor_extract(int n, const double* Cu, const double* Cv, const double* Cw, const Eigen::Vector3d* P, Eigen::Vector3d* Q) {
  if (n == 4) return tensor_extract_impl<4>(4, Cu, Cv, Cw, P->data(), Q->data());
  tensor_extract_impl<0>(static_cast<std::size_t>(n), Cu, Cv, Cw, P->data(), Q->data());
}

VOLTS_KERNEL void tensor_extract_transpose(int n, const double* Cu, const double* Cv, const double* Cw, Eigen::Vector3d* G) {
  if (n == 4) return tensor_extract_transpose_impl<4>(4, Cu, Cv, Cw, G->data());
  tensor_extract_transpose_impl<0>(static_cast<std::size_t>(n), Cu, Cv, Cw, G->data());
}

}  // namespace volts::tmesh::kernels
