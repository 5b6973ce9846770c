// Torus components (Liu et al. 2013, §4.1, the five steps of Fig. 4).
//
// Steps 1–3 as in the paper: a harmonic field with its min and max at the extreme points along the
// principal axis; its level set between the two saddles contains a loop around the tube that does
// not separate the surface (a meridian). Steps 4–5 are done with circle-valued harmonic fields
// instead of a second Dirichlet field and traced gradient lines: u (period 1 across that meridian)
// has meridians as level sets, v (period 1 across a loop around the ring) longitudes. Their level
// sets are inserted exactly (edge crossings) and never cross each other more than once, and the
// longitudes close up on themselves, which gradient lines of a ring field do not do on a twisted
// torus (holonomy). Equally spaced levels give equally spaced cross sections in the harmonic sense.
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <sstream>

#include "core/errors.h"
#include "split/harmonic.h"
#include "split/isoline.h"
#include "split/split_internal.h"

namespace volts::split::detail {

using surface::Mesh;
using VI = Mesh::Vertex_index;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kLongitudeLabel = 1000;  // cut labels: cross section k -> k, longitude j -> 1000 + j

Eigen::Vector3d pt(const Mesh& m, int v) {
  const auto& p = m.point(VI(v));
  return {p.x(), p.y(), p.z()};
}

Eigen::Vector3d principal_axis(const Mesh& m) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto v : m.vertices()) mean += pt(m, static_cast<int>(v));
  mean /= static_cast<double>(m.number_of_vertices());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (auto v : m.vertices()) {
    const Eigen::Vector3d d = pt(m, static_cast<int>(v)) - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  return es.eigenvectors().col(2);
}

bool separates(const Mesh& m, const std::vector<int>& loop) {
  const auto label = regions_cut_by(m, {loop});
  return *std::max_element(label.begin(), label.end()) > 0;
}

// Whether the level set {f = c} has a loop that does not separate the surface (tried on a copy).
bool has_ring_section(const Mesh& m, const std::vector<double>& f, double c) {
  Mesh copy = m;
  std::vector<double> g = f;
  try {
    for (const auto& loop : insert_isoline(copy, g, c))
      if (!separates(copy, loop)) return true;
  } catch (const core::TopologyError&) {
  }
  return false;
}

// Shortest edge loop that leaves meridian A on one side of A[i] and comes back from the other side
// without touching A elsewhere: it runs once around the ring. Returns its length (inf if none).
// Vertices in `blocked` are avoided.
double ring_loop_through(const Mesh& m, const std::vector<int>& A, int i, const std::vector<int>& blocked, std::vector<int>* out) {
  const int a = A[i], n = static_cast<int>(A.size());
  std::vector<char> on_a(m.number_of_vertices(), 0);
  for (int v : A) on_a[v] = 1;
  for (int v : blocked) on_a[v] = 1;
  const auto hn = m.halfedge(VI(a), VI(A[(i + 1) % n])), hp = m.halfedge(VI(a), VI(A[(i + n - 1) % n]));
  std::vector<char> right(m.number_of_vertices(), 0);
  for (auto h = m.opposite(m.prev(hn)); h != hp; h = m.opposite(m.prev(h))) right[m.target(h)] = 1;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(m.number_of_vertices(), inf);
  std::vector<int> from(m.number_of_vertices(), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (auto h : CGAL::halfedges_around_source(VI(a), m)) {
    const int x = static_cast<int>(m.target(h));
    if (on_a[x] || !right[x]) continue;
    dist[x] = (pt(m, x) - pt(m, a)).norm();
    from[x] = a;
    queue.push({dist[x], x});
  }
  while (!queue.empty()) {
    const auto [d, x] = queue.top();
    queue.pop();
    if (d > dist[x]) continue;
    for (auto h : CGAL::halfedges_around_source(VI(x), m)) {
      const int y = static_cast<int>(m.target(h));
      if (on_a[y]) continue;
      const double dy = d + (pt(m, x) - pt(m, y)).norm();
      if (dy < dist[y]) dist[y] = dy, from[y] = x, queue.push({dy, y});
    }
  }
  int best = -1;
  double best_d = inf;
  for (auto h : CGAL::halfedges_around_source(VI(a), m)) {
    const int y = static_cast<int>(m.target(h));
    if (on_a[y] || right[y] || dist[y] == inf) continue;
    const double dy = dist[y] + (pt(m, y) - pt(m, a)).norm();
    if (dy < best_d) best_d = dy, best = y;
  }
  if (best < 0) return inf;
  out->clear();
  for (int x = best; x != a; x = from[x]) out->push_back(x);
  out->push_back(a);
  std::reverse(out->begin(), out->end());
  return best_d;
}

// The shortest loop once around the ring through any vertex of A (at most 64 tried, evenly spaced).
// The shortest through a given vertex may wind around the tube as well (a helix through the outer
// equator is shorter than the outer equator); the shortest of all does not.
std::vector<int> shortest_ring_loop(const Mesh& m, const std::vector<int>& A, const std::vector<int>& blocked = {}) {
  const std::size_t n = A.size(), step = std::max<std::size_t>(1, n / 64);
  std::vector<int> best, loop;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; i += step) {
    const double d = ring_loop_through(m, A, static_cast<int>(i), blocked, &loop);
    if (d < best_d) best_d = d, best = loop;
  }
  if (best.empty()) throw core::TopologyError("split: no loop runs around the ring from the first cross section; is the surface a torus?");
  return best;
}

// Circular mean of a periodic field (period 1) over some vertices, in [0, 1).
double circular_mean(const std::vector<int>& vs, const std::vector<double>& f) {
  double s = 0, c = 0;
  for (int v : vs) s += std::sin(2 * kPi * f[v]), c += std::cos(2 * kPi * f[v]);
  double m = std::atan2(s, c) / (2 * kPi);
  return m - std::floor(m);
}

// Mean dihedral angle along a closed curve: how sharp it is.
double sharpness(const Mesh& m, const std::vector<int>& loop) {
  double sum = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const auto h = m.halfedge(VI(loop[i]), VI(loop[(i + 1) % loop.size()]));
    const auto n1 = CGAL::Polygon_mesh_processing::compute_face_normal(m.face(h), m);
    const auto n2 = CGAL::Polygon_mesh_processing::compute_face_normal(m.face(m.opposite(h)), m);
    sum += std::acos(std::clamp(n1 * n2, -1.0, 1.0));
  }
  return sum / static_cast<double>(loop.size());
}

struct Line {
  bool sharp = false;
  int vertex = -1;       // sharp: an input vertex on it (ids of existing vertices never change)
  double v = 0;          // level of v (not sharp) or circular mean of v (sharp)
  double v_lo = 0, v_hi = 0;  // sharp: range of v around the mean
  double sharpness = 0;
  bool corner = false;   // one of the four lines at cube edges
  int disk_level = -1;   // closed by the disk's rim arc DiskCuts::v_arc[disk_level] (its level runs through two corners)
};

double circ_dist(double a, double b) { return std::abs(circle_difference(a, b, 1.0)); }

// Level k of n equally spaced levels of a periodic field (period 1), starting at `first`; with
// protected vertices, the levels are spread over the rest of the circle so that none crosses the
// arc their values cover (plus a margin), which then lies between level n-1 and level 0.
double level_avoiding(const std::vector<int>& protect, const std::vector<double>& f, int k, int n, double first) {
  if (protect.empty()) return first + static_cast<double>(k) / n;
  std::vector<int> vs = protect;
  const double m = circular_mean(vs, f);
  double lo = 0, hi = 0;
  for (int v : vs) {
    const double d = circle_difference(m, f[v], 1.0);
    lo = std::min(lo, d), hi = std::max(hi, d);
  }
  const double free_arc = 1.0 - (hi - lo);
  if (free_arc < 0.1 * n / 4.0)
    throw core::TopologyError("split: the disk where the two tori meet spans " + std::to_string(static_cast<int>(100 * (1 - free_arc))) +
                              "% of a torus's turn; it must fit between two cuts — set split.extreme_points");
  const double margin = 0.1 * free_arc / n;
  double level = m + hi + margin + k * (free_arc - 2 * margin) / (n - 1);
  return level - std::floor(level);
}

// The level nearest to c halfway between two consecutive vertex values, so that no vertex lies on
// the level set (a level through vertices makes slivers, or whole triangles on the level, on
// symmetric meshes).
double between_vertices(double c, const std::vector<double>& f, double period) {
  double below = -std::numeric_limits<double>::infinity(), above = std::numeric_limits<double>::infinity();
  for (double x : f) {
    const double d = circle_difference(c, x, period);
    if (d <= 0) below = std::max(below, d);
    if (d >= 0) above = std::min(above, d);
  }
  if (below == 0 && above == 0) {  // c is a vertex value: take the wider gap beside it
    double b2 = -std::numeric_limits<double>::infinity(), a2 = std::numeric_limits<double>::infinity();
    for (double x : f) {
      const double d = circle_difference(c, x, period);
      if (d < 0) b2 = std::max(b2, d);
      if (d > 0) a2 = std::min(a2, d);
    }
    if (-b2 > a2) above = 0, below = b2;
    else below = 0, above = a2;
  }
  if (!std::isfinite(below) || !std::isfinite(above)) return c;
  double level = c + 0.5 * (below + above);
  if (period > 0) level -= period * std::floor(level / period);
  return level;
}

// Sum of the field's steps along a chain of vertices (period 1): its change, not taken modulo 1.
double change_along(const std::vector<int>& chain, const std::vector<double>& f) {
  double s = 0;
  for (std::size_t i = 0; i + 1 < chain.size(); ++i) s += circle_difference(f[chain[i]], f[chain[i + 1]], 1.0);
  return s;
}

// The disk made one patch: its rim is cut at four corner vertices into two arcs that close
// cross sections and two that close longitudinal lines. The cross sections through the disk are
// the level sets of u through its corners outside the disk, closed by the rim arcs; u (and v) are
// the periodic fields with values on the whole rim (disk_cuts: the natural ones, corrected so the
// two ends of each closing arc agree). Constant values on whole arcs were tried: the kink in the
// boundary data makes the level sets leave the corners tangentially (docs/status.md, session 13).
struct DiskCuts {
  std::vector<Constraint> u, v;
  std::array<double, 2> u_level{}, v_level{};  // per field: the two levels (as stored), lower first going up over the disk
  std::array<std::array<int, 2>, 2> u_ends{}, v_ends{};  // the corners each level set joins (same order as the levels)
  std::array<std::vector<int>, 2> u_arc, v_arc;  // the rim arc closing each level set (from its first end to its second)
};

// The disk's range of a periodic field (rim and inside vertices), lifted around ref.
std::pair<double, double> disk_range(const DiskPatch& disk, const std::vector<double>& f, double ref) {
  double lo = 0, hi = 0;
  for (const auto* vs : {&disk.rim, &disk.inside})
    for (int x : *vs) lo = std::min(lo, circle_difference(ref, f[x], 1.0)), hi = std::max(hi, circle_difference(ref, f[x], 1.0));
  return {ref + lo, ref + hi};
}

DiskCuts disk_cuts(const Mesh& m, DiskPatch& disk, const std::vector<double>& u0, const std::vector<double>& v0, const std::array<double, 2>& min_span) {
  const auto& R = disk.rim;
  const int nr = static_cast<int>(R.size());
  if (nr < 8) throw core::TopologyError("split: the disk between the two tori has only " + std::to_string(nr) + " rim vertices; refine the mesh");
  const double mu = circular_mean(R, u0), mv = circular_mean(R, v0);
  std::vector<double> du(nr), dv(nr);  // rim values relative to the means
  double su = 0, sv = 0;
  for (int i = 0; i < nr; ++i) {
    du[i] = circle_difference(mu, u0[R[i]], 1.0), dv[i] = circle_difference(mv, v0[R[i]], 1.0);
    su = std::max(su, std::abs(du[i])), sv = std::max(sv, std::abs(dv[i]));
  }
  if (!(su > 0) || !(sv > 0)) throw core::TopologyError("split: the disk between the two tori has no extent around the ring or the tube");
  std::array<int, 4> at{};  // rim positions of the corners
  if (disk.corners[0] < 0) {
    // First guess: the rim's own corners, the rim points furthest along the four diagonals of its
    // principal axes, each scaled to the rim's extent along it (on a rounded rectangle, on the
    // roundings). The diagonals of the ring and tube fields instead put the eight's neck corners on
    // its flat faces, 0.2 in from the waist's outline: the disk's sides then wrapped around the
    // outline, its cube's cross sections met it at nearly 180° and the pillow folded there (105
    // elements of the eight not certified valid, 30 with these; docs/status.md, session 15).
    // (Corners where the rim's normal is diagonal, further out on the roundings, gave 396.)
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const int v : R) centre += pt(m, v);
    centre /= nr;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const int v : R) cov += (pt(m, v) - centre) * (pt(m, v) - centre).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Eigen::Vector3d e1 = eig.eigenvectors().col(2), e2 = eig.eigenvectors().col(1);
    std::vector<double> x1(nr), x2(nr);
    double s1 = 0, s2 = 0;
    for (int i = 0; i < nr; ++i) {
      x1[i] = (pt(m, R[i]) - centre).dot(e1), x2[i] = (pt(m, R[i]) - centre).dot(e2);
      s1 = std::max(s1, std::abs(x1[i])), s2 = std::max(s2, std::abs(x2[i]));
    }
    if (!(s1 > 0) || !(s2 > 0)) throw core::TopologyError("split: the rim of the disk between the two tori lies on a line");
    const std::array<std::array<double, 2>, 4> dirs{{{1, 1}, {1, -1}, {-1, -1}, {-1, 1}}};
    for (int k = 0; k < 4; ++k) {
      double best = -std::numeric_limits<double>::infinity();
      for (int i = 0; i < nr; ++i)
        if (const double x = dirs[k][0] * x1[i] / s1 + dirs[k][1] * x2[i] / s2; x > best) best = x, at[k] = i;
    }
    std::sort(at.begin(), at.end());
    for (int k = 0; k < 4; ++k)
      if (at[k] == at[(k + 1) % 4]) throw core::TopologyError("split: the disk between the two tori has fewer than four distinct corners; refine the mesh");
    // Then moved (one rim vertex at a time) while that makes the arcs' ends agree better on the
    // field they keep.
    // Consecutive diagonal corners share a sign of u or of v: arcs 0, 2 keep u if corners 0, 1 do.
    const bool u02 = std::abs(du[at[0]] - du[at[1]]) / su < std::abs(dv[at[0]] - dv[at[1]]) / sv;
    auto mismatch = [&](const std::array<int, 4>& c) {
      double e = 0;
      for (int k = 0; k < 4; ++k) {
        const bool keeps_u = (k % 2 == 0) == u02;
        e += keeps_u ? std::pow((du[c[k]] - du[c[(k + 1) % 4]]) / su, 2) : std::pow((dv[c[k]] - dv[c[(k + 1) % 4]]) / sv, 2);
      }
      return e;
    };
    for (bool moved = true; moved;) {
      moved = false;
      for (int k = 0; k < 4; ++k)
        for (int step : {-1, 1}) {
          std::array<int, 4> c = at;
          c[k] = (c[k] + step + nr) % nr;
          if (c[k] == at[(k + 1) % 4] || c[k] == at[(k + 3) % 4] || mismatch(c) >= mismatch(at) - 1e-15) continue;
          at = c, moved = true;
        }
    }
    for (int k = 0; k < 4; ++k) disk.corners[k] = R[at[k]];
  } else {
    for (int k = 0; k < 4; ++k) {
      const auto it = std::find(R.begin(), R.end(), disk.corners[k]);
      if (it == R.end()) throw std::logic_error("split: a disk corner is not on its rim");
      at[k] = static_cast<int>(it - R.begin());
    }
  }
  // Rotate so that the corners run forward along the rim from at[0].
  for (int r = 0; r < 4 && !(((at[1] - at[0] + nr) % nr) < ((at[2] - at[0] + nr) % nr) && ((at[2] - at[0] + nr) % nr) < ((at[3] - at[0] + nr) % nr)); ++r)
    std::rotate(at.begin(), at.begin() + 1, at.end());
  std::array<std::vector<int>, 4> arc;
  for (int k = 0; k < 4; ++k)
    for (int i = at[k];; i = (i + 1) % nr) {
      arc[k].push_back(R[i]);
      if (i == at[(k + 1) % 4]) break;
    }
  // Arcs p and p + 2 close cross sections (u changes less along them), p + 1 and p + 3 longitudes.
  auto rel = [&](int k, const std::vector<double>& f, double scale) { return std::abs(change_along(arc[k], f)) / scale; };
  const int p = rel(0, u0, su) + rel(2, u0, su) - rel(0, v0, sv) - rel(2, v0, sv) <= rel(1, u0, su) + rel(3, u0, su) - rel(1, v0, sv) - rel(3, v0, sv) ? 0 : 1;
  DiskCuts out;
  // Field f closes its level sets by arcs c and c + 2. Its values on the whole rim are the natural
  // field's, lifted along the rim, made equal at the two ends of each of those arcs (a correction
  // linear in arc length along every arc), then stretched about the first level so that the disk
  // spans at least `min_span` of a turn: the disk's cube then gets its share of the ring (the
  // natural span is the angle the disk subtends from the hole, a tenth of a turn on an eight),
  // and the level sets leave the corners across the rim, as the natural ones do.
  auto fill = [&](int c, const std::vector<double>& f0, double min_span, std::vector<Constraint>& cons, std::array<double, 2>& level,
                  std::array<std::array<int, 2>, 2>& ends, std::array<std::vector<int>, 2>& arcs) {
    std::vector<double> F(nr);  // lifted along the rim from at[0]
    F[at[0]] = f0[R[at[0]]];
    for (int s = 1; s < nr; ++s) {
      const int i = (at[0] + s) % nr, j = (i + nr - 1) % nr;
      F[i] = F[j] + circle_difference(f0[R[j]], f0[R[i]], 1.0);
    }
    const auto& A = arc[c];
    const auto& B = arc[(c + 2) % 4];
    const double a = 0.5 * (F[at[c]] + F[at[(c + 1) % 4]]), b = 0.5 * (F[at[(c + 2) % 4]] + F[at[(c + 3) % 4]]);
    std::array<double, 4> target{};  // per corner
    target[static_cast<std::size_t>(c)] = target[static_cast<std::size_t>((c + 1) % 4)] = a;
    target[static_cast<std::size_t>((c + 2) % 4)] = target[static_cast<std::size_t>((c + 3) % 4)] = b;
    const double stretch = std::abs(b - a) < min_span ? min_span / std::abs(b - a) : 1.0;
    for (int k = 0; k < 4; ++k) {
      const auto& X = arc[k];
      std::vector<double> len(X.size(), 0.0);
      for (std::size_t i = 1; i < X.size(); ++i) len[i] = len[i - 1] + (pt(m, X[i]) - pt(m, X[i - 1])).norm();
      const int i0 = at[k], i1 = at[(k + 1) % 4];
      const double d0 = target[static_cast<std::size_t>(k)] - F[i0], d1 = target[static_cast<std::size_t>((k + 1) % 4)] - F[i1];
      for (std::size_t i = 0; i + 1 < X.size(); ++i) {  // each arc's last vertex is the next arc's first
        const double t = len[i] / len.back();
        const double x = i == 0 ? target[static_cast<std::size_t>(k)] : F[(i0 + static_cast<int>(i)) % nr] + (1 - t) * d0 + t * d1;  // corners exactly
        cons.push_back({X[i], a + stretch * (x - a)});
      }
    }
    const double b_lifted = a + stretch * (b - a);
    const double sa = a - std::floor(a), sb = b_lifted - std::floor(b_lifted);  // as stored by periodic_harmonic_field
    // The level set closed by arc A runs from A.back() around to A.front(); the rim arc A closes it.
    if (b_lifted > a) level = {sa, sb}, ends = {{{A.front(), A.back()}, {B.front(), B.back()}}}, arcs = {A, B};
    else level = {sb, sa}, ends = {{{B.front(), B.back()}, {A.front(), A.back()}}}, arcs = {B, A};
  };
  fill(p, u0, min_span[0], out.u, out.u_level, out.u_ends, out.u_arc);
  fill(p + 1, v0, min_span[1], out.v, out.v_level, out.v_ends, out.v_arc);
  return out;
}

}  // namespace

std::vector<double> height_field(const Mesh& mesh, const Params& prm, CriticalPoints* cp) {
  int lo = -1, hi = -1;
  if (!prm.extreme_points.empty()) {
    if (prm.extreme_points.size() != 2) throw core::ConfigError("split.extreme_points must be two points [[x,y,z], [x,y,z]]");
    lo = nearest_vertex(mesh, prm.extreme_points[0]);
    hi = nearest_vertex(mesh, prm.extreme_points[1]);
  } else {
    const Eigen::Vector3d axis = principal_axis(mesh);
    double flo = std::numeric_limits<double>::infinity(), fhi = -flo;
    for (auto v : mesh.vertices()) {
      const double h = pt(mesh, static_cast<int>(v)).dot(axis);
      if (h < flo) flo = h, lo = static_cast<int>(v);
      if (h > fhi) fhi = h, hi = static_cast<int>(v);
    }
  }
  if (lo == hi)
    throw core::TopologyError("split: the min and max of the harmonic field fall on the same vertex " + std::to_string(lo) +
                              "; set split.extreme_points to two distinct points");
  std::vector<double> f = harmonic_field(mesh, {{lo, 0.0}, {hi, 1.0}});
  *cp = critical_points(mesh, f);
  return f;
}

std::vector<std::pair<double, double>> saddle_gaps(const std::vector<double>& f, const CriticalPoints& cp) {
  std::vector<double> sv;
  for (const auto& s : cp.saddles) sv.push_back(f[s.first]);
  std::sort(sv.begin(), sv.end());
  std::vector<std::pair<double, double>> gaps;
  for (std::size_t i = 0; i + 1 < sv.size(); ++i)
    if (sv[i + 1] - sv[i] > 1e-9) gaps.push_back({sv[i + 1] - sv[i], 0.5 * (sv[i] + sv[i + 1])});
  std::sort(gaps.rbegin(), gaps.rend());
  return gaps;
}

// With a disk: sharp loops that can be the torus's corner lines, or none (then the tube field's
// levels are). The two disk lines: each rim arc on a longitudinal line closed by the shortest
// path of sharp edges between its ends around the ring, off the disk (a box-like eye: its outer
// edges); if either has none, both are the tube field's levels through the arcs. The other two:
// the only two other closed sharp loops around the ring (the hole's rims), kept off those levels.
// A sharp edge anywhere else (an edge across the tube, a junction) is left out, as it is without
// a disk.
struct DiskCornerLoops {
  std::set<Edge> edges;     // of the loops
  bool disk_lines = false;  // the rim arcs' lines are among them (four loops), else two loops
};
DiskCornerLoops disk_corner_loops(const Mesh& mesh, const std::set<Edge>& sharp, const DiskPatch& disk, const DiskCuts& dc,
                                  const std::vector<double>& u, const std::vector<double>& v) {
  if (sharp.empty()) return {};
  std::vector<char> in_disk(mesh.number_of_vertices(), 0);
  for (const auto* vs : {&disk.rim, &disk.inside})
    for (int x : *vs) in_disk[static_cast<std::size_t>(x)] = 1;
  std::map<int, std::vector<int>> adj;
  for (const auto& e : sharp) adj[e.first].push_back(e.second), adj[e.second].push_back(e.first);
  auto around_ring = [&](const std::vector<int>& loop) { return std::abs(loop_period(loop, u)) == 1 && loop_period(loop, v) == 0; };
  std::vector<std::vector<int>> loops;
  std::set<int> used;
  for (int i = 0; i < 2; ++i) {
    const auto& arc = dc.v_arc[static_cast<std::size_t>(i)];
    const int from = arc.back(), to = arc.front();
    // Dijkstra over sharp edges, inner vertices off the disk.
    std::map<int, double> dist{{from, 0.0}};
    std::map<int, int> prev;
    std::priority_queue<std::pair<double, int>, std::vector<std::pair<double, int>>, std::greater<>> q;
    q.push({0.0, from});
    while (!q.empty()) {
      const auto [dd, x] = q.top();
      q.pop();
      if (dd > dist[x] || x == to) continue;
      for (int y : adj[x]) {
        if (y != to && (in_disk[static_cast<std::size_t>(y)] || used.count(y))) continue;
        const double nd = dd + (pt(mesh, x) - pt(mesh, y)).norm();
        const auto it = dist.find(y);
        if (it != dist.end() && it->second <= nd) continue;
        dist[y] = nd, prev[y] = x;
        q.push({nd, y});
      }
    }
    if (!prev.count(to)) {
      loops.clear(), used.clear();
      break;
    }
    std::vector<int> loop = arc;  // from `to` to `from`, then back along the path
    for (int x = prev.at(to); x != from; x = prev.at(x)) loop.push_back(x);
    std::reverse(loop.begin() + static_cast<std::ptrdiff_t>(arc.size()), loop.end());
    if (loop.size() < arc.size() + 2 || !around_ring(loop)) {
      loops.clear(), used.clear();
      break;
    }
    used.insert(loop.begin(), loop.end());
    loops.push_back(std::move(loop));
  }
  // The other closed sharp loops: components of the remaining sharp edges that are simple cycles.
  std::set<Edge> rest;
  for (const auto& e : sharp)
    if (!used.count(e.first) && !used.count(e.second) && !in_disk[static_cast<std::size_t>(e.first)] && !in_disk[static_cast<std::size_t>(e.second)])
      rest.insert(e);
  std::map<int, int> degree;
  for (const auto& e : rest) ++degree[e.first], ++degree[e.second];
  std::set<int> seen;
  std::vector<std::vector<int>> others;
  for (const auto& [x0, deg0] : degree) {
    if (seen.count(x0)) continue;
    std::vector<int> comp{x0};
    seen.insert(x0);
    bool simple = true;
    for (std::size_t h = 0; h < comp.size(); ++h) {
      simple = simple && degree[comp[h]] == 2;
      for (int y : adj[comp[h]])
        if (rest.count(edge(comp[h], y)) && seen.insert(y).second) comp.push_back(y);
    }
    if (!simple) continue;
    std::set<Edge> ce;
    for (int x : comp)
      for (int y : adj[x])
        if (rest.count(edge(x, y))) ce.insert(edge(x, y));
    for (auto& l : chain_loops(ce))
      if (around_ring(l)) others.push_back(std::move(l));
  }
  if (others.size() != 2) return {};
  DiskCornerLoops out;
  out.disk_lines = !loops.empty();
  if (!out.disk_lines)  // the levels through the arcs must not cross them
    for (const auto& l : others)
      for (int x : l)
        for (const double level : dc.v_level)
          if (std::abs(circle_difference(level, v[static_cast<std::size_t>(x)], 1.0)) < 0.05) return {};
  loops.insert(loops.end(), others.begin(), others.end());
  for (const auto& l : loops)
    for (std::size_t k = 0; k < l.size(); ++k) out.edges.insert(edge(l[k], l[(k + 1) % l.size()]));
  return out;
}

bool loop_separates(const Mesh& m, const std::vector<int>& loop) { return separates(m, loop); }

double level_between_vertices(double c, const std::vector<double>& f) { return between_vertices(c, f, 0.0); }

Decomposition split_torus(const Mesh& input, const std::set<Edge>& sharp_in, const Params& prm, const std::vector<int>& protect_in,
                          const std::vector<int>& first_cross_section, DiskPatch* disk) {
  if (prm.torus_cubes < 4 || prm.torus_cubes > 16) throw core::ConfigError("split.torus_cubes must be in [4, 16]");
  Mesh mesh = input;
  std::set<Edge> sharp = disk ? std::set<Edge>{} : sharp_in;  // with a disk: only its corner loops, below
  Decomposition d;
  d.genus = 1;
  const std::vector<int> protect = disk ? std::vector<int>{} : protect_in;

  // Steps 1–3: the first cross section A.
  std::vector<double> f;
  std::vector<int> A;
  std::vector<std::array<int, 3>> splits;
  IsolineOptions opt;
  opt.splits = &splits;
  if (!first_cross_section.empty()) {
    A = first_cross_section;
    f.assign(mesh.number_of_vertices(), 0.0);
  } else if (!prm.cross_section_plane.empty()) {
    const auto& q = prm.cross_section_plane;
    if (q.size() != 6) throw core::ConfigError("split.cross_section_plane must be [px, py, pz, nx, ny, nz]");
    const Eigen::Vector3d p0(q[0], q[1], q[2]), n = Eigen::Vector3d(q[3], q[4], q[5]).normalized();
    if (!n.allFinite()) throw core::ConfigError("split.cross_section_plane has a zero normal");
    for (auto v : mesh.vertices()) f.push_back((pt(mesh, static_cast<int>(v)) - p0).dot(n));
    const auto loops = insert_isoline(mesh, f, between_vertices(0.0, f, 0.0), opt);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& l : loops) {
      if (separates(mesh, l)) continue;
      double dmin = std::numeric_limits<double>::infinity();
      for (int v : l) dmin = std::min(dmin, (pt(mesh, v) - p0).norm());
      if (dmin < best) best = dmin, A = l;
    }
    if (A.empty())
      throw core::TopologyError("split: the plane split.cross_section_plane cuts no loop around the tube of the torus; move it so it crosses the ring");
  } else {
    CriticalPoints cp;
    f = height_field(mesh, prm, &cp);
    d.critical_min = static_cast<int>(cp.minima.size());
    d.critical_max = static_cast<int>(cp.maxima.size());
    d.critical_saddle = cp.saddle_count();
    const std::vector<std::pair<double, double>> gaps = saddle_gaps(f, cp);
    double level = std::numeric_limits<double>::quiet_NaN();
    for (const auto& [w, c] : gaps)
      if (has_ring_section(mesh, f, c)) {
        level = c;
        break;
      }
    if (std::isnan(level)) {
      std::ostringstream s;
      s << "split: no level set of the harmonic field between its saddles (" << cp.minima.size() << " min, "
        << cp.maxima.size() << " max, " << cp.saddle_count()
        << " saddles) is a cross section around the tube; set split.extreme_points (two points at opposite ends of the "
           "ring) or split.cross_section_plane";
      throw core::TopologyError(s.str());
    }
    for (const auto& l : insert_isoline(mesh, f, between_vertices(level, f, 0.0), opt))
      if (A.empty() && !separates(mesh, l)) A = l;
  }
  apply_splits(sharp, splits);

  // Step 4–5: circle-valued fields around the ring (u) and around the tube (v).
  std::vector<double> u = periodic_harmonic_field(mesh, A);
  // The loop around the ring that v is cut along: a closed sharp curve around the ring if there is
  // one (it is a longitude by design), else the shortest loop once around the ring.
  std::vector<int> Lr;
  if (!sharp.empty())
    for (const auto& loop : chain_loops(sharp))
      if (Lr.empty() && std::abs(loop_period(loop, u)) == 1) Lr = loop;
  std::vector<int> disk_vertices;
  if (disk) {
    disk_vertices = disk->rim;
    disk_vertices.insert(disk_vertices.end(), disk->inside.begin(), disk->inside.end());
  }
  if (Lr.empty()) Lr = shortest_ring_loop(mesh, A, disk_vertices);
  std::vector<double> v = periodic_harmonic_field(mesh, Lr);
  // A disk made one patch: u and v again, with its rim's arcs as level sets.
  std::optional<DiskCuts> dc;
  bool disk_sharp_lines = false;  // with a disk: its rim arcs' lines are sharp loops
  std::vector<char> off_disk;  // face mask: the faces not in the disk (the disk's level sets are inserted outside it)
  if (disk) {
    for (int x : A)
      if (std::find(disk_vertices.begin(), disk_vertices.end(), x) != disk_vertices.end())
        throw core::TopologyError("split: the first cross section of a torus runs through the disk where it meets the other torus");
    // The disk's sector spans at least one cube of the ring (narrower, its T-mesh folded: session
    // 13), its tube span at least a quarter turn.
    dc = disk_cuts(mesh, *disk, u, v, {1.0 / prm.torus_cubes, 0.25});
    u = periodic_harmonic_field(mesh, A, dc->u);
    v = periodic_harmonic_field(mesh, Lr, dc->v);
    std::vector<char> in_disk(mesh.number_of_vertices(), 0);
    for (int x : disk_vertices) in_disk[x] = 1;
    off_disk.assign(mesh.number_of_faces(), 0);
    for (auto fc : mesh.faces())
      for (auto x : CGAL::vertices_around_face(mesh.halfedge(fc), mesh))
        if (!in_disk[x]) off_disk[fc] = 1;
    const DiskCornerLoops dl = disk_corner_loops(mesh, sharp_in, *disk, *dc, u, v);
    sharp = dl.edges;
    disk_sharp_lines = dl.disk_lines;
  }
  // Level k of count - 1 more levels after a disk's two (level[0], level[1], lifted: level[0] +
  // span), spread evenly over the rest of the turn but kept off the disk (whose range of the field
  // is wider than [level 0, level 1] where its rim bulges between corners).
  auto spread_level = [&](const std::vector<double>& f, const std::array<double, 2>& level, int k, int count) {
    const double span = level[1] - level[0] + (level[1] < level[0] ? 1.0 : 0.0);
    const auto [lo, hi] = disk_range(*disk, f, level[0]);
    const double margin = 0.02;
    if (1.0 - (hi - lo) < 2 * margin * count)
      throw core::TopologyError("split: the disk where the two tori meet covers " + std::to_string(static_cast<int>(100 * (hi - lo))) +
                                "% of a torus's turn; set split.extreme_points");
    double at = level[0] + span + k * (1.0 - span) / count;
    at = std::clamp(at, hi + margin * k, lo + 1.0 - margin * (count - k));
    return between_vertices(at - std::floor(at), f, 1.0);
  };

  // Closed sharp curves must run around the ring: they become longitudinal lines.
  std::vector<Line> lines;
  for (const auto& loop : sharp.empty() ? std::vector<std::vector<int>>{} : chain_loops(sharp)) {
    const int pu = loop_period(loop, u), pv = loop_period(loop, v);
    if (std::abs(pu) != 1 || pv != 0)
      throw core::TopologyError("split: the closed sharp curve through vertex " + std::to_string(loop[0]) +
                                " does not run once around the ring of the torus (it winds " + std::to_string(pu) + " time(s) around the ring and " +
                                std::to_string(pv) + " around the tube); sharp curves across the tube are not supported yet — "
                                "raise classify.sharp_angle_deg to ignore it, or use route: tet");
    Line l;
    l.sharp = true;
    l.vertex = *std::min_element(loop.begin(), loop.end());
    l.v = circular_mean(loop, v);
    l.v_lo = l.v_hi = 0;
    for (int x : loop) {
      const double dv = circle_difference(l.v, v[x], 1.0);
      l.v_lo = std::min(l.v_lo, dv), l.v_hi = std::max(l.v_hi, dv);
    }
    l.sharpness = sharpness(mesh, loop);
    lines.push_back(l);
  }
  // Four corner lines: the sharpest sharp curves at least 1/8 turn apart, then new levels of v in
  // the widest gaps.
  std::vector<int> order(lines.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return lines[a].sharpness > lines[b].sharpness; });
  int corners = 0;
  for (int i : order) {
    if (corners == 4) break;
    bool far = true;
    for (const auto& l : lines) far &= !(l.corner && circ_dist(l.v, lines[i].v) < 0.125);
    if (far) lines[i].corner = true, ++corners;
  }
  if (dc && disk_sharp_lines) {  // the disk's sharp corner loops: all four are cube edges
    for (auto& l : lines) l.corner = true;
    corners = 4;
  } else if (dc && !sharp.empty()) {  // two lines closed by the disk's rim, two sharp loops
    for (auto& l : lines) l.corner = true;
    for (int i = 0; i < 2; ++i) lines.push_back({false, -1, dc->v_level[i], 0, 0, 0, true, i});
    corners = 4;
  } else if (dc) {  // two lines closed by the disk's rim, two spread over the rest of the tube
    for (int i = 0; i < 2; ++i) lines.push_back({false, -1, dc->v_level[i], 0, 0, 0, true, i});
    for (int k = 1; k <= 2; ++k) lines.push_back({false, -1, spread_level(v, dc->v_level, k, 3), 0, 0, 0, true});
    corners = 4;
  }
  while (corners < 4) {
    if (lines.empty()) {
      for (int k = 0; k < 4; ++k) lines.push_back({false, -1, level_avoiding(protect, v, k, 4, 0.125), 0, 0, 0, true});
      break;
    }
    // Widest gap between consecutive lines (by their v extent), a new line at its middle.
    std::sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) { return a.v < b.v; });
    double widest = -1, at = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const Line& a = lines[i];
      const Line& b = lines[(i + 1) % lines.size()];
      const double start = a.v + a.v_hi, end = b.v + b.v_lo + (i + 1 == lines.size() ? 1.0 : 0.0);
      if (end - start > widest) widest = end - start, at = 0.5 * (start + end);
    }
    lines.push_back({false, -1, at - std::floor(at), 0, 0, 0, true});
    ++corners;
  }
  std::sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) { return a.v < b.v; });

  // Insert the cross sections (levels of u), then the new longitudes (levels of v).
  const int n = prm.torus_cubes;
  double first_level = 0.5 / n;
  if (!prm.cross_section_point.empty()) {
    if (!protect_in.empty() || disk) throw core::ConfigError("split.cross_section_point is not supported for surfaces of genus 2 yet");
    first_level = u[nearest_vertex(mesh, prm.cross_section_point[0])];
  }
  LabelledEdges cuts;
  IsolineOptions ou = opt, ov = opt;
  ou.period = ov.period = 1.0;
  ou.carried = {{&v, 1.0}, {&f, 0.0}};
  ov.carried = {{&u, 1.0}, {&f, 0.0}};
  auto take = [&](std::vector<std::vector<int>> loops, const std::vector<double>& other, const std::string& what) {
    std::vector<int> keep;
    for (auto& l : loops)
      if (std::abs(loop_period(l, other)) == 1 && keep.empty()) keep = std::move(l);
      else
        throw core::TopologyError("split: the " + what + " is not a single loop (" + std::to_string(loops.size()) +
                                  " loops); the harmonic field has spurious critical points — set split.extreme_points or "
                                  "split.cross_section_plane, or refine the mesh");
    if (keep.empty()) throw core::TopologyError("split: the " + what + " does not run around the torus");
    return keep;
  };
  // Level of cross section k: with a disk, the first two along its rim, the others spread over the
  // rest of the ring.
  auto cross_section_level = [&](int k) {
    if (!dc) return between_vertices(level_avoiding(protect, u, k, n, first_level), u, 1.0);
    if (k < 2) return dc->u_level[static_cast<std::size_t>(k)];
    return spread_level(u, dc->u_level, k - 1, n - 1);
  };
  if (dc) ou.face_mask = ov.face_mask = &off_disk;
  // A level set through two corners of the disk: its chain outside the disk, closed by the rim arc.
  auto close_by_arc = [&](std::vector<std::vector<int>> chains, const std::vector<int>& arc, const std::string& what) {
    if (chains.size() != 1 || !((chains[0].front() == arc.front() && chains[0].back() == arc.back()) ||
                                (chains[0].front() == arc.back() && chains[0].back() == arc.front())))
      throw core::TopologyError("split: the " + what + " through the corners of the disk where the tori meet is not one curve from corner to corner (" +
                                std::to_string(chains.size()) + " pieces); set split.extreme_points or refine the mesh");
    std::vector<int> loop = std::move(chains[0]);
    if (loop.front() == arc.front()) std::reverse(loop.begin(), loop.end());
    loop.insert(loop.end(), arc.begin() + 1, arc.end() - 1);
    return loop;
  };
  for (int k = 0; k < n; ++k) {
    splits.clear();
    auto loops = insert_isoline(mesh, u, cross_section_level(k), ou);
    apply_splits(sharp, splits);
    apply_splits(cuts, splits);
    const std::string what = "cross section " + std::to_string(k);
    const auto loop = take(dc && k < 2 ? std::vector<std::vector<int>>{close_by_arc(std::move(loops), dc->u_arc[static_cast<std::size_t>(k)], what)} : std::move(loops), v, what);
    add_loop(cuts, loop, k);
  }
  for (std::size_t j = 0; j < lines.size(); ++j) {
    if (lines[j].sharp) continue;
    splits.clear();
    const int dl = lines[j].disk_level;
    auto loops = insert_isoline(mesh, v, dl >= 0 ? lines[j].v : between_vertices(lines[j].v, v, 1.0), ov);
    apply_splits(sharp, splits);
    apply_splits(cuts, splits);
    const std::string what = "longitudinal line " + std::to_string(j);
    if (dl >= 0) loops = {close_by_arc(std::move(loops), dc->v_arc[static_cast<std::size_t>(dl)], what)};
    add_loop(cuts, take(std::move(loops), u, what), kLongitudeLabel + static_cast<int>(j));
  }
  if (!sharp.empty())
    for (const auto& loop : chain_loops(sharp))
      for (std::size_t j = 0; j < lines.size(); ++j)
        if (lines[j].sharp && std::find(loop.begin(), loop.end(), lines[j].vertex) != loop.end())
          add_loop(cuts, loop, kLongitudeLabel + static_cast<int>(j));

  // Patches: regions between the cuts; corners where a cross section meets a longitudinal line.
  const int nv = static_cast<int>(mesh.number_of_vertices());
  std::vector<std::set<int>> labels_at(nv);
  std::set<Edge> cut_set;
  for (const auto& [e, label] : cuts) {
    cut_set.insert(e);
    labels_at[e.first].insert(label);
    labels_at[e.second].insert(label);
  }
  std::vector<char> is_corner(nv, 0), is_cube_corner(nv, 0);
  std::map<std::pair<int, int>, int> crossing;  // (cross section, line) -> vertex
  for (int x = 0; x < nv; ++x) {
    if (labels_at[x].size() < 2) continue;
    is_corner[x] = 1;
    int cs = -1, line = -1;
    for (int l : labels_at[x]) (l >= kLongitudeLabel ? line : cs) = l;
    if (labels_at[x].size() != 2 || cs < 0 || line < 0)
      throw core::TopologyError("split: cuts of the torus meet at vertex " + std::to_string(x) + " other than a cross section crossing a longitudinal line");
    line -= kLongitudeLabel;
    if (!crossing.emplace(std::pair{cs, line}, x).second)
      throw core::TopologyError("split: cross section " + std::to_string(cs) + " crosses longitudinal line " + std::to_string(line) +
                                " more than once; the sharp curves are too wavy for the harmonic cross sections — set split.cross_section_plane or use route: tet");
    if (lines[line].corner) is_cube_corner[x] = 1;
  }
  std::vector<int> face_region;
  const auto regs = regions(mesh, cut_set, &face_region);
  copy_mesh(mesh, d.layout);
  const int m = static_cast<int>(lines.size());
  std::vector<int> corner_lines;
  for (int j = 0; j < m; ++j)
    if (lines[j].corner) corner_lines.push_back(j);
  d.components.resize(n);
  d.tori.resize(1);
  for (int k = 0; k < n; ++k) {
    d.components[k].type = ComponentType::torus_cube;
    d.components[k].torus = 0;
    d.components[k].faces.resize(6);
    d.tori[0].components.push_back(k);
  }
  for (std::size_t r = 0; r < regs.size(); ++r) {
    Patch p = quad_patch(regs[r], is_corner, "torus patch", static_cast<int>(r));
    std::set<int> cs, ln;
    for (int s = 0; s < 4; ++s) {
      const auto& side = p.sides[s];
      const int label = cuts.at(edge(side[0], side[1]));
      (label >= kLongitudeLabel ? ln : cs).insert(label >= kLongitudeLabel ? label - kLongitudeLabel : label);
    }
    if (cs.size() != 2 || ln.size() != 2) throw core::TopologyError("split: torus patch " + std::to_string(r) + " is not bounded by two cross sections and two longitudinal lines");
    const int c0 = *cs.begin(), c1 = *cs.rbegin();
    const int comp = (c1 == c0 + 1) ? c0 : (c0 == 0 && c1 == n - 1 ? n - 1 : -1);
    const int l0 = *ln.begin(), l1 = *ln.rbegin();
    const int line = (l1 == l0 + 1) ? l0 : (l0 == 0 && l1 == m - 1 ? m - 1 : -1);
    if (comp < 0 || line < 0) throw core::TopologyError("split: torus patch " + std::to_string(r) + " spans non-adjacent cuts");
    int face = 3;  // the interval of corner lines [corner_lines[i], corner_lines[i+1]) holding `line`
    for (int i = 0; i < 4; ++i)
      if (line >= corner_lines[i] && (i == 3 || line < corner_lines[i + 1])) face = i;
    d.components[comp].faces[face].patches.push_back(static_cast<int>(r));
    d.components[comp].patches.push_back(static_cast<int>(r));
    d.layout.patches.push_back(std::move(p));
  }
  // Cross sections as internal faces: cross section k lies between components k-1 and k.
  for (int k = 0; k < n; ++k) {
    std::set<Edge> es;
    for (const auto& [e, label] : cuts)
      if (label == k) es.insert(e);
    const auto loops = chain_loops(es);
    d.layout.internal_faces.push_back(internal_face(loops.at(0), is_cube_corner, k));
    d.cross_section_lines.push_back(loops.at(0));
  }
  for (int j = 0; j < m; ++j) {
    std::set<Edge> es;
    for (const auto& [e, label] : cuts)
      if (label == kLongitudeLabel + j) es.insert(e);
    d.longitude_lines.push_back(chain_loops(es).at(0));
  }
  auto at = [&](int cs, int line) {
    const auto it = crossing.find({cs % n, line % m});
    if (it == crossing.end())
      throw core::TopologyError("split: cross section " + std::to_string(cs % n) + " does not cross longitudinal line " + std::to_string(line % m));
    return it->second;
  };
  for (int k = 0; k < n; ++k) {
    auto& comp = d.components[k];
    for (int i = 0; i < 4; ++i) {
      const int a = corner_lines[i], b = corner_lines[(i + 1) % 4];
      comp.faces[i].corners = {at(k, a), at(k + 1, a), at(k + 1, b), at(k, b)};
    }
    comp.faces[4].internal_face = k;
    comp.faces[4].corners = d.layout.internal_faces[k].corners;
    comp.faces[5].internal_face = (k + 1) % n;
    comp.faces[5].corners = d.layout.internal_faces[(k + 1) % n].corners;
    std::sort(comp.patches.begin(), comp.patches.end());
    d.tori[0].cross_sections.push_back((k + 1) % n);
    d.contacts.push_back({k, (k + 1) % n, "internal_face", (k + 1) % n});
  }
  d.quad_patches = static_cast<int>(d.layout.patches.size());
  d.field = f;
  d.ring_field = u;
  d.tube_field = v;
  return d;
}

}  // namespace volts::split::detail
