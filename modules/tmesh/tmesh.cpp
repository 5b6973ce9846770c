#include "tmesh/tmesh.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "core/errors.h"
#include "core/log.h"
#include "core/parallel.h"
#include "tmesh/pillow.h"
#include "viz/viz.h"

namespace volts::tmesh {

using Vec3 = std::array<double, 3>;

int TMesh::elements() const {
  int n = 1;
  for (int a = 0; a < 3; ++a) n *= static_cast<int>(bezier::element_spans(knots[a], degree).size());
  return n;
}

namespace {

// Collocation matrix of the B-spline basis at the Greville points (square, non-singular by
// Schoenberg–Whitney).
Eigen::MatrixXd collocation(const std::vector<double>& knots, int degree, const std::vector<double>& g) {
  const int n = static_cast<int>(g.size());
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, n);
  for (int a = 0; a < n; ++a) {
    const auto b = bezier::basis_functions(knots, degree, g[a]);
    for (int k = 0; k <= degree; ++k) N(a, b.span - degree + k) = b.values[k];
  }
  return N;
}

void check(const Params& params) {
  if (params.level < 1 || params.level > 7) throw core::ConfigError("tmesh.level must be in [1, 7], got " + std::to_string(params.level));
  if (params.degree < 1 || params.degree > 5) throw core::ConfigError("tmesh.degree must be in [1, 5], got " + std::to_string(params.degree));
  if (params.pillow_layers < 0 || params.pillow_layers > 4)
    throw core::ConfigError("tmesh.pillow_layers must be in [0, 4], got " + std::to_string(params.pillow_layers));
  if (params.h_refine < 0 || params.h_refine > 3) throw core::ConfigError("tmesh.h_refine must be in [0, 3], got " + std::to_string(params.h_refine));
  if (params.deviation_samples < 2 || params.deviation_samples > 64)
    throw core::ConfigError("tmesh.deviation_samples must be in [2, 64], got " + std::to_string(params.deviation_samples));
  if (params.pillow_splits < 1 || params.pillow_splits > 8)
    throw core::ConfigError("tmesh.pillow_splits must be in [1, 8], got " + std::to_string(params.pillow_splits));
  if (params.pillow_splits > 1 && params.pillow_layers == 0)
    throw core::ConfigError("tmesh.pillow_splits " + std::to_string(params.pillow_splits) + " needs a pillow to split (tmesh.pillow_layers is 0)");
}

// The axis across the surface of a pillow slab (its surface faces all on one axis), else -1.
int slab_axis(bool pillow, const std::array<int, 6>& boundary) {
  if (!pillow) return -1;
  int axis = -1;
  for (int f = 0; f < 6; ++f) {
    if (!boundary[static_cast<std::size_t>(f)]) continue;
    if (axis >= 0 && axis != f / 2) return -1;
    axis = f / 2;
  }
  return axis;
}

}  // namespace

namespace {

// One block on the given clamped knot vectors, interpolating `map` at their Greville points.
TMesh build_block_on(const PointMap& map, int degree, const std::array<std::vector<double>, 3>& knots) {
  TMesh t;
  t.degree = degree;
  std::array<std::vector<double>, 3> g;
  for (int a = 0; a < 3; ++a) {
    t.knots[a] = knots[a];
    g[a] = bezier::greville_abscissae(t.knots[a], degree);
    t.size[a] = static_cast<int>(g[a].size());
  }
  const std::array<std::size_t, 3> m{static_cast<std::size_t>(t.size[0]), static_cast<std::size_t>(t.size[1]),
                                     static_cast<std::size_t>(t.size[2])};
  // Sample the volume map at the Greville points, then solve N ⊗ N ⊗ N · P = D one axis at a time.
  // Without a map, the structure alone (control points at the origin; h_refine sets them after).
  const std::size_t total = m[0] * m[1] * m[2];
  t.parameters.resize(total);
  for (std::size_t k = 0; k < m[2]; ++k)
    for (std::size_t j = 0; j < m[1]; ++j)
      for (std::size_t i = 0; i < m[0]; ++i) t.parameters[i + m[0] * (j + m[1] * k)] = {g[0][i], g[1][j], g[2][k]};
  if (!map) {
    t.control_points.assign(total, Vec3{0, 0, 0});
    return t;
  }
  Eigen::MatrixXd data(total, 3);
  for (std::size_t idx = 0; idx < total; ++idx) {
    const Vec3 x = map(t.parameters[idx]);
    data.row(static_cast<Eigen::Index>(idx)) << x[0], x[1], x[2];
  }
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(collocation(t.knots[axis], degree, g[axis]));
    const std::size_t stride = axis == 0 ? 1 : axis == 1 ? m[0] : m[0] * m[1];
    const std::size_t n = m[axis];
    Eigen::MatrixXd line(static_cast<Eigen::Index>(n), 3);
    for (std::size_t base = 0; base < total; ++base) {
      // base runs over the lines' first points: those with index 0 along `axis`.
      if ((base / stride) % n != 0) continue;
      for (std::size_t a = 0; a < n; ++a) line.row(static_cast<Eigen::Index>(a)) = data.row(static_cast<Eigen::Index>(base + a * stride));
      const Eigen::MatrixXd solved = lu.solve(line);
      for (std::size_t a = 0; a < n; ++a) data.row(static_cast<Eigen::Index>(base + a * stride)) = solved.row(static_cast<Eigen::Index>(a));
    }
  }
  t.control_points.resize(total);
  for (std::size_t i = 0; i < total; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    t.control_points[i] = {data(r, 0), data(r, 1), data(r, 2)};
  }
  return t;
}

}  // namespace

TMesh build_block(const PointMap& map, int degree, const std::array<int, 3>& elements) {
  std::array<std::vector<double>, 3> knots;
  for (int a = 0; a < 3; ++a) knots[a] = bezier::open_uniform_knots(elements[a], degree);
  return build_block_on(map, degree, knots);
}

TMesh build(const PointMap& map, const Params& params) {
  check(params);
  const int n = 1 << params.level;
  TMesh t = build_block(map, params.degree, {n, n, n});
  t.level = params.level;
  return t;
}

namespace {

// Points equal up to `eps` get one id: a hash grid of cell 4·eps, searched in the 27 cells around.
class PointIds {
 public:
  explicit PointIds(double eps) : eps_(eps) {}
  int id(const Vec3& x) {
    const std::array<long long, 3> c{cell(x[0]), cell(x[1]), cell(x[2])};
    // Only the cells a point within eps can lie in (one per axis unless x is within eps of a
    // cell's side), in the order of the 27 around c: the same first match.
    const std::array<long long, 3> lo{cell(x[0] - eps_), cell(x[1] - eps_), cell(x[2] - eps_)};
    const std::array<long long, 3> hi{cell(x[0] + eps_), cell(x[1] + eps_), cell(x[2] + eps_)};
    for (long long cx = lo[0]; cx <= hi[0]; ++cx)
      for (long long cy = lo[1]; cy <= hi[1]; ++cy)
        for (long long cz = lo[2]; cz <= hi[2]; ++cz) {
          const auto it = grid_.find({cx, cy, cz});
          if (it == grid_.end()) continue;
          for (const int i : it->second)
            if (std::abs(points_[i][0] - x[0]) <= eps_ && std::abs(points_[i][1] - x[1]) <= eps_ && std::abs(points_[i][2] - x[2]) <= eps_)
              return i;
        }
    points_.push_back(x);
    grid_[c].push_back(static_cast<int>(points_.size()) - 1);
    return static_cast<int>(points_.size()) - 1;
  }

 private:
  long long cell(double v) const { return static_cast<long long>(std::floor(v / (4 * eps_))); }
  // Hashed: the ids never depend on the cells' order (a cell's own list keeps its insertion
  // order). With the lookups above, the assembly's h-refinement (~200k points) 0.24 -> 0.13 s.
  struct CellHash {
    std::size_t operator()(const std::array<long long, 3>& c) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (const long long v : c) {
        h ^= static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xbf58476d1ce4e5b9ull;
      }
      return static_cast<std::size_t>(h ^ (h >> 31));
    }
  };
  double eps_;
  std::vector<Vec3> points_;
  std::unordered_map<std::array<long long, 3>, std::vector<int>, CellHash> grid_;
};

}  // namespace

namespace {

// Control point index of (i, j) on face 2*axis + side of block t: i along axis (axis+1)%3, j
// along (axis+2)%3.
std::size_t face_point(const TMesh& t, int face, int i, int j) {
  const int a = face / 2;
  std::array<int, 3> idx{};
  idx[static_cast<std::size_t>(a)] = face % 2 ? t.size[a] - 1 : 0;
  idx[static_cast<std::size_t>((a + 1) % 3)] = i;
  idx[static_cast<std::size_t>((a + 2) % 3)] = j;
  return static_cast<std::size_t>(idx[0] + t.size[0] * (idx[1] + t.size[1] * idx[2]));
}
std::array<int, 2> face_size(const TMesh& t, int face) { return {t.size[(face / 2 + 1) % 3], t.size[(face / 2 + 2) % 3]}; }

// Knots of `k` read backwards (u -> 1 - u).
std::vector<double> reversed(const std::vector<double>& k) {
  std::vector<double> r;
  for (auto it = k.rbegin(); it != k.rend(); ++it) r.push_back(1.0 - *it);
  return r;
}

using Row = std::map<int, double>;

// How a block face lies on another with the same four corners (ids at face points (0,0), (1,0),
// (0,1), (1,1), index i + 2j): along[d] is the other face's direction along this one's direction
// d, flip[d] whether it runs backwards. Throws core::TopologyError naming blocks `a` and `b`.
struct FaceFrame {
  std::array<int, 2> along{}, flip{};
};
FaceFrame face_frame(const std::array<int, 4>& here, const std::array<int, 4>& there, std::size_t a, std::size_t b) {
  std::map<int, std::array<int, 2>> at_there;
  for (int c = 0; c < 4; ++c) at_there[there[static_cast<std::size_t>(c)]] = {c & 1, c >> 1};
  std::array<std::array<int, 2>, 3> at{};
  for (int k = 0; k < 3; ++k) {
    const auto it = at_there.find(here[static_cast<std::size_t>(k)]);
    if (it == at_there.end() || at_there.size() != 4)
      throw core::TopologyError("tmesh: blocks " + std::to_string(a) + " and " + std::to_string(b) + " do not meet corner to corner");
    at[static_cast<std::size_t>(k)] = it->second;
  }
  FaceFrame fr;
  if (at[1][0] != at[0][0] && at[1][1] == at[0][1] && at[2][1] != at[0][1] && at[2][0] == at[0][0]) {
    fr.along = {0, 1};
  } else if (at[1][1] != at[0][1] && at[1][0] == at[0][0] && at[2][0] != at[0][0] && at[2][1] == at[0][1]) {
    fr.along = {1, 0};
  } else {
    throw core::TopologyError("tmesh: blocks " + std::to_string(a) + " and " + std::to_string(b) + " meet on a degenerate face");
  }
  for (int d = 0; d < 2; ++d) fr.flip[static_cast<std::size_t>(d)] = at[0][static_cast<std::size_t>(fr.along[static_cast<std::size_t>(d)])];
  return fr;
}

// The T-junction rows of the finer face (fine block bf, face ff) that meets the coarser face (bc,
// fc) corner to corner: each fine point = the knot-insertion combination of the coarse face's
// points (a tensor product of the two 1-D refinement matrices, oriented by the shared corners).
void face_rows(const std::vector<TMesh>& blocks, const std::vector<std::vector<int>>& pos, std::size_t bf, int ff, std::size_t bc, int fc,
               std::map<int, Row>* rows) {
  const TMesh& f = blocks[bf];
  const TMesh& c = blocks[bc];
  const auto nf = face_size(f, ff), nc = face_size(c, fc);
  auto corners = [&](const TMesh& t, std::size_t b, int face, std::array<int, 2> n) {
    std::array<int, 4> ids{};
    for (int k = 0; k < 4; ++k) ids[static_cast<std::size_t>(k)] = pos[b][face_point(t, face, (k & 1) * (n[0] - 1), (k >> 1) * (n[1] - 1))];
    return ids;
  };
  // along[d]: the coarse face direction of fine direction d; flip[d]: reversed.
  const auto [along, flip] = face_frame(corners(f, bf, ff, nf), corners(c, bc, fc, nc), bf, bc);
  std::array<Eigen::MatrixXd, 2> R;
  for (int d = 0; d < 2; ++d) {
    const auto& kf = f.knots[static_cast<std::size_t>((ff / 2 + 1 + d) % 3)];
    const auto& kc = c.knots[static_cast<std::size_t>((fc / 2 + 1 + along[static_cast<std::size_t>(d)]) % 3)];
    R[static_cast<std::size_t>(d)] = bezier::refinement_matrix(kc, flip[static_cast<std::size_t>(d)] ? reversed(kf) : kf, f.degree);
  }
  for (int j = 0; j < nf[1]; ++j)
    for (int i = 0; i < nf[0]; ++i) {
      const int id = f.function_ids[face_point(f, ff, i, j)];
      if (rows->count(id)) continue;
      const int ii = flip[0] ? nf[0] - 1 - i : i, jj = flip[1] ? nf[1] - 1 - j : j;
      Row row;
      for (int b = 0; b < R[1].rows(); ++b) {
        const double wb = R[1](b, jj);
        if (wb == 0.0) continue;
        for (int a = 0; a < R[0].rows(); ++a) {
          const double w = R[0](a, ii) * wb;
          if (w == 0.0) continue;
          std::array<int, 2> st{};
          st[static_cast<std::size_t>(along[0])] = a, st[static_cast<std::size_t>(along[1])] = b;
          row[c.function_ids[face_point(c, fc, st[0], st[1])]] += w;
        }
      }
      (*rows)[id] = std::move(row);
    }
}

}  // namespace

namespace {

bool touches_surface(const Block& b) {
  return std::any_of(b.boundary.begin(), b.boundary.end(), [](int f) { return f != 0; });
}

// The blocks of every cube, block j of cube k at level_of(k, j, whether it touches the surface),
// on uniform knots of that level or, if given, on knots[block] (blocks in order).
std::vector<TMesh> build_with(const PolycubeMaps& maps, const Params& params, const std::function<int(std::size_t, std::size_t, bool)>& block_level,
                              const std::vector<std::array<std::vector<double>, 3>>* knots = nullptr) {
  const int n = 1 << params.level;
  const std::size_t cubes = maps.blocks.empty() ? maps.boundary.size() : maps.blocks.size();
  std::vector<TMesh> blocks;
  std::vector<std::vector<Vec3>> keys;
  double extent = 0;
  core::Progress progress("blocks", cubes);
  for (std::size_t k = 0; k < cubes; ++k) {
    const int cube = static_cast<int>(k);
    const std::vector<Block> list = maps.blocks.empty() ? cube_blocks(maps.boundary[k], {n, n, n}, params.pillow_layers) : maps.blocks[k];
    for (std::size_t j = 0; j < list.size(); ++j) {
      const Block& b = list[j];
      const int level = block_level(k, j, touches_surface(b));
      if (level < params.level || level > 7)
        throw core::ConfigError("tmesh: a block's level " + std::to_string(level) + " is outside [tmesh.level, 7]");
      const int split = 1 << (level - params.level);  // every element split in 2^3 per level
      const std::array<int, 3> elements{b.elements[0] * split, b.elements[1] * split, b.elements[2] * split};
      const PointMap map = maps.physical ? PointMap([&](const Vec3& uvw) { return maps.physical(cube, block_point(b.corners, uvw)); }) : PointMap();
      if (knots && blocks.size() >= knots->size()) throw core::InvalidInputError("tmesh: knots for " + std::to_string(knots->size()) + " blocks, the polycube has more");
      TMesh t = knots ? build_block_on(map, params.degree, (*knots)[blocks.size()]) : build_block(map, params.degree, elements);
      t.level = level;
      t.boundary = b.boundary;
      t.component = cube;
      t.corners = b.corners;
      t.kind = params.pillow_layers == 0 ? "cube" : b.pillow ? "pillow" : "core";
      std::vector<Vec3> key;
      for (const auto& uvw : t.parameters) {
        key.push_back(maps.polycube(cube, block_point(b.corners, uvw)));
        for (const double v : key.back()) extent = std::max(extent, std::abs(v));
      }
      keys.push_back(std::move(key));
      blocks.push_back(std::move(t));
    }
    progress.step(k);
  }
  progress.finish();
  // Shared control points: equal polycube points of blocks of one level. Their positions agree to
  // rounding (the same face data interpolated in another order); the first block's value is kept
  // so that the Bézier elements on both sides of a block face are exactly conforming. Points of
  // different levels are different nodes even where they coincide: the finer one is a T-junction.
  PointIds positions(1e-9 * std::max(extent, 1.0));
  std::vector<std::vector<int>> pos(blocks.size());
  std::unordered_map<std::uint64_t, int> node;  // (position, level) -> id (ids in order of first sight: no order needed)
  std::vector<Vec3> position;
  std::vector<int> level_of, position_of;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    TMesh& t = blocks[b];
    t.function_ids.resize(t.control_points.size());
    for (std::size_t i = 0; i < t.control_points.size(); ++i) {
      pos[b].push_back(positions.id(keys[b][i]));
      const std::uint64_t key = static_cast<std::uint64_t>(static_cast<std::uint32_t>(pos[b].back())) << 32 | static_cast<std::uint32_t>(t.level);
      const auto [it, fresh] = node.insert({key, static_cast<int>(position.size())});
      t.function_ids[i] = it->second;
      if (fresh) {
        position.push_back(t.control_points[i]), level_of.push_back(t.level), position_of.push_back(pos[b].back());
      } else {
        t.control_points[i] = position[static_cast<std::size_t>(it->second)];
      }
    }
  }
  // T-junctions: block faces that meet corner to corner with different levels.
  std::map<std::array<int, 4>, std::vector<std::pair<std::size_t, int>>> faces;
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (int f = 0; f < 6; ++f) {
      if (blocks[b].boundary[static_cast<std::size_t>(f)]) continue;
      const auto nf = face_size(blocks[b], f);
      std::array<int, 4> key{};
      for (int c = 0; c < 4; ++c) key[static_cast<std::size_t>(c)] = pos[b][face_point(blocks[b], f, (c & 1) * (nf[0] - 1), (c >> 1) * (nf[1] - 1))];
      std::sort(key.begin(), key.end());
      faces[key].push_back({b, f});
    }
  // Levels that differ need every inner block face to be the whole face of exactly one other
  // block: a face met by parts of several (a cube cut along a sharp line next to an uncut one)
  // would leave finer nodes inside a coarser face that no row ties to it (a crack).
  if (std::any_of(blocks.begin(), blocks.end(), [&](const TMesh& t) { return t.level != blocks.front().level; }))
    for (const auto& [key, list] : faces)
      if (list.size() != 2)
        throw core::TopologyError("tmesh: levels differ between cubes, but face " + std::to_string(list[0].second) + " of block " +
                                  std::to_string(list[0].first) + " (cube " + std::to_string(blocks[list[0].first].component) + ") is " +
                                  (list.size() == 1 ? "not the whole face of another block" : "shared by more than two blocks"));
  // Blocks on given knots must still meet face to face: a face whose points the block across it
  // lacks would hang (a crack). refinement_splits() makes faces met corner to corner agree; a
  // face met in part (box_complex) is checked here, and refused rather than written.
  if (knots) {
    std::map<int, int> blocks_at;  // polycube position -> blocks that have a point there
    for (std::size_t b = 0; b < blocks.size(); ++b)
      for (const int at : std::set<int>(pos[b].begin(), pos[b].end())) ++blocks_at[at];
    for (const auto& [key, list] : faces) {
      const auto [b, f] = list[0];
      const bool same_level = list.size() == 2 && blocks[list[1].first].level == blocks[b].level;
      std::set<int> here, there;
      const auto nf = face_size(blocks[b], f);
      for (int j = 0; j < nf[1]; ++j)
        for (int i = 0; i < nf[0]; ++i) here.insert(pos[b][face_point(blocks[b], f, i, j)]);
      bool ok = true;
      if (same_level) {
        const auto [b2, f2] = list[1];
        const auto n2 = face_size(blocks[b2], f2);
        for (int j = 0; j < n2[1]; ++j)
          for (int i = 0; i < n2[0]; ++i) there.insert(pos[b2][face_point(blocks[b2], f2, i, j)]);
        ok = here == there;
      } else if (list.size() == 1) {
        ok = std::all_of(here.begin(), here.end(), [&](int at) { return blocks_at[at] >= 2; });
      }
      if (!ok)
        throw core::TopologyError(std::string(params.pillow_splits > 1 ? "tmesh.pillow_splits" : "tmesh.refine spans") + ": face " + std::to_string(f) +
                                  " of block " + std::to_string(b) + " (cube " + std::to_string(blocks[b].component) + ", " + blocks[b].kind +
                                  ") meets a block split otherwise: " +
                                  (params.pillow_splits > 1 ? "the pillow layer cannot be split there (use pillow_splits 1)" : "its spans cannot be split there"));
    }
  }
  std::map<int, Row> rows;
  for (const auto& [key, list] : faces) {
    if (list.size() != 2) continue;
    auto [fine, coarse] = std::pair{list[0], list[1]};
    if (blocks[fine.first].level == blocks[coarse.first].level) continue;
    if (blocks[fine.first].level < blocks[coarse.first].level) std::swap(fine, coarse);
    face_rows(blocks, pos, fine.first, fine.second, coarse.first, coarse.second, &rows);
  }
  if (!rows.empty()) {
    // A row may name T-junctions of a coarser level in turn (three levels at a face): substitute
    // until every row names free nodes only; each substitution goes one level coarser.
    for (int pass = 0;; ++pass) {
      bool changed = false;
      for (auto& [id, row] : rows) {
        Row out;
        for (const auto& [m, w] : row) {
          const auto it = rows.find(m);
          if (it == rows.end()) out[m] += w;
          else for (const auto& [m2, w2] : it->second) out[m2] += w * w2, changed = true;
        }
        row = std::move(out);
      }
      if (!changed) break;
      if (pass > 8) throw core::TopologyError("tmesh: T-junction constraints form a cycle");
    }
    // Every finer node where a coarser one lies must be a T-junction, or the spline has a crack there.
    std::map<int, int> coarsest;  // position -> lowest level there
    for (std::size_t id = 0; id < position.size(); ++id) {
      auto [it, fresh] = coarsest.insert({position_of[id], level_of[id]});
      if (!fresh) it->second = std::min(it->second, level_of[id]);
    }
    for (std::size_t id = 0; id < position.size(); ++id)
      if (level_of[id] > coarsest[position_of[id]] && !rows.count(static_cast<int>(id)))
        throw core::TopologyError("tmesh: cubes of levels " + std::to_string(coarsest[position_of[id]]) + " and " + std::to_string(level_of[id]) +
                                  " meet where their blocks do not share whole faces (node " + std::to_string(id) + ")");
    for (auto& [id, row] : rows) {
      Vec3 x{0, 0, 0};
      for (const auto& [m, w] : row)
        for (int d = 0; d < 3; ++d) x[static_cast<std::size_t>(d)] += w * position[static_cast<std::size_t>(m)][static_cast<std::size_t>(d)];
      position[static_cast<std::size_t>(id)] = x;
    }
    for (TMesh& t : blocks)
      for (std::size_t i = 0; i < t.control_points.size(); ++i) {
        const auto it = rows.find(t.function_ids[i]);
        if (it == rows.end()) continue;
        t.control_points[i] = position[static_cast<std::size_t>(it->first)];
        TMesh::Constraint c;
        c.point = static_cast<int>(i);
        for (const auto& [m, w] : it->second) c.ids.push_back(m), c.weights.push_back(w);
        t.constraints.push_back(std::move(c));
      }
  } else {
    // Without T-junctions, points of different levels must not touch at all.
    std::map<int, int> level_at;
    for (std::size_t id = 0; id < position.size(); ++id) {
      auto [it, fresh] = level_at.insert({position_of[id], level_of[id]});
      if (!fresh && it->second != level_of[id])
        throw core::TopologyError("tmesh: cubes of levels " + std::to_string(std::min(it->second, level_of[id])) + " and " +
                                  std::to_string(std::max(it->second, level_of[id])) + " meet where their blocks do not share whole faces");
    }
  }
  return blocks;
}

}  // namespace

std::vector<TMesh> build(const PolycubeMaps& maps, const Params& params, const std::vector<int>& levels) {
  check(params);
  const std::size_t cubes = maps.blocks.empty() ? maps.boundary.size() : maps.blocks.size();
  if (levels.size() != cubes)
    throw core::ConfigError("tmesh: " + std::to_string(levels.size()) + " levels for " + std::to_string(cubes) + " cubes");
  for (const int l : levels)
    if (l < params.level || l > 7) throw core::ConfigError("tmesh: a cube's level " + std::to_string(l) + " is outside [tmesh.level, 7]");
  // Refinement of boundary elements (Liu et al. §5.1): the blocks on the surface at the cube's
  // level, the others (the core) one coarser, 2:1 across their faces.
  return build_with(maps, params, [&](std::size_t k, std::size_t, bool on_surface) {
    return on_surface || params.refine == "cube" ? levels[k] : std::max(params.level, levels[k] - 1);
  });
}

namespace {

bool has_surface_face(const TMesh& t) { return std::any_of(t.boundary.begin(), t.boundary.end(), [](int f) { return f != 0; }); }

// The spline of one block at the points of a tensor grid g[0] × g[1] × g[2] of its parameters:
// the sum bezier::evaluate makes (same terms, same order: the same bits), with the basis values
// of each abscissa computed once instead of at every point (with its checks of the knot vectors).
class BlockGrid {
 public:
  BlockGrid(const TMesh& t, const std::array<std::vector<double>, 3>& g) : t_(t) {
    for (std::size_t a = 0; a < 3; ++a)
      for (const double x : g[a]) basis_[a].push_back(bezier::basis_functions(t.knots[a], t.degree, x));
  }
  Vec3 at(std::size_t i, std::size_t j, std::size_t k) const {
    const bezier::BasisValues &B0 = basis_[0][i], &B1 = basis_[1][j], &B2 = basis_[2][k];
    const int p = t_.degree, n0 = t_.size[0], n1 = t_.size[1];
    Eigen::Vector3d A = Eigen::Vector3d::Zero();
    double W = 0.0;
    for (int c = 0; c <= p; ++c)
      for (int b = 0; b <= p; ++b)
        for (int a = 0; a <= p; ++a) {
          const Vec3& x = t_.control_points[static_cast<std::size_t>((B0.span - p + a) + n0 * ((B1.span - p + b) + n1 * (B2.span - p + c)))];
          const double w = 1.0 * B0.values[a] * B1.values[b] * B2.values[c];  // bezier::evaluate's weight 1 first
          A += w * Eigen::Vector3d(x[0], x[1], x[2]);
          W += w;
        }
    const Eigen::Vector3d y = A / W;
    return {y[0], y[1], y[2]};
  }

 private:
  const TMesh& t_;
  std::array<std::vector<bezier::BasisValues>, 3> basis_;
};

// Per block, for each face on the surface (2·axis + side), per element face (index i + n·j: i
// along axis (axis+1)%3's spans, n their count, j along (axis+2)%3's): the largest distance, on
// a uniform grid of `points` per element direction, corners included (a point on an element edge
// counts for the elements on both sides), and the spline's bend along each of the two directions
// (the largest second difference of the grid's points along it inside the element, ~ h²·|x''|:
// what halving that direction's span divides by four). Empty for the other faces. Blocks in
// parallel: the distance is a const query (an AABB tree).
struct FaceDeviation {
  std::array<std::vector<double>, 6> dev, bend_u, bend_v;
};
std::vector<FaceDeviation> element_face_deviation(const std::vector<TMesh>& ts, const std::function<double(const Vec3&)>& distance, int points) {
  std::vector<FaceDeviation> out(ts.size());
  core::parallel_for(ts.size(), [&](std::size_t b) {
    const TMesh& t = ts[b];
    if (!has_surface_face(t)) return;
    std::array<std::vector<double>, 3> g;
    std::array<std::vector<std::array<std::size_t, 2>>, 3> owner;  // per abscissa: the first and last element it lies in
    std::array<std::vector<char>, 3> inside;                       // per abscissa: strictly inside its element
    std::array<std::size_t, 3> n{};
    for (std::size_t a = 0; a < 3; ++a) {
      const auto iv = bezier::element_intervals(t.knots[a], t.degree);
      n[a] = iv.size();
      for (std::size_t e = 0; e < iv.size(); ++e)
        for (int i = e == 0 ? 0 : 1; i < points; ++i) {
          g[a].push_back(iv[e][0] + (iv[e][1] - iv[e][0]) * i / (points - 1));
          owner[a].push_back({e, i == points - 1 && e + 1 < iv.size() ? e + 1 : e});
          inside[a].push_back(i > 0 && i < points - 1);
        }
    }
    const BlockGrid grid(t, g);
    for (int f = 0; f < 6; ++f) {
      if (!t.boundary[static_cast<std::size_t>(f)]) continue;
      const std::size_t a = static_cast<std::size_t>(f / 2), u = (a + 1) % 3, v = (a + 2) % 3, fs = static_cast<std::size_t>(f);
      std::vector<double>& d = out[b].dev[fs];
      d.assign(n[u] * n[v], 0.0);
      out[b].bend_u[fs].assign(n[u] * n[v], 0.0);
      out[b].bend_v[fs].assign(n[u] * n[v], 0.0);
      std::vector<Eigen::Vector3d> x(g[u].size() * g[v].size());  // the face's grid points, u fastest
      std::array<std::size_t, 3> at{};
      at[a] = f % 2 ? g[a].size() - 1 : 0;
      for (at[u] = 0; at[u] < g[u].size(); ++at[u])
        for (at[v] = 0; at[v] < g[v].size(); ++at[v]) {
          const Vec3 y = grid.at(at[0], at[1], at[2]);
          x[at[u] + g[u].size() * at[v]] = Eigen::Vector3d(y[0], y[1], y[2]);
          const double dist = distance(y);
          for (std::size_t i = owner[u][at[u]][0]; i <= owner[u][at[u]][1]; ++i)
            for (std::size_t j = owner[v][at[v]][0]; j <= owner[v][at[v]][1]; ++j) d[i + n[u] * j] = std::max(d[i + n[u] * j], dist);
        }
      const std::size_t su = 1, sv = g[u].size();
      for (std::size_t q = 0; q < g[v].size(); ++q)
        for (std::size_t p = 0; p < g[u].size(); ++p) {
          const std::size_t k = p + sv * q;
          for (std::size_t j = owner[v][q][0]; j <= owner[v][q][1]; ++j)
            if (inside[u][p]) {
              double& w = out[b].bend_u[fs][owner[u][p][0] + n[u] * j];
              w = std::max(w, (x[k - su] - 2 * x[k] + x[k + su]).norm());
            }
          for (std::size_t i = owner[u][p][0]; i <= owner[u][p][1]; ++i)
            if (inside[v][q]) {
              double& w = out[b].bend_v[fs][i + n[u] * owner[v][q][0]];
              w = std::max(w, (x[k - sv] - 2 * x[k] + x[k + sv]).norm());
            }
        }
    }
  }, 1);
  return out;
}

// Per block of ts: the largest distance at its boundary faces (0 without one), on
// element_face_deviation's grid.
std::vector<double> block_deviation(const std::vector<TMesh>& ts, const std::function<double(const Vec3&)>& distance, int points) {
  std::vector<double> dev(ts.size(), 0.0);
  const std::vector<FaceDeviation> faces = element_face_deviation(ts, distance, points);
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (const std::vector<double>& f : faces[b].dev)
      for (const double x : f) dev[b] = std::max(dev[b], x);
  return dev;
}

}  // namespace

namespace {

// Span splits across block faces (refinement_splits(), Params::refine "spans"): a face that two
// blocks share corner to corner ties each of its two tangent directions on one side to the
// matching direction on the other, so that both sides split its spans alike.
struct Tie {
  std::size_t b[2];
  std::size_t axis[2];
  bool flip;
};

// The ties of every face met corner to corner, found by the corners in polycube space (as
// build() finds shared points), whatever the blocks' levels. Faces met in part (box_complex)
// tie nothing: build_with checks those.
std::vector<Tie> face_ties(const PolycubeMaps& maps, const std::vector<TMesh>& coarse) {
  std::vector<std::array<Vec3, 8>> corner(coarse.size());
  double extent = 1;
  for (std::size_t b = 0; b < coarse.size(); ++b)
    for (int c = 0; c < 8; ++c) {
      corner[b][static_cast<std::size_t>(c)] = maps.polycube(coarse[b].component, block_point(coarse[b].corners, Vec3{double(c & 1), double((c >> 1) & 1), double(c >> 2)}));
      for (const double v : corner[b][static_cast<std::size_t>(c)]) extent = std::max(extent, std::abs(v));
    }
  PointIds ids(1e-9 * extent);
  std::map<std::array<int, 4>, std::vector<std::pair<std::size_t, int>>> faces;
  std::vector<std::array<std::array<int, 4>, 6>> face_corners(coarse.size());
  for (std::size_t b = 0; b < coarse.size(); ++b)
    for (int f = 0; f < 6; ++f) {
      const int ax = f / 2;
      for (int k = 0; k < 4; ++k) {
        std::array<int, 3> bit{};
        bit[static_cast<std::size_t>(ax)] = f % 2, bit[static_cast<std::size_t>((ax + 1) % 3)] = k & 1, bit[static_cast<std::size_t>((ax + 2) % 3)] = k >> 1;
        face_corners[b][static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] = ids.id(corner[b][static_cast<std::size_t>(bit[0] + 2 * bit[1] + 4 * bit[2])]);
      }
      if (coarse[b].boundary[static_cast<std::size_t>(f)]) continue;
      std::array<int, 4> key = face_corners[b][static_cast<std::size_t>(f)];
      std::sort(key.begin(), key.end());
      faces[key].push_back({b, f});
    }
  std::vector<Tie> ties;
  for (const auto& [key, list] : faces) {
    if (list.size() != 2) continue;
    const auto [b0, f0] = list[0];
    const auto [b1, f1] = list[1];
    const FaceFrame fr = face_frame(face_corners[b0][static_cast<std::size_t>(f0)], face_corners[b1][static_cast<std::size_t>(f1)], b0, b1);
    for (int d = 0; d < 2; ++d)
      ties.push_back({{b0, b1},
                      {static_cast<std::size_t>((f0 / 2 + 1 + d) % 3), static_cast<std::size_t>((f1 / 2 + 1 + fr.along[static_cast<std::size_t>(d)]) % 3)},
                      fr.flip[static_cast<std::size_t>(d)] != 0});
  }
  return ties;
}

// Across every tie, each span splits alike on both sides (a finer side's r spans as the coarser
// side's one): the largest count wins until every tie agrees. `what` names the caller in the
// core::TopologyError thrown where span counts do not nest.
void propagate_splits(const std::vector<Tie>& ties, std::vector<SpanSplits>& out, const std::string& what) {
  for (bool changed = true; changed;) {
    changed = false;
    for (const Tie& t : ties) {
      std::vector<int>& u = out[t.b[0]][t.axis[0]];
      std::vector<int>& v = out[t.b[1]][t.axis[1]];
      const std::size_t nu = u.size(), nv = v.size(), n = std::min(nu, nv), r = std::max(nu, nv) / n;
      if (n == 0 || r * n != std::max(nu, nv))
        throw core::TopologyError(what + ": blocks " + std::to_string(t.b[0]) + " and " + std::to_string(t.b[1]) + " meet with " +
                                  std::to_string(nu) + " and " + std::to_string(nv) + " elements along one face direction");
      // Span i of the side with n spans is spans r·i … r·i + r − 1 of the other, in u's direction.
      for (std::size_t i = 0; i < n; ++i) {
        auto at_v = [&](std::size_t j) { return t.flip ? nv - 1 - j : j; };
        int m = 0;
        for (std::size_t q = 0; q < nu / n; ++q) m = std::max(m, u[i * (nu / n) + q]);
        for (std::size_t q = 0; q < nv / n; ++q) m = std::max(m, v[at_v(i * (nv / n) + q)]);
        for (std::size_t q = 0; q < nu / n; ++q) changed |= std::exchange(u[i * (nu / n) + q], m) != m;
        for (std::size_t q = 0; q < nv / n; ++q) changed |= std::exchange(v[at_v(i * (nv / n) + q)], m) != m;
      }
    }
  }
}

// The knots of `t` with span s along axis a split in splits[a][s] equal parts; `up` (optional):
// per axis, per span of the result, the span of `t` it lies in.
std::array<std::vector<double>, 3> split_knots(const TMesh& t, const SpanSplits& splits, std::array<std::vector<int>, 3>* up = nullptr) {
  std::array<std::vector<double>, 3> k;
  for (std::size_t a = 0; a < 3; ++a) {
    const std::vector<double>& c = t.knots[a];
    int span = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      k[a].push_back(c[i]);
      if (i + 1 == c.size() || c[i + 1] <= c[i]) continue;
      const int m = splits[a][static_cast<std::size_t>(span)];
      for (int q = 1; q < m; ++q) k[a].push_back(c[i] + (c[i + 1] - c[i]) * q / m);
      if (up)
        for (int q = 0; q < m; ++q) (*up)[a].push_back(span);
      ++span;
    }
  }
  return k;
}

// Adaptive spans (Params::refine "spans"): where an element face on the surface deviates by more
// than `tol`, its two spans along the surface are halved by knot insertion, and every span a block
// face ties to them too (propagate_splits), so blocks still meet face to face on one level: no
// T-junction, and each inserted knot runs on as a whole knot plane — the slab rule that keeps the
// basis analysis-suitable (tspline/suitable.h: per-leaf octree refinement does not). Spans next
// to each other differ by one halving at most (2:1 grading). Rounds until every face is within
// `tol`, its spans were halved max_level − level times, or a round gains nothing (the input's
// faceting: undone); blocks are rebuilt on the new knots by interpolating the volume map.
// GCC 12 reports a free of a non-heap pointer in this function's vectors of SpanSplits at -O2
// (a known false positive of -Wfree-nonheap-object on inlined vector destructors).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wfree-nonheap-object"
std::vector<TMesh> refine_spans(const PolycubeMaps& maps, const Params& params, std::vector<TMesh> blocks, Levels& lv,
                                std::vector<double>& block_dev) {
  const double tol = params.epsilon_rel * maps.diagonal;
  const int points = deviation_points(params), max_depth = params.max_level - params.level;
  constexpr double kGain = 0.8;  // as the levels' (build()): a fifth closer at least
  constexpr double kBend = 0.25;  // a direction bent a quarter as much as the other halves too
  const std::size_t nb = blocks.size();
  const std::vector<Tie> ties = face_ties(maps, blocks);
  auto spans = [](const TMesh& t, std::size_t a) { return bezier::element_intervals(t.knots[a], t.degree).size(); };
  std::vector<std::vector<int>> depth(3 * nb);  // per block b and axis a (3b + a), per span: halvings so far
  std::size_t laid_out = 0;
  for (std::size_t b = 0; b < nb; ++b)
    for (std::size_t a = 0; a < 3; ++a) depth[3 * b + a].assign(spans(blocks[b], a), 0), laid_out += depth[3 * b + a].size();
  std::vector<FaceDeviation> dev = element_face_deviation(blocks, maps.surface_distance, points);
  std::vector<std::array<std::vector<char>, 6>> saturated(nb);
  for (std::size_t b = 0; b < nb; ++b)
    for (std::size_t f = 0; f < 6; ++f) saturated[b][f].assign(dev[b].dev[f].size(), 0);
  std::vector<std::array<std::vector<double>, 3>> knots(nb);
  std::vector<SpanSplits> up(nb);  // per block, axis, new span: the span it halves (or is)
  for (;;) {
    std::vector<SpanSplits> split(nb);
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t a = 0; a < 3; ++a) split[b][a].assign(depth[3 * b + a].size(), 1);
    bool any = false, capped = false, stuck = false;
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t f = 0; f < 6; ++f) {
        const std::size_t u = (f / 2 + 1) % 3, v = (f / 2 + 2) % 3, nu = depth[3 * b + u].size();
        for (std::size_t e = 0; e < dev[b].dev[f].size(); ++e) {
          if (!(dev[b].dev[f][e] > tol)) continue;
          if (saturated[b][f][e]) {
            stuck = true;
            continue;
          }
          // The directions whose bend is at least kBend of the larger: a face curved one way (a
          // cylinder's) halves that way only.
          const double bu = dev[b].bend_u[f][e], bv = dev[b].bend_v[f][e], top = std::max(bu, bv);
          for (const auto& [axis, span, bend] : {std::tuple{u, e % nu, bu}, std::tuple{v, e / nu, bv}}) {
            if (!(bend >= kBend * top)) continue;
            if (depth[3 * b + axis][span] < max_depth) split[b][axis][span] = 2, any = true;
            else capped = true;
          }
        }
      }
    if (!any) {
      lv.stop = capped ? "max_level" : stuck ? "no_gain" : "within_epsilon";
      break;
    }
    // Ties and 2:1 grading until both hold; a span halved by either keeps within max_depth, since
    // tied spans have one depth and grading only follows a deeper neighbour.
    for (bool graded = false; !graded;) {
      propagate_splits(ties, split, "tmesh.refine spans");
      graded = true;
      for (std::size_t b = 0; b < nb; ++b)
        for (std::size_t a = 0; a < 3; ++a)
          for (std::size_t i = 0; i + 1 < depth[3 * b + a].size(); ++i) {
            const int d0 = depth[3 * b + a][i] + (split[b][a][i] > 1), d1 = depth[3 * b + a][i + 1] + (split[b][a][i + 1] > 1);
            if (d0 > d1 + 1) split[b][a][i + 1] = 2, graded = false;
            if (d1 > d0 + 1) split[b][a][i] = 2, graded = false;
          }
    }
    for (std::size_t b = 0; b < nb; ++b) up[b] = {}, knots[b] = split_knots(blocks[b], split[b], &up[b]);
    std::vector<TMesh> next;
    try {
      next = build_with(maps, params, [&](std::size_t, std::size_t, bool) { return params.level; }, &knots);
    } catch (const core::TopologyError& e) {
      core::log_warning(std::string("tmesh: adaptive spans stop: ") + e.what());
      lv.stop = "not_face_to_face";  // `blocks` are still the last conforming ones
      break;
    }
    std::vector<FaceDeviation> next_dev = element_face_deviation(next, maps.surface_distance, points);
    // A face halved for its own deviation gained if it is within tol now or a fifth closer; one
    // that did not is saturated, and so are the faces in a saturated one.
    bool gained = false;
    std::vector<std::array<std::vector<char>, 6>> next_saturated(nb);
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t f = 0; f < 6; ++f) {
        next_saturated[b][f].assign(next_dev[b].dev[f].size(), 0);
        const std::size_t u = (f / 2 + 1) % 3, v = (f / 2 + 2) % 3, nu = up[b][u].size(), pnu = depth[3 * b + u].size();
        for (std::size_t e = 0; e < next_dev[b].dev[f].size(); ++e) {
          const std::size_t pi = static_cast<std::size_t>(up[b][u][e % nu]), pj = static_cast<std::size_t>(up[b][v][e / nu]), pe = pi + pnu * pj;
          if (saturated[b][f][pe]) {
            next_saturated[b][f][e] = 1;
            continue;
          }
          if (!(dev[b].dev[f][pe] > tol) || (split[b][u][pi] == 1 && split[b][v][pj] == 1)) continue;
          if (next_dev[b].dev[f][e] <= tol || next_dev[b].dev[f][e] <= kGain * dev[b].dev[f][pe]) gained = true;
          else next_saturated[b][f][e] = 1;
        }
      }
    // A round that leaves the worst deviation higher (and above tol) is undone too: the
    // interpolation on finer knots can miss more elsewhere (the generated cube-with-hole at ε
    // 0.0002: one round halved 184 spans where faces gained, and the worst went 7.21e-4 → 7.33e-4
    // of the diagonal, at the hole's faceting).
    auto worst = [](const std::vector<FaceDeviation>& d) {
      double w = 0;
      for (const FaceDeviation& x : d)
        for (const std::vector<double>& f : x.dev)
          for (const double v : f) w = std::max(w, v);
      return w;
    };
    if (!gained || worst(next_dev) > std::max(worst(dev), tol)) {  // the round bought elements and no accuracy: undone
      lv.stop = "no_gain";
      break;
    }
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t a = 0; a < 3; ++a) {
        std::vector<int> d;
        for (const int p : up[b][a]) d.push_back(depth[3 * b + a][static_cast<std::size_t>(p)] + (split[b][a][static_cast<std::size_t>(p)] > 1));
        depth[3 * b + a] = std::move(d);
      }
    blocks = std::move(next), dev = std::move(next_dev), saturated = std::move(next_saturated);
    ++lv.refinements;
  }
  std::size_t now = 0;
  lv.refined_blocks = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    bool refined = false;
    for (std::size_t a = 0; a < 3; ++a) {
      now += depth[3 * b + a].size();
      refined = refined || std::any_of(depth[3 * b + a].begin(), depth[3 * b + a].end(), [](int d) { return d > 0; });
    }
    lv.refined_blocks += refined ? 1 : 0;
  }
  lv.knots_inserted = static_cast<int>(now - laid_out);
  lv.span_units.assign(nb, {0.0, 0.0, 0.0});
  for (std::size_t b = 0; b < nb; ++b)
    for (std::size_t a = 0; a < 3; ++a)
      for (const int d : depth[3 * b + a]) lv.span_units[b][a] += std::ldexp(1.0, -d);
  block_dev.assign(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b)
    for (const std::vector<double>& f : dev[b].dev)
      for (const double x : f) block_dev[b] = std::max(block_dev[b], x);
  return blocks;
}
#pragma GCC diagnostic pop

}  // namespace

int deviation_points(const Params& params) { return (params.deviation_samples - 1) * (1 << params.h_refine) + 1; }

std::vector<double> boundary_deviation(const std::vector<TMesh>& ts, const std::function<double(const Vec3&)>& distance, int points) {
  if (points < 2) throw core::ConfigError("tmesh::boundary_deviation: at least 2 points per element direction, got " + std::to_string(points));
  int components = 0;
  for (const auto& t : ts) components = std::max(components, t.component + 1);
  std::vector<double> dev(static_cast<std::size_t>(components), 0.0);
  const std::vector<double> per_block = block_deviation(ts, distance, points);
  for (std::size_t b = 0; b < ts.size(); ++b) dev[static_cast<std::size_t>(ts[b].component)] = std::max(dev[static_cast<std::size_t>(ts[b].component)], per_block[b]);
  return dev;
}

std::vector<TMesh> build(const PolycubeMaps& maps, const Params& params, Levels* out) {
  check(params);
  if (!(params.epsilon_rel >= 0 && params.epsilon_rel <= 1))
    throw core::ConfigError("tmesh.epsilon_rel must be in [0, 1], got " + std::to_string(params.epsilon_rel));
  if (params.max_level < 1 || params.max_level > 7) throw core::ConfigError("tmesh.max_level must be in [1, 7], got " + std::to_string(params.max_level));
  if (params.refine != "boundary" && params.refine != "cube" && params.refine != "spans")
    throw core::ConfigError("tmesh.refine must be boundary, cube or spans, got '" + params.refine + "'");
  const std::size_t cubes = maps.blocks.empty() ? maps.boundary.size() : maps.blocks.size();
  Levels lv;
  lv.level.assign(cubes, params.level);
  std::vector<TMesh> blocks = build(maps, params, lv.level);
  const bool measure = maps.surface_distance && maps.diagonal > 0;
  const bool adaptive = measure && params.epsilon_rel > 0 && params.max_level > params.level;
  lv.stop = "disabled";
  // Levels are per block (Liu et al. §5.1 refines boundary elements): blocks on the surface go
  // finer by their own deviation, the others only as 2:1 balance asks; with refine "cube" a
  // cube's blocks keep one level, its finest.
  const std::size_t nb = blocks.size();
  std::vector<std::size_t> offset(cubes + 1, 0);  // first block of each cube
  for (const TMesh& t : blocks) ++offset[static_cast<std::size_t>(t.component) + 1];
  for (std::size_t k = 0; k < cubes; ++k) offset[k + 1] += offset[k];
  auto per_cube = [&](const std::vector<double>& per_block) {
    std::vector<double> dev(cubes, 0.0);
    for (std::size_t i = 0; i < nb; ++i) dev[static_cast<std::size_t>(blocks[i].component)] = std::max(dev[static_cast<std::size_t>(blocks[i].component)], per_block[i]);
    return dev;
  };
  auto record = [&](const std::vector<double>& per_block) {
    lv.cube_deviation_rel.clear();
    for (const double d : per_cube(per_block)) lv.cube_deviation_rel.push_back(d / maps.diagonal);
    lv.deviation_rel = lv.cube_deviation_rel.empty() ? 0.0 : *std::max_element(lv.cube_deviation_rel.begin(), lv.cube_deviation_rel.end());
  };
  if (measure && !adaptive) record(block_deviation(blocks, maps.surface_distance, deviation_points(params)));
  if (adaptive && params.refine == "spans") {
    std::vector<double> dev;
    blocks = refine_spans(maps, params, std::move(blocks), lv, dev);
    record(dev);
  } else if (adaptive) {
    const double tol = params.epsilon_rel * maps.diagonal;
    std::vector<int> level(nb, params.level);
    auto build_levels = [&](const std::vector<int>& l) {
      return build_with(maps, params, [&](std::size_t k, std::size_t j, bool) { return l[offset[k] + j]; });
    };
    // Blocks that share a point (2:1 balance across faces, edges and corners).
    std::vector<std::set<std::size_t>> near(nb);
    {
      std::map<std::array<long long, 3>, std::set<std::size_t>> at;
      const double cell = 1e-9 * maps.diagonal;
      for (std::size_t i = 0; i < nb; ++i)
        for (const auto& x : blocks[i].control_points) at[{std::llround(x[0] / cell), std::llround(x[1] / cell), std::llround(x[2] / cell)}].insert(i);
      for (const auto& [key, set] : at)
        for (const std::size_t i : set)
          for (const std::size_t j : set)
            if (i != j) near[i].insert(j);
    }
    // A block whose deviation a level did not lower by kGain is saturated: what is left is the
    // input's own faceting (the volume map's boundary is the triangulated surface, which a smooth
    // spline through its points misses by the facets' sagitta at any level).
    constexpr double kGain = 0.8;
    std::vector<double> dev = block_deviation(blocks, maps.surface_distance, deviation_points(params)), last;
    std::vector<int> previous;
    std::vector<char> saturated(nb, 0);
    for (;;) {
      if (!last.empty()) {
        bool gained = false;
        for (std::size_t i = 0; i < nb; ++i) {
          if (level[i] == previous[i] || last[i] <= tol) continue;  // not refined for its own deviation
          if (dev[i] <= tol || dev[i] <= kGain * last[i]) gained = true;  // within ε now, or a fifth closer
          else saturated[i] = 1;
        }
        // A round that left the worst deviation higher than before (and above ε) is undone too,
        // as refine_spans' rounds: the interpolation on finer knots can miss more elsewhere.
        const double worst_last = *std::max_element(last.begin(), last.end()), worst_now = *std::max_element(dev.begin(), dev.end());
        if (!gained || worst_now > std::max(worst_last, tol)) {  // the last round bought elements and no accuracy: undo it
          level = previous, --lv.refinements, dev = last;
          blocks = build_levels(level);
          lv.stop = "no_gain";
          break;
        }
      }
      std::vector<int> next = level;
      bool refine = false, capped = false;
      for (std::size_t i = 0; i < nb; ++i)
        if (dev[i] > tol && !saturated[i]) {
          if (next[i] < params.max_level) ++next[i], refine = true;
          else capped = true;
        }
      // The surface blocks of the same cube that share an edge with a refined one follow it: a
      // coarser neighbour would keep their common edge at its level (T-junctions), while the
      // distance there counts for one side only (a slab under a plane sees its bulging edge
      // curve on the plane, 0; the slab under the cylinder beside it does not).
      const std::vector<int> raised = next;
      for (std::size_t i = 0; i < nb; ++i)
        if (raised[i] > level[i])
          for (const std::size_t j : near[i])
            if (blocks[j].component == blocks[i].component && has_surface_face(blocks[j])) next[j] = std::max(next[j], raised[i]);
      if (!refine) {
        lv.stop = capped ? "max_level" : std::any_of(saturated.begin(), saturated.end(), [](char x) { return x != 0; }) ? "no_gain" : "within_epsilon";
        break;
      }
      for (bool changed = true; changed;) {
        changed = false;
        if (params.refine == "cube")
          for (std::size_t k = 0; k < cubes; ++k) {
            const int top = *std::max_element(next.begin() + static_cast<std::ptrdiff_t>(offset[k]), next.begin() + static_cast<std::ptrdiff_t>(offset[k + 1]));
            for (std::size_t i = offset[k]; i < offset[k + 1]; ++i)
              if (next[i] != top) next[i] = top, changed = true;
          }
        for (std::size_t i = 0; i < nb; ++i)  // 2:1: raise the coarser of two blocks that touch
          for (const std::size_t j : near[i])
            if (next[i] < next[j] - 1) next[i] = next[j] - 1, changed = true;
      }
      try {
        blocks = build_levels(next);
      } catch (const core::TopologyError& e) {
        core::log_warning(std::string("tmesh: adaptive levels stop: ") + e.what());
        lv.stop = "not_face_to_face";  // `blocks` are still those of `level`
        break;
      }
      previous = level, level = next, last = dev;
      ++lv.refinements;
      dev = block_deviation(blocks, maps.surface_distance, deviation_points(params));
    }
    record(dev);
    lv.level.assign(cubes, params.level);
    for (std::size_t i = 0; i < nb; ++i) lv.level[static_cast<std::size_t>(blocks[i].component)] = std::max(lv.level[static_cast<std::size_t>(blocks[i].component)], level[i]);
    lv.refined_blocks = static_cast<int>(std::count_if(level.begin(), level.end(), [&](int l) { return l > params.level; }));
  }
  if (out) *out = lv;
  return blocks;
}

std::vector<SpanSplits> refinement_splits(const PolycubeMaps& maps, const Params& params, const std::vector<TMesh>& coarse, int times) {
  check(params);
  if (times < 0 || times > 3) throw core::ConfigError("tmesh.h_refine must be in [0, 3], got " + std::to_string(times));
  std::vector<SpanSplits> out(coarse.size());
  for (std::size_t b = 0; b < coarse.size(); ++b) {
    const int axis = slab_axis(coarse[b].kind == "pillow", coarse[b].boundary);
    for (int a = 0; a < 3; ++a)
      out[b][static_cast<std::size_t>(a)].assign(bezier::element_intervals(coarse[b].knots[static_cast<std::size_t>(a)], coarse[b].degree).size(),
                                                 (1 << times) * (a == axis ? params.pillow_splits : 1));
  }
  if (params.pillow_splits == 1) return out;
  propagate_splits(face_ties(maps, coarse), out, "tmesh.pillow_splits");
  return out;
}

std::vector<TMesh> h_refine(const PolycubeMaps& maps, const Params& params, const std::vector<TMesh>& coarse, int times, std::vector<int>* parent) {
  check(params);
  if (times < 0 || times > 3) throw core::ConfigError("tmesh.h_refine must be in [0, 3], got " + std::to_string(times));
  if (parent) parent->clear();
  if (times == 0 && params.pillow_splits == 1) {
    if (parent) {
      int n = 0;
      for (const TMesh& t : coarse) n += t.elements();
      parent->resize(static_cast<std::size_t>(n));
      for (int e = 0; e < n; ++e) (*parent)[static_cast<std::size_t>(e)] = e;
    }
    return coarse;
  }
  // The structure (knots, ids, T-junction rows) is build()'s at every block's level + times; its
  // positions are not needed, so there is no physical map (no sampling, no solve). With
  // pillow_splits, or spans refined one by one (Params::refine "spans"), the knots are the coarse
  // ones with every span split as refinement_splits() says.
  std::vector<std::array<std::vector<double>, 3>> knots;
  const bool on_knots = params.pillow_splits > 1 || params.refine == "spans";
  if (on_knots) {
    const std::vector<SpanSplits> splits = refinement_splits(maps, params, coarse, times);
    for (std::size_t b = 0; b < coarse.size(); ++b) knots.push_back(split_knots(coarse[b], splits[b]));
  }
  PolycubeMaps structure = maps;
  structure.physical = nullptr;  // the structure alone: its positions are set below
  std::vector<std::size_t> offset;  // first block of each cube in `coarse`
  for (std::size_t b = 0; b < coarse.size(); ++b)
    if (b == 0 || coarse[b].component != coarse[b - 1].component) offset.push_back(b);
  offset.push_back(coarse.size());
  std::vector<TMesh> fine = build_with(structure, params, [&](std::size_t k, std::size_t j, bool) {
    const std::size_t b = k + 1 < offset.size() ? offset[k] + j : coarse.size();
    if (b >= coarse.size() || coarse[b].component != static_cast<int>(k))
      throw core::InvalidInputError("tmesh h-refinement: the T-mesh's blocks are not those of its polycube (cube " + std::to_string(k) + ", block " + std::to_string(j) + ")");
    return coarse[b].level + times;
  }, on_knots ? &knots : nullptr);
  if (fine.size() != coarse.size())
    throw core::InvalidInputError("tmesh h-refinement: " + std::to_string(coarse.size()) + " blocks, but the polycube has " + std::to_string(fine.size()));
  // Positions: each block's fine points are the knot-insertion refinement of its coarse points,
  // Rᵀ·P per axis (bezier::refinement_matrix); a node shared by blocks keeps the first block's
  // value (the others agree to rounding: one face, refined alike), and T-junctions are put where
  // their rows say, as build() does.
  double extent = 0;
  for (const TMesh& t : coarse)
    for (const auto& x : t.control_points)
      for (const double v : x) extent = std::max(extent, std::abs(v));
  const double tol = 1e-9 * std::max(extent, 1.0);
  int ids = 0;
  for (const TMesh& t : fine)
    for (const int id : t.function_ids) ids = std::max(ids, id + 1);
  std::vector<Vec3> position(static_cast<std::size_t>(ids));
  std::vector<char> seen(static_cast<std::size_t>(ids), 0);
  for (std::size_t b = 0; b < fine.size(); ++b) {
    const TMesh& c = coarse[b];
    TMesh& t = fine[b];
    if (c.degree != t.degree || c.corners != t.corners)
      throw core::InvalidInputError("tmesh h-refinement: block " + std::to_string(b) + " is not the polycube's (degree or corners differ)");
    std::array<Eigen::MatrixXd, 3> R;
    for (int a = 0; a < 3; ++a) R[static_cast<std::size_t>(a)] = bezier::refinement_matrix(c.knots[static_cast<std::size_t>(a)], t.knots[static_cast<std::size_t>(a)], t.degree);
    // Along u, then v, then w: X(i',j,k) = Σ_i R0(i,i') P(i,j,k), and so on.
    std::array<int, 3> n = c.size;
    std::vector<Eigen::Vector3d> cur;
    for (const auto& x : c.control_points) cur.emplace_back(x[0], x[1], x[2]);
    for (int a = 0; a < 3; ++a) {
      const Eigen::MatrixXd& M = R[static_cast<std::size_t>(a)];
      std::array<int, 3> m = n;
      m[static_cast<std::size_t>(a)] = static_cast<int>(M.cols());
      std::vector<Eigen::Vector3d> next(static_cast<std::size_t>(m[0] * m[1] * m[2]), Eigen::Vector3d::Zero());
      for (int k = 0; k < m[2]; ++k)
        for (int j = 0; j < m[1]; ++j)
          for (int i = 0; i < m[0]; ++i) {
            std::array<int, 3> out{i, j, k}, in = out;
            Eigen::Vector3d s = Eigen::Vector3d::Zero();
            for (int r = 0; r < n[static_cast<std::size_t>(a)]; ++r) {
              const double w = M(r, out[static_cast<std::size_t>(a)]);
              if (w == 0) continue;
              in[static_cast<std::size_t>(a)] = r;
              s += w * cur[static_cast<std::size_t>(in[0] + n[0] * (in[1] + n[1] * in[2]))];
            }
            next[static_cast<std::size_t>(i + m[0] * (j + m[1] * k))] = s;
          }
      cur.swap(next), n = m;
    }
    if (n != t.size) throw core::InvalidInputError("tmesh h-refinement: block " + std::to_string(b) + " refines to another grid than the polycube's");
    for (std::size_t i = 0; i < cur.size(); ++i) {
      const std::size_t id = static_cast<std::size_t>(t.function_ids[i]);
      const Vec3 x{cur[i].x(), cur[i].y(), cur[i].z()};
      if (!seen[id]) {
        seen[id] = 1, position[id] = x;
        continue;
      }
      if (std::hypot(x[0] - position[id][0], x[1] - position[id][1], x[2] - position[id][2]) > tol)
        throw core::NumericalError("tmesh h-refinement: blocks disagree at node " + std::to_string(id) + ": the T-mesh is not C0 there");
    }
  }
  for (TMesh& t : fine)
    for (const auto& con : t.constraints) {
      Vec3 x{0, 0, 0};
      for (std::size_t r = 0; r < con.ids.size(); ++r)
        for (int d = 0; d < 3; ++d) x[static_cast<std::size_t>(d)] += con.weights[r] * position[static_cast<std::size_t>(con.ids[r])][static_cast<std::size_t>(d)];
      const Vec3& y = position[static_cast<std::size_t>(t.function_ids[static_cast<std::size_t>(con.point)])];
      if (std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]) > tol)
        throw core::NumericalError("tmesh h-refinement: a T-junction of block level " + std::to_string(t.level) + " is off its row: the T-mesh is not C0 there");
      position[static_cast<std::size_t>(t.function_ids[static_cast<std::size_t>(con.point)])] = x;
    }
  for (TMesh& t : fine)
    for (std::size_t i = 0; i < t.control_points.size(); ++i) t.control_points[i] = position[static_cast<std::size_t>(t.function_ids[i])];
  if (parent) {
    // Fine element (blocks in order, i fastest) -> the coarse element holding its centre.
    int first = 0;
    for (std::size_t b = 0; b < fine.size(); ++b) {
      std::array<std::vector<int>, 3> up;
      std::array<int, 3> nc{};
      for (int a = 0; a < 3; ++a) {
        const auto ci = bezier::element_intervals(coarse[b].knots[static_cast<std::size_t>(a)], coarse[b].degree);
        nc[static_cast<std::size_t>(a)] = static_cast<int>(ci.size());
        for (const auto& iv : bezier::element_intervals(fine[b].knots[static_cast<std::size_t>(a)], fine[b].degree)) {
          const double mid = 0.5 * (iv[0] + iv[1]);
          int k = 0;
          while (k + 1 < static_cast<int>(ci.size()) && mid > ci[static_cast<std::size_t>(k)][1]) ++k;
          up[static_cast<std::size_t>(a)].push_back(k);
        }
      }
      for (const int k : up[2])
        for (const int j : up[1])
          for (const int i : up[0]) parent->push_back(first + i + nc[0] * (j + nc[1] * k));
      first += nc[0] * nc[1] * nc[2];
    }
  }
  return fine;
}

const std::array<std::array<int, 3>, 8>& hex_corner_neighbours() {
  static const std::array<std::array<int, 3>, 8> nb = {{{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7}, {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}}};
  return nb;
}

double trilinear_min_scaled_jacobian(const std::array<Vec3, 8>& x) {
  const auto& nb = hex_corner_neighbours();
  double worst = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    Eigen::Matrix3d J;
    for (int e = 0; e < 3; ++e)
      for (int k = 0; k < 3; ++k) J(k, e) = x[nb[c][e]][k] - x[c][k];
    const double l = J.col(0).norm() * J.col(1).norm() * J.col(2).norm();
    worst = std::min(worst, l > 0 ? J.determinant() / l : 0.0);
  }
  return worst;
}

core::Json to_json(const TMesh& t) {
  std::vector<double> cp, par;
  for (const auto& p : t.control_points) cp.insert(cp.end(), p.begin(), p.end());
  for (const auto& p : t.parameters) par.insert(par.end(), p.begin(), p.end());
  core::Json j{{"level", t.level}, {"degree", t.degree}, {"knots", t.knots}, {"size", t.size},
                    {"control_points", cp}, {"parameters", par}, {"boundary", t.boundary}, {"component", t.component},
                    {"corners", t.corners}, {"kind", t.kind}, {"function_ids", t.function_ids}, {"constraints", [&] {
                      core::Json c = core::Json::array();
                      for (const auto& k : t.constraints) {
                        c.push_back({{"point", k.point}, {"ids", k.ids}, {"weights", k.weights}});
                        if (k.smooth) c.back()["smooth"] = true;
                      }
                      return c;
                    }()}};
  if (!t.free_nodes.empty()) {
    core::Json f = core::Json::array();
    for (const auto& n : t.free_nodes) f.push_back({n.id, n.point[0], n.point[1], n.point[2]});
    j["free_nodes"] = f;
  }
  return j;
}

TMesh from_json(const core::Json& j, const std::string& file) {
  TMesh t;
  try {
    t.level = core::require(j, "level", file).get<int>();
    t.degree = core::require(j, "degree", file).get<int>();
    t.knots = core::require(j, "knots", file).get<std::array<std::vector<double>, 3>>();
    t.size = core::require(j, "size", file).get<std::array<int, 3>>();
    // The ranges of the config (tmesh.level, tmesh.degree): larger values would overflow 1 << level.
    if (t.level < 1 || t.level > 7 || t.degree < 1 || t.degree > 5)
      throw core::InvalidInputError(file + ": tmesh level " + std::to_string(t.level) + " or degree " +
                                    std::to_string(t.degree) + " out of range (level 1..7, degree 1..5)");
    for (int a = 0; a < 3; ++a) bezier::check_knot_vector(t.knots[a], t.degree, "tmesh knot vector");
    // One control point per B-spline function: the sizes follow from the knots, so their product
    // is bounded by the file's length.
    for (int a = 0; a < 3; ++a)
      if (t.size[a] != static_cast<int>(t.knots[a].size()) - t.degree - 1)
        throw core::InvalidInputError(file + ": tmesh size " + std::to_string(t.size[a]) + " does not match its " +
                                      std::to_string(t.knots[a].size()) + " knots of degree " + std::to_string(t.degree));
    if (j.contains("boundary")) t.boundary = j["boundary"].get<std::array<int, 6>>();
    if (j.contains("component")) t.component = j["component"].get<int>();
    if (j.contains("function_ids")) t.function_ids = j["function_ids"].get<std::vector<int>>();
    if (j.contains("corners")) t.corners = j["corners"].get<std::array<Vec3, 8>>();
    // A pillowed complex of cubes (complex.h) reaches into neighbouring cubes by less than half a cube.
    for (const auto& c : t.corners)
      for (const double x : c)
        if (!(x >= -0.5 && x <= 1.5)) throw core::InvalidInputError(file + ": tmesh block corner outside [-0.5, 1.5]^3, its cube's parameters and the pillow's reach");
    if (j.contains("kind")) t.kind = j["kind"].get<std::string>();
    if (t.kind != "cube" && t.kind != "core" && t.kind != "pillow")
      throw core::InvalidInputError(file + ": unknown tmesh block kind '" + t.kind + "'");
    const auto cp = core::require(j, "control_points", file).get<std::vector<double>>();
    const auto par = core::require(j, "parameters", file).get<std::vector<double>>();
    const std::size_t n = static_cast<std::size_t>(t.size[0]) * t.size[1] * t.size[2];
    if (cp.size() != 3 * n || par.size() != 3 * n)
      throw core::InvalidInputError(file + ": control point count does not match size");
    if (!t.function_ids.empty() && t.function_ids.size() != n)
      throw core::InvalidInputError(file + ": tmesh function_ids has " + std::to_string(t.function_ids.size()) +
                                    " entries for " + std::to_string(n) + " control points");
    for (const int id : t.function_ids)
      if (id < 0) throw core::InvalidInputError(file + ": tmesh function_ids holds a negative id");
    for (const double x : cp)
      if (!std::isfinite(x)) throw core::InvalidInputError(file + ": a tmesh control point is not finite");
    if (j.contains("constraints"))
      for (const auto& k : j["constraints"]) {
        TMesh::Constraint c;
        c.point = core::require(k, "point", file).get<int>();
        c.ids = core::require(k, "ids", file).get<std::vector<int>>();
        c.weights = core::require(k, "weights", file).get<std::vector<double>>();
        if (k.contains("smooth")) {
          if (!k["smooth"].is_boolean()) throw core::InvalidInputError(file + ": tmesh constraint key \"smooth\" is not a boolean");
          c.smooth = k["smooth"].get<bool>();
        }
        if (c.point < 0 || static_cast<std::size_t>(c.point) >= n || (!t.constraints.empty() && c.point <= t.constraints.back().point))
          throw core::InvalidInputError(file + ": tmesh constraint point " + std::to_string(c.point) + " out of range or order");
        if (t.function_ids.empty()) throw core::InvalidInputError(file + ": tmesh constraints without function_ids");
        if (c.ids.empty() || c.ids.size() != c.weights.size())
          throw core::InvalidInputError(file + ": tmesh constraint of point " + std::to_string(c.point) + " has " + std::to_string(c.ids.size()) +
                                        " ids and " + std::to_string(c.weights.size()) + " weights");
        double sum = 0;
        for (std::size_t k2 = 0; k2 < c.ids.size(); ++k2) {
          if (c.ids[k2] < 0 || !std::isfinite(c.weights[k2])) throw core::InvalidInputError(file + ": tmesh constraint with a negative id or a weight that is not finite");
          sum += c.weights[k2];
        }
        if (!(std::abs(sum - 1) <= 1e-9))
          throw core::InvalidInputError(file + ": tmesh constraint of point " + std::to_string(c.point) + " has weights summing to " + std::to_string(sum) + ", not 1");
        t.constraints.push_back(std::move(c));
      }
    if (j.contains("free_nodes"))
      for (const auto& f : j["free_nodes"]) {
        if (!f.is_array() || f.size() != 4) throw core::InvalidInputError(file + ": tmesh free node is not [id, x, y, z]");
        TMesh::FreeNode node;
        node.id = f[0].get<int>();
        node.point = {f[1].get<double>(), f[2].get<double>(), f[3].get<double>()};
        if (node.id < 0 || !std::isfinite(node.point[0]) || !std::isfinite(node.point[1]) || !std::isfinite(node.point[2]) ||
            (!t.free_nodes.empty() && node.id <= t.free_nodes.back().id))
          throw core::InvalidInputError(file + ": tmesh free node " + std::to_string(node.id) + " with a negative id, out of order or not finite");
        t.free_nodes.push_back(node);
      }
    for (std::size_t i = 0; i < n; ++i) {
      t.control_points.push_back({cp[3 * i], cp[3 * i + 1], cp[3 * i + 2]});
      t.parameters.push_back({par[3 * i], par[3 * i + 1], par[3 * i + 2]});
    }
  } catch (const core::Json::exception& e) {
    throw core::InvalidInputError(file + ": malformed tmesh: " + e.what());
  }
  return t;
}

namespace {

// Global id of control point i of block b (block after block when a block has no ids).
std::vector<std::vector<int>> global_ids(const std::vector<TMesh>& ts, int* count) {
  std::vector<std::vector<int>> ids(ts.size());
  int next = 0;
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const auto& t = ts[b];
    if (t.function_ids.empty()) {
      for (std::size_t i = 0; i < t.control_points.size(); ++i) ids[b].push_back(next++);
    } else {
      ids[b] = t.function_ids;
    }
  }
  int n = next;
  for (const auto& v : ids)
    for (const int i : v) n = std::max(n, i + 1);
  *count = n;
  return ids;
}

// The spline at the corners of t's elements, each span split as `splits` says (none: not split),
// index i + (n0+1)*(j + (n1+1)*k), and in n the number of (split) elements per direction.
std::vector<Vec3> corner_grid(const TMesh& t, std::array<int, 3>* n, const SpanSplits* splits = nullptr) {
  std::array<std::vector<double>, 3> g;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto intervals = bezier::element_intervals(t.knots[a], t.degree);
    if (splits && (*splits)[a].size() != intervals.size())
      throw core::ConfigError("tmesh: " + std::to_string((*splits)[a].size()) + " split counts for " + std::to_string(intervals.size()) + " element spans");
    for (std::size_t e = 0; e < intervals.size(); ++e) {
      const auto& iv = intervals[e];
      const int m = splits ? (*splits)[a][e] : 1;
      for (int i = 0; i < m; ++i) g[a].push_back(i == 0 ? iv[0] : iv[0] + (iv[1] - iv[0]) * i / m);
    }
    g[a].push_back(intervals.back()[1]);
    (*n)[a] = static_cast<int>(g[a].size()) - 1;
  }
  const BlockGrid grid(t, g);
  std::vector<Vec3> x;
  for (std::size_t k = 0; k < g[2].size(); ++k)
    for (std::size_t j = 0; j < g[1].size(); ++j)
      for (std::size_t i = 0; i < g[0].size(); ++i) x.push_back(grid.at(i, j, k));
  return x;
}

// Calls f(corners in VTK order) for every element of t, as a trilinear hex of its corner points.
template <class F>
void for_each_trilinear_element(const TMesh& t, F&& f, const SpanSplits* splits = nullptr) {
  std::array<int, 3> n{};
  const std::vector<Vec3> x = corner_grid(t, &n, splits);
  auto at = [&](int i, int j, int k) { return static_cast<std::size_t>(i + (n[0] + 1) * (j + (n[1] + 1) * k)); };
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::array<std::size_t, 8> h = {at(i, j, k), at(i + 1, j, k), at(i + 1, j + 1, k), at(i, j + 1, k),
                                              at(i, j, k + 1), at(i + 1, j, k + 1), at(i + 1, j + 1, k + 1), at(i, j + 1, k + 1)};
        std::array<Vec3, 8> c;
        for (int a = 0; a < 8; ++a) c[a] = x[h[a]];
        f(c);
      }
}

// Irregular surface nodes are block corners: inside a block's surface face, and along an edge
// two surface faces share, every node has four surface neighbours at any level. A corner's
// valence is the number of surface block edges (edges of a block face on the surface) that
// leave it, matched across blocks and levels by the corner control points (clamped, so they
// interpolate the spline: the same point in every block that has it).
int irregular_surface_corners(const std::vector<TMesh>& ts) {
  double extent = 0;
  for (const TMesh& t : ts)
    for (const Vec3& x : t.control_points) extent = std::max({extent, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
  const double cell = 1e-9 * std::max(extent, 1e-300);
  using Key = std::array<long long, 3>;
  auto key = [&](const Vec3& x) { return Key{std::llround(x[0] / cell), std::llround(x[1] / cell), std::llround(x[2] / cell)}; };
  std::map<Key, std::set<Key>> edges;
  for (const TMesh& t : ts)
    for (int corner = 0; corner < 8; ++corner) {
      std::array<int, 3> idx{}, side{};
      for (std::size_t a = 0; a < 3; ++a) side[a] = (corner >> a) & 1, idx[a] = side[a] * (t.size[a] - 1);
      auto point = [&](const std::array<int, 3>& i) { return t.control_points[static_cast<std::size_t>(i[0] + t.size[0] * (i[1] + t.size[1] * i[2]))]; };
      auto on = [&](std::size_t a) { return t.boundary[2 * a + static_cast<std::size_t>(side[a])] != 0; };  // the face of axis a at this corner
      if (!on(0) && !on(1) && !on(2)) continue;
      const Key x = key(point(idx));
      for (std::size_t a = 0; a < 3; ++a) {
        if (!on((a + 1) % 3) && !on((a + 2) % 3)) continue;  // the edge along axis a lies on no surface face
        std::array<int, 3> other = idx;
        other[a] = t.size[a] - 1 - idx[a];
        const Key y = key(point(other));
        if (y != x) edges[x].insert(y);
      }
    }
  return static_cast<int>(std::count_if(edges.begin(), edges.end(), [](const auto& e) { return e.second.size() != 4; }));
}

}  // namespace

NodeCounts count_nodes(const std::vector<TMesh>& ts) {
  NodeCounts c;
  const auto ids = global_ids(ts, &c.nodes);
  std::vector<char> on_surface(static_cast<std::size_t>(c.nodes), 0), junction(static_cast<std::size_t>(c.nodes), 0);
  std::vector<std::set<int>> nb(static_cast<std::size_t>(c.nodes));
  std::vector<char> named(static_cast<std::size_t>(c.nodes), 0);  // named by a T-junction's row: on a face between levels
  std::vector<Vec3> position(static_cast<std::size_t>(c.nodes), Vec3{0, 0, 0});
  // A T-junction whose row weighs one coarser node by more than a half is that node's point in
  // the finer net (knot insertion's vertex point: 6/8 per direction across a face, (6/8)^2 on it);
  // its links in the finer net are that node's links toward the finer side.
  // Where several do (near a clamped end), the one that weighs it most.
  std::vector<int> twin(static_cast<std::size_t>(c.nodes), -1);  // per node, its point in the finer net
  std::vector<double> twin_weight(static_cast<std::size_t>(c.nodes), 0.5 + 1e-9);
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (const auto& k : ts[b].constraints) {
      if (k.smooth) continue;  // a clamped extra of a C2 face (continuity.h), not a T-junction
      const int u = ids[b][static_cast<std::size_t>(k.point)];
      junction[static_cast<std::size_t>(u)] = 1;
      for (std::size_t r = 0; r < k.ids.size(); ++r) {
        const int m = k.ids[r];
        if (m < 0 || m >= c.nodes) continue;
        named[static_cast<std::size_t>(m)] = 1;
        if (k.weights[r] > twin_weight[static_cast<std::size_t>(m)]) twin_weight[static_cast<std::size_t>(m)] = k.weights[r], twin[static_cast<std::size_t>(m)] = u;
      }
    }
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const TMesh& t = ts[b];
    for (int k = 0; k < t.size[2]; ++k)
      for (int j = 0; j < t.size[1]; ++j)
        for (int i = 0; i < t.size[0]; ++i) {
          const int idx[3] = {i, j, k};
          const auto at = static_cast<std::size_t>(i + t.size[0] * (j + t.size[1] * k));
          const int id = ids[b][at];
          position[static_cast<std::size_t>(id)] = t.control_points[at];
          for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side)
              if (t.boundary[2 * a + side] && idx[a] == (side ? t.size[a] - 1 : 0)) on_surface[static_cast<std::size_t>(id)] = 1;
          for (int a = 0; a < 3; ++a) {
            if (idx[a] + 1 >= t.size[a]) continue;
            const std::size_t stride = a == 0 ? 1 : a == 1 ? static_cast<std::size_t>(t.size[0]) : static_cast<std::size_t>(t.size[0]) * t.size[1];
            const int other = ids[b][at + stride];
            if (other == id) continue;
            nb[static_cast<std::size_t>(id)].insert(other);
            nb[static_cast<std::size_t>(other)].insert(id);
          }
        }
  }
  // A node on a face toward a finer level (every point of the face named by rows or, on its rim,
  // a T-junction toward a coarser one) that is no T-junction itself has one neighbour across it in the T-mesh, a T-junction of the finer
  // net that its own net does not link: one per direction across (coplanar faces of two blocks
  // at one node are one direction).
  std::vector<std::vector<Eigen::Vector3d>> across(static_cast<std::size_t>(c.nodes));
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const TMesh& t = ts[b];
    for (int f = 0; f < 6; ++f) {
      if (t.boundary[static_cast<std::size_t>(f)]) continue;
      const int a = f / 2, u = (a + 1) % 3, w = (a + 2) % 3;
      if (t.size[a] < 2) continue;
      std::vector<std::size_t> pts;
      bool interface = true;
      for (int j = 0; j < t.size[w] && interface; ++j)
        for (int i = 0; i < t.size[u] && interface; ++i) {
          std::array<int, 3> idx{};
          idx[static_cast<std::size_t>(a)] = f % 2 ? t.size[a] - 1 : 0, idx[static_cast<std::size_t>(u)] = i, idx[static_cast<std::size_t>(w)] = j;
          const auto at = static_cast<std::size_t>(idx[0] + t.size[0] * (idx[1] + t.size[1] * idx[2]));
          const auto id = static_cast<std::size_t>(ids[b][at]);
          interface = named[id] || junction[id];  // a T-junction of its own on the face's rim (three levels)
          if (named[id] && !junction[id]) pts.push_back(at);
        }
      if (!interface) continue;
      const std::size_t stride = a == 0 ? 1 : a == 1 ? static_cast<std::size_t>(t.size[0]) : static_cast<std::size_t>(t.size[0]) * t.size[1];
      for (const std::size_t at : pts) {
        const std::size_t in = f % 2 ? at - stride : at + stride;
        const auto& x = t.control_points[at];
        const auto& y = t.control_points[in];
        Eigen::Vector3d d(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
        if (!(d.norm() > 0)) continue;
        d.normalize();
        auto& dirs = across[static_cast<std::size_t>(ids[b][at])];
        if (std::none_of(dirs.begin(), dirs.end(), [&](const Eigen::Vector3d& e) { return e.dot(d) > 0.9; })) dirs.push_back(d);
      }
    }
  }
  // Links of T-junctions that are a node's point in the finer net go to that node, except those
  // along a link it has (a coarser and a finer link along a face between levels are one).
  std::vector<std::set<int>> links = nb;
  auto direction = [&](int from, int to) {
    const Vec3& x = position[static_cast<std::size_t>(from)];
    const Vec3& y = position[static_cast<std::size_t>(to)];
    const Eigen::Vector3d e(y[0] - x[0], y[1] - x[1], y[2] - x[2]);
    return e.norm() > 0 ? Eigen::Vector3d(e.normalized()) : Eigen::Vector3d::Zero();
  };
  std::vector<char> twinned(static_cast<std::size_t>(c.nodes), 0);
  for (int v = 0; v < c.nodes; ++v) {
    const int u = twin[static_cast<std::size_t>(v)];
    if (u < 0) continue;
    twinned[static_cast<std::size_t>(v)] = 1;
    auto& l = links[static_cast<std::size_t>(v)];
    for (const int w : nb[static_cast<std::size_t>(u)]) {
      const Eigen::Vector3d d = direction(u, w);  // in the finer net's own frame
      if (w != v && d.norm() > 0 && std::none_of(l.begin(), l.end(), [&](int m) { return direction(v, m).dot(d) > 0.9; })) l.insert(w);
    }
  }
  for (int v = 0; v < c.nodes; ++v) {
    const auto& n = links[static_cast<std::size_t>(v)];
    if (n.empty()) continue;  // an id no block uses
    if (junction[static_cast<std::size_t>(v)]) {  // a T-junction: on a face or an edge of the coarser net, neither regular nor irregular
      ++c.t_junctions;
      if (on_surface[static_cast<std::size_t>(v)]) ++c.surface;
      continue;
    }
    if (named[static_cast<std::size_t>(v)]) ++c.level_interface;
    // Across a face toward a finer level: the finer net's links at the node's point there, else
    // (no vertex point) one per direction where the node links no node that way already.
    const int extra = twinned[static_cast<std::size_t>(v)] ? 0 : static_cast<int>(std::count_if(across[static_cast<std::size_t>(v)].begin(), across[static_cast<std::size_t>(v)].end(), [&](const Eigen::Vector3d& d) {
      return std::none_of(n.begin(), n.end(), [&](int w) { return direction(v, w).dot(d) > 0.9; });
    }));
    if (on_surface[static_cast<std::size_t>(v)]) {
      ++c.surface;
    } else if (static_cast<int>(n.size()) + extra != 6) {
      ++c.irregular_interior;
    }
  }
  c.irregular_surface = irregular_surface_corners(ts);
  return c;
}

double min_element_scaled_jacobian(const TMesh& t, int h_refine) {
  if (h_refine < 0 || h_refine > 3) throw core::ConfigError("tmesh::min_element_scaled_jacobian: h_refine must be in [0, 3], got " + std::to_string(h_refine));
  SpanSplits splits;
  for (std::size_t a = 0; a < 3; ++a) splits[a].assign(bezier::element_intervals(t.knots[a], t.degree).size(), 1 << h_refine);
  return min_element_scaled_jacobian(t, splits);
}

double min_element_scaled_jacobian(const TMesh& t, const SpanSplits& splits) {
  for (const auto& axis : splits)
    for (const int s : axis)
      if (s < 1 || s > 64) throw core::ConfigError("tmesh::min_element_scaled_jacobian: splits must be in [1, 64], got " + std::to_string(s));
  double worst = std::numeric_limits<double>::infinity();
  for_each_trilinear_element(t, [&](const std::array<Vec3, 8>& c) { worst = std::min(worst, trilinear_min_scaled_jacobian(c)); }, &splits);
  return worst;
}

core::Json report_figures(const std::vector<TMesh>& ts, double before, double after) {
  const NodeCounts nc = count_nodes(ts);
  std::size_t control_points = 0;
  int elements = 0, level = 0, min_level = ts.empty() ? 0 : ts.front().level;
  std::set<int> cubes, constrained, free_nodes;  // functions: the nodes without a row, and the free nodes
  for (const auto& t : ts) {
    for (const auto& k : t.constraints)
      if (!t.function_ids.empty()) constrained.insert(t.function_ids[static_cast<std::size_t>(k.point)]);
    for (const auto& f : t.free_nodes) free_nodes.insert(f.id);
    control_points += t.control_points.size();
    elements += t.elements();
    level = std::max(level, t.level);
    min_level = std::min(min_level, t.level);
    cubes.insert(t.component);
  }
  return core::Json{{"nodes", nc.nodes},
                    {"functions", nc.nodes - static_cast<int>(constrained.size()) + static_cast<int>(free_nodes.size())},
                    {"t_junctions", nc.t_junctions},
                    {"level_interface_nodes", nc.level_interface},
                    {"min_level", min_level},
                    {"control_points", control_points},
                    {"cubes", cubes.size()},
                    {"blocks", ts.size()},
                    {"elements", elements},
                    {"max_level", level},
                    {"irregular_nodes_surface", nc.irregular_surface},
                    {"irregular_nodes_interior", nc.irregular_interior},
                    {"min_scaled_jacobian_before", before},
                    {"min_scaled_jacobian_after", after}};
}

double write_vtu(const std::string& path, const std::vector<TMesh>& ts, const std::vector<std::pair<std::string, std::vector<double>>>& extra) {
  viz::UnstructuredGrid g;
  viz::Field sj{"scaled_jacobian", 1, {}}, comp{"component", 1, {}}, block{"block", 1, {}}, pillow{"pillow", 1, {}};
  double worst = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const TMesh& t = ts[b];
    for_each_trilinear_element(t, [&](const std::array<Vec3, 8>& c) {
      std::vector<int> cell;
      for (const auto& p : c) cell.push_back(static_cast<int>(g.points.size())), g.points.push_back(p);
      const double s = trilinear_min_scaled_jacobian(c);
      worst = std::min(worst, s);
      g.cells.push_back(cell);
      g.cell_types.push_back(12);  // VTK_HEXAHEDRON
      sj.values.push_back(s);
      comp.values.push_back(t.component);
      block.values.push_back(static_cast<double>(b));
      pillow.values.push_back(t.kind == "pillow" ? 1 : 0);
    });
  }
  g.cell_fields = {sj, comp, block, pillow};
  for (const auto& [name, values] : extra) {
    if (values.size() != g.cells.size())
      throw std::invalid_argument("tmesh.vtu: field " + name + " has " + std::to_string(values.size()) + " values for " + std::to_string(g.cells.size()) + " elements");
    g.cell_fields.push_back(viz::Field{name, 1, values});
  }
  viz::write_vtu(path, g);
  return worst;
}

}  // namespace volts::tmesh
