// Point location in parameter space: CGAL AABB tree over the mapped tets' bounding boxes, then
// barycentric coordinates from a precomputed inverse per tet.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/errors.h"
#include "volmap/volmap.h"

namespace volts::volmap {
namespace {

using K = surface::Kernel;
using Vec = Eigen::Vector3d;

// AABB primitive: the bounding box of one tet (inflated by the snap tolerance), so the tree returns
// candidates and the containment test stays ours (with its tolerance).
struct BoxPrimitive {
  using Id = int;
  using Datum = K::Iso_cuboid_3;
  using Point = K::Point_3;
  BoxPrimitive() = default;
  BoxPrimitive(int id, const Vec& lo, const Vec& hi) : id_(id), lo_(lo), hi_(hi) {}
  // AABB_tree::insert(first, beyond) builds primitives from the iterators.
  explicit BoxPrimitive(std::vector<BoxPrimitive>::const_iterator it) : BoxPrimitive(*it) {}
  Id id() const { return id_; }
  Datum datum() const { return Datum(reference_point(), Point(hi_[0], hi_[1], hi_[2])); }
  Point reference_point() const { return Point(lo_[0], lo_[1], lo_[2]); }
  bool contains(const Vec& q) const { return (q.array() >= lo_.array()).all() && (q.array() <= hi_.array()).all(); }

 private:
  int id_ = -1;
  Vec lo_, hi_;
};

using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, BoxPrimitive>>;

// Traversal of the tree for a point with plain double comparisons (the kernel's filtered
// predicates cost more than the whole barycentric test); calls f(id) for every box containing it.
template <class F>
struct PointTraversal {
  F& f;
  bool go_further() const { return true; }
  void intersection(const Vec& q, const BoxPrimitive& p) {
    if (p.contains(q)) f(p.id());
  }
  template <class Node>
  bool do_intersect(const Vec& q, const Node& node) const {
    const CGAL::Bbox_3& b = node.bbox();
    return q[0] >= b.xmin() && q[0] <= b.xmax() && q[1] >= b.ymin() && q[1] <= b.ymax() && q[2] >= b.zmin() && q[2] <= b.zmax();
  }
};

constexpr double kInsideTol = 1e-10;  // barycentric: points on shared faces belong to both tets

}  // namespace

struct Locator::Impl {
  std::vector<Vec> parameter, physical;
  std::vector<std::array<int, 4>> tets;
  std::vector<Eigen::Matrix3d> inverse;  // per tet: lambda_1..3 = inverse * (x - p0)
  double snap = 0;                        // absolute snap distance
  Tree tree;

  std::array<double, 4> bary(int t, const Vec& x) const {
    const Vec l = inverse[t] * (x - parameter[tets[t][0]]);
    return {1 - l.sum(), l[0], l[1], l[2]};
  }

  template <class F>
  void for_candidates(const Vec& x, F&& f) const {
    PointTraversal<F> traversal{f};
    tree.traversal(x, traversal);
  }

  // Squared distance from x to tet t (CGAL, its four faces; x is outside it), and as the snapped
  // point the barycentric coordinates of x clamped to the tet (within O(distance) of x).
  double nearest(int t, const Vec& x, std::array<double, 4>& b) const {
    const auto& tt = tets[t];
    const auto P = [&](int j) {
      const Vec& p = parameter[tt[j]];
      return K::Point_3(p[0], p[1], p[2]);
    };
    const K::Point_3 q(x[0], x[1], x[2]);
    double best = HUGE_VAL;
    for (const auto& f : tetmesh::kOutwardFace)
      best = std::min(best, CGAL::to_double(CGAL::squared_distance(q, K::Triangle_3(P(f[0]), P(f[1]), P(f[2])))));
    b = bary(t, x);
    for (double& c : b) c = std::max(c, 0.0);
    const double s = b[0] + b[1] + b[2] + b[3];
    for (double& c : b) c = s > 0 ? c / s : 0.25;
    return best;
  }
};

Locator::Locator(const VolumeMap& map, double snap_tolerance_rel) : impl_(std::make_unique<Impl>()) {
  if (!(snap_tolerance_rel >= 0 && snap_tolerance_rel < 1)) throw core::ConfigError("volmap snap tolerance must be in [0, 1)");
  Impl& m = *impl_;
  m.parameter = map.parameter;
  m.physical = map.physical;
  m.tets = map.tets;
  Vec lo = Vec::Constant(HUGE_VAL), hi = Vec::Constant(-HUGE_VAL);
  for (const Vec& p : m.parameter) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  m.snap = m.parameter.empty() ? 0 : snap_tolerance_rel * (hi - lo).norm();
  m.inverse.resize(m.tets.size());
  std::vector<BoxPrimitive> prims;  // const_iterators below: the constructor AABB_tree uses
  prims.reserve(m.tets.size());
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) {
    const auto& tt = m.tets[t];
    Eigen::Matrix3d E;
    for (int j = 0; j < 3; ++j) E.col(j) = m.parameter[tt[j + 1]] - m.parameter[tt[0]];
    // A flat tet (a failed map) gets a zero inverse: it then contains only its corner p0 region.
    m.inverse[t] = Eigen::Matrix3d::Zero();
    if (E.determinant() != 0) m.inverse[t] = E.inverse();
    Vec a = m.parameter[tt[0]], b = a;
    for (int j = 1; j < 4; ++j) a = a.cwiseMin(m.parameter[tt[j]]), b = b.cwiseMax(m.parameter[tt[j]]);
    a.array() -= m.snap, b.array() += m.snap;
    prims.emplace_back(t, a, b);
  }
  m.tree.insert(prims.cbegin(), prims.cend());
  m.tree.build();
}

Locator::~Locator() = default;
Locator::Locator(Locator&&) noexcept = default;
Locator& Locator::operator=(Locator&&) noexcept = default;

int Locator::containing_tet(const std::array<double, 3>& uvw, std::array<double, 4>* bary) const {
  const Impl& m = *impl_;
  const Vec x(uvw[0], uvw[1], uvw[2]);
  int best = -1;
  std::array<double, 4> best_b{};
  m.for_candidates(x, [&](int t) {
    if (best >= 0 && t > best) return;
    const auto b = m.bary(t, x);
    if (std::min(std::min(b[0], b[1]), std::min(b[2], b[3])) >= -kInsideTol) best = t, best_b = b;
  });
  if (best < 0 && m.snap > 0) {
    double best_d = m.snap * m.snap;
    std::vector<int> near;  // rare (outside the domain): a second pass collects the candidates
    m.for_candidates(x, [&](int t) { near.push_back(t); });
    std::sort(near.begin(), near.end());
    for (int t : near) {
      std::array<double, 4> b;
      const double d = m.nearest(t, x, b);
      if (d <= best_d && (best < 0 || d < best_d)) best = t, best_d = d, best_b = b;
    }
  }
  if (best >= 0 && bary) *bary = best_b;
  return best;
}

std::optional<std::array<double, 3>> Locator::physical(const std::array<double, 3>& uvw) const {
  std::array<double, 4> b;
  const int t = containing_tet(uvw, &b);
  if (t < 0) return std::nullopt;
  Vec p = Vec::Zero();
  for (int j = 0; j < 4; ++j) p += b[j] * impl_->physical[impl_->tets[t][j]];
  return std::array<double, 3>{p[0], p[1], p[2]};
}

std::vector<int> Locator::tets_containing(const std::array<double, 3>& uvw, double bary_tolerance) const {
  const Impl& m = *impl_;
  const Vec x(uvw[0], uvw[1], uvw[2]);
  std::vector<int> r;
  m.for_candidates(x, [&](int t) {
    const auto b = m.bary(t, x);
    if (std::min(std::min(b[0], b[1]), std::min(b[2], b[3])) >= -bary_tolerance) r.push_back(t);
  });
  std::sort(r.begin(), r.end());
  return r;
}

}  // namespace volts::volmap
