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
  // The cells within tol of x: its own, and a neighbour only along an axis where x is within tol
  // of the cell's side (cells are >= 1000 tol wide: almost always one cell to look in).
  std::array<std::array<long long, 2>, 3> range{};
  for (int d = 0; d < 3; ++d) {
    const double f = (x[d] - origin_[d]) / cell_;
    const long long k = static_cast<long long>(std::floor(f));
    const double in = (f - static_cast<double>(k)) * cell_;
    range[static_cast<std::size_t>(d)] = {in <= tol_ ? k - 1 : k, cell_ - in <= tol_ ? k + 1 : k};
  }
  for (long long i = range[0][0]; i <= range[0][1]; ++i)
    for (long long j = range[1][0]; j <= range[1][1]; ++j)
      for (long long l = range[2][0]; l <= range[2][1]; ++l) {
        const auto it = grid_.find({i, j, l});
        if (it == grid_.end()) continue;
        for (int n = it->second; n >= 0; n = next_[static_cast<std::size_t>(n)])
          if ((points_[static_cast<std::size_t>(n)] - x).norm() <= tol_) return n;
      }
  return -1;
}

int PointIndex::find_or_add(const Eigen::Vector3d& x) {
  const int found = find(x);
  if (found >= 0) return found;
  const int n = static_cast<int>(points_.size());
  points_.push_back(x);
  const auto [it, fresh] = grid_.try_emplace(key(x), n);
  next_.push_back(fresh ? -1 : it->second);
  it->second = n;
  return n;
}

void PointIndex::reserve(std::size_t n) {
  points_.reserve(n);
  next_.reserve(n);
  grid_.reserve(n);
}

}  // namespace volts::extract
