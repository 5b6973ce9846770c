// volts::octree — the adaptive octree of one cube in index space (Liu et al. 2013, §5.1; issue 7
// item 1), groundwork for the adaptive T-mesh.
//
// §5.1: "For each boundary element, we check the local distance from the T-mesh boundary to the
// input boundary, and subdivide the element if the distance is greater than a given threshold ε
// ... T-junctions are introduced if two neighboring elements have different subdivision levels."
// refine() takes that test as a predicate; balance() adds the 2:1 condition (ours, not the paper's:
// it keeps every T-junction at a face centre or edge midpoint, which the T-mesh templates need);
// t_junctions() lists the hanging nodes.
//
// Hand-written rather than CGAL::Orthtree because CGAL 5.5 (Debian 12) grade() only looks at the 6
// face directions (adjacent_node), so it leaves edge-adjacent leaves unbalanced, and it reports no
// T-junctions; it is also built around a point set, which we do not have.
//
// Index space: the root is the integer box [0, 2^max_level]^3; a cell of level l has side
// 2^(max_level - l) and its corners are multiples of that side. Faces are numbered 2*axis + side
// (side 0: the low face). Edges are numbered 4*a + sb + 2*sc: a is the edge's direction, b = (a+1)%3
// and c = (a+2)%3 the two other axes, sb and sc the edge's side (0 low, 1 high) on them.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace volts::octree {

/// Parameters of an Octree.
struct OctreeParams {
  int max_level = 6;  ///< deepest level: leaves of side 1 in a root of side 2^max_level [0, 16]
};

using Index3 = std::array<int, 3>;
using Vec3 = std::array<double, 3>;

/// A cell: the integer box [lo, lo + side]^3 of a level, and the same box in [0,1]^3.
struct Cell {
  int level = 0;
  Index3 lo{0, 0, 0};
  int side = 1;  ///< 2^(max_level - level)
  Vec3 unit_lo{0, 0, 0};
  Vec3 unit_hi{1, 1, 1};
  Index3 hi() const { return {lo[0] + side, lo[1] + side, lo[2] + side}; }
};

/// A hanging node: a leaf vertex in the open interior of a face or an edge of another leaf.
struct TJunction {
  enum class On { face, edge };
  Index3 node{0, 0, 0};
  int leaf = -1;      ///< the leaf whose face or edge the node is on
  On on = On::face;
  int index = 0;      ///< face (0..5) or edge (0..11) of that leaf, numbered as in the file comment
};

/// Two leaves sharing a face or an edge whose levels differ by more than one.
struct UnbalancedPair {
  int fine = -1;    ///< leaf id of the deeper leaf
  int coarse = -1;  ///< leaf id of the shallower leaf
  bool edge_only = false;  ///< they share an edge but no face
};

/// What check() found; ok() when the leaves tile the root and are 2:1 balanced.
struct CheckResult {
  std::int64_t volume = 0;       ///< sum of the leaves' volumes
  std::int64_t root_volume = 0;  ///< (2^max_level)^3
  int misshapen = 0;   ///< leaves outside the root, not aligned to their side, or of the wrong side
  int overlaps = 0;    ///< leaves inside another leaf (dyadic boxes overlap only so), duplicates included
  std::vector<UnbalancedPair> unbalanced;
  bool tiles() const { return misshapen == 0 && overlaps == 0 && volume == root_volume; }
  bool ok() const { return tiles() && unbalanced.empty(); }
};

/// The octree: a vector of nodes (integer corner, level, index of the first of 8 consecutive
/// children or -1 for a leaf), so a point is located by descending from the root. Leaf ids are
/// positions in leaves(); they change whenever refine() or balance() splits something.
class Octree {
 public:
  /// Only the root. Throws core::ConfigError for parameters out of range.
  explicit Octree(const OctreeParams& params = {});

  int max_level() const { return max_level_; }
  int root_side() const { return 1 << max_level_; }

  /// Splits every leaf for which `split` is true, then its children, and so on, down to
  /// max_level. Returns the number of splits.
  int refine(const std::function<bool(const Cell&)>& split);
  /// Splits leaves until any two leaves sharing a face or an edge differ by at most one level
  /// (corner-only contact is not constrained). Only forced splits: the result is the coarsest
  /// balanced refinement. Returns the number of splits (0 on a balanced tree).
  int balance();

  const std::vector<Cell>& leaves() const { return leaves_; }
  /// Leaves outside leaf `leaf` touching its face `face` with positive area: one as large or
  /// larger, or several smaller. Empty on the root's boundary.
  std::vector<int> face_neighbours(int leaf, int face) const;
  /// Every (node, leaf) pair where a leaf vertex lies in the open interior of a face or an edge of
  /// that leaf, sorted by node. A node may hang on several leaves (e.g. on the edges of two).
  std::vector<TJunction> t_junctions() const;
  /// The leaves' vertices (the T-mesh nodes), sorted and without duplicates.
  std::vector<Index3> nodes() const;
  /// The leaf containing the unit index cell [p, p + 1]^3, or -1 outside the root.
  int locate(const Index3& p) const;

 private:
  struct Node {
    Index3 lo;
    int level;
    int first_child;  ///< -1: a leaf
  };
  void split(int node);
  int locate_node(const Index3& p) const;
  void rebuild_leaves();
  Cell cell(const Node& n) const;

  int max_level_;
  std::vector<Node> nodes_;
  std::vector<Cell> leaves_;
  std::vector<int> leaf_node_;  ///< node index of each leaf
  std::vector<int> node_leaf_;  ///< leaf id of each node, -1 for inner nodes
};

/// Tiling and balance of the leaves, from the leaf list alone (not from the tree's links), so it
/// also checks the tree's bookkeeping.
CheckResult check(const Octree& tree);

}  // namespace volts::octree
