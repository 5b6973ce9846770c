// volts::extract — points merged within a tolerance: the nodes Gmsh's elements share and the
// global functions of C0 Bézier elements (bezier_basis) are the distinct points of the elements.
// A hash grid of cells much larger than the tolerance: a match lies in the same or a neighbouring
// cell, so merging n points costs O(n).
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

 private:
  struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const;
  };
  std::array<long long, 3> key(const Eigen::Vector3d& x) const;
  Eigen::Vector3d origin_;
  double tol_ = 0, cell_ = 1;
  std::vector<Eigen::Vector3d> points_;
  std::unordered_map<std::array<long long, 3>, std::vector<int>, KeyHash> grid_;
};

}  // namespace volts::extract
