#include "bezier/bezier_tet.h"

#include <cmath>
#include <string>

#include "core/errors.h"

namespace volts::bezier {

namespace {

int tet_number(int k) { return k * (k + 1) * (k + 2) / 6; }

void check_dim(int dim, int degree, const char* who) {
  if ((dim != 2 && dim != 3) || degree < 0)
    throw core::InvalidInputError(std::string(who) + ": dimension " + std::to_string(dim) + ", degree " +
                                  std::to_string(degree) + " (need dimension 2 or 3, degree >= 0)");
}

// One de Casteljau step on a degree-m net: c'_α = Σ_k λ_k c_{α+e_k}, |α| = m-1.
template <class T>
std::vector<T> casteljau_step(int dim, int m, const std::vector<T>& net, const Eigen::Vector4d& l) {
  std::vector<T> out(static_cast<std::size_t>(simplex_size(dim, m - 1)));
  const int n3 = dim == 3 ? m - 1 : 0;
  int o = 0;
  for (int a3 = 0; a3 <= n3; ++a3)
    for (int a2 = 0; a2 <= m - 1 - a3; ++a2)
      for (int a1 = 0; a1 <= m - 1 - a3 - a2; ++a1) {
        T v = l[0] * net[simplex_index(dim, m, a1, a2, a3)] + l[1] * net[simplex_index(dim, m, a1 + 1, a2, a3)] +
              l[2] * net[simplex_index(dim, m, a1, a2 + 1, a3)];
        if (dim == 3) v += l[3] * net[simplex_index(dim, m, a1, a2, a3 + 1)];
        out[o++] = v;
      }
  return out;
}

template <class T>
std::vector<T> restrict_impl(int dim, int n, const std::vector<T>& coefs, const std::vector<Eigen::Vector4d>& v) {
  check_dim(dim, n, "restrict_to_simplex");
  if (static_cast<int>(coefs.size()) != simplex_size(dim, n) || static_cast<int>(v.size()) != dim + 1)
    throw core::InvalidInputError("restrict_to_simplex: " + std::to_string(coefs.size()) + " coefficients and " +
                                  std::to_string(v.size()) + " vertices for dimension " + std::to_string(dim) +
                                  ", degree " + std::to_string(n));
  std::vector<T> out(coefs.size());
  // c'_β = P(v0^b0, v1^b1, v2^b2, v3^b3); the blossom is symmetric, so the v3, v2, v1 prefixes are
  // shared between the β that use them.
  std::vector<T> net3 = coefs;
  const int n3 = dim == 3 ? n : 0;
  for (int b3 = 0; b3 <= n3; ++b3) {
    std::vector<T> net2 = net3;
    for (int b2 = 0; b2 <= n - b3; ++b2) {
      std::vector<T> net1 = net2;
      for (int b1 = 0; b1 <= n - b3 - b2; ++b1) {
        const int k = n - b3 - b2 - b1;
        std::vector<T> net0 = net1;
        for (int t = k; t > 0; --t) net0 = casteljau_step(dim, t, net0, v[0]);
        out[simplex_index(dim, n, b1, b2, b3)] = net0[0];
        if (k > 0) net1 = casteljau_step(dim, k, net1, v[1]);
      }
      if (n - b3 - b2 > 0) net2 = casteljau_step(dim, n - b3 - b2, net2, v[2]);
    }
    if (dim == 3 && n - b3 > 0) net3 = casteljau_step(dim, n - b3, net3, v[3]);
  }
  return out;
}

template <class P>
std::vector<Eigen::Vector4d> homogeneous(const P& patch) {
  std::vector<Eigen::Vector4d> h(patch.points.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double w = patch.weight(static_cast<int>(i));
    h[i] << w * patch.points[i], w;
  }
  return h;
}

template <class P>
P from_homogeneous(int degree, const std::vector<Eigen::Vector4d>& h, bool rational) {
  P out;
  out.degree = degree;
  out.points.resize(h.size());
  if (rational) out.weights.resize(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (!(h[i][3] > 0.0)) throw core::InvalidInputError("simplex Bézier: a resulting weight is not positive");
    out.points[i] = h[i].head<3>() / h[i][3];
    if (rational) out.weights[i] = h[i][3];
  }
  return out;
}

template <class P>
void check_patch(int dim, const P& p, const char* name) {
  if (p.degree < 1) throw core::InvalidInputError(std::string(name) + ": degree " + std::to_string(p.degree) + ", must be >= 1");
  const std::size_t n = static_cast<std::size_t>(simplex_size(dim, p.degree));
  if (p.points.size() != n)
    throw core::InvalidInputError(std::string(name) + ": " + std::to_string(p.points.size()) + " control points, degree " +
                                  std::to_string(p.degree) + " needs " + std::to_string(n));
  if (!p.weights.empty()) {
    if (p.weights.size() != n)
      throw core::InvalidInputError(std::string(name) + ": " + std::to_string(p.weights.size()) + " weights for " +
                                    std::to_string(n) + " control points");
    for (std::size_t i = 0; i < n; ++i)
      if (!(p.weights[i] > 0.0) || !std::isfinite(p.weights[i]))
        throw core::InvalidInputError(std::string(name) + ": weight " + std::to_string(i) + " is not finite and positive");
  }
}

// Value and first partials (homogeneous) of a degree-n net at barycentric λ: de Casteljau down to
// degree 1, whose d+1 coefficients c_k give F = Σ λ_k c_k and dF/du_i = n (c_i - c_0).
template <class P>
Eigen::Vector3d evaluate_impl(int dim, const P& patch, const Eigen::Vector4d& l, Eigen::Matrix<double, 3, Eigen::Dynamic>* J) {
  std::vector<Eigen::Vector4d> net = homogeneous(patch);
  for (int m = patch.degree; m > 1; --m) net = casteljau_step(dim, m, net, l);
  Eigen::Vector4d H = Eigen::Vector4d::Zero();
  for (int k = 0; k <= dim; ++k) H += l[k] * net[k == 0 ? 0 : simplex_index(dim, 1, k == 1, k == 2, k == 3)];
  const Eigen::Vector3d x = H.head<3>() / H[3];
  if (J) {
    J->resize(3, dim);
    for (int i = 1; i <= dim; ++i) {
      const Eigen::Vector4d dH = patch.degree * (net[simplex_index(dim, 1, i == 1, i == 2, i == 3)] - net[0]);
      J->col(i - 1) = (dH.head<3>() - x * dH[3]) / H[3];  // quotient rule
    }
  }
  return x;
}

template <class P>
P elevate_impl(int dim, const P& patch, int m) {
  if (m < patch.degree)
    throw core::InvalidInputError("elevate_degree: cannot lower degree " + std::to_string(patch.degree) + " to " + std::to_string(m));
  std::vector<Eigen::Vector4d> h = homogeneous(patch);
  for (int n = patch.degree; n < m; ++n) {
    // c'_α = Σ_k α_k/(n+1) c_{α-e_k}, |α| = n+1.
    std::vector<Eigen::Vector4d> e(static_cast<std::size_t>(simplex_size(dim, n + 1)));
    for (const auto& a : simplex_multi_indices(dim, n + 1)) {
      Eigen::Vector4d v = Eigen::Vector4d::Zero();
      if (a[0] > 0) v += double(a[0]) / (n + 1) * h[simplex_index(dim, n, a[1], a[2], a[3])];
      if (a[1] > 0) v += double(a[1]) / (n + 1) * h[simplex_index(dim, n, a[1] - 1, a[2], a[3])];
      if (a[2] > 0) v += double(a[2]) / (n + 1) * h[simplex_index(dim, n, a[1], a[2] - 1, a[3])];
      if (a[3] > 0) v += double(a[3]) / (n + 1) * h[simplex_index(dim, n, a[1], a[2], a[3] - 1)];
      e[simplex_index(dim, n + 1, a[1], a[2], a[3])] = v;
    }
    h = std::move(e);
  }
  return from_homogeneous<P>(m, h, patch.is_rational());
}

}  // namespace

int simplex_size(int dim, int degree) {
  return dim == 2 ? (degree + 1) * (degree + 2) / 2 : (degree + 1) * (degree + 2) * (degree + 3) / 6;
}

int simplex_index(int dim, int n, int a1, int a2, int a3) {
  // Multi-indices with a smaller a3 come first (tet_number counts them), then smaller a2 within
  // the layer of degree m = n - a3 (a2 rows of decreasing length), then a1.
  const int m = n - a3;
  const int before3 = dim == 3 ? tet_number(n + 1) - tet_number(n + 1 - a3) : 0;
  return before3 + a2 * (m + 1) - a2 * (a2 - 1) / 2 + a1;
}

std::vector<std::array<int, 4>> simplex_multi_indices(int dim, int n) {
  std::vector<std::array<int, 4>> out;
  const int n3 = dim == 3 ? n : 0;
  for (int a3 = 0; a3 <= n3; ++a3)
    for (int a2 = 0; a2 <= n - a3; ++a2)
      for (int a1 = 0; a1 <= n - a3 - a2; ++a1) out.push_back({n - a1 - a2 - a3, a1, a2, a3});
  return out;
}

void check(const BezierTriangle& tri) { check_patch(2, tri, "BezierTriangle"); }
void check(const BezierTet& tet) { check_patch(3, tet, "BezierTet"); }

Eigen::Vector3d evaluate(const BezierTriangle& tri, const Eigen::Vector2d& st, Eigen::Matrix<double, 3, 2>* jacobian) {
  check(tri);
  Eigen::Matrix<double, 3, Eigen::Dynamic> J;
  const Eigen::Vector3d x = evaluate_impl(2, tri, Eigen::Vector4d(1 - st[0] - st[1], st[0], st[1], 0), jacobian ? &J : nullptr);
  if (jacobian) *jacobian = J;
  return x;
}

Eigen::Vector3d evaluate(const BezierTet& tet, const Eigen::Vector3d& uvw, Eigen::Matrix3d* jacobian) {
  check(tet);
  Eigen::Matrix<double, 3, Eigen::Dynamic> J;
  const Eigen::Vector4d l(1 - uvw.sum(), uvw[0], uvw[1], uvw[2]);
  const Eigen::Vector3d x = evaluate_impl(3, tet, l, jacobian ? &J : nullptr);
  if (jacobian) *jacobian = J;
  return x;
}

BezierTriangle elevate_degree(const BezierTriangle& tri, int m) {
  check(tri);
  return elevate_impl(2, tri, m);
}

BezierTet elevate_degree(const BezierTet& tet, int m) {
  check(tet);
  return elevate_impl(3, tet, m);
}

Eigen::Vector4d blossom(int dim, int degree, const std::vector<Eigen::Vector4d>& net, const std::vector<Eigen::Vector4d>& args) {
  check_dim(dim, degree, "blossom");
  if (static_cast<int>(net.size()) != simplex_size(dim, degree) || static_cast<int>(args.size()) != degree)
    throw core::InvalidInputError("blossom: " + std::to_string(net.size()) + " coefficients and " + std::to_string(args.size()) +
                                  " arguments for degree " + std::to_string(degree));
  std::vector<Eigen::Vector4d> b = net;
  for (int m = degree; m > 0; --m) b = casteljau_step(dim, m, b, args[degree - m]);
  return b[0];
}

std::vector<double> restrict_to_simplex(int dim, int degree, const std::vector<double>& coefs,
                                        const std::vector<Eigen::Vector4d>& vertices) {
  return restrict_impl(dim, degree, coefs, vertices);
}

std::vector<Eigen::Vector4d> restrict_to_simplex(int dim, int degree, const std::vector<Eigen::Vector4d>& coefs,
                                                 const std::vector<Eigen::Vector4d>& vertices) {
  return restrict_impl(dim, degree, coefs, vertices);
}

std::array<std::array<Eigen::Vector4d, 4>, 8> tet_split_children() {
  const auto e = [](int i) { return Eigen::Vector4d(Eigen::Vector4d::Unit(i)); };
  const auto m = [&](int i, int j) { return Eigen::Vector4d(0.5 * (e(i) + e(j))); };
  return {{{e(0), m(0, 1), m(0, 2), m(0, 3)},
           {m(0, 1), e(1), m(1, 2), m(1, 3)},
           {m(0, 2), m(1, 2), e(2), m(2, 3)},
           {m(0, 3), m(1, 3), m(2, 3), e(3)},
           // The octahedron around the diagonal m02–m13; its other vertices form the cycle
           // m01, m03, m23, m12 (consecutive ones share an original vertex).
           {m(0, 2), m(1, 3), m(0, 1), m(0, 3)},
           {m(0, 2), m(1, 3), m(0, 3), m(2, 3)},
           {m(0, 2), m(1, 3), m(2, 3), m(1, 2)},
           {m(0, 2), m(1, 3), m(1, 2), m(0, 1)}}};
}

std::array<BezierTet, 8> subdivide(const BezierTet& tet) {
  check(tet);
  const std::vector<Eigen::Vector4d> h = homogeneous(tet);
  std::array<BezierTet, 8> out;
  const auto children = tet_split_children();
  for (int c = 0; c < 8; ++c) {
    const std::vector<Eigen::Vector4d> v(children[c].begin(), children[c].end());
    out[c] = from_homogeneous<BezierTet>(tet.degree, restrict_impl(3, tet.degree, h, v), tet.is_rational());
  }
  return out;
}

}  // namespace volts::bezier
