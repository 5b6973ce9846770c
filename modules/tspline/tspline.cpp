// Cubic T-spline basis of an octree T-mesh: anchors and local knot vectors by ray casting, direct
// evaluation, Bézier extraction per element of the Bézier mesh (Liu et al. 2013 §5.3).
#include "tspline/tspline.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "bezier/bernstein.h"
#include "bezier/bspline.h"
#include "core/errors.h"

namespace volts::tspline {
namespace {

using octree::Cell;
using octree::Index3;

// The knot vector of one function padded with 3 distinct knots on each side, so that the function
// is B-spline number 3 of a valid knot vector whose domain is exactly its support [k0, k4].
std::vector<double> padded(const LocalKnots& k) {
  std::vector<double> K;
  K.reserve(11);
  for (int d = 3; d >= 1; --d) K.push_back(double(k[0] - d));
  for (int v : k) K.push_back(double(v));
  for (int d = 1; d <= 3; ++d) K.push_back(double(k[4] + d));
  return K;
}

// Calls f(b) for the flat index b = x + buckets (y + buckets z) of every bucket (cubes of
// `bucket_side` unit cells, `buckets` per axis) holding a unit cell of the box first..last (inclusive
// unit-cell indices), z slowest.
template <class F>
void for_each_bucket(const Index3& first, const Index3& last, int bucket_side, int buckets, F&& f) {
  Index3 b0, b1;
  for (int a = 0; a < 3; ++a) {
    b0[a] = first[a] / bucket_side;
    b1[a] = last[a] / bucket_side;
  }
  for (int z = b0[2]; z <= b1[2]; ++z)
    for (int y = b0[1]; y <= b1[1]; ++y)
      for (int x = b0[0]; x <= b1[0]; ++x) f(x + buckets * (y + buckets * z));
}

// Positions > x (dir +1) or < x (dir -1) along axis a of the line through `node` where it meets a
// T-mesh face perpendicular to a: the nearest two, nearest first. Every leaf whose closed box
// contains a point of the line contains one of the (up to 4) unit index columns around the line,
// so walking these columns leaf by leaf (locate) finds all faces the line meets, in order.
std::vector<int> ray_hits(const octree::Octree& tree, const Index3& node, int a, int dir) {
  const int S = tree.root_side();
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  std::vector<int> hits;
  for (int db = -1; db <= 0; ++db)
    for (int dc = -1; dc <= 0; ++dc) {
      Index3 p = node;
      p[b] += db;
      p[c] += dc;
      if (p[b] < 0 || p[b] >= S || p[c] < 0 || p[c] >= S) continue;
      int x = node[a];
      for (int found = 0; found < 2;) {
        p[a] = dir > 0 ? x : x - 1;  // the unit cell just beyond x in the ray's direction
        if (p[a] < 0 || p[a] >= S) break;
        const int leaf = tree.locate(p);
        if (leaf < 0) throw core::NumericalError("tspline: octree locate failed inside the root");
        const Cell& cell = tree.leaves()[leaf];
        x = dir > 0 ? cell.hi()[a] : cell.lo[a];
        hits.push_back(x);
        ++found;
      }
    }
  std::sort(hits.begin(), hits.end());
  hits.erase(std::unique(hits.begin(), hits.end()), hits.end());
  if (dir < 0) std::reverse(hits.begin(), hits.end());
  if (hits.size() > 2) hits.resize(2);
  return hits;
}

// Bernstein coefficients of the cubic B-spline on knots k over [lo, hi] (no knot strictly inside,
// [lo, hi] inside [k0, k4]): the extraction operator of the span containing [lo, hi] (knot
// insertion of the span's ends, bezier::extraction_operators), restricted to [lo, hi] by
// de Casteljau subdivision if the span is longer. Cached by the knots relative to k0.
class Coefficients1d {
 public:
  Eigen::Vector4d operator()(const LocalKnots& k, int lo, int hi) {
    LocalKnots rel;
    for (int i = 0; i < 5; ++i) rel[i] = k[i] - k[0];
    const std::array<int, 7> key{rel[0], rel[1], rel[2], rel[3], rel[4], lo - k[0], hi - k[0]};
    const auto found = cache_.find(key);
    if (found != cache_.end()) return found->second;
    auto ops = ops_.find(rel);
    if (ops == ops_.end()) {
      const std::vector<double> K = padded(rel);
      ops = ops_.emplace(rel, Ops{K, bezier::element_spans(K, kDegree), bezier::extraction_operators(K, kDegree)}).first;
    }
    const Ops& o = ops->second;
    const double a = lo - k[0], b = hi - k[0];
    for (std::size_t e = 0; e < o.spans.size(); ++e) {
      const int s = o.spans[e];
      if (!(o.K[s] <= a && b <= o.K[s + 1])) continue;
      const int row = 6 - s;  // the function is N_3 = N_{s-3+row}
      if (row < 0 || row > 3) break;
      Eigen::Vector4d c = o.mats[e].row(row).transpose();
      if (a != o.K[s] || b != o.K[s + 1]) {
        const double len = o.K[s + 1] - o.K[s];
        c = bezier::subdivision_matrix(kDegree, (a - o.K[s]) / len, (b - o.K[s]) / len) * c;
      }
      cache_.emplace(key, c);
      return c;
    }
    throw core::NumericalError("tspline: interval [" + std::to_string(lo) + ", " + std::to_string(hi) +
                               "] is not inside one knot span of a function it was assigned to");
  }

 private:
  struct Ops {
    std::vector<double> K;
    std::vector<int> spans;
    std::vector<Eigen::MatrixXd> mats;
  };
  std::map<LocalKnots, Ops> ops_;
  std::map<std::array<int, 7>, Eigen::Vector4d> cache_;
};

bool open_overlap(const Index3& alo, const Index3& ahi, const Index3& blo, const Index3& bhi) {
  for (int a = 0; a < 3; ++a)
    if (!(alo[a] < bhi[a] && blo[a] < ahi[a])) return false;
  return true;
}

}  // namespace

TSpline::TSpline(const octree::Octree& tree) : root_side_(tree.root_side()) {
  build_functions(tree);
  build_elements(tree);
}

void TSpline::build_functions(const octree::Octree& tree) {
  const int S = root_side_;
  nodes_ = tree.nodes();
  for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
    const Index3& x = nodes_[n];
    // Per axis the variants (layer, knots): the node's own, plus the boundary layer's.
    std::array<std::vector<std::pair<int, LocalKnots>>, 3> variants;
    for (int a = 0; a < 3; ++a) {
      std::vector<int> minus = ray_hits(tree, x, a, -1), plus = ray_hits(tree, x, a, +1);
      while (minus.size() < 2) minus.push_back(0);
      while (plus.size() < 2) plus.push_back(S);
      variants[a].push_back({0, LocalKnots{minus[1], minus[0], x[a], plus[0], plus[1]}});
      if (x[a] == 0) variants[a].insert(variants[a].begin(), {-1, LocalKnots{0, 0, 0, 0, plus[0]}});
      if (x[a] == S) variants[a].push_back({+1, LocalKnots{minus[0], S, S, S, S}});
    }
    for (const auto& vz : variants[2])
      for (const auto& vy : variants[1])
        for (const auto& vx : variants[0]) {
          BlendingFunction f;
          f.anchor = x;
          f.node = n;
          f.layer = {vx.first, vy.first, vz.first};
          f.knots = {vx.second, vy.second, vz.second};
          functions_.push_back(f);
        }
  }
  weights_.assign(functions_.size(), 1.0);

  // Bucket grid: at most 16 buckets per axis.
  bucket_side_ = std::max(1, S / 16);
  buckets_ = S / bucket_side_;
  bucket_functions_.assign(std::size_t(buckets_) * buckets_ * buckets_, {});
  for (int i = 0; i < num_functions(); ++i) {
    const Index3 lo = functions_[i].support_lo(), hi = functions_[i].support_hi();
    for_each_bucket(lo, {hi[0] - 1, hi[1] - 1, hi[2] - 1}, bucket_side_, buckets_,
                    [&](int b) { bucket_functions_[b].push_back(i); });
  }
}

void TSpline::build_elements(const octree::Octree& tree) {
  Coefficients1d coefficients;
  std::vector<int> stamp(functions_.size(), -1);
  std::vector<Eigen::Triplet<double>> triplets;
  const auto& leaves = tree.leaves();
  for (int l = 0; l < static_cast<int>(leaves.size()); ++l) {
    const Cell& cell = leaves[l];
    const Index3 lo = cell.lo, hi = cell.hi();
    // Functions whose open support meets the open leaf.
    std::vector<int> on_leaf;
    for_each_bucket(lo, {hi[0] - 1, hi[1] - 1, hi[2] - 1}, bucket_side_, buckets_, [&](int b) {
      for (int i : bucket_functions_[b]) {
        if (stamp[i] == l) continue;
        stamp[i] = l;
        if (open_overlap(functions_[i].support_lo(), functions_[i].support_hi(), lo, hi)) on_leaf.push_back(i);
      }
    });
    std::sort(on_leaf.begin(), on_leaf.end());
    // Cuts: knots of these functions strictly inside the leaf, per axis.
    std::array<std::vector<int>, 3> cuts;
    for (int a = 0; a < 3; ++a) {
      cuts[a] = {lo[a], hi[a]};
      for (int i : on_leaf)
        for (int k : functions_[i].knots[a])
          if (lo[a] < k && k < hi[a]) cuts[a].push_back(k);
      std::sort(cuts[a].begin(), cuts[a].end());
      cuts[a].erase(std::unique(cuts[a].begin(), cuts[a].end()), cuts[a].end());
    }
    if (cuts[0].size() > 2 || cuts[1].size() > 2 || cuts[2].size() > 2) ++split_leaves_;
    for (std::size_t cz = 0; cz + 1 < cuts[2].size(); ++cz)
      for (std::size_t cy = 0; cy + 1 < cuts[1].size(); ++cy)
        for (std::size_t cx = 0; cx + 1 < cuts[0].size(); ++cx) {
          BezierElement e;
          e.leaf = l;
          e.lo = {cuts[0][cx], cuts[1][cy], cuts[2][cz]};
          e.hi = {cuts[0][cx + 1], cuts[1][cy + 1], cuts[2][cz + 1]};
          for (int i : on_leaf)
            if (open_overlap(functions_[i].support_lo(), functions_[i].support_hi(), e.lo, e.hi)) e.functions.push_back(i);
          triplets.clear();
          for (std::size_t r = 0; r < e.functions.size(); ++r) {
            const BlendingFunction& f = functions_[e.functions[r]];
            std::array<Eigen::Vector4d, 3> c;
            for (int a = 0; a < 3; ++a) c[a] = coefficients(f.knots[a], e.lo[a], e.hi[a]);
            for (int k = 0; k < 4; ++k)
              for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) {
                  const double v = c[0][i] * c[1][j] * c[2][k];
                  if (v != 0.0) triplets.emplace_back(int(r), i + 4 * (j + 4 * k), v);
                }
          }
          e.op.resize(static_cast<Eigen::Index>(e.functions.size()), kBernstein);
          e.op.setFromTriplets(triplets.begin(), triplets.end());
          elements_.push_back(std::move(e));
        }
  }
}

void TSpline::set_weights(std::vector<double> weights) {
  if (weights.size() != functions_.size())
    throw core::InvalidInputError("tspline: " + std::to_string(weights.size()) + " weights for " +
                                  std::to_string(functions_.size()) + " functions");
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (!(std::isfinite(weights[i]) && weights[i] > 0))
      throw core::InvalidInputError("tspline: weight " + std::to_string(i) + " = " + std::to_string(weights[i]) +
                                    " is not finite and positive");
  weights_ = std::move(weights);
}

double TSpline::partition_of_unity_error() const {
  double err = 0;
  for (const BezierElement& e : elements_)
    err = std::max(err, ((Eigen::RowVectorXd::Ones(e.op.rows()) * e.op).array() - 1.0).abs().maxCoeff());
  return err;
}

void TSpline::check_point(const Eigen::Vector3d& u, const char* what) const {
  for (int a = 0; a < 3; ++a)
    if (!(u[a] >= 0.0 && u[a] <= 1.0))
      throw core::InvalidInputError(std::string("tspline: ") + what + ": parameter (" + std::to_string(u[0]) + ", " +
                                    std::to_string(u[1]) + ", " + std::to_string(u[2]) + ") outside [0,1]^3");
}

double TSpline::basis_index(int i, const Eigen::Vector3d& x) const {
  const BlendingFunction& f = functions_[i];
  double value = 1.0;
  for (int a = 0; a < 3 && value != 0.0; ++a) {
    const LocalKnots& k = f.knots[a];
    if (x[a] < k[0] || x[a] > k[4]) return 0.0;
    const bezier::BasisValues v = bezier::basis_functions(padded(k), kDegree, x[a]);
    const int row = 3 - (v.span - kDegree);  // N_3 = values[3 - (span - 3)]
    value *= (row >= 0 && row <= kDegree) ? v.values[row] : 0.0;
  }
  return value;
}

double TSpline::basis(int i, const Eigen::Vector3d& u) const {
  if (i < 0 || i >= num_functions())
    throw core::InvalidInputError("tspline: function " + std::to_string(i) + " out of range [0, " +
                                  std::to_string(num_functions()) + ")");
  check_point(u, "basis");
  return basis_index(i, u * double(root_side_));
}

std::vector<int> TSpline::candidates(const Eigen::Vector3d& x) const {
  Index3 first, last;  // the unit cells whose closed boxes hold x
  for (int a = 0; a < 3; ++a) {
    first[a] = std::clamp(static_cast<int>(std::ceil(x[a])) - 1, 0, root_side_ - 1);
    last[a] = std::clamp(static_cast<int>(std::floor(x[a])), 0, root_side_ - 1);
  }
  std::vector<int> out;
  for_each_bucket(first, last, bucket_side_, buckets_, [&](int b) {
    const auto& v = bucket_functions_[b];
    out.insert(out.end(), v.begin(), v.end());
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<std::pair<int, double>> TSpline::basis(const Eigen::Vector3d& u) const {
  check_point(u, "basis");
  const Eigen::Vector3d x = u * double(root_side_);
  std::vector<std::pair<int, double>> out;
  for (int i : candidates(x)) {
    const Index3 lo = functions_[i].support_lo(), hi = functions_[i].support_hi();
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside = inside && x[a] >= lo[a] && x[a] <= hi[a];
    if (inside) out.push_back({i, basis_index(i, x)});
  }
  return out;
}

std::vector<std::pair<int, double>> TSpline::rational_basis(const Eigen::Vector3d& u) const {
  std::vector<std::pair<int, double>> out = basis(u);
  double sum = 0;
  for (auto& [i, v] : out) {
    v *= weights_[i];
    sum += v;
  }
  if (!(sum > 0))
    throw core::NumericalError("tspline: Σ w N = " + std::to_string(sum) + " is not positive at (" +
                               std::to_string(u[0]) + ", " + std::to_string(u[1]) + ", " + std::to_string(u[2]) + ")");
  for (auto& iv : out) iv.second /= sum;
  return out;
}

Eigen::Vector3d TSpline::evaluate(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& u) const {
  if (points.size() != functions_.size())
    throw core::InvalidInputError("tspline: " + std::to_string(points.size()) + " control points for " +
                                  std::to_string(functions_.size()) + " functions");
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (const auto& [i, r] : rational_basis(u)) x += r * points[i];
  return x;
}

Eigen::VectorXd TSpline::denominator_coefficients(int e) const {
  if (e < 0 || e >= static_cast<int>(elements_.size()))
    throw core::InvalidInputError("tspline: element " + std::to_string(e) + " out of range");
  const BezierElement& el = elements_[e];
  Eigen::VectorXd w(el.functions.size());
  for (std::size_t r = 0; r < el.functions.size(); ++r) w[Eigen::Index(r)] = weights_[el.functions[r]];
  return el.op.transpose() * w;
}

bezier::BezierHex TSpline::element_hex(int e, const std::vector<Eigen::Vector3d>& points) const {
  if (points.size() != functions_.size())
    throw core::InvalidInputError("tspline: " + std::to_string(points.size()) + " control points for " +
                                  std::to_string(functions_.size()) + " functions");
  const Eigen::VectorXd wsum = denominator_coefficients(e);
  const BezierElement& el = elements_[e];
  Eigen::MatrixXd wp(el.functions.size(), 3);
  for (std::size_t r = 0; r < el.functions.size(); ++r)
    wp.row(Eigen::Index(r)) = weights_[el.functions[r]] * points[el.functions[r]].transpose();
  const Eigen::MatrixXd hom = el.op.transpose() * wp;  // kBernstein x 3
  bezier::BezierHex hex;
  hex.degree = {kDegree, kDegree, kDegree};
  hex.points.resize(kBernstein);
  hex.weights.resize(kBernstein);
  for (int b = 0; b < kBernstein; ++b) {
    if (!(wsum[b] > 0))
      throw core::NumericalError("tspline: element " + std::to_string(e) + ": Bézier weight " + std::to_string(b) +
                                 " = " + std::to_string(wsum[b]) + " is not positive");
    hex.weights[b] = wsum[b];
    hex.points[b] = hom.row(b).transpose() / wsum[b];
  }
  return hex;
}

Eigen::Vector3d TSpline::element_point(int e, const Eigen::Vector3d& xi) const {
  if (e < 0 || e >= static_cast<int>(elements_.size()))
    throw core::InvalidInputError("tspline: element " + std::to_string(e) + " out of range");
  const BezierElement& el = elements_[e];
  Eigen::Vector3d u;
  for (int a = 0; a < 3; ++a) u[a] = (el.lo[a] + xi[a] * (el.hi[a] - el.lo[a])) / double(root_side_);
  return u;
}

}  // namespace volts::tspline
