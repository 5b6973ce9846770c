#include "bezier/jacobian_bernstein.h"

#include <array>
#include <type_traits>
#include <vector>

#include "core/errors.h"

namespace volts::bezier {

namespace {

// C(n, k) for n < 64, built once.
struct BinomialTable {
  double c[64][64] = {};
  BinomialTable() {
    for (int n = 0; n < 64; ++n) {
      c[n][0] = 1;
      for (int k = 1; k <= n; ++k) c[n][k] = c[n - 1][k - 1] + (k < n ? c[n - 1][k] : 0.0);
    }
  }
};
const BinomialTable kBinom;

struct Workspace {
  std::vector<double> du, dv, dw, cr, acc, inv;
  std::array<int, 3> inv_degree{-1, -1, -1};
};

// det J of a polynomial hex by products of scaled Bernstein arrays (ĉ_i = c_i C(n,i): products
// are plain convolutions). x_v × x_w first (6 products of the small nets), then its dot product
// with x_u, then unscaling. CP, CQ, CR > 0 fix the degrees at compile time (fully unrolled inner
// loops); 0 takes them from rp, rq, rr.
template <int CP, int CQ, int CR>
void det_kernel(int rp, int rq, int rr, const std::vector<Eigen::Vector3d>& P, Workspace& ws, double* __restrict out) {
  const int p = CP ? CP : rp, q = CQ ? CQ : rq, r = CR ? CR : rr;
  const int p1 = p + 1, q1 = q + 1, r1 = r + 1;
  const int nu = p * q1 * r1, nv = p1 * q * r1, nw = p1 * q1 * r;
  // The i extent of cr is padded to a multiple of 4 with zeros (whole SIMD vectors in the inner
  // loops); the padded product `acc` has i extent p + c0 - 1 >= 3p and is compacted at the end.
  const int c0 = (2 * p + 1 + 3) / 4 * 4, c1 = 2 * q, c2 = 2 * r, nc = c0 * c1 * c2;
  const int o0 = 3 * p, o1 = 3 * q, o2 = 3 * r, no = o0 * o1 * o2;
  const int a0 = p + c0 - 1, na = a0 * o1 * o2;
  ws.du.resize(3 * nu);
  ws.dv.resize(3 * nv);
  ws.dw.resize(3 * nw);
  ws.cr.assign(3 * nc, 0.0);
  ws.acc.assign(na, 0.0);
  double* __restrict du = ws.du.data();
  double* __restrict dv = ws.dv.data();
  double* __restrict dw = ws.dw.data();
  double* __restrict cr = ws.cr.data();
  double* __restrict acc = ws.acc.data();
  const auto at = [&](int i, int j, int k) -> const Eigen::Vector3d& { return P[i + p1 * (j + q1 * k)]; };
  for (int k = 0; k < r1; ++k)
    for (int j = 0; j < q1; ++j)
      for (int i = 0; i < p1; ++i) {
        if (i < p) {
          const double s = p * kBinom.c[p - 1][i] * kBinom.c[q][j] * kBinom.c[r][k];
          const Eigen::Vector3d d = s * (at(i + 1, j, k) - at(i, j, k));
          const int n = i + p * (j + q1 * k);
          for (int c = 0; c < 3; ++c) du[c * nu + n] = d[c];
        }
        if (j < q) {
          const double s = q * kBinom.c[p][i] * kBinom.c[q - 1][j] * kBinom.c[r][k];
          const Eigen::Vector3d d = s * (at(i, j + 1, k) - at(i, j, k));
          const int n = i + p1 * (j + q * k);
          for (int c = 0; c < 3; ++c) dv[c * nv + n] = d[c];
        }
        if (k < r) {
          const double s = r * kBinom.c[p][i] * kBinom.c[q][j] * kBinom.c[r - 1][k];
          const Eigen::Vector3d d = s * (at(i, j, k + 1) - at(i, j, k));
          const int n = i + p1 * (j + q1 * k);
          for (int c = 0; c < 3; ++c) dw[c * nw + n] = d[c];
        }
      }
  // cr = dv × dw; dv has dims (p+1, q, r+1), dw (p+1, q+1, r), cr (2p+1, 2q, 2r).
  for (int ak = 0; ak < r1; ++ak)
    for (int aj = 0; aj < q; ++aj)
      for (int ai = 0; ai < p1; ++ai) {
        const int a = ai + p1 * (aj + q * ak);
        const double v0 = dv[a], v1 = dv[nv + a], v2 = dv[2 * nv + a];
        for (int bk = 0; bk < r; ++bk)
          for (int bj = 0; bj < q1; ++bj) {
            const double* __restrict w0 = dw + p1 * (bj + q1 * bk);
            const double* __restrict w1 = w0 + nw;
            const double* __restrict w2 = w0 + 2 * nw;
            double* __restrict o = cr + ai + c0 * ((aj + bj) + c1 * (ak + bk));
            for (int bi = 0; bi < p1; ++bi) {
              o[bi] += v1 * w2[bi] - v2 * w1[bi];
              o[nc + bi] += v2 * w0[bi] - v0 * w2[bi];
              o[2 * nc + bi] += v0 * w1[bi] - v1 * w0[bi];
            }
          }
      }
  // acc = du · cr; du dims (p, q+1, r+1), acc (p + c0 - 1, 3q, 3r).
  for (int ak = 0; ak < r1; ++ak)
    for (int aj = 0; aj < q1; ++aj)
      for (int ai = 0; ai < p; ++ai) {
        const int a = ai + p * (aj + q1 * ak);
        const double u0 = du[a], u1 = du[nu + a], u2 = du[2 * nu + a];
        for (int bk = 0; bk < c2; ++bk)
          for (int bj = 0; bj < c1; ++bj) {
            const double* __restrict x0 = cr + c0 * (bj + c1 * bk);
            const double* __restrict x1 = x0 + nc;
            const double* __restrict x2 = x0 + 2 * nc;
            double* __restrict o = acc + ai + a0 * ((aj + bj) + o1 * (ak + bk));
            for (int bi = 0; bi < c0; ++bi) o[bi] += u0 * x0[bi] + u1 * x1[bi] + u2 * x2[bi];
          }
      }
  // Unscale by 1 / (C(3p-1,i) C(3q-1,j) C(3r-1,k)), tabulated per degree.
  if (ws.inv_degree != std::array<int, 3>{p, q, r}) {
    ws.inv.resize(no);
    for (int k = 0; k < o2; ++k)
      for (int j = 0; j < o1; ++j)
        for (int i = 0; i < o0; ++i)
          ws.inv[i + o0 * (j + o1 * k)] = 1.0 / (kBinom.c[o0 - 1][i] * kBinom.c[o1 - 1][j] * kBinom.c[o2 - 1][k]);
    ws.inv_degree = {p, q, r};
  }
  const double* __restrict inv = ws.inv.data();
  for (int jk = 0; jk < o1 * o2; ++jk)
    for (int i = 0; i < o0; ++i) out[i + o0 * jk] = acc[i + a0 * jk] * inv[i + o0 * jk];
}

// The cubic kernel is compiled twice, for AVX2/FMA (x86-64-v3) and baseline x86-64, and the
// loader picks one at startup (GCC function multiversioning): the inner loops are short fixed
// length vectors, where 4-wide FMA roughly doubles the throughput.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("arch=x86-64-v3", "default"), flatten))
#endif
void det_kernel_cubic(const std::vector<Eigen::Vector3d>& P, Workspace& ws, double* out) {
  det_kernel<3, 3, 3>(3, 3, 3, P, ws, out);
}

Workspace& workspace() {
  thread_local Workspace ws;
  return ws;
}

// Generic determinants of polynomial matrices (rows of components), by exact products.
template <class Poly>
Poly combine(const Poly& a, const Poly& b, double sb) {
  Poly c = a;
  for (std::size_t i = 0; i < c.coefs.size(); ++i) c.coefs[i] += sb * b.coefs[i];
  return c;
}

template <class Poly>
Poly det3(const std::array<Poly, 3>& r0, const std::array<Poly, 3>& r1, const std::array<Poly, 3>& r2) {
  Poly d;
  for (int c = 0; c < 3; ++c) {
    const int a = (c + 1) % 3, b = (c + 2) % 3;
    const Poly minor = combine(multiply(r1[a], r2[b]), multiply(r1[b], r2[a]), -1.0);
    const Poly term = multiply(r0[c], minor);
    d = c == 0 ? term : combine(d, term, 1.0);
  }
  return d;
}

// det of the 4x4 matrix with rows H, Hu, Hv, Hw (Laplace expansion along the first row).
template <class Poly>
Poly det4(const std::array<std::array<Poly, 4>, 4>& rows) {
  Poly d;
  for (int c = 0; c < 4; ++c) {
    std::array<std::array<Poly, 3>, 3> m;
    for (int r = 1; r < 4; ++r)
      for (int cc = 0, k = 0; cc < 4; ++cc)
        if (cc != c) m[r - 1][k++] = rows[r][cc];
    const Poly term = multiply(rows[0][c], det3(m[0], m[1], m[2]));
    d = c == 0 ? term : combine(d, term, c % 2 ? -1.0 : 1.0);
  }
  return d;
}

// Homogeneous component c (0..2: w·x, 3: w) of a hex as a tensor polynomial, and its derivative.
TensorBernstein hex_component(const BezierHex& h, int c) {
  TensorBernstein f;
  f.degree = h.degree;
  f.coefs.resize(h.num_points());
  for (int n = 0; n < h.num_points(); ++n) f.coefs[n] = h.weight(n) * (c < 3 ? h.points[n][c] : 1.0);
  return f;
}

TensorBernstein derivative(const TensorBernstein& f, int d) {
  TensorBernstein g;
  g.degree = f.degree;
  g.degree[d] -= 1;
  const int n0 = f.degree[0] + 1, n1 = f.degree[1] + 1;
  const int g0 = g.degree[0] + 1, g1 = g.degree[1] + 1;
  g.coefs.resize(static_cast<std::size_t>(g0) * g1 * (g.degree[2] + 1));
  for (int k = 0; k <= g.degree[2]; ++k)
    for (int j = 0; j <= g.degree[1]; ++j)
      for (int i = 0; i <= g.degree[0]; ++i) {
        int nx[3] = {i, j, k};
        nx[d] += 1;
        g.coefs[i + g0 * (j + g1 * k)] =
            f.degree[d] * (f.coefs[nx[0] + n0 * (nx[1] + n1 * nx[2])] - f.coefs[i + n0 * (j + n1 * k)]);
      }
  return g;
}

SimplexBernstein tet_component(const BezierTet& t, int c) {
  SimplexBernstein f;
  f.degree = t.degree;
  f.coefs.resize(t.points.size());
  for (std::size_t n = 0; n < t.points.size(); ++n)
    f.coefs[n] = t.weight(static_cast<int>(n)) * (c < 3 ? t.points[n][c] : 1.0);
  return f;
}

// d/du_d of a tet polynomial (d = 1, 2, 3): n Σ (c_{β+e_d} - c_{β+e_0}) B^{n-1}_β.
SimplexBernstein derivative(const SimplexBernstein& f, int d) {
  SimplexBernstein g;
  g.degree = f.degree - 1;
  for (const auto& b : simplex_multi_indices(3, g.degree))
    g.coefs.push_back(f.degree * (f.coefs[simplex_index(3, f.degree, b[1] + (d == 1), b[2] + (d == 2), b[3] + (d == 3))] -
                                  f.coefs[simplex_index(3, f.degree, b[1], b[2], b[3])]));
  return g;
}

template <class Element, class Poly, class Component>
Poly determinant(const Element& e, Component component) {
  if (!e.is_rational()) {
    std::array<std::array<Poly, 3>, 3> rows;
    for (int c = 0; c < 3; ++c) {
      const Poly x = component(e, c);
      for (int d = 0; d < 3; ++d) rows[d][c] = derivative(x, d + (std::is_same<Poly, SimplexBernstein>::value ? 1 : 0));
    }
    return det3(rows[0], rows[1], rows[2]);
  }
  std::array<std::array<Poly, 4>, 4> rows;
  for (int c = 0; c < 4; ++c) {
    // H = (w, w·x): det[H; H_u; H_v; H_w] = W^4 det J (with w last it would be -W^4 det J).
    rows[0][c] = component(e, c == 0 ? 3 : c - 1);
    for (int d = 0; d < 3; ++d) rows[d + 1][c] = derivative(rows[0][c], d + (std::is_same<Poly, SimplexBernstein>::value ? 1 : 0));
  }
  return det4(rows);
}

}  // namespace

void jacobian_determinant(const BezierHex& hex, TensorBernstein& out) {
  check(hex);
  if (hex.is_rational()) {
    out = determinant<BezierHex, TensorBernstein>(hex, hex_component);
    return;
  }
  const auto& [p, q, r] = hex.degree;
  out.degree = {3 * p - 1, 3 * q - 1, 3 * r - 1};
  out.coefs.resize(static_cast<std::size_t>(9) * p * q * r * 3);
  if (p == 3 && q == 3 && r == 3)
    det_kernel_cubic(hex.points, workspace(), out.coefs.data());
  else if (p == 2 && q == 2 && r == 2)
    det_kernel<2, 2, 2>(2, 2, 2, hex.points, workspace(), out.coefs.data());
  else
    det_kernel<0, 0, 0>(p, q, r, hex.points, workspace(), out.coefs.data());
}

TensorBernstein jacobian_determinant(const BezierHex& hex) {
  TensorBernstein out;
  jacobian_determinant(hex, out);
  return out;
}

SimplexBernstein jacobian_determinant(const BezierTet& tet) {
  check(tet);
  return determinant<BezierTet, SimplexBernstein>(tet, tet_component);
}

}  // namespace volts::bezier
