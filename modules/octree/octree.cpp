// Adaptive octree of one cube in index space: refinement, 2:1 face+edge balance, hanging nodes.
#include "octree/octree.h"

#include <algorithm>
#include <map>
#include <string>
#include <unordered_map>

#include "core/errors.h"

namespace volts::octree {
namespace {

// The 6 face and 12 edge directions: offsets with one or two non-zero components.
std::vector<Index3> face_and_edge_directions() {
  std::vector<Index3> dirs;
  for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x) {
        const int nonzero = (x != 0) + (y != 0) + (z != 0);
        if (nonzero == 1 || nonzero == 2) dirs.push_back({x, y, z});
      }
  return dirs;
}

// A unit index cell just outside the box [lo, lo + side] in direction d, touching it (at the low
// end along the axes where d is 0). Any leaf at most as deep as the box that shares with it the face
// or edge of direction d contains that cell, since dyadic cells nest.
Index3 outside_sample(const Index3& lo, int side, const Index3& d) {
  Index3 p;
  for (int a = 0; a < 3; ++a) p[a] = d[a] < 0 ? lo[a] - 1 : (d[a] > 0 ? lo[a] + side : lo[a]);
  return p;
}

bool inside_root(const Index3& p, int root) {
  return p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] < root && p[1] < root && p[2] < root;
}

// check() key of a well-shaped cell: coordinates below 2^16, level below 2^5.
std::uint64_t key(int level, const Index3& lo) {
  return (std::uint64_t(level) << 48) | (std::uint64_t(lo[0]) << 32) | (std::uint64_t(lo[1]) << 16) | std::uint64_t(lo[2]);
}

}  // namespace

Octree::Octree(const OctreeParams& params) : max_level_(params.max_level) {
  if (params.max_level < 0 || params.max_level > 16)
    throw core::ConfigError("octree.max_level must be in [0, 16], got " + std::to_string(params.max_level));
  nodes_.push_back({{0, 0, 0}, 0, -1});
  rebuild_leaves();
}

Cell Octree::cell(const Node& n) const {
  Cell c;
  c.level = n.level;
  c.lo = n.lo;
  c.side = 1 << (max_level_ - n.level);
  const double root = root_side();
  for (int a = 0; a < 3; ++a) {
    c.unit_lo[a] = n.lo[a] / root;
    c.unit_hi[a] = (n.lo[a] + c.side) / root;
  }
  return c;
}

void Octree::split(int node) {
  const Node n = nodes_[node];
  const int half = 1 << (max_level_ - n.level - 1);
  const int first = static_cast<int>(nodes_.size());
  for (int c = 0; c < 8; ++c)  // child c = x + 2y + 4z, bit set: upper half on that axis
    nodes_.push_back({{n.lo[0] + (c & 1) * half, n.lo[1] + ((c >> 1) & 1) * half, n.lo[2] + ((c >> 2) & 1) * half},
                      n.level + 1, -1});
  nodes_[node].first_child = first;
}

int Octree::locate_node(const Index3& p) const {
  if (!inside_root(p, root_side())) return -1;
  int n = 0;
  while (nodes_[n].first_child >= 0) {
    const int half = 1 << (max_level_ - nodes_[n].level - 1);
    int c = 0;
    for (int a = 0; a < 3; ++a)
      if (p[a] >= nodes_[n].lo[a] + half) c |= 1 << a;
    n = nodes_[n].first_child + c;
  }
  return n;
}

int Octree::locate(const Index3& p) const {
  const int n = locate_node(p);
  return n < 0 ? -1 : node_leaf_[n];
}

void Octree::rebuild_leaves() {
  leaves_.clear();
  leaf_node_.clear();
  node_leaf_.assign(nodes_.size(), -1);
  for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
    if (nodes_[n].first_child >= 0) continue;
    node_leaf_[n] = static_cast<int>(leaves_.size());
    leaf_node_.push_back(n);
    leaves_.push_back(cell(nodes_[n]));
  }
}

int Octree::refine(const std::function<bool(const Cell&)>& split_cell) {
  std::vector<int> todo = leaf_node_;
  int splits = 0;
  while (!todo.empty()) {
    const int n = todo.back();
    todo.pop_back();
    if (nodes_[n].level >= max_level_ || !split_cell(cell(nodes_[n]))) continue;
    split(n);
    ++splits;
    for (int c = 0; c < 8; ++c) todo.push_back(nodes_[n].first_child + c);
  }
  rebuild_leaves();
  return splits;
}

int Octree::balance() {
  static const std::vector<Index3> dirs = face_and_edge_directions();
  std::vector<int> todo = leaf_node_;
  int splits = 0;
  while (!todo.empty()) {
    const int n = todo.back();
    todo.pop_back();
    if (nodes_[n].first_child >= 0) continue;  // split since it was queued; its children are queued
    const int level = nodes_[n].level;
    const int side = 1 << (max_level_ - level);
    for (const Index3& d : dirs) {
      const Index3 p = outside_sample(nodes_[n].lo, side, d);
      // Every split here is forced (a leaf two levels coarser than a neighbour), so the result is
      // the coarsest balanced refinement; the new children are queued to propagate.
      for (int m = locate_node(p); m >= 0 && nodes_[m].level < level - 1; m = locate_node(p)) {
        split(m);
        ++splits;
        for (int c = 0; c < 8; ++c) todo.push_back(nodes_[m].first_child + c);
      }
    }
  }
  rebuild_leaves();
  return splits;
}

std::vector<int> Octree::face_neighbours(int leaf, int face) const {
  const Cell& c = leaves_.at(leaf);
  const int a = face / 2, b = (a + 1) % 3, e = (a + 2) % 3;
  // The one-cell-thick slab just outside the face; a leaf touches the face with positive area iff
  // it overlaps that slab.
  const int slab_lo = face % 2 ? c.lo[a] + c.side : c.lo[a] - 1;
  std::vector<int> out;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& n = nodes_[stack.back()];
    const int idx = stack.back();
    stack.pop_back();
    const int s = 1 << (max_level_ - n.level);
    if (n.lo[a] > slab_lo || n.lo[a] + s <= slab_lo) continue;
    if (n.lo[b] >= c.lo[b] + c.side || n.lo[b] + s <= c.lo[b]) continue;
    if (n.lo[e] >= c.lo[e] + c.side || n.lo[e] + s <= c.lo[e]) continue;
    if (n.first_child < 0) {
      out.push_back(node_leaf_[idx]);
    } else {
      for (int k = 0; k < 8; ++k) stack.push_back(n.first_child + k);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Index3> Octree::nodes() const {
  std::vector<Index3> out;
  out.reserve(leaves_.size() * 8);
  for (const Cell& c : leaves_)
    for (int k = 0; k < 8; ++k)
      out.push_back({c.lo[0] + (k & 1) * c.side, c.lo[1] + ((k >> 1) & 1) * c.side, c.lo[2] + ((k >> 2) & 1) * c.side});
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<TJunction> Octree::t_junctions() const {
  std::vector<TJunction> out;
  const int root = root_side();
  for (const Index3& p : nodes()) {
    // Every leaf whose closed box holds p contains one of the 8 unit cells around p.
    std::vector<int> around;
    for (int o = 0; o < 8; ++o) {
      const Index3 q{p[0] - ((o & 1) ? 0 : 1), p[1] - ((o & 2) ? 0 : 1), p[2] - ((o & 4) ? 0 : 1)};
      if (inside_root(q, root)) around.push_back(locate(q));
    }
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    for (int leaf : around) {
      const Cell& c = leaves_[leaf];
      const Index3 hi = c.hi();
      int on = 0, free_axis = -1;
      for (int a = 0; a < 3; ++a) {
        if (p[a] == c.lo[a] || p[a] == hi[a]) ++on;
        else free_axis = a;
      }
      if (on == 1) {  // strictly inside a face: the face's axis is the one p is on
        for (int a = 0; a < 3; ++a)
          if (p[a] == c.lo[a] || p[a] == hi[a]) out.push_back({p, leaf, TJunction::On::face, 2 * a + (p[a] == hi[a])});
      } else if (on == 2) {  // strictly inside the edge along free_axis
        const int b = (free_axis + 1) % 3, e = (free_axis + 2) % 3;
        out.push_back({p, leaf, TJunction::On::edge, 4 * free_axis + (p[b] == hi[b]) + 2 * (p[e] == hi[e])});
      }  // on == 3: a corner of the leaf, not hanging there
    }
  }
  return out;
}

CheckResult check(const Octree& tree) {
  static const std::vector<Index3> dirs = face_and_edge_directions();
  const int max_level = tree.max_level(), root = tree.root_side();
  const auto& leaves = tree.leaves();
  CheckResult r;
  r.root_volume = std::int64_t(root) * root * root;
  std::unordered_map<std::uint64_t, int> by_key;  // well-shaped leaves by (level, corner)
  std::vector<char> good(leaves.size(), 0);
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const Cell& c = leaves[i];
    r.volume += std::int64_t(c.side) * c.side * c.side;
    bool shaped = c.level >= 0 && c.level <= max_level && c.side == (1 << (max_level - c.level));
    for (int a = 0; a < 3 && shaped; ++a)
      shaped = c.lo[a] >= 0 && c.lo[a] + c.side <= root && c.lo[a] % c.side == 0;
    if (!shaped) {
      ++r.misshapen;
      continue;
    }
    good[i] = 1;
    if (!by_key.emplace(key(c.level, c.lo), static_cast<int>(i)).second) ++r.overlaps;  // duplicate
  }
  // The leaf (from the list) containing the unit cell p: the deepest listed ancestor of p.
  auto containing = [&](const Index3& p) {
    for (int l = max_level; l >= 0; --l) {
      const int s = 1 << (max_level - l);
      const auto it = by_key.find(key(l, {p[0] / s * s, p[1] / s * s, p[2] / s * s}));
      if (it != by_key.end()) return it->second;
    }
    return -1;
  };
  std::map<std::pair<int, int>, bool> pairs;  // (fine, coarse) -> found only across edges
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    if (!good[i]) continue;
    const Cell& c = leaves[i];
    // Dyadic boxes overlap only by nesting: look for a listed strict ancestor.
    for (int l = c.level - 1; l >= 0; --l) {
      const int s = 1 << (max_level - l);
      if (by_key.count(key(l, {c.lo[0] / s * s, c.lo[1] / s * s, c.lo[2] / s * s}))) ++r.overlaps;
    }
    for (const Index3& d : dirs) {
      const Index3 p = outside_sample(c.lo, c.side, d);
      if (!inside_root(p, root)) continue;
      const int n = containing(p);
      if (n < 0 || leaves[n].level >= c.level - 1) continue;
      const bool edge = (d[0] != 0) + (d[1] != 0) + (d[2] != 0) == 2;
      const auto it = pairs.emplace(std::make_pair(static_cast<int>(i), n), edge).first;
      it->second = it->second && edge;
    }
  }
  for (const auto& [p, edge_only] : pairs) r.unbalanced.push_back({p.first, p.second, edge_only});
  return r;
}

}  // namespace volts::octree
