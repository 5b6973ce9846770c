#include "polycube/patch_map.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "core/errors.h"

namespace volts::polycube {

namespace {

using Vec3 = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

double dist(const Vec3& a, const Vec3& b) { return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2])); }

template <class P>
double angle_at(const P& p, const P& q, const P& r, int dim) {  // angle at p in triangle pqr
  double d = 0, la = 0, lb = 0;
  for (int k = 0; k < dim; ++k) {
    const double a = q[k] - p[k], b = r[k] - p[k];
    d += a * b, la += a * a, lb += b * b;
  }
  if (la == 0 || lb == 0) return 0;
  return std::acos(std::clamp(d / std::sqrt(la * lb), -1.0, 1.0));
}

}  // namespace

double chain_length(const split::Layout& L, const std::vector<int>& chain) {
  double s = 0;
  for (std::size_t i = 1; i < chain.size(); ++i) s += dist(L.points[chain[i - 1]], L.points[chain[i]]);
  return s;
}

std::vector<double> arc_length_fractions(const split::Layout& L, const std::vector<int>& chain) {
  std::vector<double> s(chain.size(), 0.0);
  for (std::size_t i = 1; i < chain.size(); ++i) s[i] = s[i - 1] + dist(L.points[chain[i - 1]], L.points[chain[i]]);
  for (double& x : s) x = s.back() > 0 ? x / s.back() : 0.0;
  return s;
}

std::vector<char> consistent_orientation(const split::Layout& L, const std::vector<int>& triangles) {
  std::vector<char> rev(triangles.size(), 0), seen(triangles.size(), 0);
  std::map<std::pair<int, int>, std::vector<int>> by_edge;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& tr = L.triangles[triangles[i]];
    for (int k = 0; k < 3; ++k) by_edge[{std::min(tr[k], tr[(k + 1) % 3]), std::max(tr[k], tr[(k + 1) % 3])}].push_back(static_cast<int>(i));
  }
  auto has_directed = [&](int i, int a, int b) {  // triangle i, as oriented now, runs a -> b
    const auto& tr = L.triangles[triangles[i]];
    for (int k = 0; k < 3; ++k)
      if (tr[k] == a && tr[(k + 1) % 3] == b) return !rev[i];
    return static_cast<bool>(rev[i]);
  };
  for (std::size_t start = 0; start < triangles.size(); ++start) {
    if (seen[start]) continue;
    seen[start] = 1;
    std::vector<int> stack = {static_cast<int>(start)};
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      const auto& tr = L.triangles[triangles[i]];
      for (int k = 0; k < 3; ++k) {
        const int a = tr[k], b = tr[(k + 1) % 3];
        for (int j : by_edge[{std::min(a, b), std::max(a, b)}]) {
          if (seen[j]) continue;
          seen[j] = 1;
          // i runs a -> b (or b -> a); j must run the other way.
          rev[j] = has_directed(j, a, b) == has_directed(i, a, b);
          stack.push_back(j);
        }
      }
    }
  }
  return rev;
}

std::map<int, std::array<double, 2>> harmonic_positions(const split::Layout& L, const std::vector<int>& triangles,
                                                        const std::map<int, std::array<double, 2>>& fixed,
                                                        const PatchMapParams& params, const std::string& what) {
  if (params.weights != "mean-value" && params.weights != "uniform")
    throw core::ConfigError("polycube.weights must be 'mean-value' or 'uniform', not '" + params.weights + "'");
  std::map<int, std::array<double, 2>> at;  // ordered: deterministic assembly
  for (int t : triangles)
    for (int v : L.triangles[t]) {
      const auto f = fixed.find(v);
      at.emplace(v, f == fixed.end() ? std::array<double, 2>{0, 0} : f->second);
    }
  std::map<int, int> unknown;
  for (const auto& [v, x] : at)
    if (!fixed.count(v)) unknown.emplace(v, static_cast<int>(unknown.size()));
  if (unknown.empty()) return at;
  std::vector<std::map<int, double>> w(unknown.size());
  for (int t : triangles) {
    const auto& tr = L.triangles[t];
    for (int c = 0; c < 3; ++c) {
      const int i = tr[c], j = tr[(c + 1) % 3], k = tr[(c + 2) % 3];
      const auto ui = unknown.find(i);
      if (ui == unknown.end()) continue;
      if (params.weights == "uniform") {
        w[ui->second][j] += 0.5, w[ui->second][k] += 0.5;  // each edge is seen from two triangles
        continue;
      }
      const double half = std::tan(angle_at(L.points[i], L.points[j], L.points[k], 3) / 2);
      w[ui->second][j] += half / dist(L.points[i], L.points[j]);
      w[ui->second][k] += half / dist(L.points[i], L.points[k]);
    }
  }
  const int nu = static_cast<int>(unknown.size());
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nu, 2);
  for (const auto& [v, row] : unknown) {
    double sum = 0;
    for (const auto& [j, wij] : w[row]) {
      sum += wij;
      const auto uj = unknown.find(j);
      if (uj != unknown.end()) trip.emplace_back(row, uj->second, -wij);
      else rhs(row, 0) += wij * at.at(j)[0], rhs(row, 1) += wij * at.at(j)[1];
    }
    trip.emplace_back(row, row, sum);
  }
  Eigen::SparseMatrix<double> A(nu, nu);
  A.setFromTriplets(trip.begin(), trip.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(A);
  if (lu.info() != Eigen::Success) throw core::NumericalError("polycube: the disk map of " + what + " is singular");
  const Eigen::MatrixXd x = lu.solve(rhs);
  if (lu.info() != Eigen::Success || !x.allFinite()) throw core::NumericalError("polycube: the disk map of " + what + " failed");
  for (const auto& [v, row] : unknown) at[v] = {x(row, 0), x(row, 1)};
  return at;
}

namespace {

// Per triangle: 1 if its image turns against the majority or is degenerate (CGAL exact
// orientation; the majority's is the patch's own: on the surface its triangles all turn alike,
// once oriented consistently — a patch may hold fill triangles stored the other way round: the
// disk where two tori meet). `rev` from consistent_orientation.
std::vector<char> flipped_images(const split::Layout& L, const std::vector<int>& triangles, const std::vector<char>& rev,
                                 const std::map<int, std::array<double, 2>>& at, int* good_sign = nullptr) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  int positive = 0, negative = 0;
  std::vector<CGAL::Orientation> o;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    auto tr = L.triangles[triangles[i]];
    if (rev[i]) std::swap(tr[1], tr[2]);
    const std::array<std::array<double, 2>, 3> x{at.at(tr[0]), at.at(tr[1]), at.at(tr[2])};
    o.push_back(CGAL::orientation(K::Point_2(x[0][0], x[0][1]), K::Point_2(x[1][0], x[1][1]), K::Point_2(x[2][0], x[2][1])));
    positive += o.back() == CGAL::POSITIVE, negative += o.back() == CGAL::NEGATIVE;
  }
  const CGAL::Orientation good = positive >= negative ? CGAL::POSITIVE : CGAL::NEGATIVE;
  if (good_sign) *good_sign = good == CGAL::POSITIVE ? 1 : -1;
  std::vector<char> flipped(o.size());
  for (std::size_t i = 0; i < o.size(); ++i) flipped[i] = o[i] != good;
  return flipped;
}

}  // namespace

MapQuality map_quality(const split::Layout& L, const std::vector<int>& triangles, const std::map<int, std::array<double, 2>>& at) {
  const std::vector<char> rev = consistent_orientation(L, triangles);
  MapQuality q;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    auto tr = L.triangles[triangles[i]];
    if (rev[i]) std::swap(tr[1], tr[2]);
    const std::array<std::array<double, 2>, 3> x{at.at(tr[0]), at.at(tr[1]), at.at(tr[2])};
    for (int k = 0; k < 3; ++k) {
      const double on_surface = angle_at(L.points[tr[k]], L.points[tr[(k + 1) % 3]], L.points[tr[(k + 2) % 3]], 3);
      const double in_plane = angle_at(x[k], x[(k + 1) % 3], x[(k + 2) % 3], 2);
      q.max_angle_distortion_deg = std::max(q.max_angle_distortion_deg, std::abs(in_plane - on_surface) * 180 / kPi);
    }
  }
  const std::vector<char> flipped = flipped_images(L, triangles, rev, at);
  q.flipped_triangles = static_cast<int>(std::count(flipped.begin(), flipped.end(), 1));
  return q;
}

namespace {

// The centroid of the kernel of a vertex's link: the points from which every link edge (a, b)
// turns `sign` (the intersection of those half-planes, clipped from a box around the link;
// Sutherland-Hodgman). nullopt if it is empty.
std::optional<std::array<double, 2>> kernel_centroid(const std::vector<std::array<std::array<double, 2>, 2>>& link, int sign) {
  using P = std::array<double, 2>;
  double lo0 = HUGE_VAL, lo1 = HUGE_VAL, hi0 = -HUGE_VAL, hi1 = -HUGE_VAL;
  for (const auto& e : link)
    for (const P& p : e) lo0 = std::min(lo0, p[0]), lo1 = std::min(lo1, p[1]), hi0 = std::max(hi0, p[0]), hi1 = std::max(hi1, p[1]);
  const double pad = (hi0 - lo0) + (hi1 - lo1);
  std::vector<P> poly{{lo0 - pad, lo1 - pad}, {hi0 + pad, lo1 - pad}, {hi0 + pad, hi1 + pad}, {lo0 - pad, hi1 + pad}};
  for (const auto& [a, b] : link) {
    auto side = [&](const P& x) { return sign * ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])); };
    std::vector<P> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const P& p = poly[i];
      const P& q = poly[(i + 1) % poly.size()];
      const double sp = side(p), sq = side(q);
      if (sp > 0) out.push_back(p);
      if ((sp > 0) != (sq > 0)) {
        const double t = sp / (sp - sq);
        out.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
      }
    }
    poly = std::move(out);
    if (poly.size() < 3) return std::nullopt;
  }
  double area = 0, cx = 0, cy = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const P& p = poly[i];
    const P& q = poly[(i + 1) % poly.size()];
    const double c = p[0] * q[1] - q[0] * p[1];
    area += c, cx += (p[0] + q[0]) * c, cy += (p[1] + q[1]) * c;
  }
  if (!(std::abs(area) > 0)) return std::nullopt;
  return P{cx / (3 * area), cy / (3 * area)};
}

}  // namespace

int unfold_free_vertices(const split::Layout& L, const std::vector<int>& triangles, const std::map<int, std::array<double, 2>>& fixed,
                         std::map<int, std::array<double, 2>>& at, int sweeps) {
  const std::vector<char> rev = consistent_orientation(L, triangles);
  int sign = 1;
  std::vector<char> flipped = flipped_images(L, triangles, rev, at, &sign);
  long left = std::count(flipped.begin(), flipped.end(), 1);
  if (left == 0) return 0;  // the usual case: nothing to do
  // Per vertex: its incident triangles (indices into `triangles`).
  std::map<int, std::vector<std::size_t>> around;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (int v : L.triangles[triangles[i]]) around[v].push_back(i);
  for (int sweep = 0; sweep < sweeps && left > 0; ++sweep) {
    std::map<int, std::array<double, 2>> moved = at;
    std::set<int> free;
    for (std::size_t i = 0; i < triangles.size(); ++i)
      if (flipped[i])
        for (int v : L.triangles[triangles[i]])
          if (!fixed.count(v)) free.insert(v);
    for (int v : free) {
      // Its link edges, each turning like the surface's triangles when followed by v.
      std::vector<std::array<std::array<double, 2>, 2>> link;
      for (std::size_t i : around.at(v)) {
        auto tr = L.triangles[triangles[i]];
        if (rev[i]) std::swap(tr[1], tr[2]);
        const int k = tr[0] == v ? 0 : tr[1] == v ? 1 : 2;
        link.push_back({moved.at(tr[(k + 1) % 3]), moved.at(tr[(k + 2) % 3])});
      }
      if (const auto c = kernel_centroid(link, sign)) moved[v] = *c;
    }
    const std::vector<char> after = flipped_images(L, triangles, rev, moved);
    const long n = std::count(after.begin(), after.end(), 1);
    if (n >= left) break;  // no gain: keep the map as it was
    at = std::move(moved), flipped = after, left = n;
  }
  return static_cast<int>(left);
}

double layout_volume(const split::Layout& layout, const std::vector<std::array<double, 3>>& at, Fills fills) {
  double v = 0;
  for (std::size_t t = 0; t < layout.triangles.size(); ++t) {
    if (fills == Fills::skip && layout.filled[t]) continue;
    const auto &a = at[static_cast<std::size_t>(layout.triangles[t][0])], &b = at[static_cast<std::size_t>(layout.triangles[t][1])],
               &c = at[static_cast<std::size_t>(layout.triangles[t][2])];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  return v;
}

std::vector<PatchMap> map_patches(const split::Decomposition& d, const PatchMapParams& params) {
  const split::Layout& L = d.layout;
  static const std::array<std::array<double, 2>, 4> corner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  std::vector<PatchMap> out;
  for (std::size_t pi = 0; pi < L.patches.size(); ++pi) {
    const split::Patch& P = L.patches[pi];
    // Sides onto the square's edges by arc length, the interior by one solve.
    std::map<int, std::array<double, 2>> fixed;
    for (int k = 0; k < 4; ++k) {
      const auto frac = arc_length_fractions(L, P.sides[k]);
      const auto& a = corner[k];
      const auto& b = corner[(k + 1) % 4];
      for (std::size_t i = 0; i < P.sides[k].size(); ++i) fixed[P.sides[k][i]] = {a[0] + frac[i] * (b[0] - a[0]), a[1] + frac[i] * (b[1] - a[1])};
    }
    out.push_back(solve_patch_map(L, P.triangles, fixed, params, "patch " + std::to_string(pi)));
  }
  return out;
}

PatchMap solve_patch_map(const split::Layout& L, const std::vector<int>& triangles, const std::map<int, std::array<double, 2>>& fixed,
                         const PatchMapParams& params, const std::string& what) {
  const auto at = harmonic_positions(L, triangles, fixed, params, what);
  PatchMap m;
  for (const auto& [v, x] : at) m.vertices.push_back(v), m.st.push_back(x);
  const MapQuality q = map_quality(L, triangles, at);
  m.flipped_triangles = q.flipped_triangles;
  m.max_angle_distortion_deg = q.max_angle_distortion_deg;
  return m;
}

}  // namespace volts::polycube
