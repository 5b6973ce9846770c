// volts::extract — points merged within a tolerance: the nodes Gmsh's elements share and the
// global functions of C0 Bézier elements (bezier_basis) are the distinct points of the elements.
// A hash grid of cells much larger than the tolerance: a match lies in the point's cell or, where
// the point is within the tolerance of a side, the cell across it; merging n points costs O(n).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace volts::extract {

class PointIndex {
 public:
  /// Points within `tol` of each other are one (tol >= 0); `box` holds every point given.
  PointIndex(const Eigen::AlignedBox3d& box, double tol);
  /// The index of a point within tol of x added before, else x's new index.
  int find_or_add(const Eigen::Vector3d& x);
  /// The index of a point within tol of x, or -1.
  int find(const Eigen::Vector3d& x) const;
  const std::vector<Eigen::Vector3d>& points() const { return points_; }
  /// Room for n points without rehashing.
  void reserve(std::size_t n);

 private:
  using Key = std::array<long long, 3>;
  Key key(const Eigen::Vector3d& x) const;
  /// The slot of cell k in the table: its own, or the empty one where it would go.
  std::size_t slot(const Key& k) const;
  void grow(std::size_t size);
  Eigen::Vector3d origin_;
  double tol_ = 0, cell_ = 1;
  std::vector<Eigen::Vector3d> points_;
  // Per cell its last point; each point links to the previous one in its cell (-1 ends). The
  // cells are an open-addressing table (linear probing, at most half full) whose slot holds the
  // cell's last point alone (its key is that point's): 4 bytes a slot. std::unordered_map's node
  // per cell made merging the eight's 573,440 .vtu points cost 0.1 s; memory touched the first
  // time costs more than the arithmetic on this project's VMs.
  std::vector<int> heads_;  // -1: empty slot
  std::size_t cells_ = 0;
  std::vector<int> next_;
};

}  // namespace volts::extract
