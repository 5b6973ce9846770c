#include "tmesh/continuity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "bezier/bspline.h"
#include "core/errors.h"

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
  auto distance = [](const Vec3& x, const Vec3& y) { return std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]); };
  using RowKey = std::vector<double>;  // (nA, nB) for unit intervals, else the knots across the face
  std::map<RowKey, LineRows> rows_of;
  std::vector<Line> lines;
  std::vector<int> face_of_line;
  // Faces of two blocks of one level, neither with T-junctions.
  const std::vector<SharedFace> faces = shared_faces(blocks);
  const int pairs = static_cast<int>(faces.size());
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
    if (params.fit_ratio && params.project && lines.size() > face_first) {
      // The rows at ratio rho (A's knots scaled by rho against B's) and how far they move the
      // face's extras (sum of squares).
      auto rows_at = [&](double rho) {
        std::vector<double> sa = ka, sb = kb;
        for (double& x : sa) x *= rho;
        for (double& x : sb) x += la * (rho - 1);
        return line_rows_on(sa, la * rho, sb, la * rho + lb);
      };
      auto cost = [&](double log_rho) {
        const LineRows rows = rows_at(std::exp(log_rho));
        double c = 0;
        for (std::size_t l = face_first; l < lines.size(); ++l)
          for (int side = 0; side < 2; ++side) {
            const double d = distance(row_point_of(rows, lines[l].refs, side), position[static_cast<std::size_t>(side ? lines[l].extra_b : lines[l].extra_a)]);
            c += d * d;
          }
        return c;
      };
      // Golden-section search on log rho in [-log 8, log 8] (the cost is smooth in rho).
      const double g = 0.5 * (std::sqrt(5.0) - 1.0);
      double lo = -std::log(8.0), hi = std::log(8.0);
      double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = cost(x1), f2 = cost(x2);
      for (int iter = 0; iter < 40 && hi - lo > 1e-4; ++iter) {
        if (f1 <= f2) hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = cost(x1);
        else lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = cost(x2);
      }
      // The search finds a local minimum: index space's ratio when that moves less.
      const double best = f1 <= f2 ? x1 : x2;
      const LineRows rows = rows_at(std::exp(std::min(f1, f2) <= cost(0.0) ? best : 0.0));
      for (std::size_t l = face_first; l < lines.size(); ++l) lines[l].rows = rows;
    }
  }
  // A row names free points only: drop lines whose rows name another line's extra (or whose
  // extras are another's), until none does.
  std::vector<char> keep(lines.size(), 1);
  for (bool changed = true; changed;) {
    changed = false;
    std::map<int, int> extra_count;
    for (std::size_t l = 0; l < lines.size(); ++l)
      if (keep[l]) ++extra_count[lines[l].extra_a], ++extra_count[lines[l].extra_b];
    for (std::size_t l = 0; l < lines.size(); ++l) {
      if (!keep[l]) continue;
      bool bad = extra_count[lines[l].extra_a] > 1 || extra_count[lines[l].extra_b] > 1 || lines[l].extra_a == lines[l].extra_b;
      for (const int ref : lines[l].refs) bad = bad || extra_count.count(ref) > 0;
      if (bad) keep[l] = 0, changed = true;
    }
  }
  if (params.project && (std::isfinite(params.max_move_rel) || params.surface_layer))
    for (std::size_t l = 0; l < lines.size(); ++l)
      for (int side = 0; side < 2 && keep[l]; ++side) {
        const int extra = side ? lines[l].extra_b : lines[l].extra_a;
        const Vec3& y = position[static_cast<std::size_t>(extra)];
        // Its nearest neighbour in its block's grid (a thin slab's: across the slab).
        double reach = std::numeric_limits<double>::infinity();
        for (const auto& [blk, at] : where[static_cast<std::size_t>(extra)]) {
          const TMesh& t = blocks[static_cast<std::size_t>(blk)];
          const std::array<int, 3> g = grid_index(t, at);
          for (int axis = 0; axis < 3; ++axis)
            for (const int step : {-1, 1}) {
              std::array<int, 3> n = g;
              n[static_cast<std::size_t>(axis)] += step;
              if (n[static_cast<std::size_t>(axis)] < 0 || n[static_cast<std::size_t>(axis)] >= t.size[axis]) continue;
              reach = std::min(reach, distance(y, t.control_points[local_index(t, n)]));
            }
        }
        const double move = distance(row_point(lines[l], side), y);
        if (move > params.max_move_rel * reach || (lines[l].surface && move > params.surface_move_max)) keep[l] = 0, ++r.lines_kept;
      }
  if (!params.project)  // only where the spline is C2 along the line already
    for (std::size_t l = 0; l < lines.size(); ++l)
      for (int side = 0; side < 2 && keep[l]; ++side) {
        const Vec3 x = row_point(lines[l], side);
        const Vec3& y = position[static_cast<std::size_t>(side ? lines[l].extra_b : lines[l].extra_a)];
        if (std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]) > tol) keep[l] = 0;
      }
  std::vector<std::vector<TMesh::Constraint>> added(blocks.size());
  std::set<int> faces_used;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (!keep[l]) continue;
    const Line& line = lines[l];
    for (int side = 0; side < 2; ++side) {
      const int extra = side ? line.extra_b : line.extra_a;
      const std::array<double, 3>& wt = side ? line.rows.b : line.rows.a;
      const Vec3 x = row_point(line, side);
      r.moved_max = std::max(r.moved_max, distance(x, position[static_cast<std::size_t>(extra)]));
      for (const auto& [blk, at] : where[static_cast<std::size_t>(extra)]) {
        blocks[static_cast<std::size_t>(blk)].control_points[at] = x;
        TMesh::Constraint c;
        c.point = static_cast<int>(at);
        c.smooth = true;
        for (int k = 0; k < 3; ++k)
          if (wt[static_cast<std::size_t>(k)] != 0) c.ids.push_back(line.refs[static_cast<std::size_t>(k)]), c.weights.push_back(wt[static_cast<std::size_t>(k)]);
        added[static_cast<std::size_t>(blk)].push_back(std::move(c));
      }
      ++r.constrained;
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
  std::set<int> constrained;
  std::map<int, std::set<int>> named_by;  // node -> the constrained points whose rows name it
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (const auto& k : blocks[b].constraints) {
      constrained.insert(blocks[b].function_ids[static_cast<std::size_t>(k.point)]);
      for (const int m : k.ids) named_by[m].insert(blocks[b].function_ids[static_cast<std::size_t>(k.point)]);
      if (!k.smooth || k.ids.size() != 3) continue;
      const std::array<int, 3> key{k.ids[0], k.ids[1], k.ids[2]};
      const int side = holds(static_cast<int>(b), key[0]) ? 0 : 1;
      lines[key][static_cast<std::size_t>(side)] = {blocks[b].function_ids[static_cast<std::size_t>(k.point)], {k.weights[0], k.weights[1], k.weights[2]}};
    }
  // The rows of every point by id, then written into each block that holds the point.
  std::map<int, std::pair<std::vector<int>, std::vector<double>>> rows;
  std::map<int, std::set<int>> free_of_block;  // block -> free node ids its rows name
  std::map<int, Vec3> free_point;
  int rewritten = 0;
  constexpr double kTol = 1e-9;
  auto unit = [](double x) { return x >= -kTol && x <= 1 + kTol; };
  for (const auto& [key, sides] : lines) {
    const auto& [ta, f, tb] = key;
    // F becomes a row: no other row may name it, and it must be free.
    if (sides[0].extra < 0 || sides[1].extra < 0 || constrained.count(f) || named_by[f] != std::set<int>{sides[0].extra, sides[1].extra}) continue;
    const auto& w = sides[0].w;  // XA = w0 TA + w1 F + w2 TB
    const auto& u = sides[1].w;  // XB = u0 TA + u1 F + u2 TB
    if (std::abs(w[1]) < kTol || std::abs(u[1]) < kTol) continue;
    const double b = -u[0] / u[1], d = -w[2] / w[1], c = 1 - b - d;
    const double a = w[0] + w[1] * b, e = u[2] + u[1] * d;
    if (!(unit(a) && unit(b) && unit(c) && unit(d) && unit(e)) || std::abs((1 - a) - w[1] * c) > kTol || std::abs((1 - e) - u[1] * c) > kTol || !(1 - a > kTol))
      continue;
    const int v = nodes++;
    const Vec3 xa = position(sides[0].extra), pa = position(ta);
    Vec3 pv{};
    for (int k = 0; k < 3; ++k) pv[static_cast<std::size_t>(k)] = (xa[static_cast<std::size_t>(k)] - a * pa[static_cast<std::size_t>(k)]) / (1 - a);
    free_point[v] = pv;
    rows[sides[0].extra] = {{ta, v}, {a, 1 - a}};
    rows[f] = {{ta, v, tb}, {b, c, d}};
    rows[sides[1].extra] = {{v, tb}, {1 - e, e}};
    for (const int id : {sides[0].extra, f, sides[1].extra})
      for (const auto& [blk, at] : where[static_cast<std::size_t>(id)]) free_of_block[blk].insert(v);
    ++rewritten;
  }
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    TMesh& t = blocks[b];
    bool changed = false;
    for (auto& k : t.constraints) {
      const auto it = rows.find(t.function_ids[static_cast<std::size_t>(k.point)]);
      if (it == rows.end()) continue;
      k.ids = it->second.first, k.weights = it->second.second, changed = true;
    }
    for (std::size_t i = 0; i < t.function_ids.size(); ++i) {  // face points: new rows
      const auto it = rows.find(t.function_ids[i]);
      if (it == rows.end() || std::any_of(t.constraints.begin(), t.constraints.end(), [&](const TMesh::Constraint& k) { return k.point == static_cast<int>(i); })) continue;
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
