#include "bezier/bspline.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"

namespace volts::bezier {

namespace {

int num_functions(const std::vector<double>& knots, int degree) {
  return static_cast<int>(knots.size()) - degree - 1;
}

// Piegl & Tiller A2.2: the p+1 non-zero functions of degree p on span s at t. Denominators are
// knot differences that contain the (non-empty) span, so they never vanish.
Eigen::VectorXd values_on_span(const std::vector<double>& U, int s, int p, double t) {
  Eigen::VectorXd N(p + 1);
  std::vector<double> left(p + 1), right(p + 1);
  N[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - U[s + 1 - j];
    right[j] = U[s + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = N[r] / (right[r + 1] + left[j - r]);
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
  return N;
}

// Boehm insertion of knot x into the knot vector L, applied to every row of M (row = one spline's
// coefficients in the current basis): Q_i = alpha_i P_i + (1 - alpha_i) P_{i-1}, alpha clamped to
// [0,1]. Written with clamped alphas over all functions rather than around a span because the end
// knots of an element are the ends of its local knot vector's domain; the out-of-range P_{-1} and
// P_nf then always get weight 0.
void insert_knot(std::vector<double>& L, Eigen::MatrixXd& M, int p, double x) {
  const int nf = static_cast<int>(M.cols());
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(M.rows(), nf + 1);
  for (int i = 0; i <= nf; ++i) {
    double alpha;
    if (L[i + p] <= x) {
      alpha = 1.0;
    } else if (L[i] >= x) {
      alpha = 0.0;
    } else {
      alpha = (x - L[i]) / (L[i + p] - L[i]);
    }
    if (i < nf && alpha != 0.0) Q.col(i) += alpha * M.col(i);
    if (i > 0 && alpha != 1.0) Q.col(i) += (1.0 - alpha) * M.col(i - 1);
  }
  L.insert(std::upper_bound(L.begin(), L.end(), x), x);
  M = std::move(Q);
}

}  // namespace

void check_knot_vector(const std::vector<double>& knots, int degree, const char* what) {
  const std::string w(what);
  if (degree < 0) throw core::InvalidInputError(w + ": negative degree " + std::to_string(degree));
  const std::size_t need = 2 * static_cast<std::size_t>(degree + 1);
  if (knots.size() < need)
    throw core::InvalidInputError(w + ": " + std::to_string(knots.size()) + " knots, degree " +
                                  std::to_string(degree) + " needs at least " + std::to_string(need));
  int mult = 1;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i]))
      throw core::InvalidInputError(w + ": knot " + std::to_string(i) + " is not finite");
    if (i == 0) continue;
    if (knots[i] < knots[i - 1])
      throw core::InvalidInputError(w + ": knots decrease at index " + std::to_string(i));
    mult = knots[i] == knots[i - 1] ? mult + 1 : 1;
    if (mult > degree + 1)
      throw core::InvalidInputError(w + ": knot " + std::to_string(knots[i]) + " repeated more than degree+1 = " +
                                    std::to_string(degree + 1) + " times");
  }
  const int n = num_functions(knots, degree);
  if (!(knots[degree] < knots[n])) throw core::InvalidInputError(w + ": empty parametric domain");
}

int find_span(const std::vector<double>& knots, int degree, double t) {
  check_knot_vector(knots, degree);
  const int p = degree;
  const int n = num_functions(knots, p);
  if (!(t >= knots[p] && t <= knots[n]))
    throw core::InvalidInputError("find_span: t = " + std::to_string(t) + " outside the domain [" +
                                  std::to_string(knots[p]) + ", " + std::to_string(knots[n]) + "]");
  const auto it = std::upper_bound(knots.begin() + p + 1, knots.begin() + n, t);
  int s = static_cast<int>(it - knots.begin()) - 1;
  while (knots[s] == knots[s + 1]) --s;  // only at t == knots[n] with repeated end knots
  return s;
}

BasisValues basis_functions(const std::vector<double>& knots, int degree, double t, bool with_derivatives) {
  const int p = degree;
  BasisValues out;
  out.span = find_span(knots, p, t);
  out.values = values_on_span(knots, out.span, p, t);
  if (with_derivatives) {
    out.derivatives = Eigen::VectorXd::Zero(p + 1);
    if (p > 0) {
      // N'_{i,p} = p N_{i,p-1}/(u_{i+p}-u_i) - p N_{i+1,p-1}/(u_{i+p+1}-u_{i+1}); lower[k-1] is N_{s-p+k,p-1}.
      const Eigen::VectorXd lower = values_on_span(knots, out.span, p - 1, t);
      const int s = out.span;
      for (int k = 0; k <= p; ++k) {
        const int i = s - p + k;
        double d = 0.0;
        if (k >= 1) d += lower[k - 1] / (knots[i + p] - knots[i]);
        if (k <= p - 1) d -= lower[k] / (knots[i + p + 1] - knots[i + 1]);
        out.derivatives[k] = p * d;
      }
    }
  }
  return out;
}

std::vector<double> greville_abscissae(const std::vector<double>& knots, int degree) {
  check_knot_vector(knots, degree);
  const int p = degree;
  const int n = num_functions(knots, p);
  std::vector<double> g(n);
  for (int i = 0; i < n; ++i) {
    if (p == 0) {
      g[i] = 0.5 * (knots[i] + knots[i + 1]);
    } else {
      double sum = 0.0;
      for (int k = 1; k <= p; ++k) sum += knots[i + k];
      g[i] = sum / p;
    }
  }
  return g;
}

std::vector<double> open_uniform_knots(int elements, int degree) {
  if (elements < 1) throw core::InvalidInputError("open_uniform_knots: needs at least one element");
  if (degree < 0) throw core::InvalidInputError("open_uniform_knots: negative degree");
  std::vector<double> knots(degree + 1, 0.0);
  for (int i = 1; i < elements; ++i) knots.push_back(static_cast<double>(i) / elements);
  knots.insert(knots.end(), degree + 1, 1.0);
  return knots;
}

std::vector<int> element_spans(const std::vector<double>& knots, int degree) {
  check_knot_vector(knots, degree);
  std::vector<int> spans;
  for (int s = degree; s < num_functions(knots, degree); ++s)
    if (knots[s] < knots[s + 1]) spans.push_back(s);
  return spans;
}

std::vector<std::array<double, 2>> element_intervals(const std::vector<double>& knots, int degree) {
  std::vector<std::array<double, 2>> out;
  for (int s : element_spans(knots, degree)) out.push_back({knots[s], knots[s + 1]});
  return out;
}

std::vector<Eigen::MatrixXd> extraction_operators(const std::vector<double>& knots, int degree) {
  const int p = degree;
  std::vector<Eigen::MatrixXd> ops;
  for (int s : element_spans(knots, p)) {
    // The p+1 functions on span s are fully defined by the 2p+2 knots knots[s-p .. s+p+1].
    std::vector<double> L(knots.begin() + (s - p), knots.begin() + (s + p + 2));
    const double a = L[p], b = L[p + 1];
    int mult_a = 0, mult_b = 0;
    for (int i = p; i >= 0 && L[i] == a; --i) ++mult_a;
    for (int i = p + 1; i <= 2 * p + 1 && L[i] == b; ++i) ++mult_b;
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(p + 1, p + 1);
    const int ra = std::max(0, p - mult_a), rb = std::max(0, p - mult_b);
    for (int r = 0; r < ra; ++r) insert_knot(L, M, p, a);
    for (int r = 0; r < rb; ++r) insert_knot(L, M, p, b);
    // With a and b of multiplicity >= p, the refined functions ra..ra+p restricted to [a,b] are
    // exactly the Bernstein polynomials of the element.
    ops.push_back(M.block(0, ra, p + 1, p + 1));
  }
  return ops;
}

Eigen::MatrixXd refinement_matrix(const std::vector<double>& coarse, const std::vector<double>& fine, int degree) {
  check_knot_vector(coarse, degree, "refinement: coarse knot vector");
  check_knot_vector(fine, degree, "refinement: fine knot vector");
  constexpr double kSame = 1e-12;
  if (std::abs(coarse.front() - fine.front()) > kSame || std::abs(coarse.back() - fine.back()) > kSame)
    throw core::InvalidInputError("refinement: the fine knot vector spans another interval than the coarse one");
  // The knots of `fine` missing from `coarse`, as a merge of the two sorted sequences.
  std::vector<double> insert;
  std::size_t c = 0;
  for (const double x : fine) {
    if (c < coarse.size() && std::abs(coarse[c] - x) <= kSame) {
      ++c;
    } else if (c < coarse.size() && coarse[c] < x) {
      break;  // a coarse knot that `fine` skips
    } else {
      insert.push_back(x);
    }
  }
  if (c != coarse.size())
    throw core::InvalidInputError("refinement: the fine knot vector lacks the coarse knot " + std::to_string(coarse[c]));
  std::vector<double> L = coarse;
  const int n = static_cast<int>(coarse.size()) - degree - 1;
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n);
  for (const double x : insert) insert_knot(L, M, degree, x);
  return M;
}

}  // namespace volts::bezier
