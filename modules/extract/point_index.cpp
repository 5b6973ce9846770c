#include "extract/point_index.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace volts::extract {

PointIndex::PointIndex(const Eigen::AlignedBox3d& box, double tol) : origin_(box.isEmpty() ? Eigen::Vector3d::Zero() : box.min()), tol_(tol) {
  const double diagonal = box.isEmpty() ? 0.0 : box.diagonal().norm();
  cell_ = std::max({1e-6 * diagonal, 1e3 * tol, std::numeric_limits<double>::min()});
}

std::size_t PointIndex::KeyHash::operator()(const std::array<long long, 3>& k) const {
  return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
}

std::array<long long, 3> PointIndex::key(const Eigen::Vector3d& x) const {
  std::array<long long, 3> k{};
  for (int d = 0; d < 3; ++d) k[static_cast<std::size_t>(d)] = static_cast<long long>(std::floor((x[d] - origin_[d]) / cell_));
  return k;
}

int PointIndex::find(const Eigen::Vector3d& x) const {
  const auto k = key(x);
  for (long long dx = -1; dx <= 1; ++dx)
    for (long long dy = -1; dy <= 1; ++dy)
      for (long long dz = -1; dz <= 1; ++dz) {
        const auto it = grid_.find({k[0] + dx, k[1] + dy, k[2] + dz});
        if (it == grid_.end()) continue;
        for (const int n : it->second)
          if ((points_[static_cast<std::size_t>(n)] - x).norm() <= tol_) return n;
      }
  return -1;
}

int PointIndex::find_or_add(const Eigen::Vector3d& x) {
  const int found = find(x);
  if (found >= 0) return found;
  const int n = static_cast<int>(points_.size());
  points_.push_back(x);
  grid_[key(x)].push_back(n);
  return n;
}

}  // namespace volts::extract
