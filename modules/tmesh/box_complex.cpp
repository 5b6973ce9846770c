// Boxes of one frame cut into sub-boxes that meet in whole faces (complex.h, BoxLayout).
// Written by hand: CGAL and the other libraries have no conforming refinement of an axis-aligned
// box complex (Nef polyhedra would give the union's faces, not a conforming hex partition).
#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"
#include "tmesh/complex.h"

namespace volts::tmesh {

namespace {

std::string box_name(int b) { return "box " + std::to_string(b); }

// Box a's hi face along `axis` is box b's lo face, points of b being points of a moved by `shift`.
struct Touch {
  int a = 0, b = 0, axis = 0;
  Vec3 shift{0, 0, 0};
};

// Inserts x into the sorted list unless a value lies within gap; true if inserted.
bool insert_sorted(std::vector<double>& v, double x, double gap) {
  const auto it = std::lower_bound(v.begin(), v.end(), x);
  if ((it != v.end() && *it - x <= gap) || (it != v.begin() && x - *(it - 1) <= gap)) return false;
  v.insert(it, x);
  return true;
}

}  // namespace

Vec3 BoxComplex::to_frame(int cube, const Vec3& uvw) const {
  const auto& e = extent.at(static_cast<std::size_t>(cube));
  Vec3 x;
  for (int d = 0; d < 3; ++d) x[d] = e[0][d] + uvw[d] * (e[1][d] - e[0][d]);
  return x;
}

std::vector<std::array<double, 3>> BoxComplex::pillow(double thickness) const {
  std::vector<std::array<double, 3>> p(extent.size());
  for (std::size_t c = 0; c < extent.size(); ++c)
    for (int d = 0; d < 3; ++d) p[c][static_cast<std::size_t>(d)] = thickness / (extent[c][1][d] - extent[c][0][d]);
  return p;
}

std::optional<std::pair<int, Vec3>> BoxComplex::locate(const Vec3& x, int prefer, double tol) const {
  const double t = tol * size;
  auto holds = [&](std::size_t i, const Vec3& y) {
    for (int d = 0; d < 3; ++d)
      if (!(y[d] >= extent[i][0][d] - t && y[d] <= extent[i][1][d] + t)) return false;
    return true;
  };
  auto found = [&](std::size_t i, const Vec3& y) {
    Vec3 u;
    for (int d = 0; d < 3; ++d) u[d] = std::clamp((y[d] - extent[i][0][d]) / (extent[i][1][d] - extent[i][0][d]), 0.0, 1.0);
    return std::make_pair(static_cast<int>(i), u);
  };
  if (prefer >= 0 && static_cast<std::size_t>(prefer) < extent.size() && holds(static_cast<std::size_t>(prefer), x))
    return found(static_cast<std::size_t>(prefer), x);
  for (std::size_t i = 0; i < extent.size(); ++i)
    if (holds(i, x)) return found(i, x);
  // Across a closure only from the side of the face it closes (past face fa of box a, within the
  // face, into box b; or past fb of b into a): a point in a gap of the layout is not carried to
  // whatever box the shift happens to reach.
  auto past = [&](int b, int f, const Vec3& y) {
    const auto& B = boxes[static_cast<std::size_t>(b)];
    const int d = f / 2;
    for (int e = 0; e < 3; ++e)
      if (e != d && !(y[e] >= B[0][e] - t && y[e] <= B[1][e] + t)) return false;
    return f % 2 ? y[d] >= B[1][d] - t : y[d] <= B[0][d] + t;
  };
  for (const auto& c : closures)
    for (const double sign : {1.0, -1.0}) {
      if (!past(sign > 0 ? c.a : c.b, sign > 0 ? c.fa : c.fb, x)) continue;
      const Vec3 y{x[0] + sign * c.shift[0], x[1] + sign * c.shift[1], x[2] + sign * c.shift[2]};
      for (std::size_t i = 0; i < extent.size(); ++i)
        if (box[i] == (sign > 0 ? c.b : c.a) && holds(i, y)) return found(i, y);
    }
  return std::nullopt;
}

BoxComplex box_complex(const BoxLayout& layout, const std::vector<std::array<std::vector<double>, 3>>& cuts) {
  const auto& B = layout.boxes;
  const int n = static_cast<int>(B.size());
  if (!cuts.empty() && static_cast<int>(cuts.size()) != n)
    throw core::ConfigError("tmesh: cuts for " + std::to_string(cuts.size()) + " of " + std::to_string(n) + " boxes");
  BoxComplex r;
  r.closures = layout.closures;
  r.boxes = layout.boxes;
  r.size = 0;
  for (int b = 0; b < n; ++b)
    for (int d = 0; d < 3; ++d) {
      const double lo = B[static_cast<std::size_t>(b)][0][d], hi = B[static_cast<std::size_t>(b)][1][d];
      if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) throw core::TopologyError("tmesh: " + box_name(b) + " is empty or not finite along axis " + std::to_string(d));
      r.size = std::max({r.size, std::abs(lo), std::abs(hi), hi - lo});
    }
  const double eps = 1e-12 * r.size, gap = 1e-9 * r.size;
  auto lo = [&](int b, int d) { return B[static_cast<std::size_t>(b)][0][d]; };
  auto hi = [&](int b, int d) { return B[static_cast<std::size_t>(b)][1][d]; };
  // Which faces touch: a's hi face on b's lo face, the rectangles overlapping with positive area.
  std::vector<Touch> touches;
  auto overlaps = [&](int a, int b, int axis, const Vec3& s) {
    for (int t = 0; t < 3; ++t)
      if (t != axis && !(std::min(hi(a, t) + s[t], hi(b, t)) - std::max(lo(a, t) + s[t], lo(b, t)) > eps)) return false;
    return true;
  };
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      if (a == b) continue;
      bool interiors = true;
      for (int d = 0; d < 3; ++d) interiors = interiors && std::min(hi(a, d), hi(b, d)) - std::max(lo(a, d), lo(b, d)) > eps;
      if (interiors && a < b) throw core::TopologyError("tmesh: " + box_name(a) + " and " + box_name(b) + " overlap");
      for (int d = 0; d < 3; ++d)
        if (std::abs(hi(a, d) - lo(b, d)) <= eps && overlaps(a, b, d, {0, 0, 0})) touches.push_back({a, b, d, {0, 0, 0}});
    }
  for (std::size_t i = 0; i < layout.closures.size(); ++i) {
    const auto& c = layout.closures[i];
    const std::string name = "closure " + std::to_string(i) + " (" + box_name(c.a) + " face " + std::to_string(c.fa) + ", " + box_name(c.b) + " face " + std::to_string(c.fb) + ")";
    if (c.a < 0 || c.a >= n || c.b < 0 || c.b >= n || c.fa < 0 || c.fa > 5 || c.fb < 0 || c.fb > 5 || c.fa / 2 != c.fb / 2 || c.fa % 2 == c.fb % 2)
      throw core::TopologyError("tmesh: " + name + ": not two opposite faces of boxes of the layout");
    const int d = c.fa / 2;
    for (int t = 0; t < 3; ++t)
      if (t != d && c.shift[t] != 0) throw core::TopologyError("tmesh: " + name + ": the shift is not along the faces' axis");
    const double from = c.fa % 2 ? hi(c.a, d) : lo(c.a, d), to = c.fb % 2 ? hi(c.b, d) : lo(c.b, d);
    if (std::abs(from + c.shift[d] - to) > eps) throw core::TopologyError("tmesh: " + name + ": the shift does not take one face onto the other");
    Touch t = c.fa % 2 ? Touch{c.a, c.b, d, c.shift} : Touch{c.b, c.a, d, {-c.shift[0], -c.shift[1], -c.shift[2]}};
    if (!overlaps(t.a, t.b, d, t.shift)) throw core::TopologyError("tmesh: " + name + ": the faces do not meet");
    touches.push_back(t);
  }
  // Bounds per box and axis: its ends, its cuts, and (until none is added) every bound of a
  // touching box strictly inside their shared face's range.
  std::vector<std::array<std::vector<double>, 3>> bounds(static_cast<std::size_t>(n));
  for (int b = 0; b < n; ++b)
    for (int d = 0; d < 3; ++d) {
      auto& v = bounds[static_cast<std::size_t>(b)][static_cast<std::size_t>(d)];
      v = {lo(b, d), hi(b, d)};
      if (cuts.empty()) continue;
      for (const double x : cuts[static_cast<std::size_t>(b)][static_cast<std::size_t>(d)]) {
        if (!(x > lo(b, d) + gap && x < hi(b, d) - gap))
          throw core::ConfigError("tmesh: cut " + std::to_string(x) + " along axis " + std::to_string(d) + " is not inside " + box_name(b));
        insert_sorted(v, x, gap);
      }
    }
  for (bool changed = true; changed;) {
    changed = false;
    for (const Touch& t : touches)
      for (int u = 0; u < 3; ++u) {
        if (u == t.axis) continue;
        const double o_lo = std::max(lo(t.a, u) + t.shift[u], lo(t.b, u)), o_hi = std::min(hi(t.a, u) + t.shift[u], hi(t.b, u));
        const std::vector<double> from_a = bounds[static_cast<std::size_t>(t.a)][static_cast<std::size_t>(u)];
        for (const double x : from_a)
          if (x + t.shift[u] >= o_lo - gap && x + t.shift[u] <= o_hi + gap)
            changed = insert_sorted(bounds[static_cast<std::size_t>(t.b)][static_cast<std::size_t>(u)], x + t.shift[u], gap) || changed;
        const std::vector<double> from_b = bounds[static_cast<std::size_t>(t.b)][static_cast<std::size_t>(u)];
        for (const double x : from_b)
          if (x >= o_lo - gap && x <= o_hi + gap)
            changed = insert_sorted(bounds[static_cast<std::size_t>(t.a)][static_cast<std::size_t>(u)], x - t.shift[u], gap) || changed;
      }
  }
  // Sub-boxes, axis 0 fastest within each box.
  std::vector<int> first(static_cast<std::size_t>(n));
  std::vector<std::array<int, 3>> dims(static_cast<std::size_t>(n));
  for (int b = 0; b < n; ++b) {
    first[static_cast<std::size_t>(b)] = static_cast<int>(r.box.size());
    const auto& bd = bounds[static_cast<std::size_t>(b)];
    for (int d = 0; d < 3; ++d) dims[static_cast<std::size_t>(b)][static_cast<std::size_t>(d)] = static_cast<int>(bd[static_cast<std::size_t>(d)].size()) - 1;
    for (std::size_t k = 0; k + 1 < bd[2].size(); ++k)
      for (std::size_t j = 0; j + 1 < bd[1].size(); ++j)
        for (std::size_t i = 0; i + 1 < bd[0].size(); ++i) {
          r.box.push_back(b);
          r.extent.push_back({Vec3{bd[0][i], bd[1][j], bd[2][k]}, Vec3{bd[0][i + 1], bd[1][j + 1], bd[2][k + 1]}});
        }
  }
  r.complex.glue.resize(r.box.size());
  auto index = [&](int b, const std::array<int, 3>& ijk) {
    const auto& m = dims[static_cast<std::size_t>(b)];
    return first[static_cast<std::size_t>(b)] + ijk[0] + m[0] * (ijk[1] + m[1] * ijk[2]);
  };
  auto unit_step = [](int d) {
    AxisMap m;
    m.t[d] = -1;
    return m;
  };
  for (int b = 0; b < n; ++b) {
    const auto& m = dims[static_cast<std::size_t>(b)];
    for (int k = 0; k < m[2]; ++k)
      for (int j = 0; j < m[1]; ++j)
        for (int i = 0; i < m[0]; ++i)
          for (int d = 0; d < 3; ++d) {
            std::array<int, 3> ijk{i, j, k}, next = ijk;
            if (++next[static_cast<std::size_t>(d)] >= m[static_cast<std::size_t>(d)]) continue;
            glue_faces(r.complex, index(b, ijk), 2 * d + 1, index(b, next), 2 * d, unit_step(d));
          }
  }
  // Across touching faces: a's sub-boxes on its hi face onto b's on its lo face with equal sides.
  for (const Touch& t : touches) {
    const int d = t.axis;
    for (std::size_t s = static_cast<std::size_t>(first[static_cast<std::size_t>(t.a)]); s < r.box.size() && r.box[s] == t.a; ++s) {
      if (r.extent[s][1][d] != hi(t.a, d)) continue;
      for (std::size_t q = static_cast<std::size_t>(first[static_cast<std::size_t>(t.b)]); q < r.box.size() && r.box[q] == t.b; ++q) {
        if (r.extent[q][0][d] != lo(t.b, d)) continue;
        bool same = true;
        for (int u = 0; u < 3 && same; ++u)
          if (u != d)
            same = std::abs(r.extent[s][0][u] + t.shift[u] - r.extent[q][0][u]) <= gap && std::abs(r.extent[s][1][u] + t.shift[u] - r.extent[q][1][u]) <= gap;
        if (same) glue_faces(r.complex, static_cast<int>(s), 2 * d + 1, static_cast<int>(q), 2 * d, unit_step(d));
      }
    }
  }
  return r;
}

namespace {

std::array<Vec3, 2> image_box(const AxisMap& m) {
  std::array<Vec3, 2> b{m(Vec3{0, 0, 0}), m(Vec3{0, 0, 0})};
  for (int i = 1; i < 8; ++i) {
    const Vec3 x = m(Vec3{double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    for (int d = 0; d < 3; ++d) b[0][d] = std::min(b[0][d], x[d]), b[1][d] = std::max(b[1][d], x[d]);
  }
  return b;
}

// The frame face that face f of a cube placed by m becomes.
int frame_face(const AxisMap& m, int f) {
  Vec3 n{0, 0, 0};
  n[f / 2] = f % 2 ? 1 : -1;
  const Vec3 w = m.linear(n);
  int a = 0;
  while (w[a] == 0) ++a;
  return 2 * a + (w[a] > 0 ? 1 : 0);
}

}  // namespace

std::vector<AxisMap> develop(const CubeComplex& k, BoxLayout& layout) {
  const std::size_t n = k.glue.size();
  std::vector<AxisMap> frame(n);
  std::vector<char> placed(n, 0);
  layout = BoxLayout{};
  if (n == 0) return frame;
  std::vector<int> queue{0};
  placed[0] = 1;
  std::vector<std::array<char, 6>> closed(n, {0, 0, 0, 0, 0, 0});
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int c = queue[head];
    for (int f = 0; f < 6; ++f) {
      const auto& g = k.glue[static_cast<std::size_t>(c)][static_cast<std::size_t>(f)];
      if (!g) continue;
      const AxisMap want = compose(frame[static_cast<std::size_t>(c)], g->map.inverse());  // g's parameters -> the frame
      if (!placed[static_cast<std::size_t>(g->cube)]) {
        frame[static_cast<std::size_t>(g->cube)] = want, placed[static_cast<std::size_t>(g->cube)] = 1;
        queue.push_back(g->cube);
        continue;
      }
      const AxisMap& have = frame[static_cast<std::size_t>(g->cube)];
      bool same = have.P == want.P, shifted = false;
      Vec3 shift{0, 0, 0};
      for (int d = 0; d < 3; ++d) shift[d] = have.t[d] - want.t[d], shifted = shifted || std::abs(shift[d]) > 1e-12;
      if (!same)
        throw core::TopologyError("tmesh: cube " + std::to_string(c) + " face " + std::to_string(f) + " is glued to cube " + std::to_string(g->cube) +
                                  " with a turn no single frame holds");
      if (!shifted || closed[static_cast<std::size_t>(c)][static_cast<std::size_t>(f)]) continue;
      closed[static_cast<std::size_t>(c)][static_cast<std::size_t>(f)] = closed[static_cast<std::size_t>(g->cube)][static_cast<std::size_t>(g->face)] = 1;
      BoxLayout::Closure cl;
      cl.a = c, cl.fa = frame_face(frame[static_cast<std::size_t>(c)], f), cl.b = g->cube, cl.fb = frame_face(have, g->face), cl.shift = shift;
      layout.closures.push_back(cl);
    }
  }
  for (std::size_t c = 0; c < n; ++c) {
    if (!placed[c]) throw core::TopologyError("tmesh: cube " + std::to_string(c) + " is not connected to cube 0 by gluings");
    layout.boxes.push_back(image_box(frame[c]));
  }
  return frame;
}

Vec3 cube_to_frame(const AxisMap& frame, const std::array<Vec3, 2>& box, const Vec3& x) {
  Vec3 y{};
  for (int f = 0; f < 3; ++f)
    for (int a = 0; a < 3; ++a)
      if (frame.P[f][a] != 0) y[f] = box[0][f] + (frame.P[f][a] > 0 ? x[a] : 1 - x[a]) * (box[1][f] - box[0][f]);
  return y;
}

Vec3 frame_to_cube(const AxisMap& frame, const std::array<Vec3, 2>& box, const Vec3& y) {
  Vec3 x{};
  for (int f = 0; f < 3; ++f)
    for (int a = 0; a < 3; ++a)
      if (frame.P[f][a] != 0) {
        const double u = (y[f] - box[0][f]) / (box[1][f] - box[0][f]);
        x[a] = frame.P[f][a] > 0 ? u : 1 - u;
      }
  return x;
}

std::vector<std::vector<Block>> blocks_in_cubes(const BoxComplex& bc, const std::vector<AxisMap>& frame, const std::vector<std::vector<Block>>& blocks) {
  if (bc.boxes.size() != frame.size()) throw core::ConfigError("tmesh: frame maps for " + std::to_string(frame.size()) + " of " + std::to_string(bc.boxes.size()) + " boxes");
  std::vector<std::vector<Block>> cores(frame.size()), slabs(frame.size());
  std::vector<std::vector<int>> slab_face(frame.size());
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const int c = bc.box.at(i);
    const AxisMap& to_frame = frame.at(static_cast<std::size_t>(c));
    // Cube axis a is frame axis fa[a] (sign sa[a]).
    std::array<int, 3> fa{}, sa{};
    for (int a = 0; a < 3; ++a)
      for (int f = 0; f < 3; ++f)
        if (to_frame.P[f][a] != 0) fa[a] = f, sa[a] = to_frame.P[f][a];
    for (const Block& b : blocks[i]) {
      Block o;
      o.pillow = b.pillow;
      for (int a = 0; a < 3; ++a) {
        o.elements[static_cast<std::size_t>(a)] = b.elements[static_cast<std::size_t>(fa[a])];
        for (int side = 0; side < 2; ++side)
          o.boundary[static_cast<std::size_t>(2 * a + side)] = b.boundary[static_cast<std::size_t>(2 * fa[a] + (sa[a] > 0 ? side : 1 - side))];
      }
      for (int j = 0; j < 8; ++j) {
        int from = 0;
        for (int a = 0; a < 3; ++a) {
          const int bit = (j >> a) & 1;
          from |= (sa[a] > 0 ? bit : 1 - bit) << fa[a];
        }
        o.corners[static_cast<std::size_t>(j)] =
            frame_to_cube(to_frame, bc.boxes[static_cast<std::size_t>(c)], bc.to_frame(static_cast<int>(i), b.corners[static_cast<std::size_t>(from)]));
      }
      if (!o.pillow) {
        cores[static_cast<std::size_t>(c)].push_back(o);
        continue;
      }
      int f = 0;
      while (!o.boundary[static_cast<std::size_t>(f)]) ++f;
      slabs[static_cast<std::size_t>(c)].push_back(o), slab_face[static_cast<std::size_t>(c)].push_back(f);
    }
  }
  std::vector<std::vector<Block>> out(frame.size());
  for (std::size_t c = 0; c < frame.size(); ++c) {
    out[c] = cores[c];
    std::vector<std::size_t> order(slabs[c].size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return slab_face[c][x] < slab_face[c][y]; });
    for (const std::size_t i : order) out[c].push_back(slabs[c][i]);
  }
  return out;
}

}  // namespace volts::tmesh
