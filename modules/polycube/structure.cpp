#include "polycube/structure.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <sstream>
#include <utility>

#include "core/errors.h"
#include "viz/viz.h"

namespace volts::polycube {

namespace {

using core::TopologyError;

std::array<int, 2> face_axes(int face) { return {(face / 2 + 1) % 3, (face / 2 + 2) % 3}; }
double plane(const Box& b, int face) { return face % 2 ? b.hi[face / 2] : b.lo[face / 2]; }

std::string num(double x) {
  std::ostringstream o;
  o.precision(17);
  o << x;
  return o.str();
}
std::string cube_name(const Structure& s, int c) { return "cube '" + s.cubes[c].label + "'"; }
std::string primitive_name(const Structure& s, int p) {
  return (s.primitives[p].torus ? "torus '" : "cube '") + s.primitives[p].label + "'";
}
std::string virtual_name(const Structure& s, int v) { return "virtual component '" + s.virtual_components[v].label + "'"; }
std::string map_text(const AxisMap& m) {
  std::string t = "{axis";
  for (int k = 0; k < 3; ++k) t += " " + std::to_string(m.axis[k]);
  t += ", scale";
  for (double x : m.scale) t += " " + num(x);
  t += ", offset";
  for (double x : m.offset) t += " " + num(x);
  return t + "}";
}

bool valid_box(const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (!(std::isfinite(b.lo[k]) && std::isfinite(b.hi[k]) && b.lo[k] < b.hi[k])) return false;
  return true;
}
bool valid_map(const AxisMap& m) {
  std::array<bool, 3> seen{};
  for (int k = 0; k < 3; ++k) {
    if (m.axis[k] < 0 || m.axis[k] > 2 || seen[m.axis[k]]) return false;
    seen[m.axis[k]] = true;
    if (!std::isfinite(m.scale[k]) || m.scale[k] == 0 || !std::isfinite(m.offset[k])) return false;
  }
  return true;
}
// Sign of the determinant of a valid map: permutation parity times the scales' signs.
int det_sign(const AxisMap& m) {
  int sign = 1;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (m.axis[i] > m.axis[j]) sign = -sign;
  for (double x : m.scale)
    if (x < 0) sign = -sign;
  return sign;
}
bool linear_identity(const AxisMap& m) { return m.axis == std::array<int, 3>{0, 1, 2} && m.scale == Point{1, 1, 1}; }
bool identity(const AxisMap& m) { return linear_identity(m) && m.offset == Point{0, 0, 0}; }

// The largest coordinate or extent of the boxes: the scale StructureParams::near_rel refers to.
double tolerance(const std::vector<Box>& boxes, const StructureParams& params) {
  double size = 0;
  for (const auto& b : boxes)
    for (int k = 0; k < 3; ++k) size = std::max({size, std::abs(b.lo[k]), std::abs(b.hi[k]), b.hi[k] - b.lo[k]});
  return params.near_rel * (size > 0 ? size : 1.0);
}
std::vector<Box> cube_boxes(const Structure& s) {
  std::vector<Box> boxes;
  for (const auto& c : s.cubes) boxes.push_back(c.box);
  return boxes;
}

// Equal, or clearly apart: an almost-equal pair would decide topology by rounding.
void not_almost(double a, double b, double tol, const std::string& who) {
  if (a != b && std::abs(a - b) <= tol)
    throw TopologyError(who + ": coordinates " + num(a) + " and " + num(b) +
                        " almost coincide; polycube coordinates must be equal or clearly apart (lattice values)");
}
// Boxes within tol of each other: only their coordinates can form slivers or near-contacts.
bool near_boxes(const Box& a, const Box& b, double tol) {
  for (int k = 0; k < 3; ++k)
    if (a.lo[k] > b.hi[k] + tol || b.lo[k] > a.hi[k] + tol) return false;
  return true;
}
void not_almost(const Box& a, const Box& b, double tol, const std::string& who) {
  if (!near_boxes(a, b, tol)) return;
  for (int k = 0; k < 3; ++k)
    for (double x : {a.lo[k], a.hi[k]})
      for (double y : {b.lo[k], b.hi[k]}) not_almost(x, y, tol, who);
}
bool overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (std::max(a.lo[k], b.lo[k]) >= std::min(a.hi[k], b.hi[k])) return false;
  return true;
}
bool inside(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.lo[k] < b.lo[k] || a.hi[k] > b.hi[k]) return false;
  return true;
}

// The flat box of a face rectangle: the face's plane along its axis, the rectangle across.
Box face_box(const Box& b, int face, const Rect& r) {
  const auto [u, v] = face_axes(face);
  Box f;
  f.lo[face / 2] = f.hi[face / 2] = plane(b, face);
  f.lo[u] = r.lo[0], f.hi[u] = r.hi[0], f.lo[v] = r.lo[1], f.hi[v] = r.hi[1];
  return f;
}
Rect rect_of(const Box& flat, int face) {
  const auto [u, v] = face_axes(face);
  return Rect{{flat.lo[u], flat.lo[v]}, {flat.hi[u], flat.hi[v]}};
}
// b's glued rectangle: the image of a's.
Rect image_rect(const Structure& s, const Gluing& g) {
  return rect_of(apply(g.map, face_box(s.cubes[g.a].box, g.fa, g.rect_a)), g.fb);
}

// A face (or rectangle) cut by the bounds of `rects` into grid cells; each cell lists the rects
// that cover it. Cell (i, j) spans [s[i], s[i+1]] x [t[j], t[j+1]]; exact: no arithmetic but
// midpoints.
struct Grid {
  std::vector<double> s, t;
  std::vector<std::vector<int>> cover;  // index i * (t.size() - 1) + j
  Rect cell(int i, int j) const { return Rect{{s[i], t[j]}, {s[i + 1], t[j + 1]}}; }
};
Grid grid_cells(const Rect& whole, const std::vector<Rect>& rects) {
  Grid g;
  for (int d = 0; d < 2; ++d) {
    auto& cuts = d == 0 ? g.s : g.t;
    cuts = {whole.lo[d], whole.hi[d]};
    for (const auto& r : rects)
      for (double x : {r.lo[d], r.hi[d]})
        if (x > whole.lo[d] && x < whole.hi[d]) cuts.push_back(x);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  }
  for (std::size_t i = 0; i + 1 < g.s.size(); ++i)
    for (std::size_t j = 0; j + 1 < g.t.size(); ++j) {
      const double ms = (g.s[i] + g.s[i + 1]) / 2, mt = (g.t[j] + g.t[j + 1]) / 2;
      std::vector<int> c;
      for (std::size_t k = 0; k < rects.size(); ++k)
        if (rects[k].lo[0] < ms && ms < rects[k].hi[0] && rects[k].lo[1] < mt && mt < rects[k].hi[1]) c.push_back(static_cast<int>(k));
      g.cover.push_back(std::move(c));
    }
  return g;
}
// Grid cells with equal labels merged into maximal runs along t, then runs across s.
template <class L>
std::vector<std::pair<Rect, L>> merge_cells(const Grid& g, const std::vector<L>& label) {
  std::vector<std::pair<Rect, L>> out;
  std::vector<std::size_t> open;  // rects that reach the current column
  const int nt = static_cast<int>(g.t.size()) - 1;
  for (int i = 0; i + 1 < static_cast<int>(g.s.size()); ++i) {
    std::vector<std::size_t> next;
    for (int j = 0; j < nt;) {
      int e = j + 1;
      while (e < nt && label[i * nt + e] == label[i * nt + j]) ++e;
      const Rect run{{g.s[i], g.t[j]}, {g.s[i + 1], g.t[e]}};
      const L& l = label[i * nt + j];
      auto it = std::find_if(open.begin(), open.end(), [&](std::size_t r) {
        return out[r].first.lo[1] == run.lo[1] && out[r].first.hi[1] == run.hi[1] && out[r].second == l;
      });
      if (it != open.end()) {
        out[*it].first.hi[0] = run.hi[0];
        next.push_back(*it);
      } else {
        next.push_back(out.size());
        out.emplace_back(run, l);
      }
      j = e;
    }
    open = std::move(next);
  }
  return out;
}

void check_index(const Structure& s, int c, const std::string& who) {
  if (c < 0 || c >= static_cast<int>(s.cubes.size())) throw TopologyError(who + ": no cube " + std::to_string(c));
}

void validate_gluing(const Structure& s, const Gluing& g, double tol) {
  check_index(s, g.a, "gluing");
  check_index(s, g.b, "gluing");
  const std::string who = "gluing of " + cube_name(s, g.a) + " face " + std::to_string(g.fa) + " to " + cube_name(s, g.b) + " face " +
                          std::to_string(g.fb);
  if (g.a == g.b) throw TopologyError(who + ": a cube cannot be glued to itself (a torus is four cubes)");
  if (g.fa < 0 || g.fa > 5 || g.fb < 0 || g.fb > 5) throw TopologyError(who + ": faces are 0..5");
  if (!valid_map(g.map)) throw TopologyError(who + ": map " + map_text(g.map) + " is not a signed axis permutation with nonzero scales");
  if (det_sign(g.map) < 0) throw TopologyError(who + ": map " + map_text(g.map) + " mirrors (det < 0)");
  const int ax_a = g.fa / 2, ax_b = g.fb / 2;
  if (g.map.axis[ax_b] != ax_a) throw TopologyError(who + ": map " + map_text(g.map) + " does not take the face normals onto each other");
  const Box& A = s.cubes[g.a].box;
  const Box& B = s.cubes[g.b].box;
  const double at = g.map.scale[ax_b] * plane(A, g.fa) + g.map.offset[ax_b];
  not_almost(at, plane(B, g.fb), tol, who);
  if (at != plane(B, g.fb))
    throw TopologyError(who + ": map " + map_text(g.map) + " takes the face plane to " + num(at) + ", not to " + num(plane(B, g.fb)));
  // a's inward direction must become b's outward one: the cubes lie on either side of the face.
  const int inward_a = g.fa % 2 ? -1 : 1, outward_b = g.fb % 2 ? 1 : -1;
  if (inward_a * (g.map.scale[ax_b] > 0 ? 1 : -1) != outward_b) throw TopologyError(who + ": map puts both cubes on the same side");
  for (const auto& [r, box, face] : {std::tuple{g.rect_a, A, g.fa}, std::tuple{image_rect(s, g), B, g.fb}}) {
    const Rect f = face_rect(box, face);
    for (int d = 0; d < 2; ++d) {
      for (double x : {r.lo[d], r.hi[d]})
        for (double y : {f.lo[d], f.hi[d], r.lo[d] == x ? r.hi[d] : r.lo[d]}) not_almost(x, y, tol, who);
      if (!(r.lo[d] < r.hi[d] && r.lo[d] >= f.lo[d] && r.hi[d] <= f.hi[d]))
        throw TopologyError(who + ": glued rectangle is empty or not inside its face");
    }
  }
}

// Adds gluings, then re-derives the faces they touch: a face rectangle glued twice undoes them.
std::vector<int> add_gluings(Structure& s, const std::vector<Gluing>& gs, double tol) {
  const std::size_t before = s.gluings.size();
  try {
    for (const auto& g : gs) {
      validate_gluing(s, g, tol);
      s.gluings.push_back(g);
    }
    for (const auto& g : gs) {
      boundary_regions(s, g.a);
      boundary_regions(s, g.b);
    }
  } catch (...) {
    s.gluings.resize(before);
    throw;
  }
  std::vector<int> ids;
  for (std::size_t i = before; i < s.gluings.size(); ++i) ids.push_back(static_cast<int>(i));
  return ids;
}

void check_box(const Box& b, const std::string& who) {
  if (!valid_box(b)) throw TopologyError(who + ": box is empty or not finite (lo < hi on every axis)");
}

// How many pieces are left of the box `host` without `removed` (face-connected cells of the grid
// their coordinates cut it into).
int remaining_pieces(const Box& host, const std::vector<Box>& removed) {
  std::array<std::vector<double>, 3> cuts;
  for (int k = 0; k < 3; ++k) {
    cuts[k] = {host.lo[k], host.hi[k]};
    for (const auto& b : removed)
      for (double x : {b.lo[k], b.hi[k]})
        if (x > host.lo[k] && x < host.hi[k]) cuts[k].push_back(x);
    std::sort(cuts[k].begin(), cuts[k].end());
    cuts[k].erase(std::unique(cuts[k].begin(), cuts[k].end()), cuts[k].end());
  }
  const int n0 = static_cast<int>(cuts[0].size()) - 1, n1 = static_cast<int>(cuts[1].size()) - 1, n2 = static_cast<int>(cuts[2].size()) - 1;
  auto id = [&](int i, int j, int k) { return (i * n1 + j) * n2 + k; };
  std::vector<int> part(static_cast<std::size_t>(n0 * n1 * n2), -1);  // -1 kept, -2 removed
  for (int i = 0; i < n0; ++i)
    for (int j = 0; j < n1; ++j)
      for (int k = 0; k < n2; ++k) {
        const Point m{(cuts[0][i] + cuts[0][i + 1]) / 2, (cuts[1][j] + cuts[1][j + 1]) / 2, (cuts[2][k] + cuts[2][k + 1]) / 2};
        for (const auto& b : removed)
          if (b.lo[0] < m[0] && m[0] < b.hi[0] && b.lo[1] < m[1] && m[1] < b.hi[1] && b.lo[2] < m[2] && m[2] < b.hi[2]) part[id(i, j, k)] = -2;
      }
  int parts = 0;
  for (int i = 0; i < n0; ++i)
    for (int j = 0; j < n1; ++j)
      for (int k = 0; k < n2; ++k) {
        if (part[id(i, j, k)] != -1) continue;
        std::deque<std::array<int, 3>> queue{{i, j, k}};
        part[id(i, j, k)] = parts;
        while (!queue.empty()) {
          const auto c = queue.front();
          queue.pop_front();
          for (int d = 0; d < 3; ++d)
            for (int step : {-1, 1}) {
              auto n = c;
              n[d] += step;
              if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= n0 || n[1] >= n1 || n[2] >= n2 || part[id(n[0], n[1], n[2])] != -1) continue;
              part[id(n[0], n[1], n[2])] = parts;
              queue.push_back(n);
            }
        }
        ++parts;
      }
  return parts;
}

void check_virtual(const Structure& s, int v, double tol) {
  const VirtualComponent& vc = s.virtual_components[v];
  check_index(s, vc.cube, virtual_name(s, v));
  const std::string who = virtual_name(s, v) + " of " + cube_name(s, vc.cube);
  const Box& host = s.cubes[vc.cube].box;
  if (vc.boxes.empty()) throw TopologyError(who + ": no box");
  std::vector<Box> all;  // every virtual box of the host
  for (const auto& w : s.virtual_components)
    if (w.cube == vc.cube) all.insert(all.end(), w.boxes.begin(), w.boxes.end());
  for (std::size_t k = 0; k < vc.boxes.size(); ++k) {
    const Box& b = vc.boxes[k];
    check_box(b, who);
    not_almost(b, host, tol, who);
    if (!inside(b, host)) throw TopologyError(who + ": box " + std::to_string(k) + " is not inside the cube");
  }
  for (std::size_t w = 0; w < s.virtual_components.size(); ++w) {
    const VirtualComponent& other = s.virtual_components[w];
    if (other.cube != vc.cube) continue;
    for (std::size_t k = 0; k < vc.boxes.size(); ++k)
      for (std::size_t l = 0; l < other.boxes.size(); ++l) {
        if (static_cast<int>(w) == v && l == k) continue;
        const std::string pair = who + " and " + virtual_name(s, static_cast<int>(w));
        not_almost(vc.boxes[k], other.boxes[l], tol, pair);
        if (overlap(vc.boxes[k], other.boxes[l])) throw TopologyError(pair + ": boxes overlap");
      }
  }
  const int parts = remaining_pieces(host, all);
  if (parts == 0) throw TopologyError(who + ": removes all of the cube");
  if (parts > 1) throw TopologyError(who + ": cuts the cube into " + std::to_string(parts) + " pieces (a cube must stay one piece)");
}

// The development: per cube its map to its part's frame, its part, and the tree edge it was
// reached by (gluing, parent), for naming the cubes of a cycle.
struct Development {
  std::vector<AxisMap> map;
  std::vector<int> part, parent, via, depth;
};
Development development(const Structure& s) {
  const int n = static_cast<int>(s.cubes.size());
  Development d{std::vector<AxisMap>(n), std::vector<int>(n, -1), std::vector<int>(n, -1), std::vector<int>(n, -1), std::vector<int>(n, 0)};
  std::vector<std::vector<int>> adjacent(n);
  for (std::size_t g = 0; g < s.gluings.size(); ++g) {
    const Gluing& x = s.gluings[g];
    if (x.closes_torus >= 0 || !valid_map(x.map) || x.a < 0 || x.b < 0 || x.a >= n || x.b >= n || x.a == x.b) continue;
    adjacent[x.a].push_back(static_cast<int>(g));
    adjacent[x.b].push_back(static_cast<int>(g));
  }
  int parts = 0;
  for (int root = 0; root < n; ++root) {
    if (d.part[root] >= 0) continue;
    d.part[root] = parts;
    std::deque<int> queue{root};
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      for (int g : adjacent[c]) {
        const Gluing& x = s.gluings[g];
        const int o = x.a == c ? x.b : x.a;
        if (d.part[o] >= 0) continue;
        // D_b ∘ T = D_a on the glued face.
        d.map[o] = x.a == c ? compose(d.map[c], inverse(x.map)) : compose(d.map[c], x.map);
        d.part[o] = parts, d.parent[o] = c, d.via[o] = g, d.depth[o] = d.depth[c] + 1;
        queue.push_back(o);
      }
    }
    ++parts;
  }
  return d;
}
// The cubes of the cycle a tree path a..b closes with gluing a-b.
std::string cycle_names(const Structure& s, const Development& d, int a, int b) {
  std::vector<int> left{a}, right{b};
  while (left.back() != right.back()) {
    if (d.depth[left.back()] >= d.depth[right.back()])
      left.push_back(d.parent[left.back()]);
    else
      right.push_back(d.parent[right.back()]);
  }
  right.pop_back();
  left.insert(left.end(), right.rbegin(), right.rend());
  std::string t;
  for (int c : left) t += (t.empty() ? "" : ", ") + ("'" + s.cubes[c].label + "'");
  return t;
}

std::string contact_name(const Structure& s, std::size_t k) {
  const Contact& x = s.contacts[k];
  const auto cube = [&](int c) { return c >= 0 && c < static_cast<int>(s.cubes.size()) ? cube_name(s, c) : "cube " + std::to_string(c); };
  return "contact '" + x.label + "' of " + cube(x.a) + " face " + std::to_string(x.fa) + " with " + cube(x.b) + " face " + std::to_string(x.fb);
}

// A contact's references, and that both its faces hold boundary (a contact lies on the solid's
// boundary, where neither cube is glued or opened).
void check_contact_record(const Structure& s, std::size_t k) {
  const Contact& x = s.contacts[k];
  const std::string who = contact_name(s, k);
  check_index(s, x.a, who);
  check_index(s, x.b, who);
  if (x.a == x.b) throw TopologyError(who + ": a cube cannot touch itself");
  if (x.fa < 0 || x.fa > 5 || x.fb < 0 || x.fb > 5) throw TopologyError(who + ": faces are 0..5");
  for (const auto& [c, f] : {std::pair{x.a, x.fa}, std::pair{x.b, x.fb}}) {
    const auto regions = boundary_regions(s, c);
    if (std::none_of(regions.begin(), regions.end(), [f = f](const FaceRegion& r) { return r.face == f && r.kind == RegionKind::boundary; }))
      throw TopologyError(who + ": face " + std::to_string(f) + " of " + cube_name(s, c) +
                          " holds no boundary (glued or opened all over); a contact lies on the solid's boundary");
  }
}

void check_references(const Structure& s) {
  const int n = static_cast<int>(s.cubes.size()), np = static_cast<int>(s.primitives.size());
  for (int c = 0; c < n; ++c) {
    check_box(s.cubes[c].box, cube_name(s, c));
    const int p = s.cubes[c].primitive;
    if (p < 0 || p >= np || std::count(s.primitives[p].cubes.begin(), s.primitives[p].cubes.end(), c) != 1)
      throw TopologyError(cube_name(s, c) + ": its primitive " + std::to_string(p) + " does not list it once");
  }
  for (int p = 0; p < np; ++p) {
    const Primitive& q = s.primitives[p];
    if (q.torus ? q.cubes.size() < 4 : q.cubes.size() != 1)
      throw TopologyError(primitive_name(s, p) + ": has " + std::to_string(q.cubes.size()) + " cubes" + (q.torus ? " (a torus needs at least 4)" : ""));
    for (int c : q.cubes) {
      check_index(s, c, primitive_name(s, p));
      if (s.cubes[c].primitive != p) throw TopologyError(primitive_name(s, p) + ": lists " + cube_name(s, c) + " of another primitive");
    }
  }
  for (const auto& g : s.gluings)
    if (g.closes_torus >= np || g.closes_torus < -1 || (g.closes_torus >= 0 && !s.primitives[g.closes_torus].torus))
      throw TopologyError("gluing closes primitive " + std::to_string(g.closes_torus) + ", not a torus");
}

// A torus: n >= 4 cubes, consecutive ones glued on whole faces, the ring closed by one gluing.
void check_torus(const Structure& s, int p) {
  const auto& cubes = s.primitives[p].cubes;
  const int n = static_cast<int>(cubes.size());
  const std::string who = primitive_name(s, p);
  std::string closing;
  int closings = 0;
  for (const auto& g : s.gluings)
    if (g.closes_torus == p) closing += std::string(closings++ ? ", " : "") + "'" + s.cubes[g.a].label + "' to '" + s.cubes[g.b].label + "'";
  if (closings != 1) throw TopologyError(who + ": " + std::to_string(closings) + " gluings close its ring (needs one)" + (closings ? ": " + closing : ""));
  for (int i = 0; i < n; ++i) {
    const int a = cubes[i], b = cubes[(i + 1) % n];
    const bool closes = i == n - 1;
    const bool whole = std::any_of(s.gluings.begin(), s.gluings.end(), [&](const Gluing& g) {
      if ((g.closes_torus == p) != closes || !((g.a == a && g.b == b) || (g.a == b && g.b == a))) return false;
      const Rect fa = face_rect(s.cubes[g.a].box, g.fa), fb = face_rect(s.cubes[g.b].box, g.fb), rb = image_rect(s, g);
      return g.rect_a.lo == fa.lo && g.rect_a.hi == fa.hi && rb.lo == fb.lo && rb.hi == fb.hi;
    });
    if (!whole)
      throw TopologyError(who + ": " + cube_name(s, a) + " and " + cube_name(s, b) + " are not glued on whole faces" +
                          (closes ? " by the ring's closing gluing" : ""));
  }
}

// Developed cubes i and j touch on a face: it must be glued there.
void check_contact(const Structure& s, const Development& d, int i, int j, const Box& A, const Box& B) {
  for (int ax = 0; ax < 3; ++ax) {
    int face = -1;
    if (A.hi[ax] == B.lo[ax]) face = 2 * ax + 1;
    if (A.lo[ax] == B.hi[ax]) face = 2 * ax;
    if (face < 0) continue;
    Box contact;
    contact.lo[ax] = contact.hi[ax] = plane(A, face);
    bool area = true;
    for (int k : face_axes(face)) {
      contact.lo[k] = std::max(A.lo[k], B.lo[k]), contact.hi[k] = std::min(A.hi[k], B.hi[k]);
      area = area && contact.lo[k] < contact.hi[k];
    }
    if (!area) continue;
    std::vector<Rect> glued;
    for (const auto& g : s.gluings)
      if (g.closes_torus < 0 && ((g.a == i && g.b == j) || (g.a == j && g.b == i)))
        glued.push_back(rect_of(apply(d.map[g.a], face_box(s.cubes[g.a].box, g.fa, g.rect_a)), face));
    const Grid grid = grid_cells(rect_of(contact, face), glued);
    for (const auto& c : grid.cover)
      if (c.empty())
        throw TopologyError(cube_name(s, i) + " and " + cube_name(s, j) + " touch on a face but are not glued there (a crack)");
  }
}

}  // namespace

Point apply(const AxisMap& m, const Point& x) {
  Point y;
  for (int k = 0; k < 3; ++k) y[k] = m.scale[k] * x[m.axis[k]] + m.offset[k];
  return y;
}

Box apply(const AxisMap& m, const Box& b) {
  const Point p = apply(m, b.lo), q = apply(m, b.hi);
  Box r;
  for (int k = 0; k < 3; ++k) r.lo[k] = std::min(p[k], q[k]), r.hi[k] = std::max(p[k], q[k]);
  return r;
}

AxisMap compose(const AxisMap& outer, const AxisMap& inner) {
  AxisMap m;
  for (int k = 0; k < 3; ++k) {
    const int j = outer.axis[k];
    m.axis[k] = inner.axis[j];
    m.scale[k] = outer.scale[k] * inner.scale[j];
    m.offset[k] = outer.scale[k] * inner.offset[j] + outer.offset[k];
  }
  return m;
}

AxisMap inverse(const AxisMap& m) {
  AxisMap r;
  for (int k = 0; k < 3; ++k) {
    const int j = m.axis[k];
    r.axis[j] = k;
    r.scale[j] = 1 / m.scale[k];
    r.offset[j] = -m.offset[k] / m.scale[k];
  }
  return r;
}

Rect face_rect(const Box& b, int face) {
  const auto [u, v] = face_axes(face);
  return Rect{{b.lo[u], b.lo[v]}, {b.hi[u], b.hi[v]}};
}

int map_face(const AxisMap& m, int face) {
  const int k = static_cast<int>(std::find(m.axis.begin(), m.axis.end(), face / 2) - m.axis.begin());
  return 2 * k + ((face % 2) ^ (m.scale[k] < 0 ? 1 : 0));
}

int add_cube(Structure& s, const std::string& label, const Box& box) {
  check_box(box, "cube '" + label + "'");
  const int p = static_cast<int>(s.primitives.size());
  s.primitives.push_back(Primitive{label, false, {static_cast<int>(s.cubes.size())}});
  s.cubes.push_back(Cube{label, box, p});
  return p;
}

int add_torus(Structure& s, const std::string& label, const Box& first, int ring_axis, int cubes) {
  check_box(first, "torus '" + label + "'");
  if (ring_axis < 0 || ring_axis > 2) throw TopologyError("torus '" + label + "': ring axis must be 0, 1 or 2");
  if (cubes < 4) throw TopologyError("torus '" + label + "': a ring of " + std::to_string(cubes) + " cubes; a torus needs at least 4");
  const int p = static_cast<int>(s.primitives.size()), c0 = static_cast<int>(s.cubes.size());
  const double lo = first.lo[ring_axis], w = first.hi[ring_axis] - lo;
  s.primitives.push_back(Primitive{label, true, {}});
  for (int i = 0; i < cubes; ++i) {
    Box b = first;
    b.lo[ring_axis] = lo + i * w, b.hi[ring_axis] = lo + (i + 1) * w;
    s.primitives[p].cubes.push_back(c0 + i);
    s.cubes.push_back(Cube{label + "/" + std::to_string(i), b, p});
  }
  const int hi_face = 2 * ring_axis + 1, lo_face = 2 * ring_axis;
  std::vector<Gluing> gs;
  for (int i = 0; i < cubes; ++i) {
    Gluing g{c0 + i, hi_face, c0 + (i + 1) % cubes, lo_face, face_rect(s.cubes[c0 + i].box, hi_face), AxisMap{}, -1};
    if (i == cubes - 1) {
      g.map.offset[ring_axis] = lo - s.cubes[c0 + i].box.hi[ring_axis];  // the period
      g.closes_torus = p;
    }
    gs.push_back(g);
  }
  add_gluings(s, gs, tolerance(cube_boxes(s), {}));
  return p;
}

std::vector<int> unite(Structure& s, int p, int q, const StructureParams& params) {
  const int np = static_cast<int>(s.primitives.size());
  if (p < 0 || q < 0 || p >= np || q >= np || p == q) throw TopologyError("unite: needs two different primitives");
  const std::string who = "union of " + primitive_name(s, p) + " and " + primitive_name(s, q);
  const double tol = tolerance(cube_boxes(s), params);
  std::vector<Gluing> gs;
  for (int a : s.primitives[p].cubes)
    for (int b : s.primitives[q].cubes) {
      const Box& A = s.cubes[a].box;
      const Box& B = s.cubes[b].box;
      const std::string pair = who + " (" + cube_name(s, a) + ", " + cube_name(s, b) + ")";
      not_almost(A, B, tol, pair);
      if (overlap(A, B)) throw TopologyError(pair + ": the cubes overlap");
      for (int ax = 0; ax < 3; ++ax) {
        const int face = A.hi[ax] == B.lo[ax] ? 2 * ax + 1 : A.lo[ax] == B.hi[ax] ? 2 * ax : -1;
        if (face < 0) continue;
        const Rect fa = face_rect(A, face), fb = face_rect(B, face ^ 1);
        Rect r;
        for (int d = 0; d < 2; ++d) r.lo[d] = std::max(fa.lo[d], fb.lo[d]), r.hi[d] = std::min(fa.hi[d], fb.hi[d]);
        if (r.lo[0] < r.hi[0] && r.lo[1] < r.hi[1]) gs.push_back(Gluing{a, face, b, face ^ 1, r, AxisMap{}, -1});
      }
    }
  if (gs.empty()) throw TopologyError(who + ": they share no face rectangle (their boxes must touch on a face of positive area in one frame)");
  return add_gluings(s, gs, tol);
}

int glue(Structure& s, int a, int fa, int b, int fb, const Rect& rect_a, const AxisMap& map, const StructureParams& params) {
  return add_gluings(s, {Gluing{a, fa, b, fb, rect_a, map, -1}}, tolerance(cube_boxes(s), params)).front();
}

int add_contact(Structure& s, const std::string& label, int a, int fa, int b, int fb) {
  s.contacts.push_back(Contact{label, a, fa, b, fb});
  try {
    check_contact_record(s, s.contacts.size() - 1);
  } catch (...) {
    s.contacts.pop_back();
    throw;
  }
  return static_cast<int>(s.contacts.size()) - 1;
}

int subtract(Structure& s, int cube, const std::string& label, const std::vector<Box>& boxes, const StructureParams& params) {
  check_index(s, cube, "virtual component '" + label + "'");
  const std::string who = "virtual component '" + label + "' of " + cube_name(s, cube);
  const Box& host = s.cubes[cube].box;
  VirtualComponent v{label, cube, {}, false};
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    check_box(boxes[k], who);
    Box c;
    for (int d = 0; d < 3; ++d) c.lo[d] = std::max(boxes[k].lo[d], host.lo[d]), c.hi[d] = std::min(boxes[k].hi[d], host.hi[d]);
    if (!valid_box(c)) throw TopologyError(who + ": box " + std::to_string(k) + " misses the cube");
    v.boxes.push_back(c);
  }
  s.virtual_components.push_back(std::move(v));
  try {
    check_virtual(s, static_cast<int>(s.virtual_components.size()) - 1, tolerance(cube_boxes(s), params));
  } catch (...) {
    s.virtual_components.pop_back();
    throw;
  }
  return static_cast<int>(s.virtual_components.size()) - 1;
}

int subtract_ring(Structure& s, int cube, const std::string& label, const Box& outer, const Box& inner, int axis,
                  const StructureParams& params) {
  if (axis < 0 || axis > 2) throw TopologyError("virtual component '" + label + "': ring axis must be 0, 1 or 2");
  check_box(outer, "virtual component '" + label + "'");
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  if (inner.lo[axis] != outer.lo[axis] || inner.hi[axis] != outer.hi[axis] || !(outer.lo[u] < inner.lo[u] && inner.lo[u] < inner.hi[u] &&
                                                                                 inner.hi[u] < outer.hi[u] && outer.lo[v] < inner.lo[v] &&
                                                                                 inner.lo[v] < inner.hi[v] && inner.hi[v] < outer.hi[v]))
    throw TopologyError("virtual component '" + label + "': the inner box must lie strictly inside the outer one across the ring axis");
  // A pinwheel: each box runs from one outer side to the next box, so the four tile the ring.
  auto box = [&](double u0, double u1, double v0, double v1) {
    Box b = outer;
    b.lo[u] = u0, b.hi[u] = u1, b.lo[v] = v0, b.hi[v] = v1;
    return b;
  };
  const std::vector<Box> ring{box(outer.lo[u], inner.hi[u], outer.lo[v], inner.lo[v]), box(inner.hi[u], outer.hi[u], outer.lo[v], inner.hi[v]),
                              box(inner.lo[u], outer.hi[u], inner.hi[v], outer.hi[v]), box(outer.lo[u], inner.lo[u], inner.lo[v], outer.hi[v])};
  const int id = subtract(s, cube, label, ring, params);
  s.virtual_components[id].torus = true;
  return id;
}

void reframe(Structure& s, int cube, const AxisMap& m) {
  check_index(s, cube, "reframe");
  if (!valid_map(m) || det_sign(m) < 0)
    throw TopologyError("reframe of " + cube_name(s, cube) + ": " + map_text(m) + " is not a signed axis permutation with nonzero scales and det > 0");
  const Box old = s.cubes[cube].box;
  const AxisMap back = inverse(m);
  for (auto& g : s.gluings) {
    if (g.a == cube) {
      const int f = map_face(m, g.fa);
      g.rect_a = rect_of(apply(m, face_box(old, g.fa, g.rect_a)), f);
      g.fa = f;
      g.map = compose(g.map, back);
    }
    if (g.b == cube) {
      g.fb = map_face(m, g.fb);
      g.map = compose(m, g.map);
    }
  }
  for (auto& v : s.virtual_components)
    if (v.cube == cube)
      for (auto& b : v.boxes) b = apply(m, b);
  s.cubes[cube].box = apply(m, old);
}

std::vector<AxisMap> develop(const Structure& s) { return development(s).map; }

std::vector<FaceRegion> boundary_regions(const Structure& s, int cube) {
  check_index(s, cube, "boundary_regions");
  for (const auto& g : s.gluings) {
    check_index(s, g.a, "gluing");
    check_index(s, g.b, "gluing");
  }
  const Box& box = s.cubes[cube].box;
  std::vector<FaceRegion> out;
  for (int f = 0; f < 6; ++f) {
    std::vector<Rect> rects;
    std::vector<std::pair<bool, int>> tag;  // (virtual, gluing or virtual component)
    for (std::size_t g = 0; g < s.gluings.size(); ++g) {
      const Gluing& x = s.gluings[g];
      if (x.a == cube && x.fa == f) rects.push_back(x.rect_a), tag.emplace_back(false, static_cast<int>(g));
      if (x.b == cube && x.fb == f) rects.push_back(image_rect(s, x)), tag.emplace_back(false, static_cast<int>(g));
    }
    for (std::size_t v = 0; v < s.virtual_components.size(); ++v)
      if (s.virtual_components[v].cube == cube)
        for (const auto& b : s.virtual_components[v].boxes)
          if (plane(b, f) == plane(box, f)) rects.push_back(face_rect(b, f)), tag.emplace_back(true, static_cast<int>(v));
    const Grid grid = grid_cells(face_rect(box, f), rects);
    std::vector<std::pair<int, int>> label;  // (gluing, virtual component)
    for (const auto& cover : grid.cover) {
      std::pair<int, int> l{-1, -1};
      for (int k : cover) {
        int& slot = tag[k].first ? l.second : l.first;
        if (slot >= 0 && slot != tag[k].second) {
          const std::string who = cube_name(s, cube) + " face " + std::to_string(f);
          if (tag[k].first)
            throw TopologyError(who + ": opened by both " + virtual_name(s, slot) + " and " + virtual_name(s, tag[k].second));
          const auto other = [&](int g) { return cube_name(s, s.gluings[g].a == cube ? s.gluings[g].b : s.gluings[g].a); };
          throw TopologyError(who + ": a rectangle is glued twice, to " + other(slot) + " and to " + other(tag[k].second));
        }
        slot = tag[k].second;
      }
      label.push_back(l);
    }
    for (const auto& [rect, l] : merge_cells(grid, label)) {
      FaceRegion r{f, rect, RegionKind::boundary, l.first, -1, l.second};
      if (l.first >= 0) r.neighbor = s.gluings[l.first].a == cube ? s.gluings[l.first].b : s.gluings[l.first].a;
      r.kind = l.second >= 0 ? RegionKind::virtual_opening : l.first >= 0 ? RegionKind::glued : RegionKind::boundary;
      out.push_back(r);
    }
  }
  return out;
}

std::vector<Wall> virtual_walls(const Structure& s, int virtual_component) {
  if (virtual_component < 0 || virtual_component >= static_cast<int>(s.virtual_components.size()))
    throw TopologyError("virtual_walls: no virtual component " + std::to_string(virtual_component));
  const VirtualComponent& vc = s.virtual_components[virtual_component];
  check_index(s, vc.cube, virtual_name(s, virtual_component));
  const Box& host = s.cubes[vc.cube].box;
  std::vector<Wall> out;
  for (std::size_t k = 0; k < vc.boxes.size(); ++k)
    for (int f = 0; f < 6; ++f) {
      const Box& b = vc.boxes[k];
      if (plane(b, f) == plane(host, f)) continue;  // an opening, not a wall
      // Faces shared with another removed box are inside the removed region.
      std::vector<Rect> shared;
      for (const auto& w : s.virtual_components)
        if (w.cube == vc.cube)
          for (const auto& o : w.boxes)
            if (plane(o, f ^ 1) == plane(b, f)) shared.push_back(face_rect(o, f ^ 1));
      const Grid grid = grid_cells(face_rect(b, f), shared);
      std::vector<int> covered;
      for (const auto& c : grid.cover) covered.push_back(c.empty() ? 0 : 1);
      for (const auto& [rect, l] : merge_cells(grid, covered))
        if (!l) out.push_back(Wall{static_cast<int>(k), f, rect});
    }
  return out;
}

void check(const Structure& s, const StructureParams& params) {
  check_references(s);
  const int n = static_cast<int>(s.cubes.size());
  if (n == 0) throw TopologyError("the structure has no cube");
  const double tol0 = tolerance(cube_boxes(s), params);
  for (const auto& g : s.gluings) validate_gluing(s, g, tol0);
  for (int p = 0; p < static_cast<int>(s.primitives.size()); ++p)
    if (s.primitives[p].torus) check_torus(s, p);
  for (int c = 0; c < n; ++c) boundary_regions(s, c);
  for (std::size_t k = 0; k < s.contacts.size(); ++k) check_contact_record(s, k);
  const Development d = development(s);
  // Contacts join parts of the development (never cubes of one part: those share a frame, so
  // where they touch must be glued); gluings and contacts together must join every cube.
  const int parts = 1 + *std::max_element(d.part.begin(), d.part.end());
  std::vector<int> joined(static_cast<std::size_t>(parts));
  for (int p = 0; p < parts; ++p) joined[p] = p;
  const std::function<int(int)> root = [&](int p) { return joined[p] == p ? p : joined[p] = root(joined[p]); };
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const Contact& x = s.contacts[k];
    if (d.part[x.a] == d.part[x.b])
      throw TopologyError(contact_name(s, k) + ": the cubes are joined by gluings (one frame), so where they touch must be a gluing, not a contact");
    joined[root(d.part[x.a])] = root(d.part[x.b]);
  }
  for (int c = 0; c < n; ++c)
    if (root(d.part[c]) != root(d.part[0]))
      throw TopologyError("the structure is not connected: no gluings" + std::string(s.contacts.empty() ? "" : " or contacts") + " join " +
                          cube_name(s, c) + " to " + cube_name(s, 0) + " (a torus's closing gluing does not count)");
  // Every gluing off the spanning tree closes a cycle: its maps must compose to the identity (a
  // torus's ring: to a translation, the period).
  for (std::size_t g = 0; g < s.gluings.size(); ++g) {
    const Gluing& x = s.gluings[g];
    if (d.via[x.a] == static_cast<int>(g) || d.via[x.b] == static_cast<int>(g)) continue;
    const AxisMap around = compose(d.map[x.b], compose(x.map, inverse(d.map[x.a])));
    if (x.closes_torus >= 0 ? linear_identity(around) : identity(around)) continue;
    if (x.closes_torus >= 0)
      throw TopologyError("the ring of " + primitive_name(s, x.closes_torus) + " (cubes " + cycle_names(s, d, x.a, x.b) +
                          ") closes with " + map_text(around) + ": a rotation, flip or scale; it must close with a translation");
    throw TopologyError("the gluings around cubes " + cycle_names(s, d, x.a, x.b) + " compose to " + map_text(around) +
                        ", not to the identity: no polycube realizes this cycle");
  }
  std::vector<Box> developed;
  for (int c = 0; c < n; ++c) developed.push_back(apply(d.map[c], s.cubes[c].box));
  const double tol = std::max(tol0, tolerance(developed, params));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (d.part[i] != d.part[j]) continue;  // no common frame: joined by a contact only
      const std::string pair = cube_name(s, i) + " and " + cube_name(s, j);
      not_almost(developed[i], developed[j], tol, pair);
      if (overlap(developed[i], developed[j])) throw TopologyError(pair + " overlap");
    }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (d.part[i] == d.part[j]) check_contact(s, d, i, j, developed[i], developed[j]);
  for (int v = 0; v < static_cast<int>(s.virtual_components.size()); ++v) check_virtual(s, v, tol);
}

core::Json to_json(const Structure& s) {
  core::Json cubes = core::Json::array(), primitives = core::Json::array(), gluings = core::Json::array(), virt = core::Json::array(),
             contacts = core::Json::array();
  for (const auto& c : s.cubes) cubes.push_back({{"label", c.label}, {"lo", c.box.lo}, {"hi", c.box.hi}, {"primitive", c.primitive}});
  for (const auto& p : s.primitives) primitives.push_back({{"label", p.label}, {"torus", p.torus}, {"cubes", p.cubes}});
  for (const auto& g : s.gluings)
    gluings.push_back({{"a", g.a}, {"fa", g.fa}, {"b", g.b}, {"fb", g.fb}, {"rect_lo", g.rect_a.lo}, {"rect_hi", g.rect_a.hi},
                       {"axis", g.map.axis}, {"scale", g.map.scale}, {"offset", g.map.offset}, {"closes_torus", g.closes_torus}});
  for (const auto& v : s.virtual_components) {
    core::Json boxes = core::Json::array();
    for (const auto& b : v.boxes) boxes.push_back({{"lo", b.lo}, {"hi", b.hi}});
    virt.push_back({{"label", v.label}, {"cube", v.cube}, {"torus", v.torus}, {"boxes", boxes}});
  }
  for (const auto& x : s.contacts)
    contacts.push_back({{"label", x.label}, {"a", x.a}, {"fa", x.fa}, {"b", x.b}, {"fb", x.fb}, {"conforming", false}});
  return core::Json{{"cubes", cubes}, {"primitives", primitives}, {"gluings", gluings}, {"virtual_components", virt}, {"contacts", contacts}};
}

namespace {

// Members of a structure's JSON, each error naming the file and the member's path.
struct Reader {
  const std::string& file;
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw core::InvalidInputError(file + ": structure" + (path.empty() ? "" : "." + path) + ": " + what);
  }
  const core::Json& at(const core::Json& j, const std::string& path, const std::string& key) const {
    if (!j.is_object()) fail(path, "must be an object");
    const auto it = j.find(key);
    if (it == j.end()) fail(path.empty() ? key : path + "." + key, "missing");
    return *it;
  }
  template <class T>
  T get(const core::Json& j, const std::string& path, const std::string& key) const {
    try {
      return at(j, path, key).get<T>();
    } catch (const core::Json::exception& e) {
      fail(path.empty() ? key : path + "." + key, e.what());
    }
  }
  const core::Json& array(const core::Json& j, const std::string& path, const std::string& key) const {
    const core::Json& a = at(j, path, key);
    if (!a.is_array()) fail(path.empty() ? key : path + "." + key, "must be an array");
    return a;
  }
  template <std::size_t N>
  std::array<double, N> numbers(const core::Json& j, const std::string& path, const std::string& key) const {
    const core::Json& a = array(j, path, key);
    const std::string where = path.empty() ? key : path + "." + key;
    if (a.size() != N) fail(where, "must hold " + std::to_string(N) + " numbers");
    std::array<double, N> x{};
    for (std::size_t i = 0; i < N; ++i) {
      if (!a[i].is_number() || !std::isfinite(a[i].get<double>())) fail(where, "must hold finite numbers");
      x[i] = a[i].get<double>();
    }
    return x;
  }
  int index(const core::Json& j, const std::string& path, const std::string& key, int lo, int end) const {
    const int i = get<int>(j, path, key);
    if (i < lo || i >= end) fail(path + "." + key, std::to_string(i) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(end) + ")");
    return i;
  }
  Box box(const core::Json& j, const std::string& path) const {
    const Box b{numbers<3>(j, path, "lo"), numbers<3>(j, path, "hi")};
    if (!valid_box(b)) fail(path, "lo < hi must hold on every axis");
    return b;
  }
};

std::string item(const std::string& list, std::size_t i) { return list + "[" + std::to_string(i) + "]"; }

}  // namespace

Structure structure_from_json(const core::Json& j, const std::string& file) {
  const Reader r{file};
  if (!j.is_object()) r.fail("", "must be an object");
  Structure s;
  const core::Json& cubes = r.array(j, "", "cubes");
  const core::Json& primitives = r.array(j, "", "primitives");
  const int n = static_cast<int>(cubes.size()), np = static_cast<int>(primitives.size());
  for (std::size_t i = 0; i < cubes.size(); ++i) {
    const std::string path = item("cubes", i);
    s.cubes.push_back(Cube{r.get<std::string>(cubes[i], path, "label"), r.box(cubes[i], path), r.index(cubes[i], path, "primitive", 0, np)});
  }
  for (std::size_t i = 0; i < primitives.size(); ++i) {
    const std::string path = item("primitives", i);
    Primitive p{r.get<std::string>(primitives[i], path, "label"), r.get<bool>(primitives[i], path, "torus"),
                r.get<std::vector<int>>(primitives[i], path, "cubes")};
    if (p.torus ? p.cubes.size() < 4 : p.cubes.size() != 1) r.fail(path + ".cubes", p.torus ? "a torus has at least 4 cubes" : "a cube primitive has 1 cube");
    for (int c : p.cubes)
      if (c < 0 || c >= n || s.cubes[c].primitive != static_cast<int>(i))
        r.fail(path + ".cubes", "cube " + std::to_string(c) + " is not a cube of this primitive");
    s.primitives.push_back(std::move(p));
  }
  for (std::size_t c = 0; c < s.cubes.size(); ++c) {
    const auto& list = s.primitives[s.cubes[c].primitive].cubes;
    if (std::count(list.begin(), list.end(), static_cast<int>(c)) != 1) r.fail(item("cubes", c) + ".primitive", "the primitive does not list this cube once");
  }
  const core::Json& gluings = r.array(j, "", "gluings");
  for (std::size_t i = 0; i < gluings.size(); ++i) {
    const core::Json& x = gluings[i];
    const std::string path = item("gluings", i);
    Gluing g{r.index(x, path, "a", 0, n), r.index(x, path, "fa", 0, 6), r.index(x, path, "b", 0, n), r.index(x, path, "fb", 0, 6),
             Rect{r.numbers<2>(x, path, "rect_lo"), r.numbers<2>(x, path, "rect_hi")}, AxisMap{}, -1};
    if (!(g.rect_a.lo[0] < g.rect_a.hi[0] && g.rect_a.lo[1] < g.rect_a.hi[1])) r.fail(path, "rect_lo < rect_hi must hold");
    g.map.axis = r.get<std::array<int, 3>>(x, path, "axis");
    g.map.scale = r.numbers<3>(x, path, "scale");
    g.map.offset = r.numbers<3>(x, path, "offset");
    if (r.array(x, path, "axis").size() != 3 || !valid_map(g.map)) r.fail(path, "axis/scale must be a permutation of 0, 1, 2 with nonzero scales");
    g.closes_torus = r.index(x, path, "closes_torus", -1, np);
    if (g.closes_torus >= 0 && !s.primitives[g.closes_torus].torus) r.fail(path + ".closes_torus", "is not a torus");
    s.gluings.push_back(g);
  }
  const core::Json& virt = r.array(j, "", "virtual_components");
  for (std::size_t i = 0; i < virt.size(); ++i) {
    const std::string path = item("virtual_components", i);
    VirtualComponent v{r.get<std::string>(virt[i], path, "label"), r.index(virt[i], path, "cube", 0, n), {},
                       r.get<bool>(virt[i], path, "torus")};
    const core::Json& boxes = r.array(virt[i], path, "boxes");
    if (boxes.empty()) r.fail(path + ".boxes", "must not be empty");
    for (std::size_t k = 0; k < boxes.size(); ++k) v.boxes.push_back(r.box(boxes[k], item(path + ".boxes", k)));
    s.virtual_components.push_back(std::move(v));
  }
  if (!j.contains("contacts")) return s;  // written before contacts existed: none
  const core::Json& contacts = r.array(j, "", "contacts");
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const core::Json& x = contacts[i];
    const std::string path = item("contacts", i);
    if (r.get<bool>(x, path, "conforming")) r.fail(path + ".conforming", "must be false (a conforming contact is a gluing)");
    s.contacts.push_back(Contact{r.get<std::string>(x, path, "label"), r.index(x, path, "a", 0, n), r.index(x, path, "fa", 0, 6),
                                 r.index(x, path, "b", 0, n), r.index(x, path, "fb", 0, 6)});
  }
  return s;
}

core::Json report_figures(const Structure& s) {
  const auto tori = std::count_if(s.primitives.begin(), s.primitives.end(), [](const Primitive& p) { return p.torus; });
  return core::Json{{"cubes", s.cubes.size()}, {"tori", tori}, {"virtual_components", s.virtual_components.size()},
                    {"gluings", s.gluings.size()}, {"contacts", s.contacts.size()}};
}

void write_structure_vtu(const std::string& path, const Structure& s) {
  const Development d = development(s);
  std::vector<AxisMap> dev = d.map;
  // Parts (joined by contacts only) side by side along x: each half its width clear of the last.
  const int parts = s.cubes.empty() ? 0 : 1 + *std::max_element(d.part.begin(), d.part.end());
  double right = 0;
  for (int p = 0; p < parts; ++p) {
    double lo = 0, hi = 0;
    bool first = true;
    for (std::size_t c = 0; c < s.cubes.size(); ++c)
      if (d.part[c] == p) {
        const Box b = apply(dev[c], s.cubes[c].box);
        lo = first ? b.lo[0] : std::min(lo, b.lo[0]), hi = first ? b.hi[0] : std::max(hi, b.hi[0]);
        first = false;
      }
    const double shift = p == 0 ? 0 : right + (hi - lo) / 2 - lo;
    for (std::size_t c = 0; c < s.cubes.size(); ++c)
      if (d.part[c] == p) dev[c].offset[0] += shift;
    right = hi + shift;
  }
  viz::UnstructuredGrid grid;
  viz::Field cube{"cube_id", 1, {}}, primitive{"primitive_id", 1, {}}, torus{"torus", 1, {}}, is_virtual{"virtual", 1, {}},
      component{"virtual_component", 1, {}}, part{"part", 1, {}};
  auto hex = [&](const Box& b, int c, int v) {
    const int first = static_cast<int>(grid.points.size());
    for (int z = 0; z < 2; ++z)
      for (const auto& [x, y] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}})
        grid.points.push_back({x ? b.hi[0] : b.lo[0], y ? b.hi[1] : b.lo[1], z ? b.hi[2] : b.lo[2]});
    grid.cells.push_back({first, first + 1, first + 2, first + 3, first + 4, first + 5, first + 6, first + 7});
    grid.cell_types.push_back(12);  // VTK_HEXAHEDRON
    const int p = s.cubes[c].primitive;
    cube.values.push_back(c);
    primitive.values.push_back(p);
    torus.values.push_back(s.primitives[p].torus ? 1 : 0);
    is_virtual.values.push_back(v >= 0 ? 1 : 0);
    component.values.push_back(v);
    part.values.push_back(d.part[c]);
  };
  for (int c = 0; c < static_cast<int>(s.cubes.size()); ++c) hex(apply(dev[c], s.cubes[c].box), c, -1);
  for (int v = 0; v < static_cast<int>(s.virtual_components.size()); ++v)
    for (const auto& b : s.virtual_components[v].boxes) hex(apply(dev[s.virtual_components[v].cube], b), s.virtual_components[v].cube, v);
  grid.cell_fields = {cube, primitive, torus, is_virtual, component, part};
  viz::write_vtu(path, grid);
}

}  // namespace volts::polycube
