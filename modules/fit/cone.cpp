#include "fit/cone.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/errors.h"

namespace volts::fit {
namespace {

constexpr double kInside = 1e-14;  // slack of the containment test inside Welzl's loop

struct Cap {
  Eigen::Vector3d axis;
  double cos = 1;
  bool ok = true;  // false: the cap would be a hemisphere or more
};

bool contains(const Cap& c, const Eigen::Vector3d& v) { return c.axis.dot(v) >= c.cos - kInside; }

Cap cap2(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d s = a + b;
  const double n = s.norm();
  if (n < 1e-15) return {Eigen::Vector3d::Zero(), 0, false};  // antipodal
  Cap c{s / n, 0, true};
  c.cos = c.axis.dot(a);
  c.ok = c.cos > 0;
  return c;
}

// The cap with a, b, c on its boundary circle, or the smallest two-point cap holding all three when
// two of them (nearly) coincide and the plane through them is undefined.
Cap cap3(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  if (len < 1e-13 * std::max({(b - a).norm(), (c - a).norm(), 1e-300})) {
    Cap best{Eigen::Vector3d::Zero(), -2, false};
    const Cap cand[3] = {cap2(a, b), cap2(a, c), cap2(b, c)};
    const Eigen::Vector3d* third[3] = {&c, &b, &a};
    for (int i = 0; i < 3; ++i)
      if (cand[i].ok && contains(cand[i], *third[i]) && cand[i].cos > best.cos) best = cand[i];
    return best;
  }
  n /= len;
  if (n.dot(a) < 0) n = -n;
  Cap r{n, n.dot(a), true};
  r.ok = r.cos > 0;  // a great circle (plane through the origin) bounds a hemisphere
  return r;
}

}  // namespace

Cone enclosing_cone(const std::vector<Eigen::Vector3d>& vectors) {
  if (vectors.empty()) throw core::InvalidInputError("enclosing_cone: no vectors");
  const int n = static_cast<int>(vectors.size());
  std::vector<Eigen::Vector3d> v(n);
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) {
    const double len = vectors[i].norm();
    if (!(len > 0) || !std::isfinite(len))
      throw core::InvalidInputError("enclosing_cone: vector " + std::to_string(i) + " is zero or not finite");
    v[i] = vectors[i] / len;
    order[i] = i;
  }
  // Fixed pseudo-random order (Welzl's expected linear time without a global RNG; deterministic).
  uint64_t state = 0x9E3779B97F4A7C15ull;
  for (int i = n - 1; i > 0; --i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    std::swap(order[i], order[static_cast<int>((state >> 33) % static_cast<uint64_t>(i + 1))]);
  }

  Cone out;
  out.half_angle = M_PI / 2;
  Cap cap{v[order[0]], 1, true};
  std::array<int, 3> support{order[0], -1, -1};
  for (int a = 1; a < n; ++a) {
    const int i = order[a];
    if (contains(cap, v[i])) continue;
    cap = {v[i], 1, true};
    support = {i, -1, -1};
    for (int b = 0; b < a; ++b) {
      const int j = order[b];
      if (contains(cap, v[j])) continue;
      cap = cap2(v[i], v[j]);
      support = {i, j, -1};
      if (!cap.ok) return out;
      for (int c = 0; c < b; ++c) {
        const int k = order[c];
        if (contains(cap, v[k])) continue;
        cap = cap3(v[i], v[j], v[k]);
        support = {i, j, k};
        if (!cap.ok) return out;
      }
    }
  }
  double min_cos = 1;
  for (const auto& x : v) min_cos = std::min(min_cos, cap.axis.dot(x));
  if (!(min_cos > 0)) return out;
  out.in_open_hemisphere = true;
  out.axis = cap.axis;
  out.min_cos = std::min(min_cos, 1.0);
  out.half_angle = std::acos(out.min_cos);
  out.support = support;
  return out;
}

}  // namespace volts::fit
