// volts::polycube — rings with a rectilinear cross section (Liu et al. 2013 §4.2: "the polycube is
// built by union of cube and torus primitives", Fig. 6(c)). The washer's cross section is a plus
// sign; mapped onto a square ring, four of its twelve sharp curves lie on cube edges and the other
// eight (four of them concave) are flattened inside faces, which folds the map everywhere
// (docs/status.md, session 11). Here the cross section becomes the polygon its sharp corners
// describe, cut into grid cells, so every sharp curve lies on an edge of the polycube.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "polycube/embedding.h"

namespace volts::polycube {

namespace {

constexpr double kPi = 3.14159265358979323846;
using Vec3 = std::array<double, 3>;

Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// Distance from q to the segment [a, b] in the plane.
double segment_distance(const std::array<double, 2>& q, const std::array<double, 2>& a, const std::array<double, 2>& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(q[0] - a[0] - t * dx, q[1] - a[1] - t * dy);
}

// Coordinates merged into grid lines: values closer than `tol` of the extent are one line (their
// mean). Returns each value's line index and the lines, normalized to [0, 1].
std::pair<std::vector<int>, std::vector<double>> grid_lines(const std::vector<double>& x, double tol) {
  std::vector<std::size_t> order(x.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return x[p] < x[q]; });
  const double extent = x[order.back()] - x[order.front()];
  std::vector<int> line(x.size());
  std::vector<double> sum;
  std::vector<int> count;
  for (std::size_t r = 0; r < order.size(); ++r) {
    if (r == 0 || x[order[r]] - x[order[r - 1]] > tol * extent) sum.push_back(0), count.push_back(0);
    sum.back() += x[order[r]], ++count.back();
    line[order[r]] = static_cast<int>(sum.size()) - 1;
  }
  std::vector<double> lines(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i) lines[i] = sum[i] / count[i];
  const double lo = lines.front(), hi = lines.back();
  for (double& v : lines) v = hi > lo ? (v - lo) / (hi - lo) : 0.0;
  return {line, lines};
}

}  // namespace

std::array<double, 3> profile_to_sector(const Profile& p, int cell, const std::array<double, 3>& x) {
  if (p.empty()) return x;
  const auto [i, j] = p.cells.at(static_cast<std::size_t>(cell));
  const auto bi = static_cast<std::size_t>(i), cj = static_cast<std::size_t>(j);
  return {x[0], p.b[bi] + x[1] * (p.b[bi + 1] - p.b[bi]), p.c[cj] + x[2] * (p.c[cj + 1] - p.c[cj])};
}

std::optional<Embedding> embed_profile_ring(const split::Decomposition& d, const std::vector<PatchMap>& maps, std::string& why) {
  auto fail = [&](const std::string& s) -> std::optional<Embedding> {
    why = s;
    return std::nullopt;
  };
  if (d.tori.size() != 1 || d.components.size() != d.tori[0].components.size()) return fail("not one torus");
  const split::Torus& T = d.tori[0];
  const int n = static_cast<int>(T.components.size());
  if (n < 3 || static_cast<int>(T.cross_sections.size()) != n) return fail("not a ring of at least three cubes with a cross section between each");
  const split::Layout& L = d.layout;
  // Loop l is cross section l, between components l and l + 1: component k runs from loop k - 1
  // (a = 0) to loop k (a = 1).
  std::vector<std::map<int, std::size_t>> position(static_cast<std::size_t>(n));  // vertex -> place in its loop
  for (int l = 0; l < n; ++l) {
    const auto& loop = L.internal_faces.at(static_cast<std::size_t>(T.cross_sections[static_cast<std::size_t>(l)])).loop;
    for (std::size_t q = 0; q < loop.size(); ++q) position[static_cast<std::size_t>(l)][loop[q]] = q;
  }
  auto loop0 = [n](int k) { return (k + n - 1) % n; };
  std::vector<std::set<int>> corners(static_cast<std::size_t>(n));  // profile corners per loop
  std::vector<std::map<int, int>> across(static_cast<std::size_t>(n));  // per component: corner at a = 0 -> corner at a = 1
  auto loop_of = [&](int k, int v) {
    for (const int l : {loop0(k), k})
      if (position[static_cast<std::size_t>(l)].count(v)) return l;
    return -1;
  };
  for (int k = 0; k < n; ++k)
    for (const int p : d.components[static_cast<std::size_t>(T.components[static_cast<std::size_t>(k)])].patches) {
      const split::Patch& P = L.patches.at(static_cast<std::size_t>(p));
      for (int j = 0; j < 4; ++j) {
        const int v = P.corners[static_cast<std::size_t>(j)], w = P.corners[static_cast<std::size_t>((j + 1) % 4)];
        const int lv = loop_of(k, v), lw = loop_of(k, w);
        if (lv < 0 || lw < 0) return fail("patch " + std::to_string(p) + " has a corner on neither cross section of its cube");
        corners[static_cast<std::size_t>(lv)].insert(v);
        if (lv == lw) continue;
        const int x = lv == loop0(k) ? v : w, y = lv == loop0(k) ? w : v;
        const auto [it, fresh] = across[static_cast<std::size_t>(k)].emplace(x, y);
        if (!fresh && it->second != y) return fail("the sharp curves along the ring branch at vertex " + std::to_string(x));
      }
    }
  const std::size_t m = corners[0].size();
  for (const auto& c : corners)
    if (c.size() != m) return fail("the cross sections have different numbers of corners");
  if (m < 6) return fail("the cross section has " + std::to_string(m) + " corners (a concave one needs at least six)");
  // Corner i of every loop: corner i of loop n - 1 in its loop order, carried around the ring.
  std::vector<std::map<int, int>> index(static_cast<std::size_t>(n));
  {
    std::vector<int> start(corners[static_cast<std::size_t>(n - 1)].begin(), corners[static_cast<std::size_t>(n - 1)].end());
    const auto& pos = position[static_cast<std::size_t>(n - 1)];
    std::sort(start.begin(), start.end(), [&](int x, int y) { return pos.at(x) < pos.at(y); });
    for (std::size_t i = 0; i < start.size(); ++i) index[static_cast<std::size_t>(n - 1)][start[i]] = static_cast<int>(i);
  }
  for (int k = 0; k < n; ++k) {
    auto& next = index[static_cast<std::size_t>(k)];
    std::map<int, int> carried;
    for (const auto& [v, i] : index[static_cast<std::size_t>(loop0(k))]) {
      const auto it = across[static_cast<std::size_t>(k)].find(v);
      if (it == across[static_cast<std::size_t>(k)].end()) return fail("no sharp curve runs along the ring from corner vertex " + std::to_string(v));
      carried[it->second] = i;
    }
    if (carried.size() != m) return fail("the sharp curves along the ring merge");
    if (k == n - 1 && carried != next) return fail("the sharp curves do not close up around the ring (a twisted ring)");
    next = carried;
  }
  // Per loop: the corners in index order must follow the loop (either way round).
  const auto M = static_cast<int>(m);
  std::vector<double> length(m, 0.0);
  std::vector<int> turn_sign;   // per corner: +1 convex, -1 concave
  for (int l = 0; l < n; ++l) {
    const auto& loop = L.internal_faces[static_cast<std::size_t>(T.cross_sections[static_cast<std::size_t>(l)])].loop;
    std::vector<int> at(m);  // corner index -> vertex
    for (const auto& [v, i] : index[static_cast<std::size_t>(l)]) at[static_cast<std::size_t>(i)] = v;
    const auto& pos = position[static_cast<std::size_t>(l)];
    const long size = static_cast<long>(loop.size());
    // Forward along the loop if the first corner met after corner 0 is corner 1 (a count of
    // vertices would be fooled by one finely meshed side).
    int dir = -1;
    for (long q = (static_cast<long>(pos.at(at[0])) + 1) % size;; q = (q + 1) % size) {
      const auto it = index[static_cast<std::size_t>(l)].find(loop[static_cast<std::size_t>(q)]);
      if (it == index[static_cast<std::size_t>(l)].end()) continue;
      dir = it->second == 1 ? 1 : -1;
      break;
    }
    std::vector<Vec3> P(m);
    for (std::size_t i = 0; i < m; ++i) {
      P[i] = L.points[static_cast<std::size_t>(at[i])];
      // Side i: along the loop from corner i to corner i + 1, with no other corner on the way.
      long q = static_cast<long>(pos.at(at[i]));
      const long end = static_cast<long>(pos.at(at[(i + 1) % m]));
      double s = 0;
      for (long guard = 0; q != end; ++guard) {
        const long r = (q + dir + size) % size;
        if (guard > size || (r != end && index[static_cast<std::size_t>(l)].count(loop[static_cast<std::size_t>(r)])))
          return fail("the corners of cross section " + std::to_string(l) + " are not in ring order");
        s += norm(minus(L.points[static_cast<std::size_t>(loop[static_cast<std::size_t>(r)])], L.points[static_cast<std::size_t>(loop[static_cast<std::size_t>(q)])]));
        q = r;
      }
      length[i] += s / n;
    }
    // Turns at the corners, about the polygon's (Newell) normal.
    Vec3 N{0, 0, 0};
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3 c = cross(P[i], P[(i + 1) % m]);
      for (int a = 0; a < 3; ++a) N[static_cast<std::size_t>(a)] += c[static_cast<std::size_t>(a)];
    }
    if (norm(N) == 0) return fail("cross section " + std::to_string(l) + " is degenerate");
    std::vector<double> turn(m);
    double total = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3 u = minus(P[i], P[(i + m - 1) % m]), w = minus(P[(i + 1) % m], P[i]);
      turn[i] = std::atan2(dot(cross(u, w), N) / norm(N), dot(u, w)) * 180 / kPi;
      total += turn[i];
    }
    if (std::abs(std::abs(total) - 360) > 30) return fail("cross section " + std::to_string(l) + " turns by " + std::to_string(total) + "° in all");
    std::vector<int> sign(m);
    for (std::size_t i = 0; i < m; ++i) {
      const double t = total > 0 ? turn[i] : -turn[i];
      if (std::abs(t - 90) < 35)
        sign[i] = 1;
      else if (std::abs(t + 90) < 35)
        sign[i] = -1;
      else
        return fail("corner " + std::to_string(i) + " of cross section " + std::to_string(l) + " turns by " + std::to_string(t) + "°, not ±90°");
    }
    if (l == 0) turn_sign = sign;
    if (sign != turn_sign) return fail("the cross sections turn differently");
  }
  const int concave = static_cast<int>(std::count(turn_sign.begin(), turn_sign.end(), -1));
  if (concave == 0) return fail("no concave corner");
  if (M - 2 * concave != 4) return fail("the corners' turns do not close a polygon");
  // The polygon: side i along direction dir[i], turning left at convex corners and right at
  // concave ones; lengths scaled per direction so that it closes.
  std::vector<std::array<int, 2>> dir(m);
  dir[0] = {1, 0};
  for (std::size_t i = 1; i < m; ++i) {
    const auto& p = dir[i - 1];
    dir[i] = turn_sign[i] > 0 ? std::array<int, 2>{-p[1], p[0]} : std::array<int, 2>{p[1], -p[0]};
  }
  std::array<std::array<double, 2>, 2> sum{};  // per axis: lengths going + and -
  for (std::size_t i = 0; i < m; ++i) {
    const int a = dir[i][0] != 0 ? 0 : 1, s = dir[i][static_cast<std::size_t>(a)] > 0 ? 0 : 1;
    sum[static_cast<std::size_t>(a)][static_cast<std::size_t>(s)] += length[i];
  }
  std::vector<double> xb(m), xc(m);
  for (std::size_t i = 0; i + 1 < m; ++i) {
    const int a = dir[i][0] != 0 ? 0 : 1, s = dir[i][static_cast<std::size_t>(a)] > 0 ? 0 : 1;
    const auto& S = sum[static_cast<std::size_t>(a)];
    const double scaled = length[i] * (S[0] + S[1]) / (2 * S[static_cast<std::size_t>(s)]);
    xb[i + 1] = xb[i] + scaled * dir[i][0], xc[i + 1] = xc[i] + scaled * dir[i][1];
  }
  const auto [ib, lines_b] = grid_lines(xb, 0.05);
  const auto [ic, lines_c] = grid_lines(xc, 0.05);
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t j = (i + 1) % m;
    if ((dir[i][0] != 0 && (ic[i] != ic[j] || ib[i] == ib[j])) || (dir[i][1] != 0 && (ib[i] != ib[j] || ic[i] == ic[j])))
      return fail("side " + std::to_string(i) + " of the cross section is shorter than 5 % of its extent");
  }
  // Cells inside (even-odd rule at their centres), and the polygon must be their boundary.
  Profile pr;
  pr.b = lines_b, pr.c = lines_c, pr.concave_corners = concave;
  const int nb = static_cast<int>(lines_b.size()) - 1, nc = static_cast<int>(lines_c.size()) - 1;
  std::vector<char> inside(static_cast<std::size_t>(nb * nc), 0);
  for (int j = 0; j < nc; ++j)
    for (int i = 0; i < nb; ++i) {
      bool in = false;
      for (std::size_t s = 0; s < m; ++s) {  // vertical sides left of the centre, crossing its row
        const std::size_t t = (s + 1) % m;
        if (ib[s] != ib[t] || ib[s] > i) continue;
        if (std::min(ic[s], ic[t]) <= j && j < std::max(ic[s], ic[t])) in = !in;
      }
      if (in) inside[static_cast<std::size_t>(i + nb * j)] = 1, pr.cells.push_back({i, j});
    }
  auto in = [&](int i, int j) { return i >= 0 && j >= 0 && i < nb && j < nc && inside[static_cast<std::size_t>(i + nb * j)]; };
  std::set<std::array<int, 3>> cell_edges, side_edges;  // unit edges (axis, i, j) from grid point (i, j)
  for (int j = 0; j <= nc; ++j)
    for (int i = 0; i <= nb; ++i) {
      if (i < nb && in(i, j) != in(i, j - 1)) cell_edges.insert({0, i, j});
      if (j < nc && in(i, j) != in(i - 1, j)) cell_edges.insert({1, i, j});
    }
  std::size_t unit_sides = 0;
  for (std::size_t s = 0; s < m; ++s) {
    const std::size_t t = (s + 1) % m;
    const int axis = ib[s] != ib[t] ? 0 : 1;
    const int lo = axis == 0 ? std::min(ib[s], ib[t]) : std::min(ic[s], ic[t]), hi = axis == 0 ? std::max(ib[s], ib[t]) : std::max(ic[s], ic[t]);
    for (int q = lo; q < hi; ++q, ++unit_sides) side_edges.insert(axis == 0 ? std::array<int, 3>{0, q, ic[s]} : std::array<int, 3>{1, ib[s], q});
  }
  if (cell_edges != side_edges || unit_sides != side_edges.size()) return fail("the cross section is not a simple rectilinear polygon");
  for (std::size_t i = 0; i < m; ++i) pr.polygon.push_back({lines_b[static_cast<std::size_t>(ib[i])], lines_c[static_cast<std::size_t>(ic[i])]});

  // The surface map: patch corners at their polygon corners, a = 0 or 1 by cross section.
  Embedding e;
  e.ring = n;
  e.profile = pr;
  e.cells.resize(static_cast<std::size_t>(n));
  e.corner_vertex.assign(static_cast<std::size_t>(n), std::array<int, 8>{-1, -1, -1, -1, -1, -1, -1, -1});
  std::vector<PlacedPatch> placed;
  for (int k = 0; k < n; ++k)
    for (const int p : d.components[static_cast<std::size_t>(T.components[static_cast<std::size_t>(k)])].patches) {
      const split::Patch& P = L.patches[static_cast<std::size_t>(p)];
      PlacedPatch pl{k, p, {}};
      std::array<int, 4> at{};
      for (int j = 0; j < 4; ++j) {
        const int v = P.corners[static_cast<std::size_t>(j)], l = loop_of(k, v);
        at[static_cast<std::size_t>(j)] = index[static_cast<std::size_t>(l)].at(v);
        const auto& q = pr.polygon[static_cast<std::size_t>(at[static_cast<std::size_t>(j)])];
        pl.corners[static_cast<std::size_t>(j)] = {l == k ? 1.0 : 0.0, q[0], q[1]};
      }
      for (int j = 0; j < 4; ++j) {
        const Vec3 &A = pl.corners[static_cast<std::size_t>(j)], &B = pl.corners[static_cast<std::size_t>((j + 1) % 4)];
        const int di = (at[static_cast<std::size_t>((j + 1) % 4)] - at[static_cast<std::size_t>(j)] + M) % M;
        if (A[0] == B[0] ? (di != 1 && di != M - 1) : di != 0)
          return fail("patch " + std::to_string(p) + " does not span one side of the cross section");
      }
      if (static_cast<std::size_t>(p) >= maps.size()) return fail("patch " + std::to_string(p) + " has no map");
      placed.push_back(pl);
    }
  place_patches(e, L, placed, maps);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 8; ++c)
      e.cells[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)] = cell_point(e, k, {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)});
  for (const auto& t : L.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &p = e.points[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])], &q = e.points[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)])];
      const double r = std::hypot((p[0] + q[0]) / 2, (p[1] + q[1]) / 2), z = (p[2] + q[2]) / 2;
      const std::array<double, 2> x{r - 1, e.mirrored ? 1 - z : z};
      double gap = HUGE_VAL;
      for (std::size_t s = 0; s < m; ++s) gap = std::min(gap, segment_distance(x, pr.polygon[s], pr.polygon[(s + 1) % m]));
      e.boundary_gap = std::max(e.boundary_gap, gap);
    }
  return e;
}

}  // namespace volts::polycube
