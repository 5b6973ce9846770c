// volts::extract — points merged within a tolerance: the nodes Gmsh's elements share and the
// global functions of C0 Bézier elements (bezier_basis) are the distinct points of the elements.
// A hash grid of cells much larger than the tolerance: a match lies in the point's cell or, where
// the point is within the tolerance of a side, the cell across it; merging n points costs O(n).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <unordered_map>
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
  struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const;
  };
  std::array<long long, 3> key(const Eigen::Vector3d& x) const;
  Eigen::Vector3d origin_;
  double tol_ = 0, cell_ = 1;
  std::vector<Eigen::Vector3d> points_;
  // Per cell its last point; each point links to the previous one in its cell (-1 ends): no
  // allocation per cell, most cells hold one point.
  std::unordered_map<std::array<long long, 3>, int, KeyHash> grid_;
  std::vector<int> next_;
};

}  // namespace volts::extract
