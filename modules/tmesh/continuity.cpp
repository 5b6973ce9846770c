#include "tmesh/continuity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "bezier/bspline.h"
#include "core/errors.h"
#include "core/parallel.h"

namespace volts::tmesh {

namespace {

// The rows of one line across a face: the clamped extras of A (last element count nA) and B (nB)
// in terms of (A's point two in from the face, the face point, B's point two in), with unit knot
// intervals (one element of the level). Knot removal written as a solve: the clamped points of a
// C2 spline are Rᵀ·Q (R = refinement from the merged knots, the interface knot simple, to the
// clamped pair's, it triple); dropping the two extras leaves a square system for Q.
struct LineRows {
  std::array<double, 3> a{}, b{};
};

// The same from the interior knots of A (toward the face, which is at `ta`) and of B (from the
// face on), in one parameter: unit intervals give line_rows(nA, nB) below.
LineRows line_rows_on(const std::vector<double>& inner_a, double ta, const std::vector<double>& inner_b, double end) {
  const int nA = static_cast<int>(inner_a.size()) + 1;
  std::vector<double> merged(4, 0.0), pair(4, 0.0);
  for (const double k : inner_a) merged.push_back(k), pair.push_back(k);
  merged.push_back(ta);
  for (int r = 0; r < 3; ++r) pair.push_back(ta);
  for (const double k : inner_b) merged.push_back(k), pair.push_back(k);
  for (int r = 0; r < 4; ++r) merged.push_back(end), pair.push_back(end);
  const Eigen::MatrixXd M = bezier::refinement_matrix(merged, pair, 3).transpose();  // clamped points × merged points
  const int n = static_cast<int>(M.rows()), m = static_cast<int>(M.cols());
  const int extra_a = nA + 1, extra_b = nA + 3;
  std::vector<int> keep;
  for (int i = 0; i < n; ++i)
    if (i != extra_a && i != extra_b) keep.push_back(i);
  if (static_cast<int>(keep.size()) != m) throw core::NumericalError("raise_continuity: the knot removal is not square");
  Eigen::MatrixXd S(m, m), E(2, m);
  for (int r = 0; r < m; ++r) S.row(r) = M.row(keep[static_cast<std::size_t>(r)]);
  E.row(0) = M.row(extra_a), E.row(1) = M.row(extra_b);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
  if (!lu.isInvertible()) throw core::NumericalError("raise_continuity: the knot removal is singular");
  const Eigen::MatrixXd W = E * lu.inverse();  // 2 × kept clamped points
  LineRows rows;
  const int refs[3] = {nA, nA + 2, nA + 4};
  for (int c = 0; c < m; ++c) {
    const int i = keep[static_cast<std::size_t>(c)];
    const int* at = std::find(refs, refs + 3, i);
    if (at == refs + 3) {
      if (std::abs(W(0, c)) > 1e-9 || std::abs(W(1, c)) > 1e-9) throw core::NumericalError("raise_continuity: a row reaches past the face's neighbours");
      continue;
    }
    rows.a[static_cast<std::size_t>(at - refs)] = W(0, c), rows.b[static_cast<std::size_t>(at - refs)] = W(1, c);
  }
  return rows;
}

LineRows line_rows(int nA, int nB) {
  std::vector<double> a, b;
  for (int k = 1; k < nA; ++k) a.push_back(k);
  for (int k = nA + 1; k < nA + nB; ++k) b.push_back(k);
  return line_rows_on(a, nA, b, nA + nB);
}

// Interior knots of block t along `axis` in units of `length`, shifted by `start`, in the block's
// own direction (`forward`) or reversed (u -> 1 - u).
std::vector<double> inner_knots(const TMesh& t, int axis, double length, bool forward, double start) {
  const std::vector<double>& k = t.knots[static_cast<std::size_t>(axis)];
  std::vector<double> out;
  for (std::size_t i = static_cast<std::size_t>(t.degree) + 1; i + static_cast<std::size_t>(t.degree) + 1 < k.size(); ++i) out.push_back(k[i]);
  if (!forward) {
    std::reverse(out.begin(), out.end());
    for (double& x : out) x = 1.0 - x;
  }
  for (double& x : out) x = start + x * length;
  return out;
}

std::size_t local_index(const TMesh& t, const std::array<int, 3>& idx) {
  return static_cast<std::size_t>(idx[0] + t.size[0] * (idx[1] + t.size[1] * idx[2]));
}

std::array<int, 3> grid_index(const TMesh& t, std::size_t i) {
  const int k = static_cast<int>(i);
  return {k % t.size[0], (k / t.size[0]) % t.size[1], k / (t.size[0] * t.size[1])};
}

// Per node id below `nodes`: the (block, control point) pairs that hold it.
using Occurrences = std::vector<std::vector<std::pair<int, std::size_t>>>;
Occurrences occurrences(const std::vector<TMesh>& blocks, int nodes) {
  Occurrences where(static_cast<std::size_t>(nodes));
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (std::size_t i = 0; i < blocks[b].function_ids.size(); ++i) where[static_cast<std::size_t>(blocks[b].function_ids[i])].push_back({static_cast<int>(b), i});
  return where;
}

// One line across a face: the two extras and the three points their rows name, in that order.
struct Line {
  int extra_a = 0, extra_b = 0;
  std::array<int, 3> refs{};
  LineRows rows;
  bool surface = false;  // in the surface layer (ContinuityParams::surface_layer): its extras are surface points
};

double distance_of(const Vec3& x, const Vec3& y) { return std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]); }

// The distance from node `id` to its nearest neighbour in its blocks' grids (a thin slab's:
// across the slab).
double nearest_neighbour(const std::vector<TMesh>& blocks, const Occurrences& where, int id) {
  double reach = std::numeric_limits<double>::infinity();
  for (const auto& [blk, at] : where[static_cast<std::size_t>(id)]) {
    const TMesh& t = blocks[static_cast<std::size_t>(blk)];
    const std::array<int, 3> g = grid_index(t, at);
    for (int axis = 0; axis < 3; ++axis)
      for (const int step : {-1, 1}) {
        std::array<int, 3> n = g;
        n[static_cast<std::size_t>(axis)] += step;
        if (n[static_cast<std::size_t>(axis)] < 0 || n[static_cast<std::size_t>(axis)] >= t.size[axis]) continue;
        reach = std::min(reach, distance_of(t.control_points[at], t.control_points[local_index(t, n)]));
      }
  }
  return reach;
}

// A face's knots across it (A's toward the face at la, B's from it), its lines [first, last).
struct FaceFit {
  std::vector<double> ka, kb;
  double la = 0, lb = 0;
  std::size_t first = 0, last = 0;
  // The rows at ratio rho (A's knot intervals scaled by rho against B's).
  LineRows rows_at(double rho) const {
    std::vector<double> sa = ka, sb = kb;
    for (double& x : sa) x *= rho;
    for (double& x : sb) x += la * (rho - 1);
    return line_rows_on(sa, la * rho, sb, la * rho + lb);
  }
};

// A point E of a regular edge (four blocks around it, 2 x 2) and the 5 x 5 points around it in
// the plane across the edge, P(i, j) for i, j in [-2, 2] (i across the faces between the blocks
// on either side in one direction, j in the other; P(0, 0) = E). The four lines two points from
// the edge (u lines at j = -2, 2 across the faces at i = 0; v lines at i = -2, 2) are C2; the
// nine points P(i, j), i, j in {-2, 0, 2}, are kept (`kept`, i major) and the eight others of
// the 3 x 3 around E become rows of them: the tensor product of the u and v lines' rows.
struct EdgePoint {
  std::array<int, 9> kept{};
  std::array<int, 8> extras{};  // P(i, j), i, j in {-1, 0, 1} but (0, 0), i major
  std::array<int, 4> line{};    // u lines at j = -2, 2, then v lines at i = -2, 2
  std::array<int, 4> parity{};  // 1: the line runs from the plus side (its A block there)
  std::array<std::array<double, 9>, 8> w{};
  std::array<double, 8> reach{};  // each extra's nearest neighbour distance (the move bound's)
  bool ok = false;
  static std::pair<int, int> cell(int x) {
    static const int c[8][2] = {{-1, -1}, {-1, 0}, {-1, 1}, {0, -1}, {0, 1}, {1, -1}, {1, 0}, {1, 1}};
    return {c[x][0], c[x][1]};
  }
  static bool corner(int x) { return x == 0 || x == 2 || x == 5 || x == 7; }
  // The rows from the lines' (false where the lines on either side of the edge disagree).
  bool set_rows(const std::vector<Line>& lines) {
    using Rows = std::array<std::array<double, 3>, 3>;  // minus extra, face point, plus extra over (-2, 0, 2)
    auto oriented = [&](int which) {
      const Line& l = lines[static_cast<std::size_t>(line[static_cast<std::size_t>(which)])];
      auto reversed = [](std::array<double, 3> r) {
        std::swap(r[0], r[2]);
        return r;
      };
      Rows r{};
      r[1] = {0, 1, 0};
      if (parity[static_cast<std::size_t>(which)] == 0) r[0] = l.rows.a, r[2] = l.rows.b;
      else r[0] = reversed(l.rows.b), r[2] = reversed(l.rows.a);
      return r;
    };
    auto same = [](const Rows& x, const Rows& y) {
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          if (std::abs(x[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] - y[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)]) > 1e-12) return false;
      return true;
    };
    const Rows ru = oriented(0), rv = oriented(2);
    if (!same(ru, oriented(1)) || !same(rv, oriented(3))) return false;
    for (int x = 0; x < 8; ++x) {
      const auto [i, j] = cell(x);
      for (int k = 0; k < 9; ++k)
        w[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)] = ru[static_cast<std::size_t>(i + 1)][static_cast<std::size_t>(k / 3)] * rv[static_cast<std::size_t>(j + 1)][static_cast<std::size_t>(k % 3)];
    }
    return true;
  }
};

// The regular edge points whose four lines are among `lines`.
std::vector<EdgePoint> edge_points(const std::vector<TMesh>& blocks, const Occurrences& where, const std::vector<Line>& lines) {
  std::map<std::array<int, 3>, int> line_at;
  for (std::size_t l = 0; l < lines.size(); ++l) line_at[lines[l].refs] = static_cast<int>(l);
  auto local_of = [&](int id, int block) -> long {
    for (const auto& [blk, at] : where[static_cast<std::size_t>(id)])
      if (blk == block) return static_cast<long>(at);
    return -1;
  };
  // A block, E's grid index in it, and unit steps away from the edge along i and along j.
  struct Quadrant {
    int block = -1;
    std::array<int, 3> e{}, di{}, dj{};
    int at(const std::vector<TMesh>& bs, int a, int b) const {
      const TMesh& t = bs[static_cast<std::size_t>(block)];
      std::array<int, 3> g{};
      for (int d = 0; d < 3; ++d) {
        g[static_cast<std::size_t>(d)] = e[static_cast<std::size_t>(d)] + a * di[static_cast<std::size_t>(d)] + b * dj[static_cast<std::size_t>(d)];
        if (g[static_cast<std::size_t>(d)] < 0 || g[static_cast<std::size_t>(d)] >= t.size[d]) return -1;
      }
      return t.function_ids[local_index(t, g)];
    }
  };
  auto unit_step = [](const std::array<int, 3>& from, const std::array<int, 3>& to, std::array<int, 3>& step) {
    int moved = 0;
    for (int d = 0; d < 3; ++d) {
      step[static_cast<std::size_t>(d)] = to[static_cast<std::size_t>(d)] - from[static_cast<std::size_t>(d)];
      moved += std::abs(step[static_cast<std::size_t>(d)]);
    }
    return moved == 1;
  };
  // The inward step along E's other boundary axis in quadrant q (not the axis of `known`).
  auto other_step = [&](Quadrant& q, const std::array<int, 3>& known, std::array<int, 3>& step) {
    const TMesh& t = blocks[static_cast<std::size_t>(q.block)];
    int found = 0;
    for (int d = 0; d < 3; ++d) {
      if (known[static_cast<std::size_t>(d)] != 0) continue;
      if (q.e[static_cast<std::size_t>(d)] == 0 || q.e[static_cast<std::size_t>(d)] == t.size[d] - 1) {
        step = {0, 0, 0};
        step[static_cast<std::size_t>(d)] = q.e[static_cast<std::size_t>(d)] == 0 ? 1 : -1;
        ++found;
      }
    }
    return found == 1;
  };
  // The block across from q's face through the point `id` (held by exactly q's block and it).
  auto across = [&](int id, int block) {
    if (id < 0 || where[static_cast<std::size_t>(id)].size() != 2) return -1;
    for (const auto& [blk, at] : where[static_cast<std::size_t>(id)])
      if (blk != block) return blk;
    return -1;
  };
  std::vector<EdgePoint> out;
  for (std::size_t id = 0; id < where.size(); ++id) {
    const auto& occ = where[id];
    if (occ.size() != 4) continue;
    std::set<int> distinct;
    for (const auto& o : occ) distinct.insert(o.first);
    if (distinct.size() != 4) continue;
    const int E = static_cast<int>(id);
    Quadrant q00, q10, q01, q11;
    q00.block = occ[0].first, q00.e = grid_index(blocks[static_cast<std::size_t>(q00.block)], occ[0].second);
    {
      const TMesh& t = blocks[static_cast<std::size_t>(q00.block)];
      std::array<int, 2> axes{};
      int n = 0;
      for (int d = 0; d < 3; ++d)
        if (q00.e[static_cast<std::size_t>(d)] == 0 || q00.e[static_cast<std::size_t>(d)] == t.size[d] - 1) {
          if (n < 2) axes[static_cast<std::size_t>(n)] = d;
          ++n;
        }
      if (n != 2) continue;  // a block corner, not an edge point
      q00.di[static_cast<std::size_t>(axes[0])] = q00.e[static_cast<std::size_t>(axes[0])] == 0 ? 1 : -1;
      q00.dj[static_cast<std::size_t>(axes[1])] = q00.e[static_cast<std::size_t>(axes[1])] == 0 ? 1 : -1;
    }
    // P(0, -1) is on the face between q00 and q10, P(-1, 0) on the one between q00 and q01.
    q10.block = across(q00.at(blocks, 0, 1), q00.block);
    q01.block = across(q00.at(blocks, 1, 0), q00.block);
    if (q10.block < 0 || q01.block < 0 || q10.block == q01.block) continue;
    for (const auto& o : occ)
      if (o.first != q00.block && o.first != q10.block && o.first != q01.block) q11.block = o.first;
    if (q11.block < 0 || local_of(E, q10.block) < 0 || local_of(E, q01.block) < 0) continue;
    auto grid_in = [&](int node, int block, std::array<int, 3>& g) {
      const long at = node < 0 ? -1 : local_of(node, block);
      if (at < 0) return false;
      g = grid_index(blocks[static_cast<std::size_t>(block)], static_cast<std::size_t>(at));
      return true;
    };
    std::array<int, 3> g{};
    bool fine = grid_in(E, q10.block, q10.e) && grid_in(E, q01.block, q01.e) && grid_in(E, q11.block, q11.e);
    fine = fine && grid_in(q00.at(blocks, 0, 1), q10.block, g) && unit_step(q10.e, g, q10.dj) && other_step(q10, q10.dj, q10.di);
    fine = fine && grid_in(q00.at(blocks, 1, 0), q01.block, g) && unit_step(q01.e, g, q01.di) && other_step(q01, q01.di, q01.dj);
    fine = fine && grid_in(q10.at(blocks, 1, 0), q11.block, g) && unit_step(q11.e, g, q11.di);
    fine = fine && grid_in(q01.at(blocks, 0, 1), q11.block, g) && unit_step(q11.e, g, q11.dj);
    if (!fine) continue;
    auto P = [&](int i, int j) {
      if (i > 0 && j > 0) return q11.at(blocks, i, j);
      if (i > 0) return q10.at(blocks, i, -j);
      if (j > 0) return q01.at(blocks, -i, j);
      return q00.at(blocks, -i, -j);
    };
    // The quadrants agree on the points they share.
    if (P(0, -2) != q10.at(blocks, 0, 2) || P(-2, 0) != q01.at(blocks, 2, 0) || P(2, 0) != q11.at(blocks, 2, 0) || P(0, 2) != q11.at(blocks, 0, 2) || P(0, 0) != E)
      continue;
    EdgePoint e;
    bool all = true;
    for (int k = 0; k < 9; ++k) all = all && (e.kept[static_cast<std::size_t>(k)] = P(2 * (k / 3) - 2, 2 * (k % 3) - 2)) >= 0;
    for (int x = 0; x < 8; ++x) {
      const auto [i, j] = EdgePoint::cell(x);
      all = all && (e.extras[static_cast<std::size_t>(x)] = P(i, j)) >= 0;
    }
    if (!all) continue;
    // The four lines (refs from minus to plus) with their extras P(-1, .) / P(1, .) or P(., -1) / P(., 1).
    auto find_line = [&](int which, int a, int f, int b, int minus, int plus) {
      auto it = line_at.find({a, f, b});
      int parity = 0;
      if (it == line_at.end()) it = line_at.find({b, f, a}), parity = 1;
      if (it == line_at.end()) return false;
      const Line& l = lines[static_cast<std::size_t>(it->second)];
      if ((parity ? l.extra_b : l.extra_a) != minus || (parity ? l.extra_a : l.extra_b) != plus) return false;
      e.line[static_cast<std::size_t>(which)] = it->second, e.parity[static_cast<std::size_t>(which)] = parity;
      return true;
    };
    const auto& K = e.kept;
    if (find_line(0, K[0], K[3], K[6], P(-1, -2), P(1, -2)) && find_line(1, K[2], K[5], K[8], P(-1, 2), P(1, 2)) &&
        find_line(2, K[0], K[1], K[2], P(-2, -1), P(-2, 1)) && find_line(3, K[6], K[7], K[8], P(2, -1), P(2, 1)))
      out.push_back(e);
  }
  return out;
}

}  // namespace

std::vector<SharedFace> shared_faces(const std::vector<TMesh>& blocks) {
  std::map<std::array<int, 4>, std::vector<std::pair<int, int>>> faces;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const TMesh& t = blocks[b];
    if (t.function_ids.size() != t.control_points.size())
      throw core::InvalidInputError("shared_faces: block " + std::to_string(b) + " has no function ids (blocks must share their face points)");
    for (int f = 0; f < 6; ++f) {
      if (t.boundary[static_cast<std::size_t>(f)]) continue;
      const int a = f / 2, u = (a + 1) % 3, w = (a + 2) % 3;
      std::array<int, 4> key{};
      for (int c = 0; c < 4; ++c) {
        std::array<int, 3> idx{};
        idx[static_cast<std::size_t>(a)] = f % 2 ? t.size[a] - 1 : 0;
        idx[static_cast<std::size_t>(u)] = (c & 1) ? t.size[u] - 1 : 0, idx[static_cast<std::size_t>(w)] = (c & 2) ? t.size[w] - 1 : 0;
        key[static_cast<std::size_t>(c)] = t.function_ids[local_index(t, idx)];
      }
      std::sort(key.begin(), key.end());
      faces[key].push_back({static_cast<int>(b), f});
    }
  }
  std::vector<SharedFace> out;
  for (const auto& [key, list] : faces)
    if (list.size() == 2) out.push_back({list[0].first, list[0].second, list[1].first, list[1].second});
  return out;
}

ContinuityResult raise_continuity(std::vector<TMesh>& blocks, const ContinuityParams& params) {
  if (params.margin < 2 || params.margin > 100) throw core::ConfigError("raise_continuity: margin must be in [2, 100]");
  if (!(params.max_move_rel >= 0) || !(params.surface_move_max >= 0))
    throw core::ConfigError("raise_continuity: max_move_rel and surface_move_max must be >= 0 (infinity: no bound)");
  ContinuityResult r;
  int nodes = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const TMesh& t = blocks[b];
    if (t.degree != 3) throw core::ConfigError("raise_continuity: C2 across block faces is for cubic blocks (block " + std::to_string(b) + " has degree " + std::to_string(t.degree) + ")");
    if (t.function_ids.size() != t.control_points.size())
      throw core::InvalidInputError("raise_continuity: block " + std::to_string(b) + " has no function ids (blocks must share their face points)");
    for (const int id : t.function_ids) nodes = std::max(nodes, id + 1);
  }
  if (!params.lengths.empty()) {
    if (params.lengths.size() != blocks.size())
      throw core::InvalidInputError("raise_continuity: " + std::to_string(params.lengths.size()) + " block lengths for " + std::to_string(blocks.size()) + " blocks");
    for (const auto& l : params.lengths)
      for (const double x : l)
        if (!(x > 0)) throw core::InvalidInputError("raise_continuity: a block length is not positive");
  }
  const Occurrences where = occurrences(blocks, nodes);
  // Positions of the nodes (any occurrence).
  std::vector<Vec3> position(static_cast<std::size_t>(nodes));
  Eigen::AlignedBox3d box;
  for (std::size_t id = 0; id < where.size(); ++id)
    if (!where[id].empty()) {
      position[id] = blocks[static_cast<std::size_t>(where[id][0].first)].control_points[where[id][0].second];
      box.extend(Eigen::Vector3d(position[id][0], position[id][1], position[id][2]));
    }
  const double tol = 1e-9 * std::max(1.0, box.isEmpty() ? 0.0 : box.diagonal().norm());
  auto row_point_of = [&](const LineRows& rows, const std::array<int, 3>& refs, int side) {
    const std::array<double, 3>& wt = side ? rows.b : rows.a;
    Vec3 x{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) x[static_cast<std::size_t>(d)] += wt[static_cast<std::size_t>(k)] * position[static_cast<std::size_t>(refs[static_cast<std::size_t>(k)])][static_cast<std::size_t>(d)];
    return x;
  };
  auto row_point = [&](const Line& line, int side) { return row_point_of(line.rows, line.refs, side); };
  using RowKey = std::vector<double>;  // (nA, nB) for unit intervals, else the knots across the face
  std::map<RowKey, LineRows> rows_of;
  std::vector<Line> lines;
  std::vector<int> face_of_line;
  // Faces of two blocks of one level, neither with T-junctions.
  const std::vector<SharedFace> faces = shared_faces(blocks);
  const int pairs = static_cast<int>(faces.size());
  std::vector<FaceFit> fits(static_cast<std::size_t>(pairs));
  for (int face_index = 0; face_index < pairs; ++face_index) {
    const auto [ba, fa, bb, fb] = faces[static_cast<std::size_t>(face_index)];
    const TMesh& A = blocks[static_cast<std::size_t>(ba)];
    const TMesh& B = blocks[static_cast<std::size_t>(bb)];
    const int a = fa / 2, u = (a + 1) % 3, w = (a + 2) % 3, ab = fb / 2;
    if (A.level != B.level || !A.constraints.empty() || !B.constraints.empty() || A.size[a] < 4 || B.size[ab] < 4 ||
        A.size[u] * A.size[w] != B.size[(ab + 1) % 3] * B.size[(ab + 2) % 3])
      continue;
    const int nA = A.size[a] - 3, nB = B.size[ab] - 3;
    // Knot intervals across the face in the spline's units (params.lengths): unit ones (the net as
    // laid out or h-refined) give the rows of (nA, nB); others those of the knots themselves.
    // A runs toward the face (at la), B away from it (from la on).
    const double la = params.lengths.empty() ? nA : params.lengths[static_cast<std::size_t>(ba)][static_cast<std::size_t>(a)];
    const double lb = params.lengths.empty() ? nB : params.lengths[static_cast<std::size_t>(bb)][static_cast<std::size_t>(ab)];
    const std::vector<double> ka = inner_knots(A, a, la, fa % 2 == 1, 0.0), kb = inner_knots(B, ab, lb, fb % 2 == 0, la);
    bool unit = params.lengths.empty() || (std::abs(la - nA) < 1e-12 && std::abs(lb - nB) < 1e-12);
    for (std::size_t k = 0; unit && !params.lengths.empty() && k < ka.size(); ++k) unit = std::abs(ka[k] - static_cast<double>(k + 1)) < 1e-9;
    for (std::size_t k = 0; unit && !params.lengths.empty() && k < kb.size(); ++k) unit = std::abs(kb[k] - static_cast<double>(nA + 1 + static_cast<int>(k))) < 1e-9;
    const RowKey key = unit ? RowKey{{static_cast<double>(nA), static_cast<double>(nB)}} : RowKey{[&] {
      std::vector<double> all = ka;
      all.push_back(-1);  // separates A's knots from B's
      all.insert(all.end(), kb.begin(), kb.end());
      all.push_back(la), all.push_back(la + lb);
      return all;
    }()};
    auto it = rows_of.find(key);
    if (it == rows_of.end()) it = rows_of.emplace(key, unit ? line_rows(nA, nB) : line_rows_on(ka, la, kb, la + lb)).first;
    const std::size_t face_first = lines.size();
    // Rims on the surface (surface_layer) keep no margin where only A and B hold the rim: where a
    // third block does (a concave edge of the surface, three blocks around it: an irregular
    // edge), two faces' lines would end on the same face point, so the margin stays.
    auto open_rim = [&](int axis, int side) {
      if (!params.surface_layer || !A.boundary[static_cast<std::size_t>(2 * axis + side)]) return false;
      const int o = 3 - a - axis;  // the rim's own direction
      std::array<int, 3> idx{};
      idx[static_cast<std::size_t>(a)] = fa % 2 ? A.size[a] - 1 : 0;
      idx[static_cast<std::size_t>(axis)] = side ? A.size[axis] - 1 : 0;
      idx[static_cast<std::size_t>(o)] = A.size[o] / 2;
      return where[static_cast<std::size_t>(A.function_ids[local_index(A, idx)])].size() == 2;
    };
    auto rim_low = [&](int axis) { return open_rim(axis, 0) ? 0 : params.margin; };
    auto rim_high = [&](int axis) { return open_rim(axis, 1) ? 0 : params.margin; };
    for (int j = rim_low(w); j < A.size[w] - rim_high(w); ++j)
      for (int i = rim_low(u); i < A.size[u] - rim_high(u); ++i) {
        auto in_a = [&](int d) {
          std::array<int, 3> idx{};
          idx[static_cast<std::size_t>(a)] = fa % 2 ? A.size[a] - 1 - d : d, idx[static_cast<std::size_t>(u)] = i, idx[static_cast<std::size_t>(w)] = j;
          return A.function_ids[local_index(A, idx)];
        };
        const int face = in_a(0);
        // The same point in B, and B's line inward from it.
        std::size_t local = 0;
        bool found = false;
        for (const auto& [blk, at] : where[static_cast<std::size_t>(face)])
          if (blk == bb) local = at, found = true;
        if (!found) throw core::TopologyError("raise_continuity: blocks " + std::to_string(ba) + " and " + std::to_string(bb) + " share a face but not its point " + std::to_string(face));
        std::array<int, 3> idx = grid_index(B, local);
        if (idx[static_cast<std::size_t>(ab)] != (fb % 2 ? B.size[ab] - 1 : 0)) throw core::TopologyError("raise_continuity: a shared point is not on its block's face");
        auto in_b = [&](int d) {
          std::array<int, 3> k = idx;
          k[static_cast<std::size_t>(ab)] = fb % 2 ? B.size[ab] - 1 - d : d;
          return B.function_ids[local_index(B, k)];
        };
        const bool surface = (A.boundary[static_cast<std::size_t>(2 * u)] && i == 0) || (A.boundary[static_cast<std::size_t>(2 * u + 1)] && i == A.size[u] - 1) ||
                             (A.boundary[static_cast<std::size_t>(2 * w)] && j == 0) || (A.boundary[static_cast<std::size_t>(2 * w + 1)] && j == A.size[w] - 1);
        lines.push_back({in_a(1), in_b(1), {in_a(2), face, in_b(2)}, it->second, surface});
        face_of_line.push_back(face_index);
      }
    fits[static_cast<std::size_t>(face_index)] = {ka, kb, la, lb, face_first, lines.size()};
  }
  // Regular edge points (ContinuityParams::regular_edges): their four lines, and the faces on
  // either side of each edge linked (one ratio: the tensor rows need the same knots on both).
  std::vector<EdgePoint> edges = params.regular_edges ? edge_points(blocks, where, lines) : std::vector<EdgePoint>{};
  for (EdgePoint& e : edges)
    for (int x = 0; x < 8; ++x) e.reach[static_cast<std::size_t>(x)] = nearest_neighbour(blocks, where, e.extras[static_cast<std::size_t>(x)]);
  std::vector<int> parent(static_cast<std::size_t>(pairs)), flip(static_cast<std::size_t>(pairs), 0);
  std::vector<char> conflict(static_cast<std::size_t>(pairs), 0);
  for (int f = 0; f < pairs; ++f) parent[static_cast<std::size_t>(f)] = f;
  // The root of face f and f's parity against it (ratio rho at the root is 1/rho at f when odd).
  auto find = [&](int f) {
    int parity = 0;
    while (parent[static_cast<std::size_t>(f)] != f) parity ^= flip[static_cast<std::size_t>(f)], f = parent[static_cast<std::size_t>(f)];
    return std::pair<int, int>{f, parity};
  };
  auto unite = [&](int x, int y, int parity) {
    const auto [rx, px] = find(x);
    const auto [ry, py] = find(y);
    if (rx == ry) {
      if ((px ^ py) != parity) conflict[static_cast<std::size_t>(rx)] = 1;
      return;
    }
    parent[static_cast<std::size_t>(ry)] = rx, flip[static_cast<std::size_t>(ry)] = px ^ py ^ parity;
    if (conflict[static_cast<std::size_t>(ry)]) conflict[static_cast<std::size_t>(rx)] = 1;
  };
  for (const EdgePoint& e : edges) {
    unite(face_of_line[static_cast<std::size_t>(e.line[0])], face_of_line[static_cast<std::size_t>(e.line[1])], e.parity[0] ^ e.parity[1]);
    unite(face_of_line[static_cast<std::size_t>(e.line[2])], face_of_line[static_cast<std::size_t>(e.line[3])], e.parity[2] ^ e.parity[3]);
  }
  // Whether line l's extras stay within the bounds (max_move_rel, surface_move_max) with `rows`.
  std::vector<std::array<double, 2>> reach(lines.size(), {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()});
  const bool bounded = params.project && (std::isfinite(params.max_move_rel) || params.surface_layer);
  if (bounded)
    for (std::size_t l = 0; l < lines.size(); ++l) reach[l] = {nearest_neighbour(blocks, where, lines[l].extra_a), nearest_neighbour(blocks, where, lines[l].extra_b)};
  auto within = [&](std::size_t l, const LineRows& rows) {
    for (int side = 0; side < 2; ++side) {
      const double move = distance_of(row_point_of(rows, lines[l].refs, side), position[static_cast<std::size_t>(side ? lines[l].extra_b : lines[l].extra_a)]);
      if (move > params.max_move_rel * reach[l][static_cast<std::size_t>(side)] || (lines[l].surface && move > params.surface_move_max)) return false;
    }
    return true;
  };
  auto kept_row_point = [&](const EdgePoint& e, int x) {
    Vec3 p{0, 0, 0};
    for (int k = 0; k < 9; ++k)
      for (int d = 0; d < 3; ++d) p[static_cast<std::size_t>(d)] += e.w[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)] * position[static_cast<std::size_t>(e.kept[static_cast<std::size_t>(k)])][static_cast<std::size_t>(d)];
    return p;
  };
  // Whether an edge point's eight extras stay within the bounds (its rows set).
  auto edge_within = [&](const EdgePoint& e) {
    const bool surface = std::any_of(e.line.begin(), e.line.end(), [&](int l) { return lines[static_cast<std::size_t>(l)].surface; });
    for (int x = 0; x < 8; ++x) {
      const int id = e.extras[static_cast<std::size_t>(x)];
      const double move = distance_of(kept_row_point(e, x), position[static_cast<std::size_t>(id)]);
      if (move > params.max_move_rel * e.reach[static_cast<std::size_t>(x)] || (surface && move > params.surface_move_max)) return false;
    }
    return true;
  };
  if (params.fit_ratio && params.project) {
    // Per face, the ratio of knot intervals that moves the extras least (sum of squares), by
    // golden-section search on its logarithm in [-log 8, log 8]; index space's ratio when that
    // moves less (the search finds a local minimum).
    using Members = std::vector<std::pair<int, int>>;  // (face, parity against the first)
    auto fit = [&](const Members& members) {
      auto cost = [&](double log_rho) {
        double c = 0;
        for (const auto& [f, parity] : members) {
          const FaceFit& ff = fits[static_cast<std::size_t>(f)];
          const LineRows rows = ff.rows_at(std::exp(parity ? -log_rho : log_rho));
          for (std::size_t l = ff.first; l < ff.last; ++l)
            for (int side = 0; side < 2; ++side) {
              const double d = distance_of(row_point_of(rows, lines[l].refs, side), position[static_cast<std::size_t>(side ? lines[l].extra_b : lines[l].extra_a)]);
              c += d * d;
            }
        }
        return c;
      };
      const double g = 0.5 * (std::sqrt(5.0) - 1.0);
      double lo = -std::log(8.0), hi = std::log(8.0);
      double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = cost(x1), f2 = cost(x2);
      for (int iter = 0; iter < 40 && hi - lo > 1e-4; ++iter) {
        if (f1 <= f2) hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = cost(x1);
        else lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = cost(x2);
      }
      return std::min(f1, f2) <= cost(0.0) ? (f1 <= f2 ? x1 : x2) : 0.0;
    };
    std::vector<char> passes(lines.size(), 0);
    auto set = [&](const Members& members, double log_rho, bool count_only) {
      int passing = 0;
      for (const auto& [f, parity] : members) {
        const FaceFit& ff = fits[static_cast<std::size_t>(f)];
        const LineRows rows = ff.rows_at(std::exp(parity ? -log_rho : log_rho));
        for (std::size_t l = ff.first; l < ff.last; ++l) {
          passes[l] = within(l, rows) ? 1 : 0;
          passing += passes[l];
          if (!count_only) lines[l].rows = rows;
        }
      }
      return passing;
    };
    // The fits on two threads (each reads the positions alone; the assembly's 0.4 s of fitting
    // was this stage's longest serial step); set() after them in face order, as before.
    std::vector<double> own(static_cast<std::size_t>(pairs), 0.0);
    std::vector<int> fitted;  // faces with lines
    for (int f = 0; f < pairs; ++f)
      if (fits[static_cast<std::size_t>(f)].last > fits[static_cast<std::size_t>(f)].first) fitted.push_back(f);
    core::parallel_for(fitted.size(), [&](std::size_t k) { own[static_cast<std::size_t>(fitted[k])] = fit({{fitted[k], 0}}); }, 4);
    std::map<int, Members> sheets;  // root -> (face, parity)
    for (const int f : fitted) {
      set({{f, 0}}, own[static_cast<std::size_t>(f)], false);
      const auto [root, parity] = find(f);
      if (!conflict[static_cast<std::size_t>(root)]) sheets[root].push_back({f, parity});
    }
    // Faces linked through regular edges (a sheet) need one ratio for the edges' tensor rows. One
    // ratio for a whole sheet moves its lines more than each face's own, so more lines may leave
    // the bounds (the plate with every sheet shared: 8,582 lines and 13 edge points, against 9,913
    // lines and none as below; the torus gains 76 and loses none): a sheet takes its shared ratio when
    // that keeps as many C2 functions — two per line within the bounds, four per edge point
    // whose two lines in the sheet are (the other four come with its other direction's sheet).
    std::map<int, std::vector<std::array<int, 2>>> edge_lines_of;  // root -> edge points' line pairs
    for (const EdgePoint& e : edges)
      for (const int pair : {0, 2})
        edge_lines_of[find(face_of_line[static_cast<std::size_t>(e.line[static_cast<std::size_t>(pair)])]).first].push_back(
            {e.line[static_cast<std::size_t>(pair)], e.line[static_cast<std::size_t>(pair + 1)]});
    std::map<int, std::pair<int, double>> shared_sheets;  // root -> (its lines within the bounds alone, the shared ratio)
    // Sheets on two threads too: each touches its own lines' `passes` and rows alone (a sheet's
    // edge point pairs are lines of its faces).
    std::vector<std::pair<int, const Members*>> linked;
    for (const auto& [root, members] : sheets)
      if (members.size() >= 2) linked.emplace_back(root, &members);
    std::vector<std::optional<std::pair<int, double>>> taken(linked.size());
    core::parallel_for(linked.size(), [&](std::size_t k) {
      const auto& [root, members] = linked[k];
      int alone = 0;
      for (const auto& [f, parity] : *members) alone += set({{f, 0}}, own[static_cast<std::size_t>(f)], true);
      const double shared = fit(*members);
      int together = 2 * set(*members, shared, true);
      if (const auto it = edge_lines_of.find(root); it != edge_lines_of.end())
        for (const auto& [l0, l1] : it->second) together += passes[static_cast<std::size_t>(l0)] && passes[static_cast<std::size_t>(l1)] ? 4 : 0;
      if (together >= 2 * alone) set(*members, shared, false), taken[k] = std::pair{alone, shared};
    }, 1);
    for (std::size_t k = 0; k < linked.size(); ++k)
      if (taken[k]) shared_sheets[linked[k].first] = *taken[k];
    // Then counted again with the edge points that hold (both directions' sheets shared, their
    // extras within the bounds): a sheet whose edges do not goes back to its faces' own ratios.
    for (int pass = 0; pass < 2; ++pass) {
      std::map<int, int> held;  // root -> 4 per edge point's line pair that holds
      for (EdgePoint& e : edges) {
        if (!e.set_rows(lines) || !edge_within(e)) continue;
        bool lines_within = true;
        for (const int l : e.line) lines_within = lines_within && within(static_cast<std::size_t>(l), lines[static_cast<std::size_t>(l)].rows);
        if (!lines_within) continue;
        for (const int pair : {0, 2}) held[find(face_of_line[static_cast<std::size_t>(e.line[static_cast<std::size_t>(pair)])]).first] += 4;
      }
      for (auto it = shared_sheets.begin(); it != shared_sheets.end();) {
        const auto& [root, figures] = *it;
        if (2 * set(sheets[root], figures.second, true) + held[root] >= 2 * figures.first) {
          ++it;
          continue;
        }
        for (const auto& [f, parity] : sheets[root]) set({{f, 0}}, own[static_cast<std::size_t>(f)], false);
        it = shared_sheets.erase(it);
      }
    }
  }
  // Each edge point's rows: the tensor product of its u lines' and v lines' rows (which must
  // agree on either side of the edge).
  for (EdgePoint& e : edges) e.ok = e.set_rows(lines);
  // A row names free points only: drop lines whose rows name another line's extra (or whose
  // extras are another's), and edge points likewise or with a line dropped, until none does.
  std::vector<char> keep(lines.size(), 1);
  for (bool changed = true; changed;) {
    changed = false;
    std::map<int, int> extra_count;
    for (std::size_t l = 0; l < lines.size(); ++l)
      if (keep[l]) ++extra_count[lines[l].extra_a], ++extra_count[lines[l].extra_b];
    for (const EdgePoint& e : edges)
      if (e.ok)
        for (const int x : e.extras) ++extra_count[x];
    for (std::size_t l = 0; l < lines.size(); ++l) {
      if (!keep[l]) continue;
      bool bad = extra_count[lines[l].extra_a] > 1 || extra_count[lines[l].extra_b] > 1 || lines[l].extra_a == lines[l].extra_b;
      for (const int ref : lines[l].refs) bad = bad || extra_count.count(ref) > 0;
      if (bad) keep[l] = 0, changed = true;
    }
    for (EdgePoint& e : edges) {
      if (!e.ok) continue;
      bool bad = false;
      for (const int x : e.extras) bad = bad || extra_count[x] > 1;
      for (const int ref : e.kept) bad = bad || extra_count.count(ref) > 0;
      for (const int l : e.line) bad = bad || !keep[static_cast<std::size_t>(l)];
      if (bad) e.ok = false, changed = true;
    }
  }
  if (bounded)
    for (std::size_t l = 0; l < lines.size(); ++l)
      if (keep[l] && !within(l, lines[l].rows)) keep[l] = 0, ++r.lines_kept;
  if (!params.project)  // only where the spline is C2 along the line already
    for (std::size_t l = 0; l < lines.size(); ++l)
      for (int side = 0; side < 2 && keep[l]; ++side) {
        if (distance_of(row_point(lines[l], side), position[static_cast<std::size_t>(side ? lines[l].extra_b : lines[l].extra_a)]) > tol) keep[l] = 0;
      }
  // Edge points: the same bounds on their eight extras; none with a line left C0.
  for (EdgePoint& e : edges) {
    for (const int l : e.line) e.ok = e.ok && keep[static_cast<std::size_t>(l)];
    e.ok = e.ok && (!params.project || edge_within(e));
    if (!params.project)
      for (int x = 0; x < 8 && e.ok; ++x)
        if (distance_of(kept_row_point(e, x), position[static_cast<std::size_t>(e.extras[static_cast<std::size_t>(x)])]) > tol) e.ok = false;
  }
  std::vector<std::vector<TMesh::Constraint>> added(blocks.size());
  std::set<int> faces_used;
  // Node `id` moves to x and becomes a smooth row (ids, weights) in every block that holds it.
  auto constrain = [&](int id, const Vec3& x, const std::vector<int>& ids, const std::vector<double>& weights) {
    r.moved_max = std::max(r.moved_max, distance_of(x, position[static_cast<std::size_t>(id)]));
    for (const auto& [blk, at] : where[static_cast<std::size_t>(id)]) {
      blocks[static_cast<std::size_t>(blk)].control_points[at] = x;
      TMesh::Constraint c;
      c.point = static_cast<int>(at);
      c.smooth = true;
      c.ids = ids, c.weights = weights;
      added[static_cast<std::size_t>(blk)].push_back(std::move(c));
    }
    ++r.constrained;
  };
  for (const EdgePoint& e : edges) {
    if (!e.ok) continue;
    for (int x = 0; x < 8; ++x) {
      // The corners name all nine kept points in their order (smooth_rows_as_bsplines reads the
      // edge's layout from it); the others the three their rows reach.
      std::vector<int> ids;
      std::vector<double> weights;
      for (int k = 0; k < 9; ++k)
        if (e.w[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)] != 0 || EdgePoint::corner(x))
          ids.push_back(e.kept[static_cast<std::size_t>(k)]), weights.push_back(e.w[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)]);
      constrain(e.extras[static_cast<std::size_t>(x)], kept_row_point(e, x), ids, weights);
    }
    ++r.edge_points;
  }
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (!keep[l]) continue;
    const Line& line = lines[l];
    for (int side = 0; side < 2; ++side) {
      const std::array<double, 3>& wt = side ? line.rows.b : line.rows.a;
      std::vector<int> ids;
      std::vector<double> weights;
      for (int k = 0; k < 3; ++k)
        if (wt[static_cast<std::size_t>(k)] != 0) ids.push_back(line.refs[static_cast<std::size_t>(k)]), weights.push_back(wt[static_cast<std::size_t>(k)]);
      constrain(side ? line.extra_b : line.extra_a, row_point(line, side), ids, weights);
    }
    ++r.lines;
    r.surface_lines += line.surface ? 1 : 0;
    faces_used.insert(face_of_line[l]);
  }
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (added[b].empty()) continue;
    auto& cs = blocks[b].constraints;
    cs.insert(cs.end(), added[b].begin(), added[b].end());
    std::sort(cs.begin(), cs.end(), [](const TMesh::Constraint& x, const TMesh::Constraint& y) { return x.point < y.point; });
  }
  r.faces = static_cast<int>(faces_used.size());
  r.faces_kept = pairs - r.faces;
  return r;
}

int smooth_rows_as_bsplines(std::vector<TMesh>& blocks) {
  int nodes = 0;
  for (const TMesh& t : blocks) {
    for (const int id : t.function_ids) nodes = std::max(nodes, id + 1);
    for (const auto& f : t.free_nodes) nodes = std::max(nodes, f.id + 1);
  }
  const Occurrences where = occurrences(blocks, nodes);
  auto position = [&](int id) { return blocks[static_cast<std::size_t>(where[static_cast<std::size_t>(id)].at(0).first)].control_points[where[static_cast<std::size_t>(id)][0].second]; };
  auto holds = [&](int b, int id) {
    for (const auto& [blk, at] : where[static_cast<std::size_t>(id)])
      if (blk == b) return true;
    return false;
  };
  // The smooth rows by their three ids (TA, F, TB): the extra on A's side (its block holds TA)
  // and on B's, each with its weights.
  struct Side {
    int extra = -1;
    std::array<double, 3> w{};
  };
  std::map<std::array<int, 3>, std::array<Side, 2>> lines;
  std::vector<char> constrained(static_cast<std::size_t>(nodes), 0);
  std::vector<std::vector<int>> named_by(static_cast<std::size_t>(nodes));  // node -> the constrained points whose rows name it (sorted below)
  std::map<std::array<int, 9>, std::vector<int>> corners;     // an edge point's kept nine -> its corner extras
  std::map<std::array<int, 3>, std::vector<int>> three_rows;  // a row's three ids -> the points with it
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (const auto& k : blocks[b].constraints) {
      const int point = blocks[b].function_ids[static_cast<std::size_t>(k.point)];
      const bool first = !constrained[static_cast<std::size_t>(point)];
      constrained[static_cast<std::size_t>(point)] = 1;
      for (const int m : k.ids) {
        if (m < 0 || m >= nodes) throw core::InvalidInputError("smooth_rows_as_bsplines: a row names node " + std::to_string(m) + ", no node of the blocks");
        named_by[static_cast<std::size_t>(m)].push_back(point);
      }
      if (!k.smooth) continue;
      if (k.ids.size() == 9 && first) {
        std::array<int, 9> key{};
        std::copy(k.ids.begin(), k.ids.end(), key.begin());
        corners[key].push_back(point);
      }
      if (k.ids.size() != 3) continue;
      const std::array<int, 3> key{k.ids[0], k.ids[1], k.ids[2]};
      if (first) three_rows[key].push_back(point);
      const int side = holds(static_cast<int>(b), key[0]) ? 0 : 1;
      lines[key][static_cast<std::size_t>(side)] = {point, {k.weights[0], k.weights[1], k.weights[2]}};
    }
  for (auto& v : named_by) std::sort(v.begin(), v.end()), v.erase(std::unique(v.begin(), v.end()), v.end());
  // Regular edge points (raise_continuity's regular_edges): the nine kept points in their order,
  // the four corners, and the four points between them with three-id rows.
  struct Edge {
    std::array<int, 9> kept{};
    std::array<std::array<int, 3>, 3> p{};  // P(i, j), i, j in {-1, 0, 1}
    std::array<std::array<int, 3>, 4> line_keys{};  // u lines at j = -2, 2, v lines at i = -2, 2 (minus to plus)
  };
  std::vector<Edge> edges;
  std::set<int> edge_points;  // every point an edge's rows write
  for (const auto& [K, cs] : corners) {
    if (cs.size() != 4) continue;
    Edge e;
    e.kept = K;
    e.p[1][1] = K[4];
    // A point's quadrant: the kept corner P(+-2, +-2) one of its blocks holds.
    auto shares = [&](int point, int id) {
      for (const auto& [blk, at] : where[static_cast<std::size_t>(point)])
        if (holds(blk, id)) return true;
      return false;
    };
    bool fine = true;
    int placed = 0;
    for (const int c : cs)
      for (const auto& [k, i, j] : std::array<std::array<int, 3>, 4>{{{0, 0, 0}, {2, 0, 2}, {6, 2, 0}, {8, 2, 2}}})
        if (shares(c, K[static_cast<std::size_t>(k)])) e.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = c, ++placed;
    fine = placed == 4;
    const auto across_u = three_rows.find({K[1], K[4], K[7]});  // P(-1, 0), P(1, 0)
    const auto across_v = three_rows.find({K[3], K[4], K[5]});  // P(0, -1), P(0, 1)
    fine = fine && across_u != three_rows.end() && across_u->second.size() == 2 && across_v != three_rows.end() && across_v->second.size() == 2;
    if (!fine) continue;
    for (const int x : across_u->second) e.p[shares(x, K[1]) ? 0 : 2][1] = x;
    for (const int x : across_v->second) e.p[1][shares(x, K[3]) ? 0 : 2] = x;
    std::set<int> eight;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != 1 || j != 1) eight.insert(e.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
    // Eight distinct points, and only they name the edge point.
    if (eight.size() != 8 || constrained[static_cast<std::size_t>(K[4])] || named_by[static_cast<std::size_t>(K[4])] != std::vector<int>(eight.begin(), eight.end())) continue;
    e.line_keys = {{{K[0], K[3], K[6]}, {K[2], K[5], K[8]}, {K[0], K[1], K[2]}, {K[6], K[7], K[8]}}};
    edge_points.insert(eight.begin(), eight.end());
    edges.push_back(e);
  }
  // Each line's B-spline rows (not yet written): XA = a TA + (1-a) V, F = b TA + c V + d TB,
  // XB = (1-e) V + e TB.
  struct Conversion {
    int xa = -1, xb = -1;
    double a = 0, b = 0, c = 0, d = 0, e = 0;
    Vec3 v{};
    bool ok = false;
    int id = -1;
  };
  std::map<std::array<int, 3>, Conversion> conversions;
  constexpr double kTol = 1e-9;
  auto unit = [](double x) { return x >= -kTol && x <= 1 + kTol; };
  for (const auto& [key, sides] : lines) {
    const auto& [ta, f, tb] = key;
    // F becomes a row: no other row may name it (but an edge point's), and it must be free.
    std::set<int> names;
    for (const int x : named_by[static_cast<std::size_t>(f)])
      if (!edge_points.count(x)) names.insert(x);
    if (sides[0].extra < 0 || sides[1].extra < 0 || constrained[static_cast<std::size_t>(f)] || names != std::set<int>{sides[0].extra, sides[1].extra}) continue;
    const auto& w = sides[0].w;  // XA = w0 TA + w1 F + w2 TB
    const auto& u = sides[1].w;  // XB = u0 TA + u1 F + u2 TB
    if (std::abs(w[1]) < kTol || std::abs(u[1]) < kTol) continue;
    Conversion cv;
    cv.xa = sides[0].extra, cv.xb = sides[1].extra;
    cv.b = -u[0] / u[1], cv.d = -w[2] / w[1], cv.c = 1 - cv.b - cv.d;
    cv.a = w[0] + w[1] * cv.b, cv.e = u[2] + u[1] * cv.d;
    if (!(unit(cv.a) && unit(cv.b) && unit(cv.c) && unit(cv.d) && unit(cv.e)) || std::abs((1 - cv.a) - w[1] * cv.c) > kTol ||
        std::abs((1 - cv.e) - u[1] * cv.c) > kTol || !(1 - cv.a > kTol))
      continue;
    const Vec3 xa = position(cv.xa), pa = position(ta);
    for (int k = 0; k < 3; ++k) cv.v[static_cast<std::size_t>(k)] = (xa[static_cast<std::size_t>(k)] - cv.a * pa[static_cast<std::size_t>(k)]) / (1 - cv.a);
    cv.ok = true;
    conversions[key] = cv;
  }
  // Each edge point's: the 3 x 3 points around it rows of G(k, l), k, l in (minus two-in, the
  // line's node, plus two-in) — the four kept corners, the four lines' nodes and a new node W —
  // with the tensor product of the lines' weights. An edge whose lines do not all convert, or
  // whose points are not where those rows put them, keeps its rows, and so do its lines.
  using T3 = std::array<std::array<double, 3>, 3>;
  struct EdgeConversion {
    T3 tu{}, tv{};
    std::array<std::array<int, 3>, 4> keys{};  // the lines' keys as stored
    Vec3 w{};
    bool ok = false;
    int id = -1;
  };
  std::vector<EdgeConversion> edge_conv(edges.size());
  auto oriented = [&](const std::array<int, 3>& key, std::array<int, 3>& stored, T3& t) {
    const std::array<int, 3> reversed{key[2], key[1], key[0]};
    auto it = conversions.find(key);
    const bool flipped = it == conversions.end();
    if (flipped) it = conversions.find(reversed);
    if (it == conversions.end() || !it->second.ok) return false;
    stored = flipped ? reversed : key;
    const Conversion& c = it->second;
    const T3 own{{{c.a, 1 - c.a, 0}, {c.b, c.c, c.d}, {0, 1 - c.e, c.e}}};
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)] = flipped ? own[static_cast<std::size_t>(2 - r)][static_cast<std::size_t>(2 - k)] : own[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)];
    return true;
  };
  auto near = [](const T3& x, const T3& y) {
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        if (std::abs(x[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)] - y[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)]) > kTol) return false;
    return true;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t n = 0; n < edges.size(); ++n) {
      const Edge& e = edges[n];
      EdgeConversion& ec = edge_conv[n];
      T3 tu1{}, tv1{};
      ec.ok = oriented(e.line_keys[0], ec.keys[0], ec.tu) && oriented(e.line_keys[1], ec.keys[1], tu1) && oriented(e.line_keys[2], ec.keys[2], ec.tv) &&
              oriented(e.line_keys[3], ec.keys[3], tv1) && near(ec.tu, tu1) && near(ec.tv, tv1);
      if (ec.ok) {
        // G's points; W from the edge point itself, then every other point checked.
        const auto& K = e.kept;
        std::array<std::array<Vec3, 3>, 3> G{};
        G[0][0] = position(K[0]), G[0][2] = position(K[2]), G[2][0] = position(K[6]), G[2][2] = position(K[8]);
        G[0][1] = conversions[ec.keys[2]].v, G[2][1] = conversions[ec.keys[3]].v;
        G[1][0] = conversions[ec.keys[0]].v, G[1][2] = conversions[ec.keys[1]].v;
        auto combine = [&](int i, int j, bool with_w) {
          Vec3 x{0, 0, 0};
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l) {
              if (k == 1 && l == 1 && !with_w) continue;
              const double wt = ec.tu[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] * ec.tv[static_cast<std::size_t>(j)][static_cast<std::size_t>(l)];
              for (int d = 0; d < 3; ++d) x[static_cast<std::size_t>(d)] += wt * G[static_cast<std::size_t>(k)][static_cast<std::size_t>(l)][static_cast<std::size_t>(d)];
            }
          return x;
        };
        const double cc = ec.tu[1][1] * ec.tv[1][1];
        const Vec3 rest = combine(1, 1, false), x00 = position(K[4]);
        ec.ok = cc > kTol;
        for (int d = 0; d < 3 && ec.ok; ++d) G[1][1][static_cast<std::size_t>(d)] = ec.w[static_cast<std::size_t>(d)] = (x00[static_cast<std::size_t>(d)] - rest[static_cast<std::size_t>(d)]) / cc;
        for (int i = 0; i < 3 && ec.ok; ++i)
          for (int j = 0; j < 3 && ec.ok; ++j) {
            const Vec3 y = position(e.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
            ec.ok = distance_of(combine(i, j, true), y) <= kTol * (1 + distance_of(y, Vec3{0, 0, 0}));
          }
      }
      if (ec.ok) continue;
      // Its lines keep their rows (the edge's name their face points).
      for (const auto& key : e.line_keys)
        for (const auto& k : {key, std::array<int, 3>{key[2], key[1], key[0]}}) {
          auto it = conversions.find(k);
          if (it != conversions.end() && it->second.ok) it->second.ok = false, changed = true;
        }
    }
  }
  // The rows of every point by id, then written into each block that holds the point.
  std::map<int, std::pair<std::vector<int>, std::vector<double>>> rows;
  std::map<int, std::set<int>> free_of_block;  // block -> free node ids its rows name
  std::map<int, Vec3> free_point;
  int rewritten = 0;
  auto uses = [&](int id, int v) {
    for (const auto& [blk, at] : where[static_cast<std::size_t>(id)]) free_of_block[blk].insert(v);
  };
  for (auto& [key, cv] : conversions) {
    if (!cv.ok) continue;
    const auto& [ta, f, tb] = key;
    const int v = cv.id = nodes++;
    free_point[v] = cv.v;
    rows[cv.xa] = {{ta, v}, {cv.a, 1 - cv.a}};
    rows[f] = {{ta, v, tb}, {cv.b, cv.c, cv.d}};
    rows[cv.xb] = {{v, tb}, {1 - cv.e, cv.e}};
    for (const int id : {cv.xa, f, cv.xb}) uses(id, v);
    ++rewritten;
  }
  for (std::size_t n = 0; n < edges.size(); ++n) {
    EdgeConversion& ec = edge_conv[n];
    if (!ec.ok) continue;
    const Edge& e = edges[n];
    const auto& K = e.kept;
    const int wid = ec.id = nodes++;
    free_point[wid] = ec.w;
    const std::array<std::array<int, 3>, 3> G{{{K[0], conversions[ec.keys[2]].id, K[2]},
                                               {conversions[ec.keys[0]].id, wid, conversions[ec.keys[1]].id},
                                               {K[6], conversions[ec.keys[3]].id, K[8]}}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int point = e.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
        auto& row = rows[point];
        row = {};
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l) {
            const double wt = ec.tu[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] * ec.tv[static_cast<std::size_t>(j)][static_cast<std::size_t>(l)];
            if (wt == 0) continue;
            const int g = G[static_cast<std::size_t>(k)][static_cast<std::size_t>(l)];
            row.first.push_back(g), row.second.push_back(wt);
            if (g >= static_cast<int>(where.size())) uses(point, g);  // a free node
          }
      }
  }
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    TMesh& t = blocks[b];
    bool changed = false;
    for (auto& k : t.constraints) {
      const auto it = rows.find(t.function_ids[static_cast<std::size_t>(k.point)]);
      if (it == rows.end()) continue;
      k.ids = it->second.first, k.weights = it->second.second, changed = true;
    }
    std::vector<char> has_row(t.function_ids.size(), 0);
    for (const auto& k : t.constraints) has_row[static_cast<std::size_t>(k.point)] = 1;
    for (std::size_t i = 0; i < t.function_ids.size(); ++i) {  // face points: new rows
      if (has_row[i]) continue;
      const auto it = rows.find(t.function_ids[i]);
      if (it == rows.end()) continue;
      TMesh::Constraint k;
      k.point = static_cast<int>(i), k.ids = it->second.first, k.weights = it->second.second, k.smooth = true;
      t.constraints.push_back(std::move(k));
      changed = true;
    }
    if (!changed) continue;
    std::sort(t.constraints.begin(), t.constraints.end(), [](const TMesh::Constraint& x, const TMesh::Constraint& y) { return x.point < y.point; });
    for (const int v : free_of_block[static_cast<int>(b)]) t.free_nodes.push_back({v, free_point[v]});
    std::sort(t.free_nodes.begin(), t.free_nodes.end(), [](const TMesh::FreeNode& x, const TMesh::FreeNode& y) { return x.id < y.id; });
  }
  return rewritten;
}

}  // namespace volts::tmesh
