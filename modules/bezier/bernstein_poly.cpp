#include "bezier/bernstein_poly.h"

#include <string>

#include "bezier/bernstein.h"
#include "bezier/bezier_tet.h"
#include "core/errors.h"

namespace volts::bezier {

namespace {

int tensor_size(const std::array<int, 3>& d) { return (d[0] + 1) * (d[1] + 1) * (d[2] + 1); }

void check(const TensorBernstein& f, const char* who) {
  if (f.degree[0] < 0 || f.degree[1] < 0 || f.degree[2] < 0 || static_cast<int>(f.coefs.size()) != tensor_size(f.degree))
    throw core::InvalidInputError(std::string(who) + ": tensor Bernstein polynomial with " + std::to_string(f.coefs.size()) +
                                  " coefficients for degrees " + std::to_string(f.degree[0]) + "," +
                                  std::to_string(f.degree[1]) + "," + std::to_string(f.degree[2]));
}

void check(const SimplexBernstein& f, const char* who) {
  if (f.degree < 0 || static_cast<int>(f.coefs.size()) != simplex_size(3, f.degree))
    throw core::InvalidInputError(std::string(who) + ": simplex Bernstein polynomial with " + std::to_string(f.coefs.size()) +
                                  " coefficients for degree " + std::to_string(f.degree));
}

double factorial(int n) {
  double f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

double multinomial(int n, const std::array<int, 4>& a) {
  return factorial(n) / (factorial(a[0]) * factorial(a[1]) * factorial(a[2]) * factorial(a[3]));
}

}  // namespace

double binomial(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  double b = 1;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

double evaluate(const TensorBernstein& f, const Eigen::Vector3d& uvw) {
  check(f, "evaluate");
  const Eigen::VectorXd bu = bernstein_basis(f.degree[0], uvw[0]), bv = bernstein_basis(f.degree[1], uvw[1]),
                        bw = bernstein_basis(f.degree[2], uvw[2]);
  double s = 0;
  int n = 0;
  for (int k = 0; k <= f.degree[2]; ++k)
    for (int j = 0; j <= f.degree[1]; ++j)
      for (int i = 0; i <= f.degree[0]; ++i) s += f.coefs[n++] * bu[i] * bv[j] * bw[k];
  return s;
}

double evaluate(const SimplexBernstein& f, const Eigen::Vector3d& uvw) {
  check(f, "evaluate");
  // The blossom on the diagonal: n de Casteljau steps at λ.
  const Eigen::Vector4d l(1 - uvw.sum(), uvw[0], uvw[1], uvw[2]);
  std::vector<Eigen::Vector4d> net(f.coefs.size());
  for (std::size_t i = 0; i < net.size(); ++i) net[i] = Eigen::Vector4d(f.coefs[i], 0, 0, 0);
  return blossom(3, f.degree, net, std::vector<Eigen::Vector4d>(f.degree, l))[0];
}

TensorBernstein multiply(const TensorBernstein& a, const TensorBernstein& b) {
  check(a, "multiply");
  check(b, "multiply");
  TensorBernstein c;
  for (int d = 0; d < 3; ++d) c.degree[d] = a.degree[d] + b.degree[d];
  c.coefs.assign(tensor_size(c.degree), 0.0);
  const auto scaled = [](const TensorBernstein& f) {
    std::vector<double> s(f.coefs.size());
    int n = 0;
    for (int k = 0; k <= f.degree[2]; ++k)
      for (int j = 0; j <= f.degree[1]; ++j)
        for (int i = 0; i <= f.degree[0]; ++i, ++n)
          s[n] = f.coefs[n] * binomial(f.degree[0], i) * binomial(f.degree[1], j) * binomial(f.degree[2], k);
    return s;
  };
  const std::vector<double> sa = scaled(a), sb = scaled(b);
  const int c0 = c.degree[0] + 1, c1 = c.degree[1] + 1;
  int na = 0;
  for (int ak = 0; ak <= a.degree[2]; ++ak)
    for (int aj = 0; aj <= a.degree[1]; ++aj)
      for (int ai = 0; ai <= a.degree[0]; ++ai, ++na) {
        int nb = 0;
        for (int bk = 0; bk <= b.degree[2]; ++bk)
          for (int bj = 0; bj <= b.degree[1]; ++bj)
            for (int bi = 0; bi <= b.degree[0]; ++bi, ++nb) c.coefs[(ai + bi) + c0 * ((aj + bj) + c1 * (ak + bk))] += sa[na] * sb[nb];
      }
  int n = 0;
  for (int k = 0; k <= c.degree[2]; ++k)
    for (int j = 0; j <= c.degree[1]; ++j)
      for (int i = 0; i <= c.degree[0]; ++i, ++n)
        c.coefs[n] /= binomial(c.degree[0], i) * binomial(c.degree[1], j) * binomial(c.degree[2], k);
  return c;
}

SimplexBernstein multiply(const SimplexBernstein& a, const SimplexBernstein& b) {
  check(a, "multiply");
  check(b, "multiply");
  SimplexBernstein c;
  c.degree = a.degree + b.degree;
  c.coefs.assign(simplex_size(3, c.degree), 0.0);
  const auto ia = simplex_multi_indices(3, a.degree), ib = simplex_multi_indices(3, b.degree);
  for (std::size_t i = 0; i < ia.size(); ++i) {
    const double sa = a.coefs[i] * multinomial(a.degree, ia[i]);
    for (std::size_t j = 0; j < ib.size(); ++j)
      c.coefs[simplex_index(3, c.degree, ia[i][1] + ib[j][1], ia[i][2] + ib[j][2], ia[i][3] + ib[j][3])] +=
          sa * b.coefs[j] * multinomial(b.degree, ib[j]);
  }
  const auto ic = simplex_multi_indices(3, c.degree);
  for (std::size_t i = 0; i < ic.size(); ++i) c.coefs[i] /= multinomial(c.degree, ic[i]);
  return c;
}

std::array<TensorBernstein, 8> subdivide(const TensorBernstein& f) {
  check(f, "subdivide");
  std::array<TensorBernstein, 8> out;
  std::array<std::array<Eigen::MatrixXd, 2>, 3> S;
  for (int d = 0; d < 3; ++d)
    for (int h = 0; h < 2; ++h) S[d][h] = subdivision_matrix(f.degree[d], 0.5 * h, 0.5 * (h + 1));
  const int n0 = f.degree[0] + 1, n1 = f.degree[1] + 1, n2 = f.degree[2] + 1;
  for (int c = 0; c < 8; ++c) {
    // One direction at a time (sum factorisation).
    std::vector<double> g = f.coefs, h(g.size());
    const int n[3] = {n0, n1, n2};
    for (int d = 0; d < 3; ++d) {
      const Eigen::MatrixXd& M = S[d][(c >> d) & 1];
      for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j)
          for (int i = 0; i < n0; ++i) {
            int idx[3] = {i, j, k};
            const int a = idx[d];
            double s = 0;
            for (int b = 0; b < n[d]; ++b) {
              idx[d] = b;
              s += M(a, b) * g[idx[0] + n0 * (idx[1] + n1 * idx[2])];
            }
            h[i + n0 * (j + n1 * k)] = s;
          }
      std::swap(g, h);
    }
    out[c].degree = f.degree;
    out[c].coefs = std::move(g);
  }
  return out;
}

std::array<SimplexBernstein, 8> subdivide(const SimplexBernstein& f) {
  check(f, "subdivide");
  std::array<SimplexBernstein, 8> out;
  const auto children = tet_split_children();
  for (int c = 0; c < 8; ++c) {
    out[c].degree = f.degree;
    out[c].coefs = restrict_to_simplex(3, f.degree, f.coefs, {children[c].begin(), children[c].end()});
  }
  return out;
}

}  // namespace volts::bezier
