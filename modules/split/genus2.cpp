// Two tori (Liu et al. 2013, §4.1 and the union of Fig. 6(c)): a genus-2 surface is cut along a
// level set of the first harmonic field that separates it into two one-holed tori (the waist of
// an "eight"); the loop is filled with a disk (flagged triangles) where the two tori meet, and each
// closed torus is split into a ring of cubes whose cuts avoid the disk, so the disk lies inside one
// patch of each torus (the faces the two primitives are united on).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <set>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <Eigen/Dense>

#include "classify/classify.h"
#include "core/errors.h"
#include "core/log.h"
#include "split/isoline.h"
#include "split/split_internal.h"

namespace volts::split::detail {

using surface::Mesh;

namespace {

// A loop of the level set {f = c} that cuts the surface into two parts of genus 1.
bool find_waist(const Mesh& m, const std::vector<double>& f, double c, std::vector<int>* waist) {
  Mesh copy = m;
  std::vector<double> g = f;
  try {
    for (const auto& loop : insert_isoline(copy, g, c)) {
      const auto label = regions_cut_by(copy, {loop});
      if (*std::max_element(label.begin(), label.end()) != 1) continue;
      if (region_genus(copy, label, 0) == 1 && region_genus(copy, label, 1) == 1) {
        if (waist) *waist = loop;
        return true;
      }
    }
  } catch (const core::TopologyError&) {
  }
  return false;
}

// True if `loop` with the other cuts cuts the surface into one more region than there are cuts.
bool adds_a_region(const Mesh& mesh, const std::vector<int>& loop, const std::vector<std::vector<int>>& other) {
  auto loops = other;
  loops.push_back(loop);
  const auto label = regions_cut_by(mesh, loops);
  return *std::max_element(label.begin(), label.end()) == static_cast<int>(loops.size());
}

// The loop of {f = c} (inserted) that has genus-1 regions on both sides, given the other cuts.
std::vector<int> separating_loop(Mesh& mesh, std::vector<double>& f, double c, const std::vector<std::vector<int>>& other) {
  for (const auto& loop : insert_isoline(mesh, f, c))
    if (adds_a_region(mesh, loop, other)) return loop;
  throw std::logic_error("split: a waist loop vanished on insertion");
}

// Shortest edge path on m from a to b through vertices not blocked (a and b may be).
std::vector<int> shortest_path(const Mesh& m, int a, int b, const std::vector<char>& blocked) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(m.number_of_vertices(), inf);
  std::vector<int> from(m.number_of_vertices(), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[a] = 0;
  queue.push({0, a});
  auto pos = [&](int v) {
    const auto& p = m.point(Mesh::Vertex_index(v));
    return Eigen::Vector3d(p.x(), p.y(), p.z());
  };
  while (!queue.empty()) {
    const auto [d, x] = queue.top();
    queue.pop();
    if (d > dist[x] || x == b) continue;
    for (auto h : CGAL::halfedges_around_source(Mesh::Vertex_index(x), m)) {
      const int y = static_cast<int>(m.target(h));
      if (blocked[y] && y != b) continue;
      const double dy = d + (pos(x) - pos(y)).norm();
      if (dy < dist[y]) dist[y] = dy, from[y] = x, queue.push({dy, y});
    }
  }
  if (dist[b] == inf) return {};
  std::vector<int> path;
  for (int x = b; x != -1; x = from[x]) path.push_back(x);
  std::reverse(path.begin(), path.end());
  return path;
}

// The neck's four side curves as level sets: with θ on each rim going 0, 1/4, 1/2, 3/4 at its
// corners (linear in arc length between them; rim 1's corners in their pairing with rim 0's), the
// harmonic extensions of sin 2πθ and cos 2πθ vanish on curves from corner k of one rim to corner k
// of the other (sin: k = 0, 2; cos: 1, 3) that leave both rims across them, as straight lines on a
// cylinder do. Inserted into N's neck faces (fills are not cut); their edges added to `cuts`.
// Returns false (N unchanged) if the level sets are not four such curves (a long twisted neck).
bool neck_side_isolines(Submesh& N, const std::vector<char>& neck_faces, const std::array<std::vector<int>, 2>& rim,
                        const std::array<std::array<int, 4>, 2>& corner, std::set<Edge>* cuts) {
  Mesh m = N.mesh;
  const auto pos = [&](int v) {
    const auto& q = m.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(v)));
    return Eigen::Vector3d(q.x(), q.y(), q.z());
  };
  const double two_pi = 2 * std::acos(-1.0);
  std::vector<Constraint> cs, cc;
  std::vector<char> on_rim(m.number_of_vertices(), 0);
  for (int i = 0; i < 2; ++i) {
    const auto& R = rim[static_cast<std::size_t>(i)];
    const int n = static_cast<int>(R.size());
    std::array<int, 4> at{};
    for (int k = 0; k < 4; ++k) {
      const auto it = std::find(R.begin(), R.end(), corner[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)]);
      if (it == R.end()) return false;
      at[static_cast<std::size_t>(k)] = static_cast<int>(it - R.begin());
    }
    auto ordered = [&](int dir) {
      const auto off = [&](int k) { return ((at[static_cast<std::size_t>(k)] - at[0]) * dir % n + n) % n; };
      return off(1) < off(2) && off(2) < off(3);
    };
    const int dir = ordered(1) ? 1 : ordered(-1) ? -1 : 0;
    if (dir == 0) return false;
    for (int k = 0; k < 4; ++k) {
      std::vector<int> arc;
      for (int j = at[static_cast<std::size_t>(k)];; j = ((j + dir) % n + n) % n) {
        arc.push_back(R[static_cast<std::size_t>(j)]);
        if (j == at[static_cast<std::size_t>((k + 1) % 4)]) break;
      }
      std::vector<double> len(arc.size(), 0.0);
      for (std::size_t j = 1; j < arc.size(); ++j) len[j] = len[j - 1] + (pos(arc[j]) - pos(arc[j - 1])).norm();
      for (std::size_t j = 0; j + 1 < arc.size(); ++j) {  // the last is the next arc's first
        const double theta = (k + len[j] / len.back()) / 4;
        // Exact zeros at the corners, so the level sets pass through them.
        cs.push_back({arc[j], j == 0 && k % 2 == 0 ? 0.0 : std::sin(two_pi * theta)});
        cc.push_back({arc[j], j == 0 && k % 2 == 1 ? 0.0 : std::cos(two_pi * theta)});
        on_rim[static_cast<std::size_t>(arc[j])] = 1;
      }
    }
  }
  std::vector<double> fs = harmonic_field(m, cs), fc = harmonic_field(m, cc);
  std::vector<char> mask = neck_faces;
  std::set<int> first_curves;  // vertices of the sin curves, which the cos curves must not touch
  std::set<Edge> added = *cuts;
  std::vector<std::array<int, 3>> splits;
  for (int field = 0; field < 2; ++field) {
    IsolineOptions opt;
    opt.face_mask = &mask;
    opt.splits = &splits;
    opt.carried = {{field == 0 ? &fc : &fs, 0.0}};
    splits.clear();
    const auto chains = insert_isoline(m, field == 0 ? fs : fc, 0.0, opt);
    apply_splits(added, splits);
    on_rim.resize(m.number_of_vertices(), 0);
    int found = 0;
    for (const auto& ch : chains) {
      if (ch.size() < 2) return false;
      bool ok = false;
      for (int k = field; k < 4; k += 2) {
        const int a = corner[0][static_cast<std::size_t>(k)], b = corner[1][static_cast<std::size_t>(k)];
        ok |= (ch.front() == a && ch.back() == b) || (ch.front() == b && ch.back() == a);
      }
      for (std::size_t j = 1; j + 1 < ch.size(); ++j) ok &= !on_rim[static_cast<std::size_t>(ch[j])];
      for (const int v : ch) ok &= field == 0 || !first_curves.count(v);
      if (!ok) return false;
      if (field == 0) first_curves.insert(ch.begin(), ch.end());
      for (std::size_t j = 1; j < ch.size(); ++j)
        if (!added.insert(edge(ch[j - 1], ch[j])).second) return false;  // a curve along another
      ++found;
    }
    if (found != 2) return false;
  }
  N.mesh = std::move(m);
  *cuts = std::move(added);
  return true;
}

// `vs` in the order a walk along the closed `loop` meets them, walking the way that meets ref[0],
// ref[1], ref[2] in that order (all of them on the loop).
std::array<int, 4> in_loop_order(const std::vector<int>& loop, const std::array<int, 4>& ref, const std::array<int, 4>& vs) {
  const auto n = static_cast<std::ptrdiff_t>(loop.size());
  const auto offset = [&](int v) { return ((std::find(loop.begin(), loop.end(), v) - std::find(loop.begin(), loop.end(), ref[0])) % n + n) % n; };
  const bool forward = offset(ref[1]) < offset(ref[2]);
  std::array<std::pair<std::ptrdiff_t, int>, 4> order{};
  for (std::size_t k = 0; k < 4; ++k) order[k] = {forward ? offset(vs[k]) : (n - offset(vs[k])) % n, vs[k]};
  std::sort(order.begin(), order.end());
  std::array<int, 4> out{};
  for (std::size_t k = 0; k < 4; ++k) out[k] = order[k].second;
  return out;
}

}  // namespace

// A connector end on a shoulder: the cut loop and the two concave sharp curves it runs along,
// each with the other sharp curve of its shoulder face (`convex[k]`, from concave[k]'s first
// vertex to its last, or empty): the rod's shoulder faces are lenses bounded by two curves with
// the same ends (the shank's rounded cross section cut by the thinner eye's flat faces).
struct Shoulder {
  std::vector<int> loop;
  std::array<std::vector<int>, 2> concave, convex;
};

// The loop of a shoulder (split.connector_end: shoulder): the two concave sharp curves across the
// neck nearest the cut level `end` on the waist's side (f nearly constant along each: a face
// across the neck meets a thinner part there), joined at their ends by shortest edge paths
// across the smooth sides that keep off the shoulder faces' other curves. Empty loop if there are
// not two such curves or the paths fail.
Shoulder shoulder_loop(const Mesh& mesh, const std::vector<double>& f, double waist, double end, const classify::Classification& c) {
  const double span = std::abs(end - waist);
  auto concave = [&](int a, int b) {
    const auto h = mesh.halfedge(Mesh::Vertex_index(a), Mesh::Vertex_index(b));
    if (h == Mesh::null_halfedge()) return false;
    const auto p = [&](Mesh::Vertex_index v) { return mesh.point(v); };
    const auto x = mesh.target(mesh.next(h)), y = mesh.target(mesh.next(mesh.opposite(h)));
    // y above the plane of the face (a, b, x) on its outward side: the edge is concave.
    return CGAL::orientation(p(Mesh::Vertex_index(a)), p(Mesh::Vertex_index(b)), p(x), p(y)) == CGAL::POSITIVE;
  };
  struct Candidate {
    double mean = 0;
    const classify::Curve* curve = nullptr;
  };
  std::vector<Candidate> found;
  for (const auto& k : c.curves) {
    if (k.closed || k.vertices.size() < 2) continue;
    double lo = HUGE_VAL, hi = -HUGE_VAL, sum = 0;
    for (const int v : k.vertices) lo = std::min(lo, f[static_cast<std::size_t>(v)]), hi = std::max(hi, f[static_cast<std::size_t>(v)]), sum += f[static_cast<std::size_t>(v)];
    const double mean = sum / k.vertices.size();
    // Across the neck near the cut: on the neck's side of the saddle beyond it, within a fifth of
    // the waist-to-cut distance of the cut level.
    const bool between = std::abs(mean - end) < 0.2 * span && (end > waist ? lo > waist : hi < waist);
    int concave_edges = 0;
    for (std::size_t i = 0; i + 1 < k.vertices.size(); ++i) concave_edges += concave(k.vertices[i], k.vertices[i + 1]);
    if (!between || hi - lo > 0.15 * span) continue;
    if (2 * concave_edges <= static_cast<int>(k.vertices.size()) - 1) continue;
    found.push_back({mean, &k});
  }
  if (found.size() < 2) return {};
  std::sort(found.begin(), found.end(), [&](const Candidate& x, const Candidate& y) { return std::abs(x.mean - end) < std::abs(y.mean - end); });
  const auto& A = found[0].curve->vertices;
  const auto& B = found[1].curve->vertices;
  // The other curve of a concave curve's shoulder face: same two ends, one patch in common, at
  // least two vertices between its ends (room for the end face's corners).
  auto other_curve = [&](const classify::Curve& k) {
    for (const auto& o : c.curves) {
      if (&o == &k || o.closed || o.vertices.size() < 4) continue;
      const bool same = o.vertices.front() == k.vertices.front() && o.vertices.back() == k.vertices.back();
      const bool reversed = o.vertices.front() == k.vertices.back() && o.vertices.back() == k.vertices.front();
      const bool shares = o.patch_left == k.patch_left || o.patch_left == k.patch_right || o.patch_right == k.patch_left || o.patch_right == k.patch_right;
      if (!(same || reversed) || !shares) continue;
      std::vector<int> v = o.vertices;
      if (reversed) std::reverse(v.begin(), v.end());
      return v;
    }
    return std::vector<int>{};
  };
  Shoulder sh;
  sh.concave = {A, B};
  sh.convex = {other_curve(*found[0].curve), other_curve(*found[1].curve)};
  auto pos = [&](int v) {
    const auto& q = mesh.point(Mesh::Vertex_index(v));
    return Eigen::Vector3d(q.x(), q.y(), q.z());
  };
  // B runs from the end nearest A's last vertex.
  std::vector<int> b = B;
  if ((pos(A.back()) - pos(b.back())).norm() < (pos(A.back()) - pos(b.front())).norm()) std::reverse(b.begin(), b.end());
  std::vector<char> blocked(mesh.number_of_vertices(), 0);
  for (const int v : A) blocked[static_cast<std::size_t>(v)] = 1;
  for (const int v : b) blocked[static_cast<std::size_t>(v)] = 1;
  for (const auto& k : sh.convex)
    for (const int v : k) blocked[static_cast<std::size_t>(v)] = 1;
  const std::vector<int> p1 = shortest_path(mesh, A.back(), b.front(), blocked);
  if (p1.empty()) return {};
  for (const int v : p1) blocked[static_cast<std::size_t>(v)] = 1;
  const std::vector<int> p2 = shortest_path(mesh, b.back(), A.front(), blocked);
  if (p2.empty()) return {};
  // A, the path to B, B, the path back; a vertex the pieces share once (curves that meet).
  std::vector<int> loop;
  const std::vector<int>* pieces[] = {&A, &p1, &b, &p2};
  for (const std::vector<int>* piece : pieces)
    for (const int v : *piece)
      if (loop.empty() || loop.back() != v) loop.push_back(v);
  if (loop.size() > 1 && loop.back() == loop.front()) loop.pop_back();
  std::vector<int> sorted = loop;
  std::sort(sorted.begin(), sorted.end());
  if (loop.size() < 3 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return {};  // not a simple loop
  sh.loop = std::move(loop);
  return sh;
}

int region_genus(const Mesh& m, const std::vector<int>& label, int which) {
  std::set<int> vs;
  std::set<Edge> es;
  int faces = 0;
  for (auto f : m.faces()) {
    if (label[f] != which) continue;
    ++faces;
    for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      vs.insert(static_cast<int>(m.target(h)));
      es.insert(edge(static_cast<int>(m.source(h)), static_cast<int>(m.target(h))));
    }
  }
  const int chi = static_cast<int>(vs.size()) - static_cast<int>(es.size()) + faces;
  return (1 - chi) / 2;
}

Decomposition split_two_tori(const Mesh& input, const Params& prm, const classify::Classification* cls) {
  if (!(prm.connector_cut >= 0.05 && prm.connector_cut <= 0.95)) throw core::ConfigError("split.connector_cut must be in [0.05, 0.95]");
  if (prm.connector_end != "level" && prm.connector_end != "shoulder")
    throw core::ConfigError("split.connector_end must be 'level' or 'shoulder', not '" + prm.connector_end + "'");
  if (prm.genus2 != "disk" && prm.genus2 != "connector")
    throw core::ConfigError("split.genus2 must be 'auto', 'disk' or 'connector', not '" + prm.genus2 + "'");
  const bool connector = prm.genus2 == "connector";
  Mesh mesh = input;
  CriticalPoints cp;
  std::vector<double> f = height_field(mesh, prm, &cp);
  const auto gaps = saddle_gaps(f, cp);
  double level = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [w, c] : gaps)
    if (find_waist(mesh, f, level_between_vertices(c, f), nullptr)) {
      level = level_between_vertices(c, f);
      break;
    }
  if (std::isnan(level))
    throw core::TopologyError("split: no level set of the harmonic field separates the genus-2 surface into two tori (" +
                              std::to_string(cp.minima.size()) + " min, " + std::to_string(cp.maxima.size()) + " max, " +
                              std::to_string(cp.saddle_count()) + " saddles); set split.extreme_points to the two ends of the part");
  // The cut levels: the waist, or (connector) one level on either side of it, the fraction
  // `connector_cut` of the way from the waist to the saddle at the next hole (an eight's neck is
  // the middle of its bar: 0.5; a rod's shank runs almost to its holes: 0.85).
  std::vector<double> levels{level};
  if (connector) {
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (const auto& s : cp.saddles) {
      const double x = f[static_cast<std::size_t>(s.first)];
      if (x < level) lo = std::max(lo, x);
      else hi = std::min(hi, x);
    }
    if (!std::isfinite(lo) || !std::isfinite(hi)) throw core::TopologyError("split: the waist of the genus-2 surface is not between two saddles");
    levels = {level_between_vertices(level + prm.connector_cut * (lo - level), f), level_between_vertices(level + prm.connector_cut * (hi - level), f)};
  }
  std::vector<std::vector<int>> cut_loops;
  std::vector<double> loop_level;  // the field's level of each cut (a shoulder's: its mean)
  std::vector<Shoulder> shoulders;  // per cut: its shoulder (empty loop for a level set)
  for (const double c : levels) {
    if (connector && prm.connector_end == "shoulder") {
      if (!cls) throw std::logic_error("split: shoulder ends need the classification");
      Shoulder sh = shoulder_loop(mesh, f, level, c, *cls);
      const std::vector<int>& loop = sh.loop;
      if (!loop.empty() && adds_a_region(mesh, loop, cut_loops)) {
        core::log("split: a connector end lies on a shoulder (" + std::to_string(loop.size()) + " vertices)");
        double mean = 0;
        for (const int v : loop) mean += f[static_cast<std::size_t>(v)];
        loop_level.push_back(mean / loop.size());
        cut_loops.push_back(loop);
        shoulders.push_back(std::move(sh));
        continue;
      }
    }
    cut_loops.push_back(separating_loop(mesh, f, c, cut_loops));
    loop_level.push_back(c);
    shoulders.emplace_back();
  }
  const auto region = regions_cut_by(mesh, cut_loops);
  // Regions: ring 0 (genus 1), [the neck], ring 1; ring i has cut_loops[i ? last : 0] as its rim.
  const int n_regions = static_cast<int>(cut_loops.size()) + 1;
  std::vector<int> genus(static_cast<std::size_t>(n_regions));
  for (int r = 0; r < n_regions; ++r) genus[static_cast<std::size_t>(r)] = region_genus(mesh, region, r);
  std::vector<int> rings_r, neck_r;
  for (int r = 0; r < n_regions; ++r) (genus[static_cast<std::size_t>(r)] == 1 ? rings_r : neck_r).push_back(r);
  if (rings_r.size() != 2 || neck_r.size() != (connector ? 1u : 0u))
    throw core::TopologyError("split: the cuts of the genus-2 surface do not leave two tori" + std::string(connector ? " and a neck" : ""));

  Layout L;
  copy_mesh(mesh, L);
  std::vector<std::vector<int>> tris(static_cast<std::size_t>(n_regions));
  for (std::size_t t = 0; t < region.size(); ++t) tris[static_cast<std::size_t>(region[t])].push_back(static_cast<int>(t));
  // Each ring's rim: the cut loop bounding its region.
  auto rim_of = [&](int r) {
    for (const auto& loop : cut_loops) {
      const int a = loop[0], b = loop[1];
      const auto h = mesh.halfedge(Mesh::Vertex_index(a), Mesh::Vertex_index(b));
      if (region[mesh.face(h)] == r || region[mesh.face(mesh.opposite(h))] == r) return loop;
    }
    throw std::logic_error("split: a ring has no rim");
  };
  // The rings with their disks: with a waist, ring 1 uses ring 0's fill reversed; with a neck,
  // each ring fills its own rim and the neck uses both fills reversed.
  std::array<Submesh, 2> torus;
  std::array<std::vector<int>, 2> fill, rim;
  const std::array<std::size_t, 3> layout_size{L.points.size(), L.triangles.size(), L.filled.size()};
  int planar_fills = 0;
  auto make_rings = [&](FillMethod method) {
    planar_fills = 0;
    L.points.resize(layout_size[0]), L.triangles.resize(layout_size[1]), L.filled.resize(layout_size[2]);  // fills only append
    for (int i = 0; i < 2; ++i) {
      const int r = rings_r[static_cast<std::size_t>(i)];
      rim[i] = rim_of(r);
      std::vector<int> t = tris[static_cast<std::size_t>(r)];
      std::vector<char> rev(t.size(), 0);
      if (i == 1 && !connector) {
        fill[1] = fill[0];
        t.insert(t.end(), fill[0].begin(), fill[0].end());
        rev.resize(t.size(), 1);
        torus[1] = submesh(L, t, rev);
      } else {
        torus[i] = submesh(L, t, rev);
        int planar = 0;
        fill[i] = fill_openings(torus[i], L, true, method, &planar);  // no chords: flat triangles once the disk is pressed onto a face
        planar_fills += planar;
      }
    }
  };
  // The neck's closed surface: its region and both fills reversed.
  auto neck_surface = [&] {
    std::vector<int> t = tris[static_cast<std::size_t>(neck_r[0])];
    std::vector<char> rev(t.size(), 0);
    for (int i = 0; i < 2; ++i) t.insert(t.end(), fill[i].begin(), fill[i].end());
    rev.resize(t.size(), 1);
    return submesh(L, t, rev);
  };
  make_rings(FillMethod::hole_filling);
  // A fill that clears its ring can still cross the neck on the other side (the rod's shank near
  // its eyes): then both rims are filled in their planes. The checked neck is the one used below.
  Submesh N;
  if (connector) {
    N = neck_surface();
    if (CGAL::Polygon_mesh_processing::does_self_intersect(N.mesh)) {
      core::log_verbose("split: a fill crosses the neck; both rims filled in their planes");
      make_rings(FillMethod::planar);
      N = neck_surface();
      if (CGAL::Polygon_mesh_processing::does_self_intersect(N.mesh))
        throw core::TopologyError("split: the disks closing the neck cross its surface; try another split.connector_cut");
    }
  }
  const int n_input = static_cast<int>(mesh.number_of_vertices());

  Decomposition d;
  d.genus = 2;
  d.planar_fills = planar_fills;
  d.genus2 = prm.genus2;
  d.critical_min = static_cast<int>(cp.minima.size());
  d.critical_max = static_cast<int>(cp.maxima.size());
  d.critical_saddle = cp.saddle_count();
  d.layout.points = L.points;
  std::set<int> all_fill;
  for (const auto& fl : fill) all_fill.insert(fl.begin(), fl.end());
  std::array<int, 2> disk_patch{-1, -1}, disk_component{-1, -1};
  std::array<std::array<int, 4>, 2> disk_corners{};  // layout ids
  for (int i = 0; i < 2; ++i) {
    Submesh& T = torus[i];
    const double ring_level = connector ? loop_level[static_cast<std::size_t>(std::find(cut_loops.begin(), cut_loops.end(), rim[i]) - cut_loops.begin())] : level;
    // The first field on this torus (the disk at its rim's level), and a meridian: a level set
    // between two saddles on this side that does not separate the closed torus.
    std::vector<double> g(T.mesh.number_of_vertices());
    for (std::size_t v = 0; v < g.size(); ++v) g[v] = T.layout_vertex[v] < n_input ? f[T.layout_vertex[v]] : ring_level;
    // This torus lies below its rim's level if it reaches further below than above (a shoulder's
    // rim is not one level).
    const bool below = ring_level - *std::min_element(g.begin(), g.end()) > *std::max_element(g.begin(), g.end()) - ring_level;
    // Its sharp edges (input edges of this torus; carried through the meridian's splits), for the
    // corner lines they can give with the disk.
    std::set<Edge> torus_sharp;
    if (connector && cls) {
      std::map<int, int> input_local;
      for (std::size_t v = 0; v < T.layout_vertex.size(); ++v) input_local[T.layout_vertex[v]] = static_cast<int>(v);
      for (const auto& e : sharp_edges(*cls)) {
        const auto a = input_local.find(e.first), b = input_local.find(e.second);
        if (a != input_local.end() && b != input_local.end() &&
            T.mesh.halfedge(Mesh::Vertex_index(static_cast<Mesh::size_type>(a->second)), Mesh::Vertex_index(static_cast<Mesh::size_type>(b->second))) !=
                Mesh::null_halfedge())
          torus_sharp.insert(edge(a->second, b->second));
      }
    }
    std::vector<int> meridian;
    for (const auto& [w, c] : gaps) {
      if ((c < ring_level) != below) continue;
      Mesh copy = T.mesh;
      std::vector<double> h = g;
      try {
        for (const auto& loop : insert_isoline(copy, h, level_between_vertices(c, g)))
          if (!loop_separates(copy, loop)) {
            meridian = loop;
            break;
          }
      } catch (const core::TopologyError&) {
      }
      if (meridian.empty()) continue;
      meridian.clear();
      std::vector<std::array<int, 3>> splits;
      IsolineOptions opt;
      opt.splits = &splits;
      for (const auto& loop : insert_isoline(T.mesh, g, level_between_vertices(c, g), opt))
        if (meridian.empty() && !loop_separates(T.mesh, loop)) meridian = loop;
      apply_splits(torus_sharp, splits);
      break;
    }
    if (meridian.empty())
      throw core::TopologyError("split: torus " + std::to_string(i) + " of the genus-2 surface has no level set around its tube; set split.extreme_points");
    Decomposition t;
    if (connector) {
      // The disk as one whole patch of this torus: an end face of the connector.
      std::map<int, int> local;
      for (std::size_t v = 0; v < T.layout_vertex.size(); ++v) local[T.layout_vertex[v]] = static_cast<int>(v);
      DiskPatch disk;
      for (int v : rim[i]) disk.rim.push_back(local.at(v));
      std::set<int> inside;
      for (int x : fill[i])
        for (int v : L.triangles[x])
          if (std::find(rim[i].begin(), rim[i].end(), v) == rim[i].end()) inside.insert(local.at(v));
      disk.inside.assign(inside.begin(), inside.end());
      t = split_torus(T.mesh, torus_sharp, prm, {}, meridian, &disk);
      for (int k = 0; k < 4; ++k) disk_corners[i][k] = T.layout_vertex[static_cast<std::size_t>(disk.corners[k])];
    } else {
      // The waist's disk inside one patch of each torus: no cut crosses it (the tori meet on it
      // non-conformingly; made a whole shared face, 97 % of the eight's elements were valid:
      // docs/status.md, session 13).
      std::set<int> disk_vertices(rim[i].begin(), rim[i].end());
      for (int x : fill[i])
        for (int v : L.triangles[x]) disk_vertices.insert(v);
      std::vector<int> protect;
      for (std::size_t v = 0; v < T.layout_vertex.size(); ++v)
        if (disk_vertices.count(T.layout_vertex[v])) protect.push_back(static_cast<int>(v));
      t = split_torus(T.mesh, {}, prm, protect, meridian);
    }
    const std::set<int> fill_set(fill[i].begin(), fill[i].end());
    // Merge: vertices new on this torus and its non-disk triangles are appended to the layout.
    const std::vector<int> vmap = merge_vertices(t.layout, T.layout_vertex, d.layout);
    std::vector<int> tmap(t.layout.triangles.size());
    for (std::size_t k = 0; k < tmap.size(); ++k) {
      if (k < T.layout_triangle.size() && fill_set.count(T.layout_triangle[k])) {
        tmap[k] = -1 - T.layout_triangle[k];  // a disk triangle: resolved below, they come last
        continue;
      }
      const auto& tr = t.layout.triangles[k];
      tmap[k] = static_cast<int>(d.layout.triangles.size());
      d.layout.triangles.push_back({vmap[tr[0]], vmap[tr[1]], vmap[tr[2]]});
      d.layout.filled.push_back(0);
    }
    const int patch_offset = static_cast<int>(d.layout.patches.size());
    const int comp_offset = static_cast<int>(d.components.size());
    const int face_offset = static_cast<int>(d.layout.internal_faces.size());
    for (std::size_t p = 0; p < t.layout.patches.size(); ++p) {
      Patch P = t.layout.patches[p];
      bool has_disk = false;
      for (int& x : P.triangles) {
        has_disk |= tmap[x] < 0;
        x = tmap[x];
      }
      for (int& v : P.corners) v = vmap[v];
      for (auto& s : P.sides)
        for (int& v : s) v = vmap[v];
      if (has_disk) {
        if (connector)
          for (int x : P.triangles)
            if (x >= 0) throw core::TopologyError("split: torus " + std::to_string(i) + "'s patch " + std::to_string(p) +
                                                  " holds part of its disk and part of the surface; the connector's end must be a whole patch");
        if (disk_patch[i] >= 0) throw core::TopologyError("split: the disk of torus " + std::to_string(i) + " spans several of its patches");
        disk_patch[i] = patch_offset + static_cast<int>(p);
      }
      d.layout.patches.push_back(std::move(P));
    }
    for (auto F : t.layout.internal_faces) {
      for (int& v : F.corners) v = vmap[v];
      for (auto& s : F.sides)
        for (int& v : s) v = vmap[v];
      for (int& v : F.loop) v = vmap[v];
      d.layout.internal_faces.push_back(std::move(F));
    }
    for (std::size_t c = 0; c < t.components.size(); ++c) {
      Component C = t.components[c];
      C.torus = static_cast<int>(d.tori.size());
      for (int& p : C.patches) {
        if (patch_offset + p == disk_patch[i]) disk_component[i] = comp_offset + static_cast<int>(c);
        p += patch_offset;
      }
      for (auto& F : C.faces) {
        for (int& p : F.patches) p += patch_offset;
        if (F.internal_face >= 0) F.internal_face += face_offset;
        for (int& v : F.corners) v = vmap[v];
      }
      d.components.push_back(std::move(C));
    }
    Torus R = t.tori.at(0);
    for (int& c : R.components) c += comp_offset;
    for (int& x : R.cross_sections) x += face_offset;
    d.tori.push_back(R);
    for (auto C : t.contacts) d.contacts.push_back({C.a + comp_offset, C.b + comp_offset, C.via, C.index + face_offset});
    for (auto l : t.cross_section_lines) {
      for (int& v : l) v = vmap[v];
      d.cross_section_lines.push_back(l);
    }
    for (auto l : t.longitude_lines) {
      for (int& v : l) v = vmap[v];
      d.longitude_lines.push_back(l);
    }
  }
  // The neck (connector): a cube whose bottom and top are the rings' disks and whose sides are
  // the annulus between the two rims cut by four curves joining their corners. Liu et al. (§6)
  // take the shortest distance on the surface; the corners are paired in the rotation of least
  // total shortest-path length, but the curves are level sets (neck_side_isolines), which leave
  // the rims across them; shortest edge paths only if those fail.
  int neck_component = -1, neck_bottom = -1, neck_top = -1;
  if (connector) {
    std::map<int, int> local;
    for (std::size_t v = 0; v < N.layout_vertex.size(); ++v) local[N.layout_vertex[v]] = static_cast<int>(v);
    const int nn = static_cast<int>(N.mesh.number_of_vertices());
    std::vector<char> blocked(static_cast<std::size_t>(nn), 0);
    for (std::size_t v = 0; v < N.layout_vertex.size(); ++v)
      if (N.layout_vertex[v] >= n_input) blocked[v] = 1;  // fill vertices
    for (int i = 0; i < 2; ++i)
      for (int v : rim[i]) blocked[static_cast<std::size_t>(local.at(v))] = 1;
    // A shoulder end whose faces are lenses (Shoulder::convex): the neck's end face there is its
    // disk and both lenses (Liu et al. Fig. 13: the shank ends on the eye's cross section and on
    // the shoulder around it), bounded by the outline (the rim with its concave curves replaced by
    // the convex ones), its corners on the convex curves; the lenses' ends (the disk's corners,
    // `tips`) lie inside the end face's sides. Otherwise the end face is the disk.
    std::array<std::vector<int>, 2> outline = rim;                  // layout ids
    std::array<std::array<int, 4>, 2> end_corners = disk_corners;  // layout ids, in the outline's order
    std::array<bool, 2> lensed{false, false};
    std::set<Edge> lens_cuts;  // the convex curves (local ids)
    const auto shoulder_of = [&](int i) -> const Shoulder& {
      return shoulders[static_cast<std::size_t>(std::find(cut_loops.begin(), cut_loops.end(), rim[i]) - cut_loops.begin())];
    };
    for (int i = 0; i < 2; ++i) {
      const Shoulder& sh = shoulder_of(i);
      if (sh.loop.empty() || sh.convex[0].empty() || sh.convex[1].empty()) continue;
      std::vector<int>& o = outline[i];
      std::array<std::vector<int>, 2> arcs;
      for (int k = 0; k < 2; ++k) {
        const std::vector<int>& a = sh.concave[static_cast<std::size_t>(k)];
        const std::vector<int>& b = sh.convex[static_cast<std::size_t>(k)];
        // Rotate the outline to start at a's first vertex, running along a.
        const auto at = std::find(o.begin(), o.end(), a.front());
        if (at == o.end()) throw std::logic_error("split: a shoulder's curve is not on its rim");
        std::rotate(o.begin(), at, o.end());
        if (o.size() > 1 && o[1] != a[1]) std::reverse(o.begin() + 1, o.end());
        if (o.size() < a.size() || !std::equal(a.begin(), a.end(), o.begin())) throw std::logic_error("split: a shoulder's rim does not run along its curve");
        std::vector<int> next(b.begin(), b.end());
        next.insert(next.end(), o.begin() + static_cast<std::ptrdiff_t>(a.size()), o.end());
        o = std::move(next);
        arcs[static_cast<std::size_t>(k)] = b;
      }
      // The end face's corners: on each convex curve, the vertices nearest to where a quarter of
      // the outline's length, centred on the curve, begins and ends (the face's sides about equal).
      auto point = [&](int v) { return Eigen::Vector3d(L.points[v][0], L.points[v][1], L.points[v][2]); };
      double total = 0;
      for (std::size_t k = 0; k < o.size(); ++k) total += (point(o[(k + 1) % o.size()]) - point(o[k])).norm();
      std::array<std::array<int, 2>, 2> pick{};
      for (int k = 0; k < 2; ++k) {
        const std::vector<int>& b = arcs[static_cast<std::size_t>(k)];
        std::vector<double> s(b.size(), 0.0);
        for (std::size_t j = 1; j < b.size(); ++j) s[j] = s[j - 1] + (point(b[j]) - point(b[j - 1])).norm();
        const double s0 = std::max(0.0, 0.5 * (s.back() - 0.25 * total));
        auto nearest = [&](double x, std::size_t lo, std::size_t hi) {
          std::size_t best = lo;
          for (std::size_t j = lo; j <= hi; ++j)
            if (std::abs(s[j] - x) < std::abs(s[best] - x)) best = j;
          return best;
        };
        const std::size_t j1 = nearest(s0, 1, b.size() - 3), j2 = nearest(s.back() - s0, j1 + 1, b.size() - 2);
        pick[static_cast<std::size_t>(k)] = {b[j1], b[j2]};
        for (std::size_t j = 1; j < b.size(); ++j) lens_cuts.insert(edge(local.at(b[j - 1]), local.at(b[j])));
        for (std::size_t j = 1; j + 1 < b.size(); ++j) blocked[static_cast<std::size_t>(local.at(b[j]))] = 1;
      }
      end_corners[i] = in_loop_order(o, disk_corners[i], {pick[0][0], pick[0][1], pick[1][0], pick[1][1]});
      lensed[i] = true;
      core::log("split: the connector's end face holds its disk and the shoulder's two faces (ring " + std::to_string(i) + ")");
    }
    // Pair the corners in the rotation and direction of least total length.
    std::array<std::array<std::vector<int>, 4>, 4> path;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) path[a][b] = shortest_path(N.mesh, local.at(end_corners[0][a]), local.at(end_corners[1][b]), blocked);
    auto length = [&](const std::vector<int>& pth) {
      if (pth.empty()) return std::numeric_limits<double>::infinity();
      double l = 0;
      for (std::size_t k = 1; k < pth.size(); ++k) {
        const auto& p = N.mesh.point(Mesh::Vertex_index(pth[k])), &q = N.mesh.point(Mesh::Vertex_index(pth[k - 1]));
        l += std::sqrt(CGAL::squared_distance(p, q));
      }
      return l;
    };
    double best = std::numeric_limits<double>::infinity();
    std::array<int, 4> pair{};
    for (int rot = 0; rot < 4; ++rot)
      for (int dir : {1, 3}) {
        double total = 0;
        std::array<int, 4> pr{};
        for (int a = 0; a < 4; ++a) pr[a] = (rot + dir * a) % 4, total += length(path[a][pr[a]]);
        if (total < best) best = total, pair = pr;
      }
    if (!std::isfinite(best)) throw core::TopologyError("split: the corners of the two disks are not joined across the neck");
    std::array<std::vector<int>, 2> rim_local, outline_local;
    for (int i = 0; i < 2; ++i) {
      for (int v : rim[i]) rim_local[i].push_back(local.at(v));
      for (int v : outline[i]) outline_local[i].push_back(local.at(v));
    }
    std::array<std::array<int, 4>, 2> corner_local{};
    for (int k = 0; k < 4; ++k) corner_local[0][k] = local.at(end_corners[0][k]), corner_local[1][k] = local.at(end_corners[1][pair[k]]);
    std::vector<char> is_corner(static_cast<std::size_t>(nn), 0), is_tip(static_cast<std::size_t>(nn), 0);
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 4; ++k) {
        is_corner[static_cast<std::size_t>(corner_local[i][k])] = 1;
        if (lensed[i]) is_tip[static_cast<std::size_t>(local.at(disk_corners[i][k]))] = 1;
      }
    std::set<Edge> cuts = lens_cuts;
    for (const auto& loop : rim_local)
      for (std::size_t k = 0; k < loop.size(); ++k) cuts.insert(edge(loop[k], loop[(k + 1) % loop.size()]));
    // The side curves: level sets across the neck, which leave the rims across them; the shortest
    // edge paths of the coarse eight left one corner at 21° to its rim, and that corner's element
    // could not pass a scaled Jacobian of 0.09 (docs/status.md, session 17). Not through the
    // fills or the lenses (a lens: a region of the rims and convex curves without fill faces,
    // bounded by a concave curve and its convex one only).
    std::vector<char> neck_faces(N.mesh.number_of_faces(), 1), lens_face(N.mesh.number_of_faces(), 0);
    for (std::size_t x = 0; x < N.layout_triangle.size(); ++x) neck_faces[x] = all_fill.count(N.layout_triangle[x]) ? 0 : 1;
    if (lensed[0] || lensed[1]) {
      std::set<int> on_lens_curves;  // the convex curves and the rims' concave curves
      for (const auto& [a, b] : lens_cuts) on_lens_curves.insert(a), on_lens_curves.insert(b);
      for (int i = 0; i < 2; ++i)
        if (lensed[i])
          for (const auto& a : shoulder_of(i).concave)
            for (const int v : a) on_lens_curves.insert(local.at(v));
      int lenses = 0;
      for (const Region& r : regions(N.mesh, cuts, nullptr)) {
        bool lens = r.loops.size() == 1;
        for (const int x : r.faces) lens &= neck_faces[static_cast<std::size_t>(x)] == 1;
        for (const auto& loop : r.loops)
          for (const int v : loop) lens &= on_lens_curves.count(v) > 0 || is_tip[static_cast<std::size_t>(v)];
        if (!lens) continue;
        ++lenses;
        for (const int x : r.faces) neck_faces[static_cast<std::size_t>(x)] = 0, lens_face[static_cast<std::size_t>(x)] = 1;
      }
      if (lenses != 2 * (lensed[0] + lensed[1]))
        throw core::TopologyError("split: a shoulder's faces are not two lenses between its concave and convex curves (" + std::to_string(lenses) + " found)");
    }
    if (!neck_side_isolines(N, neck_faces, outline_local, corner_local, &cuts)) {
      core::log_warning("split: the neck's side level sets are not four curves from disk to disk; using shortest edge paths");
      for (int a = 0; a < 4; ++a) {  // one after the other, each avoiding the ones before
        const std::vector<int> pth = shortest_path(N.mesh, corner_local[0][a], corner_local[1][a], blocked);
        if (pth.empty()) throw core::TopologyError("split: the neck's side curves cross; the disks' corners do not match");
        for (std::size_t k = 1; k < pth.size(); ++k) cuts.insert(edge(pth[k - 1], pth[k]));
        for (std::size_t k = 1; k + 1 < pth.size(); ++k) blocked[static_cast<std::size_t>(pth[k])] = 1;
      }
    }
    is_corner.resize(N.mesh.number_of_vertices(), 0);
    // Vertices the side curves added: appended to the layout.
    std::vector<int> neck_vertex(N.layout_vertex);
    for (std::size_t v = N.layout_vertex.size(); v < N.mesh.number_of_vertices(); ++v) {
      const auto& q = N.mesh.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(v)));
      neck_vertex.push_back(static_cast<int>(d.layout.points.size()));
      d.layout.points.push_back({q.x(), q.y(), q.z()});
    }
    std::vector<int> face_region;
    const auto regs = regions(N.mesh, cuts, &face_region);
    const std::size_t lens_count = 2 * static_cast<std::size_t>(lensed[0] + lensed[1]);
    if (regs.size() != 6 + lens_count)
      throw core::TopologyError("split: the neck is cut into " + std::to_string(regs.size()) + " patches, not the six faces of a cube" +
                                (lens_count ? " with " + std::to_string(lens_count) + " shoulder faces" : std::string()));
    Component C;
    C.type = ComponentType::cube;
    neck_component = static_cast<int>(d.components.size());
    // A lensed end's disk and lenses have the tips as corners; the side patches pass through them.
    std::vector<char> with_tips = is_corner;
    for (std::size_t v = 0; v < is_tip.size(); ++v) with_tips[v] |= is_tip[v];
    with_tips.resize(N.mesh.number_of_vertices(), 0);
    std::array<CubeFace, 2> end_face;  // per lensed end: its disk and lenses
    for (std::size_t r = 0; r < regs.size(); ++r) {
      const int x0 = regs[r].faces.front();
      const bool lens = x0 < static_cast<int>(lens_face.size()) && lens_face[static_cast<std::size_t>(x0)];
      const int lt0 = x0 < static_cast<int>(N.layout_triangle.size()) ? N.layout_triangle[static_cast<std::size_t>(x0)] : -1;
      const bool fill_region = lt0 >= 0 && all_fill.count(lt0) > 0;
      const int end = fill_region ? (std::count(fill[0].begin(), fill[0].end(), lt0) ? 0 : 1) : -1;
      const bool tips = lens || (end >= 0 && lensed[static_cast<std::size_t>(end)]);
      Patch P = quad_patch(regs[r], tips ? with_tips : is_corner, "neck patch", static_cast<int>(r));
      int lens_end = -1;
      if (lens)
        for (int i = 0; i < 2; ++i)
          for (const int v : P.corners)
            if (lensed[i] && std::count(disk_corners[i].begin(), disk_corners[i].end(), N.layout_vertex.at(static_cast<std::size_t>(v)))) lens_end = i;
      bool disk = false;
      for (int& x : P.triangles) {
        // Fill faces are never cut (masked), so they keep their index; other faces may be new.
        const int lt = x < static_cast<int>(N.layout_triangle.size()) ? N.layout_triangle[static_cast<std::size_t>(x)] : -1;
        if (lt >= 0 && all_fill.count(lt)) {
          disk = true;
          x = -1 - lt;  // resolved with the disks below
        } else {
          std::array<int, 3> tri{};
          int j = 0;
          for (const auto v : CGAL::vertices_around_face(N.mesh.halfedge(Mesh::Face_index(static_cast<Mesh::size_type>(x))), N.mesh))
            tri[static_cast<std::size_t>(j++)] = neck_vertex[static_cast<std::size_t>(v)];
          x = static_cast<int>(d.layout.triangles.size());
          d.layout.triangles.push_back(tri);
          d.layout.filled.push_back(0);
        }
      }
      for (int& v : P.corners) v = neck_vertex[static_cast<std::size_t>(v)];
      for (auto& sd : P.sides)
        for (int& v : sd) v = neck_vertex[static_cast<std::size_t>(v)];
      const int id = static_cast<int>(d.layout.patches.size());
      if (disk) {
        const int lt = -1 - P.triangles[0];
        (std::count(fill[0].begin(), fill[0].end(), lt) ? neck_bottom : neck_top) = id;
      }
      C.patches.push_back(id);
      const int joins = lens ? lens_end : end >= 0 && lensed[static_cast<std::size_t>(end)] ? end : -1;
      if (joins >= 0) {
        end_face[static_cast<std::size_t>(joins)].patches.push_back(id);
      } else {
        CubeFace F;
        F.patches = {id};
        F.corners = P.corners;
        C.faces.push_back(F);
      }
      d.layout.patches.push_back(std::move(P));
    }
    // A lensed end face: its corners in the order of its disk's (counter-clockwise from outside).
    for (int i = 0; i < 2; ++i) {
      if (!lensed[i]) continue;
      CubeFace& F = end_face[static_cast<std::size_t>(i)];
      if (F.patches.size() != 3) throw core::TopologyError("split: the connector's end face on ring " + std::to_string(i) + " is not its disk and two lenses");
      const Patch* disk = nullptr;
      for (const int id : F.patches)
        if (d.layout.patches[static_cast<std::size_t>(id)].triangles[0] < 0) disk = &d.layout.patches[static_cast<std::size_t>(id)];
      if (!disk) throw std::logic_error("split: a lensed end face without its disk");
      F.corners = in_loop_order(outline[i], disk->corners, end_corners[i]);
      C.faces.push_back(F);
    }
    d.components.push_back(std::move(C));
  }
  // The disks' triangles, once, at the end; patch references resolved.
  std::map<int, int> disk_index;
  for (int t : all_fill) {
    disk_index[t] = static_cast<int>(d.layout.triangles.size());
    d.layout.triangles.push_back(L.triangles[static_cast<std::size_t>(t)]);
    d.layout.filled.push_back(1);
  }
  for (auto& P : d.layout.patches) {
    for (int& x : P.triangles)
      if (x < 0) x = disk_index.at(-1 - x);
    std::sort(P.triangles.begin(), P.triangles.end());
  }
  if (disk_patch[0] < 0 || disk_patch[1] < 0) throw std::logic_error("split: a disk is in no patch");
  if (connector) {
    if (neck_bottom < 0 || neck_top < 0) throw std::logic_error("split: the neck has no disk faces");
    d.contacts.push_back({disk_component[0], neck_component, "filled_patch", disk_patch[0]});
    d.contacts.push_back({neck_component, disk_component[1], "filled_patch", neck_top});
  } else {
    d.contacts.push_back({disk_component[0], disk_component[1], "filled_patch", disk_patch[0]});
  }
  d.quad_patches = static_cast<int>(d.layout.patches.size());
  return d;
}

}  // namespace volts::split::detail
