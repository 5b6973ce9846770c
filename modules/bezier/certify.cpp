#include "bezier/certify.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "bezier/jacobian_bernstein.h"
#include "bezier/quadrature.h"
#include "core/errors.h"

namespace volts::bezier {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void check_params(const CertifyParams& p) {
  if (p.max_depth < 0 || p.max_depth > 20)
    throw core::InvalidInputError("certify: max_depth " + std::to_string(p.max_depth) + " is outside [0, 20]");
  if (!(p.rounding_rel >= 0.0) || !std::isfinite(p.rounding_rel))
    throw core::InvalidInputError("certify: rounding_rel must be finite and >= 0");
}

// Per-thread buffers of the hex search: 8 children and the split temporaries per level.
struct HexWorkspace {
  std::vector<double> levels;
  TensorBernstein det;
};

HexWorkspace& hex_workspace() {
  thread_local HexWorkspace ws;
  return ws;
}

// de Casteljau at 1/2 along direction d of a (n0, n1, n2) array: in → lo, hi. The array is
// `outer` blocks of `len` rows of `stride` contiguous values (the lines along d run across the
// rows), so every step averages whole rows: the same operations, line by line, as a de Casteljau
// per line, but vectorized over the stride (d = 1, 2). The halving runs in place in hi: after
// step r its row len-1-r is final, and its row 0 is lo's row r.
template <int kLen>
void split_rows(const double* __restrict in, double* __restrict lo, double* __restrict hi, int len_arg, int stride, int outer) {
  const int len = kLen ? kLen : len_arg;
  const std::size_t block = static_cast<std::size_t>(len) * stride;
  for (int o = 0; o < outer; ++o) {
    const double* __restrict src = in + o * block;
    double* __restrict l = lo + o * block;
    double* __restrict h = hi + o * block;
    for (std::size_t x = 0; x < block; ++x) h[x] = src[x];
    for (int x = 0; x < stride; ++x) l[x] = src[x];
    for (int r = 1; r < len; ++r) {
      for (int i = 0; i < len - r; ++i) {
        double* __restrict a = h + i * stride;
        const double* __restrict b = h + (i + 1) * stride;
        for (int x = 0; x < stride; ++x) a[x] = 0.5 * (a[x] + b[x]);
      }
      double* __restrict lr = l + r * stride;
      for (int x = 0; x < stride; ++x) lr[x] = h[x];
    }
  }
}

// Direction 0 (stride 1): one line at a time, in place in hi as above.
template <int kLen>
void split_lines(const double* __restrict in, double* __restrict lo, double* __restrict hi, int len_arg, int lines) {
  const int len = kLen ? kLen : len_arg;
  for (int line = 0; line < lines; ++line) {
    const double* __restrict src = in + line * len;
    double* __restrict l = lo + line * len;
    double* __restrict h = hi + line * len;
    for (int i = 0; i < len; ++i) h[i] = src[i];
    l[0] = src[0];
    for (int r = 1; r < len; ++r) {
      for (int i = 0; i < len - r; ++i) h[i] = 0.5 * (h[i] + h[i + 1]);
      l[r] = h[0];
    }
  }
}

void split_half(const double* in, double* lo, double* hi, const int n[3], int d) {
  const int stride = d == 0 ? 1 : d == 1 ? n[0] : n[0] * n[1];
  const int len = n[d];
  const int outer = n[0] * n[1] * n[2] / (stride * len);
  if (d == 0) {
    if (len == 9) split_lines<9>(in, lo, hi, len, outer);  // det J of cubic hexes: degree 8
    else split_lines<0>(in, lo, hi, len, outer);
  } else if (len == 9) {
    split_rows<9>(in, lo, hi, len, stride, outer);
  } else {
    split_rows<0>(in, lo, hi, len, stride, outer);
  }
}

struct HexSearch {
  int n[3];
  int size;
  int max_depth;
  double tol;
  HexWorkspace& ws;
  CertifyResult res;
  double lower = kInf;
  bool invalid = false, undecided = false;

  void visit(const double* c, int level, const Eigen::Vector3d& lo, double h) {
    res.depth = std::max(res.depth, level);
    for (int corner = 0; corner < 8; ++corner) {
      const int i = corner & 1 ? n[0] - 1 : 0, j = corner & 2 ? n[1] - 1 : 0, k = corner & 4 ? n[2] - 1 : 0;
      const double v = c[i + n[0] * (j + n[1] * k)];  // exact value at the corner
      if (v < res.min_detj_upper) {
        res.min_detj_upper = v;
        res.witness = lo + h * Eigen::Vector3d(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
      }
    }
    if (res.min_detj_upper <= 0.0) {
      invalid = true;
      return;
    }
    double m = c[0];
    for (int i = 1; i < size; ++i) m = std::min(m, c[i]);
    if (m > tol || level == max_depth) {
      lower = std::min(lower, m);
      if (m <= tol) undecided = true;
      return;
    }
    ++res.subdivisions;
    // The 8 children (bit0 = u half, bit1 = v, bit2 = w), then the 2 u halves and the 4 quarters
    // (u half a, v half bv at 2a + bv) of this level, computed as the children are visited: a
    // fold found in an early child (most elements not valid) skips the other splits.
    double* kids = ws.levels.data() + static_cast<std::size_t>(level) * kSlots * size;
    double* halves = kids + 8 * size;
    double* quarters = halves + 2 * size;
    split_half(c, halves, halves + size, n, 0);
    bool v_done[2] = {false, false}, w_done[4] = {false, false, false, false};
    for (int child = 0; child < 8 && !invalid; ++child) {
      const int a = child & 1, bv = (child >> 1) & 1, b = 2 * a + bv;
      if (!v_done[a]) split_half(halves + a * size, quarters + 2 * a * size, quarters + (2 * a + 1) * size, n, 1), v_done[a] = true;
      if (!w_done[b]) split_half(quarters + b * size, kids + (a | (bv << 1)) * size, kids + (a | (bv << 1) | 4) * size, n, 2), w_done[b] = true;
      visit(kids + child * size, level + 1,
            lo + 0.5 * h * Eigen::Vector3d(child & 1, (child >> 1) & 1, (child >> 2) & 1), 0.5 * h);
    }
  }
  static constexpr int kSlots = 14;  // per level: 8 children, 2 halves, 4 quarters
};

double mean(const std::vector<double>& c) {
  double s = 0;
  for (double v : c) s += v;
  return c.empty() ? 0.0 : s / static_cast<double>(c.size());
}

// ∫ det J / (1/6) over the unit tet by Gauss–Legendre on the cube collapsed onto it (Duffy):
// (a,b,c) -> (a, b(1-a), c(1-a)(1-b)), Jacobian (1-a)^2 (1-b).
double rational_tet_mean(const BezierTet& t) {
  const int n = 2 * t.degree + 2;
  const std::vector<double> g = gauss_legendre_points(n), w = gauss_legendre_weights(n);
  double s = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double a = g[i], b = g[j], c = g[k];
        Eigen::Matrix3d J;
        evaluate(t, Eigen::Vector3d(a, b * (1 - a), c * (1 - a) * (1 - b)), &J);
        s += w[i] * w[j] * w[k] * (1 - a) * (1 - a) * (1 - b) * J.determinant();
      }
  return 6 * s;
}

CertifyResult finish(CertifyResult res, bool invalid, bool undecided, double lower, double root_min) {
  res.status = invalid ? Validity::invalid : undecided ? Validity::undecided : Validity::valid;
  res.min_detj_lower = invalid ? root_min : lower;  // the root's coefficients bound everything
  return res;
}

CertifyResult certify_hex_poly(const TensorBernstein& f, const CertifyParams& params, HexWorkspace& ws) {
  for (int d = 0; d < 3; ++d)
    if (f.degree[d] < 0 || f.degree[d] > 60) throw core::InvalidInputError("certify: degree outside [0, 60]");
  HexSearch s{{f.degree[0] + 1, f.degree[1] + 1, f.degree[2] + 1}, 0, params.max_depth, 0.0, ws, {}};
  s.size = s.n[0] * s.n[1] * s.n[2];
  if (static_cast<int>(f.coefs.size()) != s.size)
    throw core::InvalidInputError("certify: " + std::to_string(f.coefs.size()) + " coefficients for degrees " +
                                  std::to_string(f.degree[0]) + "," + std::to_string(f.degree[1]) + "," + std::to_string(f.degree[2]));
  double amax = 0, root_min = kInf;
  for (double c : f.coefs) {
    amax = std::max(amax, std::abs(c));
    root_min = std::min(root_min, c);
  }
  s.tol = params.rounding_rel * amax;
  const std::size_t need = static_cast<std::size_t>(params.max_depth) * HexSearch::kSlots * s.size;
  if (ws.levels.size() < need) ws.levels.resize(need);
  s.res.min_detj_upper = kInf;
  s.visit(f.coefs.data(), 0, Eigen::Vector3d::Zero(), 1.0);
  s.res.mean_detj = mean(f.coefs);
  return finish(s.res, s.invalid, s.undecided, s.lower, root_min);
}

struct TetSearch {
  int degree;
  int max_depth;
  double tol;
  CertifyResult res;
  double lower = kInf;
  bool invalid = false, undecided = false;

  // `verts`: the sub-simplex's vertices in barycentric coordinates of the reference tet.
  void visit(const std::vector<double>& c, int level, const std::array<Eigen::Vector4d, 4>& verts) {
    res.depth = std::max(res.depth, level);
    const int n = degree;
    const int corner_index[4] = {0, simplex_index(3, n, n, 0, 0), simplex_index(3, n, 0, n, 0), simplex_index(3, n, 0, 0, n)};
    for (int k = 0; k < 4; ++k)
      if (c[corner_index[k]] < res.min_detj_upper) {
        res.min_detj_upper = c[corner_index[k]];
        res.witness = verts[k].tail<3>();
      }
    if (res.min_detj_upper <= 0.0) {
      invalid = true;
      return;
    }
    const double m = *std::min_element(c.begin(), c.end());
    if (m > tol || level == max_depth) {
      lower = std::min(lower, m);
      if (m <= tol) undecided = true;
      return;
    }
    ++res.subdivisions;
    const auto children = tet_split_children();
    for (int ch = 0; ch < 8 && !invalid; ++ch) {
      std::array<Eigen::Vector4d, 4> v;
      for (int k = 0; k < 4; ++k) {
        v[k].setZero();
        for (int j = 0; j < 4; ++j) v[k] += children[ch][k][j] * verts[j];
      }
      visit(restrict_to_simplex(3, n, c, {children[ch].begin(), children[ch].end()}), level + 1, v);
    }
  }
};

// Converts bounds of D = W^4 det J (rational elements) into bounds of det J, with W in
// [wmin, wmax] (convex hull of the weights) and W at the witness evaluated exactly.
template <class WeightPoly>
CertifyResult rational_bounds(CertifyResult r, const std::vector<double>& weights, const WeightPoly& W) {
  const auto [lo, hi] = std::minmax_element(weights.begin(), weights.end());
  const double l = r.min_detj_lower;
  r.min_detj_lower = l / std::pow(l > 0 ? *hi : *lo, 4);
  r.min_detj_upper /= std::pow(evaluate(W, r.witness), 4);
  return r;
}

}  // namespace

const char* to_string(Validity v) {
  return v == Validity::valid ? "valid" : v == Validity::invalid ? "invalid" : "undecided";
}

CertifyResult certify(const TensorBernstein& f, const CertifyParams& params) {
  check_params(params);
  return certify_hex_poly(f, params, hex_workspace());
}

CertifyResult certify(const BezierHex& hex, const CertifyParams& params) {
  check_params(params);
  HexWorkspace& ws = hex_workspace();
  jacobian_determinant(hex, ws.det);
  const CertifyResult r = certify_hex_poly(ws.det, params, ws);
  if (!hex.is_rational()) return r;
  TensorBernstein W;
  W.degree = hex.degree;
  W.coefs = hex.weights;
  CertifyResult rr = rational_bounds(r, hex.weights, W);
  rr.mean_detj = volume(hex, 2 * std::max({hex.degree[0], hex.degree[1], hex.degree[2]}) + 2);
  return rr;
}

CertifyResult certify(const SimplexBernstein& f, const CertifyParams& params) {
  check_params(params);
  if (f.degree < 0 || static_cast<int>(f.coefs.size()) != simplex_size(3, f.degree))
    throw core::InvalidInputError("certify: " + std::to_string(f.coefs.size()) + " coefficients for simplex degree " +
                                  std::to_string(f.degree));
  TetSearch s{f.degree, params.max_depth, 0.0, {}};
  double amax = 0;
  for (double c : f.coefs) amax = std::max(amax, std::abs(c));
  s.tol = params.rounding_rel * amax;
  s.res.min_detj_upper = kInf;
  s.visit(f.coefs, 0, {Eigen::Vector4d::Unit(0), Eigen::Vector4d::Unit(1), Eigen::Vector4d::Unit(2), Eigen::Vector4d::Unit(3)});
  s.res.mean_detj = mean(f.coefs);
  return finish(s.res, s.invalid, s.undecided, s.lower, *std::min_element(f.coefs.begin(), f.coefs.end()));
}

CertifyResult certify(const BezierTet& tet, const CertifyParams& params) {
  const CertifyResult r = certify(jacobian_determinant(tet), params);
  if (!tet.is_rational()) return r;
  SimplexBernstein W;
  W.degree = tet.degree;
  W.coefs = tet.weights;
  CertifyResult rr = rational_bounds(r, tet.weights, W);
  rr.mean_detj = rational_tet_mean(tet);
  return rr;
}

}  // namespace volts::bezier
