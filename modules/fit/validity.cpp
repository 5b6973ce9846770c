#include "fit/validity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/errors.h"
#include "fit/cone.h"

namespace volts::fit {
namespace {

using Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

// The differences of one family of a sub-net: unit vectors and where they start.
struct Family {
  std::vector<Vector3d> t;
  std::vector<Difference> id;
};

// Verdict on one sub-net.
struct Local {
  bool ok = true;
  Condition failed = Condition::none;
  std::array<Difference, 3> witness{};
  double value = 0;
  double margin = kInf;
};

// Appends the difference from `start` along `dir` (raw, normalised later by normalise()).
void add(Family& f, const Vector3d& from, const Vector3d& to, int dir, std::array<int, 3> start) {
  f.t.push_back(to - from);
  f.id.push_back({dir, start});
}

// Normalises every difference of the families; a difference shorter than tol·(longest) fails.
bool normalise(std::vector<Family*> families, double tol, Local& out) {
  double longest = 0;
  for (const Family* f : families)
    for (const auto& t : f->t) longest = std::max(longest, t.norm());
  for (Family* f : families)
    for (size_t a = 0; a < f->t.size(); ++a) {
      const double len = f->t[a].norm();
      if (!(len > tol * longest) || !(len > 0)) {
        out = {false, Condition::degenerate_difference, {f->id[a], Difference{}, Difference{}}, len, -kInf};
        return false;
      }
      f->t[a] /= len;
    }
  return true;
}

// Scans the sub-nets lo..hi (inclusive, I fastest) and accumulates the verdict.
template <class F>
Validity scan(std::array<int, 3> lo, std::array<int, 3> hi, const ValidityParams& params, F&& check_one) {
  Validity r;
  r.margin = kInf;
  for (int K = lo[2]; K <= hi[2]; ++K)
    for (int J = lo[1]; J <= hi[1]; ++J)
      for (int I = lo[0]; I <= hi[0]; ++I) {
        const Local l = check_one(I, J, K);
        ++r.checked;
        r.margin = std::min(r.margin, l.margin);
        if (l.ok) continue;
        ++r.failures;
        if (r.valid) {
          r.valid = false;
          r.failed = l.failed;
          r.subnet = {I, J, K};
          r.witness = l.witness;
          r.value = l.value;
        }
        if (params.stop_at_first_failure) return r;
      }
  if (r.checked == 0) r.margin = 0;
  return r;
}

// Range of sub-net first indices of one direction holding point i (all when i < 0).
void range_of(int size, int degree, int i, int& lo, int& hi) {
  if (i < 0) {
    lo = 0;
    hi = size - 1 - degree;
    return;
  }
  if (i >= size) throw core::InvalidInputError("validity check: control point index " + std::to_string(i) +
                                               " outside the net (" + std::to_string(size) + " points)");
  lo = std::max(0, i - degree);
  hi = std::min(i, size - 1 - degree);
}

// ---- Proposition 1 ----

Validity curve_impl(const CurveNet& net, int point, const ValidityParams& params) {
  check(net);
  const int d = net.degree, m = static_cast<int>(net.points.size()) - 1;
  int lo, hi;
  range_of(m + 1, d, point, lo, hi);
  return scan({lo, 0, 0}, {hi, 0, 0}, params, [&](int I, int, int) {
    Local out;
    Family f;
    for (int i = I; i < I + d; ++i) add(f, net.points[i], net.points[i + 1], 0, {i, 0, 0});
    if (!normalise({&f}, params.tolerance, out)) return out;
    const Cone c = enclosing_cone(f.t);
    out.margin = c.min_cos;
    if (c.in_open_hemisphere && c.min_cos > params.tolerance) return out;
    out.ok = false;
    out.failed = Condition::cone_aperture;
    out.value = c.aperture();
    for (int s = 0; s < 3; ++s)
      if (c.support[s] >= 0) out.witness[s] = f.id[c.support[s]];
    if (!c.in_open_hemisphere) out.witness = {f.id[0], Difference{}, Difference{}};
    return out;
  });
}

// ---- Proposition 2 ----

Validity surface_impl(const SurfaceNet& net, std::array<int, 2> point, const ValidityParams& params) {
  check(net);
  const int du = net.degree[0], dv = net.degree[1];
  std::array<int, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int d = 0; d < 2; ++d) range_of(net.size[d], net.degree[d], point[d], lo[d], hi[d]);
  auto at = [&](int i, int j) -> const Vector3d& { return net.points[net.index(i, j)]; };
  const double tol = params.tolerance;
  return scan(lo, hi, params, [&](int I, int J, int) {
    Local out;
    Family fu, fv;
    for (int j = J; j <= J + dv; ++j)
      for (int i = I; i < I + du; ++i) add(fu, at(i, j), at(i + 1, j), 0, {i, j, 0});
    for (int j = J; j < J + dv; ++j)
      for (int i = I; i <= I + du; ++i) add(fv, at(i, j), at(i, j + 1), 1, {i, j, 0});
    if (!normalise({&fu, &fv}, tol, out)) return out;
    const Cone cu = enclosing_cone(fu.t), cv = enclosing_cone(fv.t);
    if (!cu.in_open_hemisphere || !cv.in_open_hemisphere) {
      const Family& f = cu.in_open_hemisphere ? fv : fu;
      out = {false, Condition::cone_aperture, {f.id[0], Difference{}, Difference{}}, M_PI, -kInf};
      return out;
    }
    const Vector3d& U = cu.axis;
    const Vector3d& V = cv.axis;
    // Family `f` must satisfy t·A − t·B > tol, t·B >= −tol, t·(A+B) > tol (see the header).
    auto family = [&](const Family& f, const Vector3d& A, const Vector3d& B, Condition cond) {
      for (size_t a = 0; a < f.t.size(); ++a) {
        const double ta = f.t[a].dot(A), tb = f.t[a].dot(B);
        out.margin = std::min(out.margin, ta - tb);
        double bad = kInf;
        if (!(ta - tb > tol)) bad = ta - tb;
        else if (!(tb >= -tol)) bad = tb;
        else if (!(ta + tb > tol)) bad = ta + tb;
        if (bad != kInf && out.ok) {
          out.ok = false;
          out.failed = cond;
          out.witness = {f.id[a], Difference{}, Difference{}};
          out.value = bad;
        }
      }
    };
    family(fu, U, V, Condition::surface_u);
    family(fv, V, U, Condition::surface_v);
    return out;
  });
}

// ---- Proposition 3 ----

// Indices of the extreme directions of a family inside an open hemisphere around `axis`: the
// vertices of the convex hull of their gnomonic projections (great circles map to lines, so a
// direction inside the hull is a non-negative combination of the vertices).
std::vector<int> extreme_directions(const std::vector<Vector3d>& t, const Vector3d& axis) {
  const int n = static_cast<int>(t.size());
  std::vector<int> all(n);
  for (int a = 0; a < n; ++a) all[a] = a;
  if (n <= 3) return all;
  const Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  std::vector<Eigen::Vector2d> p(n);
  for (int a = 0; a < n; ++a) p[a] = Eigen::Vector2d(t[a].dot(e1), t[a].dot(e2)) / t[a].dot(axis);
  std::sort(all.begin(), all.end(), [&](int a, int b) {
    return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y());
  });
  auto cross = [&](int o, int a, int b) {
    return (p[a] - p[o]).x() * (p[b] - p[o]).y() - (p[a] - p[o]).y() * (p[b] - p[o]).x();
  };
  std::vector<int> hull(2 * n);
  int k = 0;
  for (int a = 0; a < n; ++a) {  // Andrew's monotone chain, lower then upper hull
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], all[a]) <= 0) --k;
    hull[k++] = all[a];
  }
  for (int a = n - 2, lower = k + 1; a >= 0; --a) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], all[a]) <= 0) --k;
    hull[k++] = all[a];
  }
  hull.resize(std::max(1, k - 1));
  return hull;
}

Validity solid_impl(const SolidNet& net, std::array<int, 3> point, const ValidityParams& params) {
  check(net);
  const auto& deg = net.degree;
  std::array<int, 3> lo{}, hi{};
  for (int d = 0; d < 3; ++d) range_of(net.size[d], deg[d], point[d], lo[d], hi[d]);
  const double tol = params.tolerance;
  return scan(lo, hi, params, [&](int I, int J, int K) {
    Local out;
    std::array<Family, 3> f;
    for (int k = K; k <= K + deg[2]; ++k)
      for (int j = J; j <= J + deg[1]; ++j)
        for (int i = I; i <= I + deg[0]; ++i) {
          if (i < I + deg[0]) add(f[0], net.at(i, j, k), net.at(i + 1, j, k), 0, {i, j, k});
          if (j < J + deg[1]) add(f[1], net.at(i, j, k), net.at(i, j + 1, k), 1, {i, j, k});
          if (k < K + deg[2]) add(f[2], net.at(i, j, k), net.at(i, j, k + 1), 2, {i, j, k});
        }
    if (!normalise({&f[0], &f[1], &f[2]}, tol, out)) return out;
    std::array<std::vector<int>, 3> use;
    bool reduce = !params.exhaustive;
    for (int d = 0; d < 3 && reduce; ++d) {
      const Cone c = enclosing_cone(f[d].t);
      // Outside every open hemisphere some triple is <= 0 (0 is a positive combination of the
      // family); the exhaustive loop finds it.
      if (!c.in_open_hemisphere) reduce = false;
      else use[d] = extreme_directions(f[d].t, c.axis);
    }
    for (int d = 0; d < 3 && !reduce; ++d) {
      use[d].resize(f[d].t.size());
      for (size_t a = 0; a < use[d].size(); ++a) use[d][a] = static_cast<int>(a);
    }
    int bu = -1, bv = -1, bw = -1;
    for (int v : use[1])
      for (int w : use[2]) {
        const Vector3d n = f[1].t[v].cross(f[2].t[w]);
        for (int u : use[0]) {
          const double x = f[0].t[u].dot(n);
          if (x < out.margin) {
            out.margin = x;
            bu = u, bv = v, bw = w;
          }
        }
      }
    if (out.margin > tol) return out;
    out.ok = false;
    out.failed = Condition::solid_triple;
    out.value = out.margin;
    out.witness = {f[0].id[bu], f[1].id[bv], f[2].id[bw]};
    return out;
  });
}

}  // namespace

const char* to_string(Condition c) {
  switch (c) {
    case Condition::none: return "none";
    case Condition::degenerate_difference: return "degenerate_difference";
    case Condition::cone_aperture: return "cone_aperture";
    case Condition::surface_u: return "surface_u";
    case Condition::surface_v: return "surface_v";
    case Condition::solid_triple: return "solid_triple";
    case Condition::g1_shape: return "g1_shape";
    case Condition::g1_position: return "g1_position";
    case Condition::g1_direction: return "g1_direction";
  }
  return "?";
}

std::string Validity::describe() const {
  std::ostringstream s;
  if (valid) {
    s << "valid (" << checked << " sub-nets, margin " << margin << ")";
    return s.str();
  }
  s << to_string(failed) << " on sub-net (" << subnet[0] << "," << subnet[1] << "," << subnet[2] << ")";
  const char* dir = "uvw";
  for (const Difference& d : witness)
    if (d.direction >= 0)
      s << " T^" << dir[d.direction] << "(" << d.start[0] << "," << d.start[1] << "," << d.start[2] << ")";
  s << " value " << value << "; " << failures << " of " << checked << " sub-nets fail";
  return s.str();
}

Validity check_curve(const CurveNet& net, const ValidityParams& params) { return curve_impl(net, -1, params); }
Validity check_curve_near(const CurveNet& net, int i, const ValidityParams& params) {
  if (i < 0) throw core::InvalidInputError("check_curve_near: negative control point index");
  return curve_impl(net, i, params);
}

Validity check_surface(const SurfaceNet& net, const ValidityParams& params) {
  return surface_impl(net, {-1, -1}, params);
}
Validity check_surface_near(const SurfaceNet& net, std::array<int, 2> ij, const ValidityParams& params) {
  if (ij[0] < 0 || ij[1] < 0) throw core::InvalidInputError("check_surface_near: negative control point index");
  return surface_impl(net, ij, params);
}

Validity check_solid(const SolidNet& net, const ValidityParams& params) {
  return solid_impl(net, {-1, -1, -1}, params);
}
Validity check_solid_near(const SolidNet& net, std::array<int, 3> ijk, const ValidityParams& params) {
  if (ijk[0] < 0 || ijk[1] < 0 || ijk[2] < 0)
    throw core::InvalidInputError("check_solid_near: negative control point index");
  return solid_impl(net, ijk, params);
}

// ---- Proposition 4 ----

Validity check_g1(const SolidNet& p, const SolidNet& q, const G1Params& params, double* alpha) {
  check(p);
  check(q);
  Validity r;
  if (alpha) *alpha = 0;
  if (p.size[0] != q.size[0] || p.size[1] != q.size[1] || p.degree[0] != q.degree[0] || p.degree[1] != q.degree[1]) {
    r.valid = false;
    r.failed = Condition::g1_shape;
    r.failures = 1;
    r.margin = -kInf;
    return r;
  }
  Eigen::AlignedBox3d box;
  for (const auto& x : p.points) box.extend(x);
  for (const auto& x : q.points) box.extend(x);
  const double scale = std::max(box.diagonal().norm(), std::numeric_limits<double>::min());
  const int lp = p.size[2] - 1;
  double ab = 0, bb = 0;
  for (int j = 0; j < p.size[1]; ++j)
    for (int i = 0; i < p.size[0]; ++i) {
      const Vector3d a = p.at(i, j, lp) - p.at(i, j, lp - 1), b = q.at(i, j, 1) - q.at(i, j, 0);
      ab += a.dot(b);
      bb += b.dot(b);
    }
  const double al = bb > 0 ? ab / bb : 0;
  if (alpha) *alpha = al;
  // Witness: the worst position residual if any fails, else the worst direction residual.
  double worst_pos = 0, worst_dir = 0;
  std::array<int, 2> at_pos{0, 0}, at_dir{0, 0};
  for (int j = 0; j < p.size[1]; ++j)
    for (int i = 0; i < p.size[0]; ++i) {
      ++r.checked;
      const double pos = (p.at(i, j, lp) - q.at(i, j, 0)).norm() / scale;
      const Vector3d a = p.at(i, j, lp) - p.at(i, j, lp - 1), b = q.at(i, j, 1) - q.at(i, j, 0);
      const double dir = (a - al * b).norm() / scale;
      r.failures += pos > params.tolerance_rel || dir > params.tolerance_rel;
      if (pos > worst_pos) worst_pos = pos, at_pos = {i, j};
      if (dir > worst_dir) worst_dir = dir, at_dir = {i, j};
    }
  const double worst = std::max(worst_pos, worst_dir);
  auto fail = [&](Condition c, std::array<int, 2> ij, double value) {
    r.valid = false;
    r.failed = c;
    r.subnet = {ij[0], ij[1], 0};
    r.value = value;
    r.witness = {Difference{2, {ij[0], ij[1], lp - 1}}, Difference{}, Difference{}};
  };
  if (worst_pos > params.tolerance_rel) fail(Condition::g1_position, at_pos, worst_pos);
  else if (!(al > 0)) fail(Condition::g1_direction, {0, 0}, al);
  else if (worst_dir > params.tolerance_rel) fail(Condition::g1_direction, at_dir, worst_dir);
  if (!r.valid) r.failures = std::max(r.failures, 1);
  r.margin = params.tolerance_rel - worst;
  if (!(al > 0)) r.margin = std::min(r.margin, al);
  return r;
}

}  // namespace volts::fit
