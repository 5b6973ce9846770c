#include "octree/refine.h"

#include <algorithm>
#include <cmath>

namespace volts::octree {

bool contains_point(const Cell& c, const Vec3& q) {
  for (int a = 0; a < 3; ++a)
    if (q[a] < c.unit_lo[a] || q[a] > c.unit_hi[a]) return false;
  return true;
}

bool crosses_plane(const Cell& c, const Vec3& normal, double offset) {
  double mn = 1e9, mx = -1e9;
  for (int k = 0; k < 8; ++k) {
    const double x = k & 1 ? c.unit_hi[0] : c.unit_lo[0], y = k & 2 ? c.unit_hi[1] : c.unit_lo[1],
                 z = k & 4 ? c.unit_hi[2] : c.unit_lo[2];
    const double s = normal[0] * x + normal[1] * y + normal[2] * z - offset;
    mn = std::min(mn, s);
    mx = std::max(mx, s);
  }
  return mn <= 0 && mx >= 0;
}

bool crosses_sphere(const Cell& c, const Vec3& centre, double radius) {
  double near = 0, far = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max({c.unit_lo[a] - centre[a], 0.0, centre[a] - c.unit_hi[a]});
    const double e = std::max(std::abs(centre[a] - c.unit_lo[a]), std::abs(centre[a] - c.unit_hi[a]));
    near += d * d;
    far += e * e;
  }
  return std::sqrt(near) <= radius && radius <= std::sqrt(far);
}

bool random_split(const Cell& c, std::uint64_t seed, double p) {
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ull + std::uint64_t(c.level) * 0xBF58476D1CE4E5B9ull +
                    (std::uint64_t(c.lo[0]) << 40) + (std::uint64_t(c.lo[1]) << 20) + std::uint64_t(c.lo[2]);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return (x >> 11) * 0x1.0p-53 < p;
}

int refine_toward_point(Octree& t, const Vec3& q) {
  return t.refine([&](const Cell& c) { return contains_point(c, q); });
}

int refine_toward_plane(Octree& t, const Vec3& normal, double offset) {
  return t.refine([&](const Cell& c) { return crosses_plane(c, normal, offset); });
}

int refine_toward_sphere(Octree& t, const Vec3& centre, double radius) {
  return t.refine([&](const Cell& c) { return crosses_sphere(c, centre, radius); });
}

}  // namespace volts::octree
