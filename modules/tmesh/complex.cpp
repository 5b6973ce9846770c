#include "tmesh/complex.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/errors.h"

namespace volts::tmesh {

Vec3 AxisMap::linear(const Vec3& x) const {
  Vec3 y{0, 0, 0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) y[i] += P[i][j] * x[j];
  return y;
}

Vec3 AxisMap::operator()(const Vec3& x) const {
  Vec3 y = linear(x);
  for (int i = 0; i < 3; ++i) y[i] += t[i];
  return y;
}

AxisMap compose(const AxisMap& outer, const AxisMap& inner) {
  AxisMap m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      m.P[i][j] = 0;
      for (int l = 0; l < 3; ++l) m.P[i][j] += outer.P[i][l] * inner.P[l][j];
    }
  m.t = outer(inner.t);
  return m;
}

AxisMap AxisMap::inverse() const {
  AxisMap m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.P[i][j] = P[j][i];
  const Vec3 u = m.linear(t);
  m.t = {-u[0], -u[1], -u[2]};
  return m;
}

namespace {

std::string where(int cube, int face) { return "cube " + std::to_string(cube) + " face " + std::to_string(face); }

Vec3 outward(int face) {
  Vec3 n{0, 0, 0};
  n[face / 2] = face % 2 ? 1 : -1;
  return n;
}

}  // namespace

void glue_faces(CubeComplex& k, int a, int fa, int b, int fb, const AxisMap& a_to_b) {
  const int n = static_cast<int>(k.glue.size());
  if (a < 0 || a >= n || b < 0 || b >= n || fa < 0 || fa > 5 || fb < 0 || fb > 5)
    throw core::TopologyError("tmesh: gluing " + where(a, fa) + " to " + where(b, fb) + ": no such cube face");
  if (k.glue[a][fa] || k.glue[b][fb]) throw core::TopologyError("tmesh: " + where(a, fa) + " or " + where(b, fb) + " is glued twice");
  // The face's centre goes to the other face's centre, the outward normal to the other's inward one.
  Vec3 centre{0.5, 0.5, 0.5};
  centre[fa / 2] = fa % 2;
  const Vec3 y = a_to_b(centre), na = a_to_b.linear(outward(fa)), nb = outward(fb);
  Vec3 want{0.5, 0.5, 0.5};
  want[fb / 2] = fb % 2;
  for (int i = 0; i < 3; ++i)
    if (std::abs(y[i] - want[i]) > 1e-12 || na[i] != -nb[i])
      throw core::TopologyError("tmesh: the map gluing " + where(a, fa) + " to " + where(b, fb) + " does not take one face onto the other");
  k.glue[a][fa] = CubeComplex::Glue{b, fb, a_to_b};
  k.glue[b][fb] = CubeComplex::Glue{a, fa, a_to_b.inverse()};
}

namespace {

// The direction s (entries -1, 0, 1, cube c's parameters) from corner v of cube c to its inner
// copy: per axis, toward the solid across the surface plane through v perpendicular to it.
// Occupancy of the eight octants around v: walked from c across glued faces (octant bit d = 1:
// on c's side of v along axis d). Planes facing opposite ways along one axis: refused, or s = 0
// there (OppositePlanes).
std::array<int, 3> inner_direction(const CubeComplex& k, int c, const std::array<int, 3>& v, OppositePlanes opposite) {
  struct State {
    bool occupied = false;
    int cube = -1;
    AxisMap map;  // c's parameters -> the occupying cube's
  };
  std::array<State, 8> oct;
  oct[7] = {true, c, AxisMap{}};
  std::array<int, 8> queue{7};
  int head = 0, tail = 1;
  std::array<bool, 8> seen{};
  seen[7] = true;
  std::array<int, 3> c_side{};
  for (int d = 0; d < 3; ++d) c_side[d] = v[d] == 0 ? 1 : -1;
  // Position of octant o along axis d relative to v, in c's parameters (+1 or -1).
  auto position = [&](int o, int d) { return ((o >> d) & 1) ? c_side[d] : -c_side[d]; };
  // The gluing (if any) of the face of octant o's cube toward its neighbour across axis d.
  auto glue_toward = [&](int o, int d) -> const std::optional<CubeComplex::Glue>& {
    Vec3 step{0, 0, 0};
    step[d] = -position(o, d);
    const Vec3 w = oct[o].map.linear(step);
    int axis = 0;
    while (w[axis] == 0) ++axis;
    return k.glue[oct[o].cube][2 * axis + (w[axis] > 0 ? 1 : 0)];
  };
  while (head < tail) {
    const int o = queue[head++];
    for (int d = 0; d < 3; ++d) {
      const int o2 = o ^ (1 << d);
      if (seen[o2]) continue;
      const auto& g = glue_toward(o, d);
      if (!g) continue;  // a surface face: not reached from here (perhaps from another octant)
      oct[o2] = {true, g->cube, compose(g->map, oct[o].map)};
      seen[o2] = true;
      queue[tail++] = o2;
    }
  }
  auto glued = [&](int o, int d) { return glue_toward(o, d).has_value(); };
  // A crack: two occupied octants side by side along d whose shared face is glued from neither
  // side — a ring's next cube over the plate cell beside its foot (the development is straight;
  // in the solid there is a wedge of air between them). Both faces are surface planes facing
  // each other, and the inner copy moves away from the crack within its plane: toward the
  // octant pair beside it (along another axis) that is glued, where the solid goes on.
  std::array<bool, 3> crack{};
  std::array<int, 3> away{0, 0, 0};
  for (int d = 0; d < 3; ++d)
    for (int o = 0; o < 8; ++o) {
      const int o2 = o ^ (1 << d);
      if (!((o >> d) & 1) || !oct[o].occupied || !oct[o2].occupied || glued(o, d)) continue;
      crack[d] = true;
      for (int e = 0; e < 3; ++e) {
        const int n = o ^ (1 << e), n2 = o2 ^ (1 << e);
        if (e != d && oct[n].occupied && oct[n2].occupied && glued(n, d)) away[e] = position(n, e);
      }
    }
  std::array<int, 3> s{0, 0, 0};
  for (int d = 0; d < 3; ++d) {
    bool plus = crack[d], minus = crack[d];
    for (int o = 0; o < 8; ++o) {
      if (!((o >> d) & 1)) continue;
      const bool in = oct[o].occupied, out = oct[o ^ (1 << d)].occupied;
      if (in == out) continue;
      (in ? c_side[d] : -c_side[d]) > 0 ? plus = true : minus = true;
    }
    if (plus && minus && opposite == OppositePlanes::refuse)
      throw core::TopologyError("tmesh: the polycube is not a manifold at corner (" + std::to_string(v[0]) + "," + std::to_string(v[1]) + "," +
                                std::to_string(v[2]) + ") of cube " + std::to_string(c) + ": surface planes on both sides along axis " +
                                std::to_string(d) + (crack[d] ? " (two occupied cubes side by side, not glued)" : ""));
    s[d] = plus && minus ? 0 : plus ? 1 : minus ? -1 : away[d];
  }
  return s;
}

}  // namespace

std::vector<std::vector<Block>> complex_blocks(const CubeComplex& k, int elements, int layers) {
  if (elements < 1 || layers < 1)
    throw core::ConfigError("tmesh: a pillowed cube complex needs elements >= 1 and layers >= 1, got " + std::to_string(elements) + " and " +
                            std::to_string(layers));
  const double p = static_cast<double>(layers) / (elements + 2 * layers);
  return complex_blocks(k, std::vector<std::array<int, 3>>(k.glue.size(), {elements, elements, elements}), layers,
                        std::vector<std::array<double, 3>>(k.glue.size(), {p, p, p}));
}

namespace {

// The axis of the neighbour's parameters that axis t of cube c's goes to through glue g, and the sign.
std::pair<int, int> mapped_axis(const CubeComplex::Glue& g, int t) {
  for (int a = 0; a < 3; ++a)
    if (g.map.P[a][t] != 0) return {a, g.map.P[a][t]};
  throw core::TopologyError("tmesh: a gluing map is not a signed permutation");
}

// Classes of the cubes' axes (index 3 c + d) that gluings tie: the tangential axes of every
// glued face, and with `normal` its normal axis too. Returns each index's class root.
std::vector<int> axis_classes(const CubeComplex& k, bool normal) {
  std::vector<int> up(3 * k.glue.size());
  for (std::size_t i = 0; i < up.size(); ++i) up[i] = static_cast<int>(i);
  auto find = [&](int x) {
    while (up[static_cast<std::size_t>(x)] != x) x = up[static_cast<std::size_t>(x)] = up[static_cast<std::size_t>(up[static_cast<std::size_t>(x)])];
    return x;
  };
  for (std::size_t c = 0; c < k.glue.size(); ++c)
    for (int f = 0; f < 6; ++f) {
      const auto& g = k.glue[c][static_cast<std::size_t>(f)];
      if (!g) continue;
      for (int t = 0; t < 3; ++t)
        if (normal || t != f / 2) up[static_cast<std::size_t>(find(3 * static_cast<int>(c) + t))] = find(3 * g->cube + mapped_axis(*g, t).first);
    }
  for (std::size_t i = 0; i < up.size(); ++i) up[i] = find(static_cast<int>(i));
  return up;
}

}  // namespace

std::vector<std::vector<Block>> complex_blocks(const CubeComplex& k, const std::vector<std::array<int, 3>>& counts, int layers,
                                               const std::vector<std::array<double, 3>>& p, OppositePlanes opposite) {
  if (layers < 1 || counts.size() != k.glue.size() || p.size() != k.glue.size())
    throw core::ConfigError("tmesh: a pillowed cube complex needs layers >= 1 and counts and pillow thicknesses for each of its " +
                            std::to_string(k.glue.size()) + " cubes, got " + std::to_string(layers) + ", " + std::to_string(counts.size()) +
                            " and " + std::to_string(p.size()));
  for (std::size_t c = 0; c < k.glue.size(); ++c) {
    for (int d = 0; d < 3; ++d) {
      if (counts[c][static_cast<std::size_t>(d)] < 1)
        throw core::ConfigError("tmesh: cube " + std::to_string(c) + " has " + std::to_string(counts[c][static_cast<std::size_t>(d)]) + " elements along axis " + std::to_string(d));
      if (!(p[c][static_cast<std::size_t>(d)] > 0 && p[c][static_cast<std::size_t>(d)] < 0.5))
        throw core::ConfigError("tmesh: cube " + std::to_string(c) + "'s pillow thickness " + std::to_string(p[c][static_cast<std::size_t>(d)]) +
                                " along axis " + std::to_string(d) + " is not in (0, 0.5)");
    }
    for (int f = 0; f < 6; ++f) {
      const auto& g = k.glue[c][static_cast<std::size_t>(f)];
      if (!g) continue;
      for (int t = 0; t < 3; ++t) {
        if (t == f / 2) continue;
        const int u = mapped_axis(*g, t).first;
        if (counts[c][static_cast<std::size_t>(t)] != counts[static_cast<std::size_t>(g->cube)][static_cast<std::size_t>(u)])
          throw core::TopologyError("tmesh: " + where(static_cast<int>(c), f) + " has " + std::to_string(counts[c][static_cast<std::size_t>(t)]) +
                                    " elements along axis " + std::to_string(t) + ", the " + where(g->cube, g->face) + " glued to it " +
                                    std::to_string(counts[static_cast<std::size_t>(g->cube)][static_cast<std::size_t>(u)]));
      }
    }
  }
  std::vector<std::vector<Block>> out(k.glue.size());
  for (std::size_t c = 0; c < k.glue.size(); ++c) {
    std::array<Vec3, 8> corner, inner;
    for (int i = 0; i < 8; ++i) {
      const std::array<int, 3> v{i & 1, (i >> 1) & 1, (i >> 2) & 1};
      const std::array<int, 3> s = inner_direction(k, static_cast<int>(c), v, opposite);
      for (int d = 0; d < 3; ++d) corner[i][d] = v[d], inner[i][d] = v[d] + p[c][static_cast<std::size_t>(d)] * s[d];
    }
    Block core;
    core.corners = inner;
    core.elements = counts[c];
    out[c].push_back(core);
    for (int f = 0; f < 6; ++f) {
      if (k.glue[c][static_cast<std::size_t>(f)]) continue;
      const int d = f / 2, side = f % 2;
      Block b;
      b.pillow = true;
      b.boundary[static_cast<std::size_t>(f)] = 1;
      b.elements = counts[c];
      b.elements[static_cast<std::size_t>(d)] = layers;
      for (int i = 0; i < 8; ++i) {
        // Block corner i: the cube corner with bit d = side, outer or inner by i's bit d.
        const int j = (i & ~(1 << d)) | (side << d);
        const bool outer = ((i >> d) & 1) == side;
        b.corners[i] = outer ? corner[j] : inner[j];
      }
      out[c].push_back(b);
    }
  }
  return out;
}

std::vector<std::array<double, 3>> physical_pillow(const CubeComplex& k, int elements, int layers, const std::vector<std::array<double, 3>>& length) {
  if (elements < 1 || layers < 1 || length.size() != k.glue.size())
    throw core::ConfigError("tmesh: a physical pillow needs elements >= 1, layers >= 1 and a length triple for each of the " +
                            std::to_string(k.glue.size()) + " cubes");
  for (const auto& l : length)
    for (const double x : l)
      if (!(x > 0) || !std::isfinite(x)) throw core::ConfigError("tmesh: a cube's physical length is not positive: " + std::to_string(x));
  const std::vector<int> cls = axis_classes(k, true);
  std::vector<double> sum(cls.size(), 0.0);
  std::vector<int> count(cls.size(), 0);
  for (std::size_t i = 0; i < cls.size(); ++i) {
    const std::size_t r = static_cast<std::size_t>(cls[i]);
    sum[r] += length[i / 3][i % 3], ++count[r];
  }
  double shortest = std::numeric_limits<double>::infinity();
  for (std::size_t r = 0; r < cls.size(); ++r)
    if (count[r] > 0) shortest = std::min(shortest, sum[r] / count[r]);
  const double p0 = static_cast<double>(layers) / (elements + 2 * layers);
  std::vector<std::array<double, 3>> p(k.glue.size());
  for (std::size_t i = 0; i < cls.size(); ++i) {
    const std::size_t r = static_cast<std::size_t>(cls[i]);
    p[i / 3][i % 3] = p0 * shortest / (sum[r] / count[r]);
  }
  return p;
}

std::vector<std::array<int, 3>> element_counts(const CubeComplex& k, const std::vector<std::array<int, 3>>& wanted) {
  if (wanted.size() != k.glue.size())
    throw core::ConfigError("tmesh: element counts for " + std::to_string(wanted.size()) + " of " + std::to_string(k.glue.size()) + " cubes");
  const std::vector<int> cls = axis_classes(k, false);
  std::vector<int> most(cls.size(), 0);
  for (std::size_t c = 0; c < wanted.size(); ++c)
    for (int d = 0; d < 3; ++d) {
      const int w = wanted[c][static_cast<std::size_t>(d)];
      if (w < 1) throw core::ConfigError("tmesh: cube " + std::to_string(c) + " asks for " + std::to_string(w) + " elements along axis " + std::to_string(d));
      int& m = most[static_cast<std::size_t>(cls[3 * c + static_cast<std::size_t>(d)])];
      m = std::max(m, w);
    }
  std::vector<std::array<int, 3>> out(wanted.size());
  for (std::size_t c = 0; c < wanted.size(); ++c)
    for (int d = 0; d < 3; ++d) out[c][static_cast<std::size_t>(d)] = most[static_cast<std::size_t>(cls[3 * c + static_cast<std::size_t>(d)])];
  return out;
}

std::optional<std::pair<int, Vec3>> locate(const CubeComplex& k, int c, Vec3 x, double tol) {
  for (int step = 0; step < 8; ++step) {
    int face = -1;
    for (int d = 0; d < 3 && face < 0; ++d) {
      if (x[d] < -tol) face = 2 * d;
      else if (x[d] > 1 + tol) face = 2 * d + 1;
    }
    if (face < 0) {
      for (double& v : x) v = std::min(1.0, std::max(0.0, v));
      return std::make_pair(c, x);
    }
    const auto& g = k.glue[static_cast<std::size_t>(c)][static_cast<std::size_t>(face)];
    if (!g) return std::nullopt;
    x = g->map(x);
    c = g->cube;
  }
  return std::nullopt;
}

}  // namespace volts::tmesh
