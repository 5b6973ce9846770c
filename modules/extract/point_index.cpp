#include "extract/point_index.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace volts::extract {

PointIndex::PointIndex(const Eigen::AlignedBox3d& box, double tol) : origin_(box.isEmpty() ? Eigen::Vector3d::Zero() : box.min()), tol_(tol) {
  const double diagonal = box.isEmpty() ? 0.0 : box.diagonal().norm();
  cell_ = std::max({1e-6 * diagonal, 1e3 * tol, std::numeric_limits<double>::min()});
}

namespace {

std::size_t hash(const std::array<long long, 3>& k) {
  auto h = static_cast<std::uint64_t>(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
  h ^= h >> 33, h *= 0xff51afd7ed558ccdULL, h ^= h >> 33;  // spread the bits over the mask's range
  return static_cast<std::size_t>(h);
}

}  // namespace

std::size_t PointIndex::slot(const Key& k) const {
  const std::size_t mask = heads_.size() - 1;
  std::size_t i = hash(k) & mask;
  while (heads_[i] >= 0 && key(points_[static_cast<std::size_t>(heads_[i])]) != k) i = (i + 1) & mask;
  return i;
}

void PointIndex::grow(std::size_t size) {
  std::size_t n = 64;
  while (n < size) n *= 2;
  if (n <= heads_.size()) return;
  std::vector<int> heads = std::move(heads_);
  heads_.assign(n, -1);
  for (const int h : heads)
    if (h >= 0) heads_[slot(key(points_[static_cast<std::size_t>(h)]))] = h;
}

PointIndex::Key PointIndex::key(const Eigen::Vector3d& x) const {
  std::array<long long, 3> k{};
  for (int d = 0; d < 3; ++d) k[static_cast<std::size_t>(d)] = static_cast<long long>(std::floor((x[d] - origin_[d]) / cell_));
  return k;
}

int PointIndex::find(const Eigen::Vector3d& x) const {
  if (heads_.empty()) return -1;
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
        for (int n = heads_[slot({i, j, l})]; n >= 0; n = next_[static_cast<std::size_t>(n)])
          if ((points_[static_cast<std::size_t>(n)] - x).norm() <= tol_) return n;
      }
  return -1;
}

int PointIndex::find_or_add(const Eigen::Vector3d& x) {
  const int found = find(x);
  if (found >= 0) return found;
  const int n = static_cast<int>(points_.size());
  points_.push_back(x);
  if (2 * (cells_ + 1) > heads_.size()) grow(2 * heads_.size());
  const std::size_t i = slot(key(x));
  if (heads_[i] < 0) ++cells_;
  next_.push_back(heads_[i]);
  heads_[i] = n;
  return n;
}

void PointIndex::reserve(std::size_t n) {
  points_.reserve(n);
  next_.reserve(n);
  grow(2 * n);
}

}  // namespace volts::extract
