#include "tmesh/optimize.h"

#include <nlopt.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include "bezier/bernstein.h"
#include "bezier/bezier_hex.h"
#include "bezier/bspline.h"
#include "bezier/certify.h"
#include "bezier/hex_point.h"
#include "bezier/jacobian_grid.h"
#include "core/errors.h"
#include "core/log.h"
#include "core/parallel.h"
#include "tmesh/jacobian_kernels.h"

namespace volts::tmesh {

namespace {

struct Element {
  int block;
  std::array<int, 3> e;     // element index per direction
  std::array<int, 3> first;  // first supported control point per direction
};

// The blocks' Bézier elements and which elements each control point supports.
class Spline {
 public:
  explicit Spline(std::vector<TMesh>& blocks) : blocks_(blocks), ops_(blocks.size()), point_id_(blocks.size()) {
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const TMesh& t = blocks[b];
      std::array<std::vector<int>, 3> spans;
      for (int a = 0; a < 3; ++a) {
        ops_[b][a] = bezier::extraction_operators(t.knots[a], t.degree);
        spans[a] = bezier::element_spans(t.knots[a], t.degree);
      }
      for (std::size_t k = 0; k < spans[2].size(); ++k)
        for (std::size_t j = 0; j < spans[1].size(); ++j)
          for (std::size_t i = 0; i < spans[0].size(); ++i)
            elements_.push_back({static_cast<int>(b), {static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)},
                                 {spans[0][i] - t.degree, spans[1][j] - t.degree, spans[2][k] - t.degree}});
    }
    // Global function of every control point, its occurrences and the elements it supports
    // (vectors indexed by id: the maps of these lookups took 0.1 s on the torus).
    int next = 0;
    for (const auto& t : blocks) next += static_cast<int>(t.control_points.size());
    int count = 0;
    for (std::size_t b = 0; b < blocks.size(); ++b)
      for (std::size_t i = 0; i < blocks[b].control_points.size(); ++i) {
        const int id = blocks[b].function_ids.empty() ? next++ : blocks[b].function_ids.at(i);
        if (id < 0) throw core::InvalidInputError("tmesh optimization: negative function id " + std::to_string(id));
        point_id_[b].push_back(id);
        count = std::max(count, id + 1);
      }
    occurrences_.resize(static_cast<std::size_t>(count));
    // T-junctions (TMesh::constraints) are no variables: a control point of one stands for the
    // nodes of its row, which carry it along when they move.
    expansion_.resize(static_cast<std::size_t>(count));
    dependents_.resize(static_cast<std::size_t>(count));
    for (int id = 0; id < count; ++id) expansion_[static_cast<std::size_t>(id)] = {{id, 1.0}};
    std::vector<char> junction(static_cast<std::size_t>(count), 0);
    for (std::size_t b = 0; b < blocks.size(); ++b)
      for (const auto& k : blocks[b].constraints) {
        const int id = point_id_[b].at(static_cast<std::size_t>(k.point));
        if (junction[static_cast<std::size_t>(id)]) continue;
        junction[static_cast<std::size_t>(id)] = 1;
        auto& row = expansion_[static_cast<std::size_t>(id)];
        row.clear();
        for (std::size_t r = 0; r < k.ids.size(); ++r) {
          const int m = k.ids[r];
          if (m < 0 || m >= count) throw core::InvalidInputError("tmesh optimization: a T-junction names node " + std::to_string(m) + ", which no block has");
          row.push_back({m, k.weights.at(r)});
          dependents_[static_cast<std::size_t>(m)].push_back(id);
        }
      }
    for (int id = 0; id < count; ++id)
      for (const auto& [m, w] : expansion_[static_cast<std::size_t>(id)])
        if (junction[static_cast<std::size_t>(m)] && m != id) throw core::InvalidInputError("tmesh optimization: T-junction " + std::to_string(id) + " names T-junction " + std::to_string(m));
    for (std::size_t b = 0; b < blocks.size(); ++b)
      for (std::size_t i = 0; i < point_id_[b].size(); ++i)
        occurrences_[static_cast<std::size_t>(point_id_[b][i])].push_back({static_cast<int>(b), static_cast<int>(i)});
    element_points_.resize(elements_.size());
    node_elements_.resize(static_cast<std::size_t>(count));
    for (std::size_t e = 0; e < elements_.size(); ++e) {
      const Element& el = elements_[e];
      const TMesh& t = blocks[static_cast<std::size_t>(el.block)];
      for (int c = 0; c <= t.degree; ++c)
        for (int bb = 0; bb <= t.degree; ++bb)
          for (int a = 0; a <= t.degree; ++a) {
            const int local = (el.first[0] + a) + t.size[0] * ((el.first[1] + bb) + t.size[1] * (el.first[2] + c));
            element_points_[e].push_back(local);
            // Elements in ascending order, once each (an id may repeat within an element); a
            // node supports the elements of the T-junctions that name it too.
            for (const auto& [m, w] : expansion_[static_cast<std::size_t>(id_of(el.block, local))]) {
              std::vector<int>& of = node_elements_[static_cast<std::size_t>(m)];
              if (of.empty() || of.back() != static_cast<int>(e)) of.push_back(static_cast<int>(e));
            }
          }
    }
  }

  std::size_t size() const { return elements_.size(); }

  bezier::BezierHex hex(std::size_t e) const {
    const int p = blocks_[static_cast<std::size_t>(elements_[e].block)].degree;
    bezier::BezierHex h;
    h.degree = {p, p, p};
    hex_points(e, h.points);
    return h;
  }

  // The Bézier points of element e (hex(e).points) into `out`, reusing its storage: the joint
  // rounds ask for them millions of times.
  void hex_points(std::size_t e, std::vector<Eigen::Vector3d>& out) const {
    const Element& el = elements_[e];
    const TMesh& t = blocks_[static_cast<std::size_t>(el.block)];
    const int p = t.degree;
    const auto& C = ops_[static_cast<std::size_t>(el.block)];
    const Eigen::MatrixXd& Cu = C[0][static_cast<std::size_t>(el.e[0])];
    const Eigen::MatrixXd& Cv = C[1][static_cast<std::size_t>(el.e[1])];
    const Eigen::MatrixXd& Cw = C[2][static_cast<std::size_t>(el.e[2])];
    // Bézier points = (Cu ⊗ Cv ⊗ Cw)ᵀ P, one direction at a time.
    const int n = p + 1;
    thread_local std::vector<Eigen::Vector3d> P;  // scratch: hex() runs for every element a node supports
    P.resize(static_cast<std::size_t>(n * n * n));
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto& x = t.control_points[static_cast<std::size_t>((el.first[0] + i) + t.size[0] * ((el.first[1] + j) + t.size[1] * (el.first[2] + k)))];
          P[static_cast<std::size_t>(i + n * (j + n * k))] = Eigen::Vector3d(x[0], x[1], x[2]);
        }
    out.resize(P.size());
    kernels::tensor_extract(n, Cu.data(), Cv.data(), Cw.data(), P.data(), out.data());
  }

  // The transpose of hex(e): given d/dQ of the element's Bézier points (index i + n(j + nk)),
  // writes d/dP of its control points in points_of(e)'s order (the same index layout).
  void pull_back(std::size_t e, std::vector<Eigen::Vector3d>& g) const {
    const Element& el = elements_[e];
    const auto& C = ops_[static_cast<std::size_t>(el.block)];
    const int n = blocks_[static_cast<std::size_t>(el.block)].degree + 1;
    kernels::tensor_extract_transpose(n, C[0][static_cast<std::size_t>(el.e[0])].data(), C[1][static_cast<std::size_t>(el.e[1])].data(),
                                      C[2][static_cast<std::size_t>(el.e[2])].data(), g.data());
  }

  // The x coordinates of hex(e)'s points, with its arithmetic (Vector3d sums are per coordinate).
  std::vector<double> hex_x(std::size_t e) const {
    const Element& el = elements_[e];
    const TMesh& t = blocks_[static_cast<std::size_t>(el.block)];
    const auto& C = ops_[static_cast<std::size_t>(el.block)];
    const int n = t.degree + 1;
    thread_local std::vector<double> P;
    P.resize(static_cast<std::size_t>(n * n * n));
    std::vector<double> Q(P.size());
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          P[static_cast<std::size_t>(i + n * (j + n * k))] =
              t.control_points[static_cast<std::size_t>((el.first[0] + i) + t.size[0] * ((el.first[1] + j) + t.size[1] * (el.first[2] + k)))][0];
    auto apply = [&](const Eigen::MatrixXd& M, int stride, const std::vector<double>& in, std::vector<double>& out) {
      for (std::size_t idx = 0; idx < in.size(); ++idx) {
        const int along = (static_cast<int>(idx) / stride) % n;
        const std::size_t base = idx - static_cast<std::size_t>(along * stride);
        double s = 0;
        for (int a = 0; a < n; ++a) s += M(a, along) * in[base + static_cast<std::size_t>(a * stride)];
        out[idx] = s;
      }
    };
    apply(C[0][static_cast<std::size_t>(el.e[0])], 1, P, Q);
    apply(C[1][static_cast<std::size_t>(el.e[1])], n, Q, P);
    apply(C[2][static_cast<std::size_t>(el.e[2])], n * n, P, Q);
    return Q;
  }

  const std::vector<int>& elements_of(int id) const { return node_elements_[static_cast<std::size_t>(id)]; }
  const std::vector<int>& points_of(std::size_t e) const { return element_points_[e]; }
  int id_of(int block, int local) const { return point_id_[static_cast<std::size_t>(block)][static_cast<std::size_t>(local)]; }
  int block_of(std::size_t e) const { return elements_[e].block; }
  int degree_of(std::size_t e) const { return blocks_[static_cast<std::size_t>(elements_[e].block)].degree; }

  std::array<double, 3> position(int id) const {
    const auto& [b, i] = occurrences_[static_cast<std::size_t>(id)].front();
    return blocks_[static_cast<std::size_t>(b)].control_points[static_cast<std::size_t>(i)];
  }
  void set_position(int id, const std::array<double, 3>& x) {
    for (const auto& [b, i] : occurrences_[static_cast<std::size_t>(id)]) blocks_[static_cast<std::size_t>(b)].control_points[static_cast<std::size_t>(i)] = x;
    for (const int d : dependents_[static_cast<std::size_t>(id)]) {  // T-junctions follow their rows
      std::array<double, 3> y{0, 0, 0};
      for (const auto& [m, w] : expansion_[static_cast<std::size_t>(d)]) {
        const auto p = position(m);
        for (int k = 0; k < 3; ++k) y[static_cast<std::size_t>(k)] += w * p[static_cast<std::size_t>(k)];
      }
      for (const auto& [b, i] : occurrences_[static_cast<std::size_t>(d)]) blocks_[static_cast<std::size_t>(b)].control_points[static_cast<std::size_t>(i)] = y;
    }
  }

  // The nodes a control point stands for, with weights: itself, or a T-junction's row.
  const std::vector<std::pair<int, double>>& nodes_of(int block, int local) const {
    return expansion_[static_cast<std::size_t>(id_of(block, local))];
  }

  // Faces of element e on a block face marked boundary (the input surface): 2 axis + side each.
  std::vector<int> boundary_faces(std::size_t e) const {
    const Element& el = elements_[e];
    const TMesh& t = blocks_[static_cast<std::size_t>(el.block)];
    const auto& C = ops_[static_cast<std::size_t>(el.block)];
    std::vector<int> faces;
    for (int a = 0; a < 3; ++a) {
      if (t.boundary[2 * a] && el.e[a] == 0) faces.push_back(2 * a);
      if (t.boundary[2 * a + 1] && el.e[a] + 1 == static_cast<int>(C[static_cast<std::size_t>(a)].size())) faces.push_back(2 * a + 1);
    }
    return faces;
  }

  // On the surface: on a block face marked boundary in any block it belongs to.
  bool on_surface(int id) const {
    for (const auto& [b, i] : occurrences_[static_cast<std::size_t>(id)]) {
      const TMesh& t = blocks_[static_cast<std::size_t>(b)];
      const int idx[3] = {i % t.size[0], (i / t.size[0]) % t.size[1], i / (t.size[0] * t.size[1])};
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s)
          if (t.boundary[2 * a + s] && idx[a] == (s ? t.size[a] - 1 : 0)) return true;
    }
    return false;
  }

  // Distance to the nearest control-net neighbour (in any block); with `surface_only`, to the
  // nearest one on the surface (a surface node's pillow copy lies just under it: that distance
  // does not bound a move along the surface).
  double neighbour_distance(int id, bool surface_only = false) const {
    double d = std::numeric_limits<double>::infinity();
    const auto x = position(id);
    for (const auto& [b, i] : occurrences_[static_cast<std::size_t>(id)]) {
      const TMesh& t = blocks_[static_cast<std::size_t>(b)];
      const int idx[3] = {i % t.size[0], (i / t.size[0]) % t.size[1], i / (t.size[0] * t.size[1])};
      const int stride[3] = {1, t.size[0], t.size[0] * t.size[1]};
      for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
          if (idx[a] + s < 0 || idx[a] + s >= t.size[a]) continue;
          if (surface_only && !on_surface(point_id_[static_cast<std::size_t>(b)][static_cast<std::size_t>(i + s * stride[a])])) continue;
          const auto& y = t.control_points[static_cast<std::size_t>(i + s * stride[a])];
          const double l = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
          if (l > 0) d = std::min(d, l);
        }
    }
    return d;
  }

 private:
  std::vector<TMesh>& blocks_;
  std::vector<std::array<std::vector<Eigen::MatrixXd>, 3>> ops_;  // per block and direction
  std::vector<Element> elements_;
  std::vector<std::vector<int>> element_points_;                // per element: local indices in its block
  std::vector<std::vector<std::pair<int, int>>> occurrences_;  // per id: (block, local index)
  std::vector<std::vector<int>> point_id_;                      // per block and local index: id
  std::vector<std::vector<int>> node_elements_;                 // per id: elements it supports, ascending
  std::vector<std::vector<std::pair<int, double>>> expansion_;  // per id: nodes_of()
  std::vector<std::vector<int>> dependents_;                    // per id: T-junctions whose rows name it
};

// Row x (dx/du, dx/dv, dx/dw) of bezier::jacobian_samples of a polynomial hex of degree p in each
// direction from its points' x coordinates: the same sums (bezier::grid_derivatives on one
// coordinate), so the rows are bit-identical at a third of the cost.
class XRowSamples {
 public:
  XRowSamples(int degree, int gauss_points, int grid_points) : degree_{degree, degree, degree}, grid_(static_cast<std::size_t>(grid_points)) {
    std::vector<double> t = bezier::gauss_legendre_points(gauss_points);
    for (int i = grid_points - 1; i >= 0; --i) t.insert(t.begin(), i / (grid_points - 1.0));
    for (auto& axis : axes_)
      for (const double x : t) {
        Eigen::VectorXd db;
        axis.B.push_back(bezier::bernstein_basis(degree, x, &db));
        axis.dB.push_back(db);
      }
  }

  void operator()(const std::vector<double>& x, std::vector<Eigen::RowVector3d>& out) const {
    thread_local std::vector<std::array<double, 3>> rows;
    rows.clear();
    bezier::grid_derivatives(degree_, x.data(), axes_, 0, grid_, rows);  // the grid (the corners)
    bezier::grid_derivatives(degree_, x.data(), axes_, grid_, axes_[0].B.size(), rows);  // the Gauss points
    out.clear();
    for (const auto& [xu, xv, xw] : rows) out.emplace_back(xu, xv, xw);
  }

 private:
  std::array<int, 3> degree_;
  std::size_t grid_;
  std::array<bezier::AxisBases, 3> axes_;  // at the grid's coordinates, then the Gauss points
};

// The sampled Jacobians of a node's elements as affine functions of its displacement d,
// J(d) = J0 + d ∇Nᵀ at every sample, stored entry by entry so that the search's objective (the
// minimum scaled Jacobian over them: most of the optimization's time) vectorizes. The operations
// are those of bezier::scaled_jacobian on the Eigen expression J0 + d * ∇N, in the same order
// (Eigen's 3x3 determinant, column norms summed (x² + y²) + z²), so the values are identical.
class AffineSamples {
 public:
  void add(const Eigen::Matrix3d& J0, const Eigen::RowVector3d& grad) {
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) j_[3 * c + r].push_back(J0(r, c));
      g_[c].push_back(grad[c]);
    }
  }

  double min_scaled(const double* d) const {
    const std::size_t n = g_[0].size();
    values_.resize(n);
    scaled(d, n, values_.data());
    double worst = std::numeric_limits<double>::infinity();
    for (const double v : values_) worst = std::min(worst, v);
    return worst;
  }

 private:
  // Without branches (selects instead of std::clamp's), so that the loop vectorizes.
  void scaled(const double* d, std::size_t n, double* __restrict out) const {
    const double *__restrict j00 = j_[0].data(), *__restrict j10 = j_[1].data(), *__restrict j20 = j_[2].data();
    const double *__restrict j01 = j_[3].data(), *__restrict j11 = j_[4].data(), *__restrict j21 = j_[5].data();
    const double *__restrict j02 = j_[6].data(), *__restrict j12 = j_[7].data(), *__restrict j22 = j_[8].data();
    const double *__restrict g0 = g_[0].data(), *__restrict g1 = g_[1].data(), *__restrict g2 = g_[2].data();
    const double d0 = d[0], d1 = d[1], d2 = d[2];
    for (std::size_t i = 0; i < n; ++i) {
      const double m00 = j00[i] + d0 * g0[i], m10 = j10[i] + d1 * g0[i], m20 = j20[i] + d2 * g0[i];
      const double m01 = j01[i] + d0 * g1[i], m11 = j11[i] + d1 * g1[i], m21 = j21[i] + d2 * g1[i];
      const double m02 = j02[i] + d0 * g2[i], m12 = j12[i] + d1 * g2[i], m22 = j22[i] + d2 * g2[i];
      const double n0 = std::sqrt((m00 * m00 + m10 * m10) + m20 * m20);
      const double n1 = std::sqrt((m01 * m01 + m11 * m11) + m21 * m21);
      const double n2 = std::sqrt((m02 * m02 + m12 * m12) + m22 * m22);
      const double det = m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20) + m02 * (m10 * m21 - m11 * m20);
      const double s = det / (n0 * n1 * n2);
      const double upper = 1.0 < s ? 1.0 : s;
      const double clamped = s < -1.0 ? -1.0 : upper;
      const bool degenerate = (n0 == 0.0) | (n1 == 0.0) | (n2 == 0.0);
      out[i] = degenerate ? 0.0 : clamped;
    }
  }

  std::array<std::vector<double>, 9> j_;  // J0(r, c) at index 3c + r
  std::array<std::vector<double>, 3> g_;  // ∇N
  mutable std::vector<double> values_;
};

// An element's figures. Its sample: the Gauss points and a uniform grid of `grid` points per
// direction, grid_points or, once its field dipped between those, check_points (the check grid).
// `scaled` is the minimum on its sample, `sampled` on the usual one (grid_points): every move
// keeps both from falling below the worst before it, so the worst of either never falls.
struct Quality {
  double scaled = 0;     // sampled min scaled Jacobian (on its own sample)
  bool valid = false;    // certified det J > 0
  double trilinear = 1;  // scaled Jacobian of the hex of its corner points (eq. (1)–(2))
  int grid = 0;          // points per direction of its sample's uniform grid
  double sampled = 0;    // min scaled Jacobian on the usual sample (= scaled while grid is grid_points)
  /// Not certified valid: the certifier's witness, a point of the fold; `scaled` then includes
  /// the points around it (certify_figure).
  std::optional<Eigen::Vector3d> witness;
};

// The Jacobians of h on the sample of x (x.grid) into js, and x's two sampled figures.
void sample_figures(const bezier::BezierHex& h, const OptimizeParams& params, Quality& x, std::vector<Eigen::Matrix3d>& js) {
  js = bezier::jacobian_samples(h, params.gauss_points, x.grid);
  x.scaled = bezier::summarize_jacobians(js).min_scaled;
  x.sampled = x.grid == params.grid_points ? x.scaled : bezier::sample_jacobian(h, params.gauss_points, params.grid_points).min_scaled;
}

// Half the spacing of the points around a fold's witness (in the element's parameters): the
// certifier finds folds that every sample misses a few hundredths across (the rod's pillow
// corners, where extract's finer elements see them).
constexpr double kWitnessSpacing = 1.0 / 32;

// The points around a witness, per axis (clamped to the element).
std::array<std::vector<double>, 3> witness_axes(const Eigen::Vector3d& witness) {
  std::array<std::vector<double>, 3> t;
  for (int d = 0; d < 3; ++d) t[static_cast<std::size_t>(d)] = {std::max(0.0, witness[d] - kWitnessSpacing), witness[d], std::min(1.0, witness[d] + kWitnessSpacing)};
  return t;
}

// Certifies h into x.valid. If h is not certified valid, x.witness is the certifier's witness
// and x.scaled falls to the lowest scaled Jacobian around it (≤ 0 for a fold): a fold the
// samples miss still counts in the worst figure, which every move must not lower. Returns the
// certifier's result.
bezier::CertifyResult certify_figure(const bezier::BezierHex& h, const bezier::CertifyParams& cp, Quality& x) {
  const bezier::CertifyResult c = bezier::certify(h, cp);
  x.valid = c.status == bezier::Validity::valid;
  x.witness.reset();
  if (x.valid) return c;
  x.witness = c.witness;
  const auto t = witness_axes(c.witness);
  for (const double u : t[0])
    for (const double v : t[1])
      for (const double w : t[2]) {
        Eigen::Matrix3d J;
        bezier::evaluate(h, Eigen::Vector3d(u, v, w), &J);
        x.scaled = std::min(x.scaled, bezier::scaled_jacobian(J));
      }
  return c;
}

// The lowest `scaled` (on each element's own sample) and the lowest `sampled` (the usual sample)
// over elements `els` of q, or over all of them.
std::pair<double, double> worst_figures(const std::vector<Quality>& q, const std::vector<int>& els) {
  std::pair<double, double> w{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  for (const int e : els) {
    const Quality& x = q[static_cast<std::size_t>(e)];
    w.first = std::min(w.first, x.scaled), w.second = std::min(w.second, x.sampled);
  }
  return w;
}
std::pair<double, double> worst_figures(const std::vector<Quality>& q) {
  std::vector<int> all(q.size());
  for (std::size_t e = 0; e < q.size(); ++e) all[e] = static_cast<int>(e);
  return worst_figures(q, all);
}

// The interior nodes (global ids) of element e not yet in `visited`, added to it, and with
// `surface_too` its surface nodes as well (the sliding sweeps): a node is moved once per sweep, for the worst element
// it supports.
std::vector<int> fresh_nodes(const Spline& s, std::size_t e, std::set<int>& visited, bool surface_too = false) {
  std::vector<int> nodes;
  for (const int local : s.points_of(e))
    for (const auto& [id, w] : s.nodes_of(s.block_of(e), local))
      if ((surface_too || !s.on_surface(id)) && visited.insert(id).second) nodes.push_back(id);
  return nodes;
}

// Maximizes objective(d) over the box [-h, h]^n from d, n = d.size() (NLopt's derivative-free BOBYQA: the
// objectives are minima, not smooth), at most `evaluations` calls; d and best receive the best
// point and value NLopt reported (also when it gives up on a flat or noisy objective, or stops on
// an error in the objective: callers re-evaluate at d outside NLopt, so a repeatable error comes out).
template <class F>
void maximize_in_box(F& objective, double h, int evaluations, std::vector<double>& d, double& best) {
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(d.size()));
  opt.set_lower_bounds(std::vector<double>(d.size(), -h));
  opt.set_upper_bounds(std::vector<double>(d.size(), h));
  opt.set_max_objective([](const std::vector<double>& x, std::vector<double>&, void* f) { return (*static_cast<F*>(f))(x); }, &objective);
  opt.set_maxeval(evaluations);
  opt.set_initial_step(0.25 * h);
  try {
    opt.optimize(d, best);
  } catch (const std::exception&) {
  }
}

// Scaled Jacobian of the hexahedron of a Bézier element's corner points (eq. (1)–(2)).
double corner_hex_scaled_jacobian(const bezier::BezierHex& h) {
  const int p = h.degree[0], q = h.degree[1], r = h.degree[2];
  const std::array<int, 8> at = {h.index(0, 0, 0), h.index(p, 0, 0), h.index(p, q, 0), h.index(0, q, 0),
                                 h.index(0, 0, r), h.index(p, 0, r), h.index(p, q, r), h.index(0, q, r)};
  std::array<Vec3, 8> x;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d& y = h.points[static_cast<std::size_t>(at[static_cast<std::size_t>(c)])];
    x[static_cast<std::size_t>(c)] = {y[0], y[1], y[2]};
  }
  return trilinear_min_scaled_jacobian(x);
}

// OptimizeParams::trilinear_guard: a Bézier move may not fold the corner hex of a certified-valid
// element that is not folded (folded ones are the objective's to raise).
bool trilinear_falls(const OptimizeParams& params, const Quality& before, const Quality& now) {
  return params.trilinear_guard && before.valid && before.trilinear >= 0 && now.trilinear < 0;
}

// The trilinear pass (OptimizeParams::trilinear_sweeps): after the Bézier sweeps, so that a
// move is judged against their result (its elements' sampled figures stay at or above the worst
// overall, certified-valid elements stay valid).
void trilinear_phase(Spline& s, std::vector<Quality>& q, std::vector<std::vector<Eigen::Matrix3d>>& samples, core::ThreadPool& pool,
                     const OptimizeParams& params, OptimizeResult& r) {
  const bezier::CertifyParams cp;
  if (s.size() == 0) return;
  // Every element's corner hex, kept up to date by the Bézier passes (Quality::trilinear).
  auto tri = [&q](std::size_t e) { return q[e].trilinear; };
  auto worst_tri = [&q]() {
    return std::min_element(q.begin(), q.end(), [](const Quality& a, const Quality& b) { return a.trilinear < b.trilinear; }) - q.begin();
  };
  r.trilinear_before = r.trilinear_after = tri(static_cast<std::size_t>(worst_tri()));
  const auto [floor, floor_sampled] = worst_figures(q);
  for (int sweep = 0; sweep < params.trilinear_sweeps; ++sweep) {
    std::vector<std::size_t> bad;
    for (std::size_t e = 0; e < s.size(); ++e)
      if (tri(e) < params.trilinear_target) bad.push_back(e);
    std::sort(bad.begin(), bad.end(), [&](std::size_t a, std::size_t b) { return tri(a) < tri(b); });
    if (bad.empty()) break;
    int moved = 0, tried = 0;
    std::set<int> visited;
    for (const std::size_t e : bad) {
      if (tri(e) >= params.trilinear_target) continue;
      if (tried >= params.max_nodes_per_sweep) break;
      const std::vector<int> nodes = fresh_nodes(s, e, visited);
      for (const int id : nodes) {
        if (++tried > params.max_nodes_per_sweep) break;
        const std::vector<int>& els = s.elements_of(id);
        const auto x0 = s.position(id);
        const double h = 0.5 * s.neighbour_distance(id);
        if (!std::isfinite(h) || h <= 0) continue;
        // Elements not certified valid are the Bézier pass's: a move here could deepen their
        // fold where no sample sees it.
        if (std::any_of(els.begin(), els.end(), [&](int x) { return !q[static_cast<std::size_t>(x)].valid; })) continue;
        double before = std::numeric_limits<double>::infinity();
        for (const int x : els) before = std::min(before, tri(static_cast<std::size_t>(x)));
        std::vector<double> v(els.size());
        auto objective = [&](const std::vector<double>& d) {
          s.set_position(id, {x0[0] + d[0], x0[1] + d[1], x0[2] + d[2]});
          pool.for_each(els.size(), [&](std::size_t k) { v[k] = corner_hex_scaled_jacobian(s.hex(static_cast<std::size_t>(els[k]))); }, 4);
          return *std::min_element(v.begin(), v.end());
        };
        std::vector<double> d(3, 0.0);
        double best = before;
        maximize_in_box(objective, h, params.max_evaluations, d, best);
        if ((d[0] == 0 && d[1] == 0 && d[2] == 0) || !(objective(d) > before + 1e-9)) {
          s.set_position(id, x0);
          continue;
        }
        // The Bézier elements: sampled figures not below the floor, certified-valid ones valid.
        const std::vector<double> corner = v;
        std::vector<std::vector<Eigen::Matrix3d>> js(els.size());
        std::vector<Quality> now(els.size());
        std::atomic<bool> refused{false};
        pool.for_each(els.size(), [&](std::size_t k) {
          if (refused) return;
          const std::size_t x = static_cast<std::size_t>(els[k]);
          const bezier::BezierHex hx = s.hex(x);
          now[k].grid = q[x].grid;
          sample_figures(hx, params, now[k], js[k]);
          now[k].valid = bezier::certify(hx, cp).status == bezier::Validity::valid;
          if (now[k].scaled < floor || now[k].sampled < floor_sampled || !now[k].valid) refused = true;
        }, 4);
        if (refused) {
          s.set_position(id, x0);
          continue;
        }
        for (std::size_t k = 0; k < els.size(); ++k) {
          const auto x = static_cast<std::size_t>(els[k]);
          now[k].trilinear = corner[k];
          q[x] = now[k], samples[x] = std::move(js[k]);
        }
        ++moved;
      }
    }
    r.trilinear_nodes_moved += moved;
    r.trilinear_after = tri(static_cast<std::size_t>(worst_tri()));
    core::log("trilinear sweep " + std::to_string(sweep + 1) + ": " + std::to_string(moved) + " nodes moved, worst trilinear scaled Jacobian " +
              std::to_string(r.trilinear_after));
    if (moved == 0) break;
  }
  // Where the worst one is, for a user looking at tmesh.vtu (cell = element index).
  const std::size_t w = static_cast<std::size_t>(worst_tri());
  const bezier::BezierHex h = s.hex(w);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const int i : {0, h.degree[0]})
    for (const int j : {0, h.degree[1]})
      for (const int k : {0, h.degree[2]}) c += h.points[static_cast<std::size_t>(h.index(i, j, k))] / 8.0;
  core::log("worst trilinear element: " + std::to_string(w) + " (block " + std::to_string(s.block_of(w)) + ", centre " + std::to_string(c.x()) + ", " +
            std::to_string(c.y()) + ", " + std::to_string(c.z()) + "): " + std::to_string(tri(w)));
}

// Sample grids and their Bernstein tables (tmesh/jacobian_kernels.h).
using kernels::Grid3;
using kernels::GridAxis;
using kernels::grid_axis;

// The joint phase's sample grids: the uniform grid (the 8 corners at grid_points 2) and the n^3 Gauss points (what the sampled
// figure looks at) or, for elements not certified valid (a fold can hide between those), a
// uniform grid of `dense` points per direction, element boundary included.
std::vector<Grid3> joint_grids(int degree, int gauss_points, int grid_points, int dense) {
  auto uniform = [](int n) {
    std::vector<double> t;
    for (int i = 0; i < n; ++i) t.push_back(i / (n - 1.0));
    return t;
  };
  auto iso = [](const GridAxis& g) { return Grid3{g, g, g}; };
  if (dense > 1) return {iso(grid_axis(degree, uniform(dense)))};
  return {iso(grid_axis(degree, uniform(grid_points))), iso(grid_axis(degree, bezier::gauss_legendre_points(gauss_points)))};
}

// The 3^3 grid around a fold's witness (certify_figure's points).
Grid3 witness_grid(int degree, const Eigen::Vector3d& witness) {
  const auto t = witness_axes(witness);
  return {grid_axis(degree, t[0]), grid_axis(degree, t[1]), grid_axis(degree, t[2])};
}

using kernels::scaled_jacobian_gradient;

// A surface node's frame for sliding. Away from sharp curves: its tangent plane at the closest
// surface point (two unit vectors t1, t2), its offset from the surface (kept), and its reach: half
// the distance to its nearest surface neighbour in the net, and less than 1/1.5 of the distance
// to the nearest sharp edge, so no move in the box [-reach, reach]^2 (at most √2 reach) gets to a
// sharp edge. On a sharp curve (its closest surface point within 5 % of that share of the curve),
// with `curves`: the curve's direction (t1 alone), its offset from the curve, and a reach less than
// 1/1.5 of the distance to the nearest sharp corner, so it moves along the curve and corners stay.
// Returns false for a node that may not slide (near a sharp curve but not on it, or near a corner).
struct SlideFrame {
  int dims = 0;  // 0: an interior node (3 coordinates); 2: along the surface; 1: along a sharp curve
  Eigen::Vector3d origin, offset, t1, t2;
  double reach = 0;
};

// Coordinates of a variable: x, y, z for an interior node, else its sliding dimensions.
std::size_t width(const SlideFrame& f) { return f.dims == 0 ? 3u : static_cast<std::size_t>(f.dims); }

// y (a point of f's tangent plane or curve tangent) back onto the surface (the sharp curve) at
// the node's offset from it. The search starts from the frame's own surface point, within the
// node's reach of the answer: the same closest point up to rounding, found faster (every
// evaluation projects every sliding node).
Eigen::Vector3d onto_surface(const SlideFrame& f, const SlideSurface& surface, const Eigen::Vector3d& y) {
  const Eigen::Vector3d on = y - f.offset, at = f.origin - f.offset;
  const Vec3 c = f.dims == 2 ? surface.closest({on.x(), on.y(), on.z()}, {at.x(), at.y(), at.z()}) : surface.closest_sharp({on.x(), on.y(), on.z()});
  return Eigen::Vector3d(c[0], c[1], c[2]) + f.offset;
}

bool slide_frame(const Spline& s, const SlideSurface& surface, int id, bool curves, SlideFrame& f) {
  const auto p = s.position(id);
  Vec3 n;
  const Vec3 c = surface.closest(p, &n);
  const double share = 0.5 * s.neighbour_distance(id, true);
  if (!std::isfinite(share) || share <= 0) return false;
  const double to_sharp = surface.sharp_distance(c);
  const double reach = std::min(share, to_sharp / 1.5);
  const Eigen::Vector3d N(n[0], n[1], n[2]);
  f.origin = Eigen::Vector3d(p[0], p[1], p[2]);
  if (reach >= 0.05 * share && N.squaredNorm() >= 0.5) {
    f.dims = 2;
    f.offset = f.origin - Eigen::Vector3d(c[0], c[1], c[2]);
    f.t1 = N.cross(std::abs(N.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).normalized();
    f.t2 = N.cross(f.t1);
    f.reach = reach;
    return true;
  }
  if (!curves || !(to_sharp <= 0.05 * share)) return false;
  Vec3 t;
  const Vec3 q = surface.closest_sharp(p, &t);
  const double along = std::min(share, surface.sharp_corner_distance(q) / 1.5);
  const Eigen::Vector3d T(t[0], t[1], t[2]);
  if (!(along >= 0.05 * share) || T.squaredNorm() < 0.5) return false;
  f.dims = 1;
  f.offset = f.origin - Eigen::Vector3d(q[0], q[1], q[2]);
  f.t1 = T;
  f.reach = along;
  return true;
}

// In the joint rounds' soft minimum a corner hex's scaled Jacobian t below the trilinear target
// counts as target + kTrilinearWeight (t - trilinear target): a fold weighs like a Bézier figure
// ten times as far below the target, so where the Bézier worst balances at 0.4 the corner hexes
// balance near +0.04 (with the default targets 0.5 and 0.05), not below zero.
constexpr double kTrilinearWeight = 10.0;

struct TriSample {
  double value = 0;               // in the soft minimum's units (above)
  Eigen::Matrix3d G;              // ∂(scaled Jacobian)/∂J, J's columns = neighbour - corner
  std::size_t corner = 0;         // Bézier point indices of the element
  std::array<std::size_t, 3> neighbour{};
};

// The corner-hex samples of an element (Bézier points `x`, degree p) below the trilinear target.
void tri_samples(const std::vector<Eigen::Vector3d>& x, int p, const OptimizeParams& params, std::vector<TriSample>& out) {
  out.clear();
  const std::size_t n = static_cast<std::size_t>(p) + 1;
  auto at = [n](std::size_t i, std::size_t j, std::size_t k) { return i + n * (j + n * k); };
  const std::size_t m = n - 1;
  // The element's corners in VTK hexahedron order.
  const std::array<std::size_t, 8> v = {at(0, 0, 0), at(m, 0, 0), at(m, m, 0), at(0, m, 0), at(0, 0, m), at(m, 0, m), at(m, m, m), at(0, m, m)};
  const auto& nb = hex_corner_neighbours();
  for (int c = 0; c < 8; ++c) {
    TriSample t;
    t.corner = v[static_cast<std::size_t>(c)];
    Eigen::Matrix3d J;
    for (int e = 0; e < 3; ++e) {
      t.neighbour[static_cast<std::size_t>(e)] = v[static_cast<std::size_t>(nb[c][e])];
      J.col(e) = x[t.neighbour[static_cast<std::size_t>(e)]] - x[t.corner];
    }
    const double sj = scaled_jacobian_gradient(J, t.G);
    if (!(sj < params.trilinear_target)) continue;
    t.value = params.target + kTrilinearWeight * (sj - params.trilinear_target);
    out.push_back(t);
  }
}

// Per element, the folds between its samples: where the certifier found it folded
// (Quality::witness) while its usual sample is positive, at a round's start or after a step that
// folded it (its nodes then went back). The joint objective samples around each from then on: the
// rounds raise a fold that no sample sees (the rod: 3 elements left folded under positive
// samples, every round refused), and L-BFGS does not make the same fold again (the folded twist
// at grid_points 2 ended 0.07 → 0.32). Folds the samples see are left to them: sampling around
// those too made the folded twist's second step fold 16 elements elsewhere.
using Folds = std::vector<std::vector<Eigen::Vector3d>>;
constexpr std::size_t kMaxFolds = 8;  // per element: more points only slow the rounds

void add_fold(std::vector<Eigen::Vector3d>& folds, const Eigen::Vector3d& witness) {
  if (folds.size() >= kMaxFolds) return;
  for (const Eigen::Vector3d& f : folds)
    if ((f - witness).cwiseAbs().maxCoeff() <= kWitnessSpacing) return;  // its grid covers it
  folds.push_back(witness);
}

// Marks in `chosen` every element that shares a node with a marked one, `rings` times.
void grow_by_rings(const Spline& s, int rings, std::vector<char>& chosen) {
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<char> grown = chosen;
    for (std::size_t e = 0; e < s.size(); ++e)
      if (chosen[e])
        for (const int local : s.points_of(e))
          for (const auto& [id, w] : s.nodes_of(s.block_of(e), local))
            for (const int e2 : s.elements_of(id)) grown[static_cast<std::size_t>(e2)] = 1;
    chosen.swap(grown);
  }
}

// How a joint phase runs, besides OptimizeParams.
struct JointMode {
  bool until_valid = false;  // stop once every element is certified valid
  bool folded_only = false;  // variables: the nodes of the elements not certified valid only (repair_folds)
  int rings = 0;             // the chosen elements grow by this many rings of neighbours (sharing a node)
  // No element certified valid may fall below min(this, its figure) (repair_folds: the worst
  // figure of the valid elements; by default only the round's worst figure bounds them).
  double valid_floor = -std::numeric_limits<double>::infinity();
};

// The sample points of the six faces of a hex (2 axis + side), n per direction at i/(n−1),
// quality::boundary_deviation's grid; bases per degree, built when first asked for.
class FaceGrids {
 public:
  explicit FaceGrids(int n) : n_(n) {}
  const bezier::HexPoints& face(int degree, int f) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = grids_.find(degree);
    if (it == grids_.end()) {
      std::vector<bezier::HexPoints> six;
      for (int g = 0; g < 6; ++g) {
        std::vector<Eigen::Vector3d> uvw;
        for (int a = 0; a < n_; ++a)
          for (int b = 0; b < n_; ++b) {
            Eigen::Vector3d x;
            x[g / 2] = g % 2;
            x[(g / 2 + 1) % 3] = double(a) / (n_ - 1);
            x[(g / 2 + 2) % 3] = double(b) / (n_ - 1);
            uvw.push_back(x);
          }
        six.emplace_back(std::array<int, 3>{degree, degree, degree}, uvw);
      }
      it = grids_.emplace(degree, std::move(six)).first;
    }
    return it->second[static_cast<std::size_t>(f)];
  }

 private:
  int n_;
  mutable std::mutex mutex_;
  mutable std::map<int, std::vector<bezier::HexPoints>> grids_;  // a map's nodes stay where they are
};

// max(floor, the largest distance of the faces' sample points to the surface), exactly: a sample
// within `floor` of a known surface point (its entry of `near`, else the previous sample's closest
// point) cannot raise it, so only the others are searched. `near` keeps one surface point per
// sample between calls (the step checks of a round see the same faces moved a little): on the
// assembly most samples of a step check need no search, and the closest-point queries were a
// tenth of tmesh's time.
double faces_deviation(const bezier::BezierHex& h, const std::vector<int>& faces, const FaceGrids& grids, const SlideSurface& surface,
                       double floor, std::vector<Eigen::Vector3d>& near) {
  double d = floor;
  thread_local std::vector<Eigen::Vector3d> xs;
  std::size_t at = 0;
  bool have = false;
  Eigen::Vector3d c;
  for (const int f : faces) {
    grids.face(h.degree[0], f).evaluate(h, &xs, nullptr);
    if (near.size() < at + xs.size()) near.resize(at + xs.size(), Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (std::size_t i = 0; i < xs.size(); ++i, ++at) {
      const Eigen::Vector3d& x = xs[i];
      if (!std::isnan(near[at].x())) c = near[at], have = true;
      if (have && (x - c).norm() <= d) continue;
      // Each search starts from a surface point near the answer (quality::boundary_deviation's way).
      const Vec3 y = have ? surface.closest({x.x(), x.y(), x.z()}, {c.x(), c.y(), c.z()}) : surface.closest({x.x(), x.y(), x.z()});
      c = Eigen::Vector3d(y[0], y[1], y[2]), have = true, near[at] = c;
      d = std::max(d, (x - c).norm());
    }
  }
  return d;
}

// The joint phase (OptimizeParams::joint_rounds): the interior nodes of the elements below the
// target move together, by NLopt's L-BFGS on a smooth soft minimum of the scaled Jacobian over
// the samples of every element they support,
//   S = m − (1/β) log Σ_s exp(−β (SJ_s − m)),
// with its analytic gradient. A per-node search cannot raise a plateau of equally bad elements
// that share nodes (measured on the eight: 20 pillow elements within 0.02 of the worst); a joint
// step can. Where the step costs an element its certificate (or its figure falls below the worst
// one), the nodes of that element go back (see the acceptance below); where it takes an element's
// boundary faces past OptimizeParams::max_boundary_deviation, its sliding nodes do.
void joint_phase(Spline& s, std::vector<Quality>& q, std::vector<std::vector<Eigen::Matrix3d>>& samples, Folds& folds, core::ThreadPool& pool,
                 const OptimizeParams& params, const SlideSurface* surface, OptimizeResult& r, const JointMode& mode = {}) {
  const bezier::CertifyParams cp;
  auto all_valid = [&q] { return std::all_of(q.begin(), q.end(), [](const Quality& x) { return x.valid; }); };
  if (mode.until_valid && all_valid()) return;
  const FaceGrids face_grids(params.deviation_points);
  double window = 0;  // > 0: only elements within it of the worst figure (OptimizeParams::joint_window)
  std::vector<int> refused_ids;  // the variables of the last refused round
  // This round leaves the elements not certified valid out of its objective (see the refusal below).
  bool rest_only = false;
  for (int round = 0; round < params.joint_rounds; ++round) {
    // Variables: interior nodes of the elements below the target (or not certified valid), three
    // coordinates each, and with a surface its nodes that may slide, two tangent coordinates each.
    std::vector<int> var_of;  // per node id: variable index, -1 not seen yet, -2 fixed
    std::vector<int> ids;
    std::vector<std::size_t> first;  // per variable: its first coordinate in x
    std::vector<SlideFrame> frame;   // per variable: empty for an interior node
    double select = mode.folded_only ? -std::numeric_limits<double>::infinity() : params.target;
    if (window > 0) {
      double lowest = std::numeric_limits<double>::infinity();
      for (const Quality& x : q) lowest = std::min(lowest, x.scaled);
      select = std::min(select, lowest + window);
    }
    // Corner hexes count once every element is certified valid (validity first: with the folds
    // of the start in the objective, the rod's joint rounds left 108 elements not valid).
    const bool with_tri = params.trilinear_guard && std::all_of(q.begin(), q.end(), [](const Quality& x) { return x.valid; });
    std::vector<char> chosen(s.size(), 0);
    for (std::size_t e = 0; e < s.size(); ++e)
      chosen[e] = !(q[e].valid && q[e].scaled >= select && !(with_tri && q[e].trilinear < params.trilinear_target));
    grow_by_rings(s, mode.rings, chosen);
    for (std::size_t e = 0; e < s.size(); ++e) {
      if (!chosen[e]) continue;
      for (const int local : s.points_of(e))
        for (const auto& [id, w] : s.nodes_of(s.block_of(e), local)) {
          if (static_cast<std::size_t>(id) >= var_of.size()) var_of.resize(static_cast<std::size_t>(id) + 1, -1);
          if (var_of[static_cast<std::size_t>(id)] != -1) continue;
          SlideFrame f;
          if (s.on_surface(id) && !(surface && slide_frame(s, *surface, id, params.slide_sharp_curves, f))) {
            var_of[static_cast<std::size_t>(id)] = -2;
            continue;
          }
          var_of[static_cast<std::size_t>(id)] = static_cast<int>(ids.size());
          ids.push_back(id);
          first.push_back(first.empty() ? 0 : first.back() + width(frame.back()));
          frame.push_back(f);
        }
    }
    if (ids.empty()) return;
    // A refused round leaves every node where it was, so a narrowed window that selects the same
    // nodes poses the same problem and would be refused again: narrow on without running it (the
    // rod's fixed rounds: three such rounds of 96 nodes in a row).
    if (ids == refused_ids && !rest_only) {
      window *= 0.5;
      if (!(window >= params.joint_window / 8)) return;
      core::log("joint rounds: the same nodes as the refused round; the window narrows to " + std::to_string(window));
      continue;
    }
    std::vector<int> els;  // every element a variable node supports
    {
      std::vector<char> in(s.size(), 0);
      for (const int id : ids)
        for (const int e : s.elements_of(id)) in[static_cast<std::size_t>(e)] = 1;
      for (std::size_t e = 0; e < s.size(); ++e)
        if (in[e]) els.push_back(static_cast<int>(e));
    }
    const auto [before, before_sampled] = worst_figures(q, els);
    // The boundary-deviation guard (OptimizeParams::max_boundary_deviation): the boundary faces of
    // the elements a sliding node supports, and their deviation now.
    std::vector<std::vector<int>> guard_faces(els.size());
    std::vector<double> deviation_before(els.size(), 0.0);  // max(the bound, the faces' deviation at the start)
    std::vector<std::vector<Eigen::Vector3d>> near_points(els.size());  // faces_deviation's surface points
    if (surface && params.max_boundary_deviation > 0) {
      bool sliding = false;
      for (const SlideFrame& f : frame) sliding = sliding || f.dims > 0;
      for (std::size_t k = 0; k < els.size() && sliding; ++k) {
        const std::size_t e = static_cast<std::size_t>(els[k]);
        bool slides = false;
        for (const int local : s.points_of(e))
          for (const auto& [id, w] : s.nodes_of(s.block_of(e), local)) {
            const int v = static_cast<std::size_t>(id) < var_of.size() ? var_of[static_cast<std::size_t>(id)] : -1;
            slides = slides || (v >= 0 && frame[static_cast<std::size_t>(v)].dims > 0);
          }
        if (slides) guard_faces[k] = s.boundary_faces(e);
      }
      pool.for_each(els.size(), [&](std::size_t k) {
        if (!guard_faces[k].empty())
          deviation_before[k] = faces_deviation(s.hex(static_cast<std::size_t>(els[k])), guard_faces[k], face_grids, *surface, params.max_boundary_deviation, near_points[k]);
      });
    }
    // The worst figure of the certified elements: with folds among els, a round that raises it is
    // kept even if the worst (a fold's) stays (the folds may not fall themselves, see below).
    double before_rest = std::numeric_limits<double>::infinity();
    for (const int e : els)
      if (q[static_cast<std::size_t>(e)].valid) before_rest = std::min(before_rest, q[static_cast<std::size_t>(e)].scaled);
    int invalid_before = 0;
    double tri_before = std::numeric_limits<double>::infinity();
    for (const int e : els) {
      invalid_before += q[static_cast<std::size_t>(e)].valid ? 0 : 1;
      tri_before = std::min(tri_before, q[static_cast<std::size_t>(e)].trilinear);
    }
    std::vector<double> x0(first.back() + width(frame.back())), lower(x0.size()), upper(x0.size());
    // A round whose nodes all move freely (no sliding node) runs in scaled variables: a node's
    // position is its start + h·y, h its bound (half its neighbour distance), y in [−1, 1] — a
    // diagonal preconditioner for L-BFGS, since the scaled Jacobian's gradient in a node scales
    // as 1/h. Measured: the eight's one round 157 → 68 evaluations, the rod's fixed rounds to
    // validity 5 → 3. Sliding rounds keep their tangent coordinates: scaling those too left the
    // rod at 0.186 (docs/status.md "Session 38").
    const bool scaled = std::none_of(frame.begin(), frame.end(), [](const SlideFrame& f) { return f.dims > 0; });
    std::vector<std::array<double, 3>> start(ids.size());
    std::vector<double> scale(ids.size(), 1.0);
    for (std::size_t v = 0; v < ids.size(); ++v) {
      if (frame[v].dims > 0) {  // tangent coordinates, 0 at the start
        for (std::size_t d = 0; d < width(frame[v]); ++d) lower[first[v] + d] = -frame[v].reach, upper[first[v] + d] = frame[v].reach;
        continue;
      }
      const auto p = s.position(ids[v]);
      const double h = 0.5 * s.neighbour_distance(ids[v]);
      if (scaled) {
        const bool free = std::isfinite(h) && h > 0;
        start[v] = p, scale[v] = free ? h : 1.0;
        for (std::size_t d = 0; d < 3; ++d) x0[first[v] + d] = 0, lower[first[v] + d] = free ? -1.0 : 0.0, upper[first[v] + d] = free ? 1.0 : 0.0;
        continue;
      }
      for (int d = 0; d < 3; ++d) {
        x0[first[v] + static_cast<std::size_t>(d)] = p[static_cast<std::size_t>(d)];
        lower[first[v] + static_cast<std::size_t>(d)] = p[static_cast<std::size_t>(d)] - (std::isfinite(h) ? h : 0.0);
        upper[first[v] + static_cast<std::size_t>(d)] = p[static_cast<std::size_t>(d)] + (std::isfinite(h) ? h : 0.0);
      }
    }
    // The position of variable v at x. A sliding node's coordinates are a point of its tangent
    // plane (or its curve's tangent), projected back onto the surface (the sharp curve) at its
    // offset from it (`project`) — in the objective too, so that its value is the figure the step
    // check then sees; its gradient is the tangent plane's. In the plane alone, the objective
    // overrated the step: the rod's first sliding round reached 0.344 there and 0.079 once
    // projected; projected, 0.337 (docs/status.md "Session 41").
    auto place = [&](std::size_t v, const std::vector<double>& x, bool project) -> std::array<double, 3> {
      const std::size_t at = first[v];
      const SlideFrame& f = frame[v];
      if (f.dims == 0) {
        if (scaled) return {start[v][0] + scale[v] * x[at], start[v][1] + scale[v] * x[at + 1], start[v][2] + scale[v] * x[at + 2]};
        return {x[at], x[at + 1], x[at + 2]};
      }
      const double b = f.dims == 2 ? x[at + 1] : 0.0;
      if (x[at] == 0 && b == 0) return {f.origin.x(), f.origin.y(), f.origin.z()};
      Eigen::Vector3d y = f.origin + x[at] * f.t1;
      if (f.dims == 2) y += b * f.t2;
      if (project) y = onto_surface(f, *surface, y);
      return {y.x(), y.y(), y.z()};
    };
    // Positions first (each projection is a closest-point query: on the pool), then set in order.
    std::vector<std::array<double, 3>> placed(ids.size());
    auto set_all = [&](const std::vector<double>& x, bool project) {
      if (!project || scaled) {
        for (std::size_t v = 0; v < ids.size(); ++v) s.set_position(ids[v], place(v, x, false));
        return;
      }
      pool.for_each(ids.size(), [&](std::size_t v) { placed[v] = place(v, x, true); }, 64);
      for (std::size_t v = 0; v < ids.size(); ++v) s.set_position(ids[v], placed[v]);
    };
    // Per element: its samples' scaled Jacobians and their gradients (one degree per run of
    // blocks is the common case; the table is per degree).
    std::vector<std::vector<double>> sj(els.size());
    std::vector<std::vector<TriSample>> tri(els.size());  // corner-hex samples below the trilinear target (trilinear_guard)
    std::vector<kernels::SampleMatrices> dsj(els.size());
    std::vector<std::vector<double>> ew(els.size());  // per sample exp(-β (sj - lo)), for the gradient
    std::vector<std::vector<Eigen::Vector3d>> dP(els.size());
    // Sample grids per degree, the usual ones and the dense one of elements not certified valid.
    // The folds between an element's samples (Folds) add the points around them.
    std::map<std::tuple<int, int, bool>, std::vector<Grid3>> grids;
    std::vector<std::vector<const Grid3*>> grids_of(els.size());
    std::vector<std::unique_ptr<Grid3>> witness_grids;
    for (std::size_t k = 0; k < els.size(); ++k) {
      const std::size_t e = static_cast<std::size_t>(els[k]);
      const std::tuple<int, int, bool> key{s.degree_of(e), q[e].grid, !q[e].valid};
      auto it = grids.find(key);
      if (it == grids.end())
        it = grids.emplace(key, joint_grids(s.degree_of(e), params.gauss_points, q[e].grid, !q[e].valid ? std::max(params.joint_dense_points, q[e].grid) : 0)).first;
      for (const Grid3& g : it->second) grids_of[k].push_back(&g);
      if (q[e].witness && q[e].sampled > 0) add_fold(folds[e], *q[e].witness);
      for (const Eigen::Vector3d& w : folds[e]) {
        witness_grids.push_back(std::make_unique<Grid3>(witness_grid(s.degree_of(e), w)));
        grids_of[k].push_back(witness_grids.back().get());
      }
    }
    // A narrowed round's elements lie within `window` of each other: at the configured sharpness
    // their weights are nearly equal (β·window = 0.5 at 0.0125), so the round raises their mean and
    // the worst one falls back (refused). Sharpen so that the window spans at least
    // kWindowSpan in the exponent (the defaults' 40 × 0.1 at the first narrowing).
    constexpr double kWindowSpan = 4.0;
    const double beta = window > 0 ? std::max(params.joint_sharpness, kWindowSpan / window) : params.joint_sharpness;
    std::vector<char> left_out(els.size(), 0);  // a rest-only round's folded elements
    if (rest_only)
      for (std::size_t k = 0; k < els.size(); ++k) left_out[k] = q[static_cast<std::size_t>(els[k])].valid ? 0 : 1;
    int evaluations = 0;
    std::vector<double> reached;  // the first point whose samples are all at the target
    auto objective = [&](const std::vector<double>& x, std::vector<double>& grad) {
      ++evaluations;
      set_all(x, true);
      pool.for_each(els.size(), [&](std::size_t k) {
        if (left_out[k]) return;
        const std::size_t e = static_cast<std::size_t>(els[k]);
        thread_local std::vector<Eigen::Vector3d> points;
        s.hex_points(e, points);
        kernels::SampleMatrices& J = dsj[k];  // the Jacobians, then (gradient pass) ∂SJ/∂J
        std::size_t total = 0;
        for (const Grid3* g : grids_of[k]) total += g->size();
        J.resize(total);
        std::size_t at = 0;
        for (const Grid3* g : grids_of[k]) kernels::grid_jacobians(points.data(), *g, J, at), at += g->size();
        sj[k].resize(total);
        kernels::scaled_jacobians(J, sj[k].data());
        if (with_tri) tri_samples(points, s.degree_of(e), params, tri[k]);
      });
      // The soft minimum, its sums per element on the pool (added in order: reproducible).
      std::vector<double> local_min(els.size()), local_sum(els.size());
      pool.for_each(els.size(), [&](std::size_t k) {
        if (left_out[k]) {
          local_min[k] = std::numeric_limits<double>::infinity();
          return;
        }
        local_min[k] = *std::min_element(sj[k].begin(), sj[k].end());
        for (const TriSample& t : tri[k]) local_min[k] = std::min(local_min[k], t.value);
      });
      const double lo = *std::min_element(local_min.begin(), local_min.end());
      pool.for_each(els.size(), [&](std::size_t k) {
        if (left_out[k]) {
          local_sum[k] = 0;
          return;
        }
        double z = 0;
        ew[k].resize(sj[k].size());
        for (std::size_t i = 0; i < sj[k].size(); ++i) z += ew[k][i] = std::exp(-beta * (sj[k][i] - lo));
        for (const TriSample& t : tri[k]) z += std::exp(-beta * (t.value - lo));
        local_sum[k] = z;
      });
      double Z = 0;
      for (const double z : local_sum) Z += z;
      if (!grad.empty()) {
        pool.for_each(els.size(), [&](std::size_t k) {
          const std::size_t e = static_cast<std::size_t>(els[k]);
          // Samples whose weight is below e^-20 of the largest are left out of the gradient (all of them
          // together change it by less than 1e-3 of the largest weight on the eight).
          if (left_out[k] || beta * (local_min[k] - lo) > 20) {
            dP[k].clear();
            return;
          }
          const std::size_t n = static_cast<std::size_t>(s.degree_of(e)) + 1;
          dP[k].assign(n * n * n, Eigen::Vector3d::Zero());
          thread_local std::vector<double> weight;
          weight.resize(sj[k].size());
          for (std::size_t i = 0; i < sj[k].size(); ++i) weight[i] = beta * (sj[k][i] - lo) > 20 ? 0.0 : ew[k][i] / Z;
          kernels::weighted_gradients(dsj[k], weight.data());
          std::size_t first = 0;
          for (const Grid3* g : grids_of[k]) {  // a grid whose weights are all 0 adds nothing
            if (std::any_of(weight.begin() + static_cast<std::ptrdiff_t>(first), weight.begin() + static_cast<std::ptrdiff_t>(first + g->size()),
                            [](double x) { return x != 0.0; }))
              kernels::grid_pull_back(dsj[k], first, *g, dP[k].data());
            first += g->size();
          }
          for (const TriSample& t : tri[k]) {
            const double w = std::exp(-beta * (t.value - lo)) / Z * kTrilinearWeight;
            for (int c = 0; c < 3; ++c) {
              dP[k][t.neighbour[static_cast<std::size_t>(c)]] += w * t.G.col(c);
              dP[k][t.corner] -= w * t.G.col(c);
            }
          }
          s.pull_back(e, dP[k]);
        });
        std::fill(grad.begin(), grad.end(), 0.0);
        for (std::size_t k = 0; k < els.size(); ++k) {
          const std::size_t e = static_cast<std::size_t>(els[k]);
          const std::vector<int>& pts = s.points_of(e);
          if (dP[k].empty()) continue;
          for (std::size_t j = 0; j < pts.size(); ++j)
            for (const auto& [id, wt] : s.nodes_of(s.block_of(e), pts[j])) {
              const int v = static_cast<std::size_t>(id) < var_of.size() ? var_of[static_cast<std::size_t>(id)] : -1;
              if (v < 0) continue;
              const std::size_t at = first[static_cast<std::size_t>(v)];
              const SlideFrame& f = frame[static_cast<std::size_t>(v)];
              const Eigen::Vector3d g = wt * dP[k][j];  // a T-junction's gradient reaches its nodes by its row
              if (f.dims > 0) {
                grad[at] += f.t1.dot(g);
                if (f.dims == 2) grad[at + 1] += f.t2.dot(g);
                continue;
              }
              for (std::size_t d = 0; d < 3; ++d) grad[at + d] += scale[static_cast<std::size_t>(v)] * g[static_cast<Eigen::Index>(d)];
            }
        }
      }
      // Every sample at the target: stop here (later evaluations only spread the gain).
      if (lo >= params.target + 1e-3) {
        reached = x;
        throw nlopt::forced_stop();
      }
      return lo - std::log(Z) / beta;
    };
    nlopt::opt opt(params.joint_method == OptimizeParams::JointMethod::lbfgs ? nlopt::LD_LBFGS : nlopt::LD_CCSAQ, static_cast<unsigned>(x0.size()));
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    using Objective = decltype(objective);
    opt.set_max_objective([](const std::vector<double>& x, std::vector<double>& g, void* f) { return (*static_cast<Objective*>(f))(x, g); }, &objective);
    opt.set_maxeval(params.joint_evaluations);
    // No tolerance on successive values: it stopped rounds after a few tiny line-search steps
    // (the rod: 6 evaluations), and a round without gain ends the phase; at 250 and 350
    // evaluations per round that left the rod with 1 and 8 elements folded. A round ends at
    // `joint_evaluations`, at the target, or roundoff-limited. (Stopping once the soft minimum
    // gained < 1e-4 in 50 evaluations was tried: the rod at 300 kept 3 folds.)
    std::vector<double> x = x0;
    double value = 0;
    try {
      opt.optimize(x, value);
    } catch (const std::exception&) {  // roundoff-limited: x holds the best point NLopt reported
    }
    if (!reached.empty()) x = reached;
    // Keep the step where it does no harm: the nodes of every element that lost its certificate or
    // fell below the worst figure before go back to their start, and the elements they support are
    // checked again, until none does (an element whose nodes are all back is as it was). If nodes
    // had to go back, half and a quarter of the step are tried too; the best of them (fewest
    // elements not certified valid, then the highest worst figure) is kept if the worst figure
    // rose or elements not certified valid were fixed.
    std::vector<int> index_of(s.size(), -1);
    for (std::size_t k = 0; k < els.size(); ++k) index_of[static_cast<std::size_t>(els[k])] = static_cast<int>(k);
    struct Step {
      std::vector<double> y;  // the variables after the nodes went back
      std::vector<Quality> now;
      std::vector<std::vector<Eigen::Matrix3d>> js;
      double worst = 0, tri = 0;
      int invalid = 0, reverted = 0;
      int strayed = 0;  // elements whose sliding nodes went back for the deviation bound
      double rest = std::numeric_limits<double>::infinity();  // the worst of the elements certified before
      std::vector<std::optional<Eigen::Vector3d>> made;  // per element: a fold the step made (its witness)
    };
    auto try_step = [&](double alpha) {
      Step t;
      t.y.resize(x0.size());
      for (std::size_t i = 0; i < x0.size(); ++i) t.y[i] = x0[i] + alpha * (x[i] - x0[i]);
      set_all(t.y, true);
      t.now.resize(els.size()), t.js.resize(els.size()), t.made.resize(els.size());
      std::vector<char> dirty(els.size(), 1), back(ids.size(), 0);
      for (;;) {
        std::vector<std::size_t> todo;
        for (std::size_t k = 0; k < els.size(); ++k)
          if (dirty[k]) todo.push_back(k), dirty[k] = 0;
        if (todo.empty()) break;
        std::vector<char> bad(todo.size(), 0);
        pool.for_each(todo.size(), [&](std::size_t i) {
          const std::size_t k = todo[i], e = static_cast<std::size_t>(els[k]);
          const bezier::BezierHex h = s.hex(e);
          t.now[k].grid = q[e].grid;
          sample_figures(h, params, t.now[k], t.js[k]);
          certify_figure(h, cp, t.now[k]);
          t.now[k].trilinear = corner_hex_scaled_jacobian(h);
          if (q[e].valid && !t.now[k].valid && t.now[k].sampled > 0 && !t.made[k]) t.made[k] = t.now[k].witness;
          const bool falls = t.now[k].scaled < before || t.now[k].sampled < before_sampled || (q[e].valid && !t.now[k].valid) ||
                             (q[e].valid && t.now[k].scaled < std::min(mode.valid_floor, q[e].scaled)) || trilinear_falls(params, q[e], t.now[k]) ||
                             (!q[e].valid && t.now[k].scaled < q[e].scaled);
          // (Measured only where its nodes stay otherwise: the closest points are the cost.)
          const bool strays = !falls && !guard_faces[k].empty() &&
                              faces_deviation(h, guard_faces[k], face_grids, *surface, deviation_before[k], near_points[k]) > deviation_before[k];
          // 1: all its nodes go back; 2: its boundary strays, its sliding nodes go back (its faces
          // depend on them alone; its interior nodes may still untangle it).
          bad[i] = falls ? 1 : strays ? 2 : 0;
        });
        for (std::size_t i = 0; i < todo.size(); ++i) {
          if (!bad[i]) continue;
          t.strayed += bad[i] == 2 ? 1 : 0;
          const std::size_t e = static_cast<std::size_t>(els[todo[i]]);
          for (const int local : s.points_of(e))
            for (const auto& [id, wt] : s.nodes_of(s.block_of(e), local)) {
              const int v = static_cast<std::size_t>(id) < var_of.size() ? var_of[static_cast<std::size_t>(id)] : -1;
              if (v < 0 || back[static_cast<std::size_t>(v)] || (bad[i] == 2 && frame[static_cast<std::size_t>(v)].dims == 0)) continue;
              back[static_cast<std::size_t>(v)] = 1, ++t.reverted;
              const std::size_t at = first[static_cast<std::size_t>(v)];
              for (std::size_t d = 0; d < width(frame[static_cast<std::size_t>(v)]); ++d) t.y[at + d] = x0[at + d];
              s.set_position(id, place(static_cast<std::size_t>(v), x0, false));
              for (const int e2 : s.elements_of(id)) dirty[static_cast<std::size_t>(index_of[static_cast<std::size_t>(e2)])] = 1;
            }
        }
      }
      t.worst = t.tri = std::numeric_limits<double>::infinity();
      for (const auto& x1 : t.now) t.worst = std::min(t.worst, x1.scaled), t.invalid += x1.valid ? 0 : 1, t.tri = std::min(t.tri, x1.trilinear);
      for (std::size_t k = 0; k < els.size(); ++k)
        if (q[static_cast<std::size_t>(els[k])].valid) t.rest = std::min(t.rest, t.now[k].scaled);
      return t;
    };
    auto learn = [&](const Step& t) {
      for (std::size_t k = 0; k < els.size(); ++k)
        if (t.made[k]) add_fold(folds[static_cast<std::size_t>(els[k])], *t.made[k]);
    };
    Step best = try_step(1.0);
    learn(best);
    if (best.reverted > 0)
      for (const double alpha : {0.5, 0.25}) {
        Step t = try_step(alpha);
        learn(t);
        if (t.invalid < best.invalid || (t.invalid == best.invalid && (t.worst > best.worst || (t.worst == best.worst && t.tri > best.tri))))
          best = std::move(t);
      }
    // With the trilinear guard, a round that only raises the worst corner hex (below the
    // trilinear target) is kept too: no Bézier figure fell below the worst one (reverted above).
    const bool tri_gain = with_tri && tri_before < params.trilinear_target && best.tri > tri_before + 1e-9 && best.worst >= before;
    // A fold no round fixes would otherwise refuse every round and leave the rest where it is (the
    // rod at joint_evaluations 325: 3 folded from cycle 1 on, the rest at 0.004; kept, the rest
    // rose and the folds went too: all valid in cycle 1, 0.488).
    const bool rest_gain = invalid_before > 0 && best.invalid <= invalid_before && best.worst >= before && best.rest > before_rest + 1e-9;
    const bool accepted = best.worst > before + 1e-9 || best.invalid < invalid_before || tri_gain || rest_gain;
    const double after = accepted ? best.worst : before;
    const int invalid = accepted ? best.invalid : invalid_before, reverted = best.reverted;
    set_all(accepted ? best.y : x0, true);
    int slid = 0;
    for (std::size_t v = 0; v < ids.size() && accepted; ++v)
      slid += frame[v].dims > 0 && (best.y[first[v]] != 0 || (frame[v].dims == 2 && best.y[first[v] + 1] != 0)) ? 1 : 0;
    if (accepted) r.surface_nodes_slid += slid, r.deviation_put_back += best.strayed;
    if (accepted)
      for (std::size_t k = 0; k < els.size(); ++k) q[static_cast<std::size_t>(els[k])] = best.now[k], samples[static_cast<std::size_t>(els[k])] = std::move(best.js[k]);
    core::log(std::string(surface ? "sliding" : "joint") + " round " + std::to_string(round + 1) + ": " + std::to_string(ids.size()) + " nodes (" + std::to_string(slid) + " slid along the surface), " + std::to_string(els.size()) +
              " elements, " + std::to_string(evaluations) + " evaluations, worst sampled scaled Jacobian " + std::to_string(before) + " -> " +
              std::to_string(after) + ", not certified valid " + std::to_string(invalid_before) + " -> " +
              std::to_string(invalid) + ", " + std::to_string(reverted) + " nodes put back" +
              (best.strayed > 0 ? " (" + std::to_string(best.strayed) + " elements' sliding nodes for the deviation bound)" : "") +
              (accepted ? "" : " (step refused)"));
    if (!accepted) {
      refused_ids = ids;
      // Refused with folds among its elements: a fold whose figure no move raises (its samples
      // depend on fixed points only, or it holds the soft minimum so that the other samples weigh
      // nothing) refuses every round. Once, the same round runs without the folded elements in its
      // objective; it is kept if the certified elements' worst rises (rest_gain; no fold may fall).
      const bool any_valid = std::any_of(els.begin(), els.end(), [&q](int e) { return q[static_cast<std::size_t>(e)].valid; });
      if (invalid_before > 0 && !rest_only && any_valid) {
        rest_only = true;
        core::log("joint rounds: the next leaves the elements not certified valid out of its objective");
        continue;
      }
      rest_only = false;
      // Refused (the step cost elements more than it gained them): go on with the elements near
      // the worst only, then with half that window, while every element is certified valid.
      window = window > 0 ? 0.5 * window : params.joint_window;
      if (invalid_before > 0 || !(window >= params.joint_window / 8) || !(window > 0)) return;
      core::log("joint rounds go on with the elements within " + std::to_string(window) + " of the worst");
      continue;
    }
    ++r.joint_rounds;
    if (after >= params.stop_at && all_valid()) return;  // OptimizeParams::stop_at
    rest_only = false;
    refused_ids.clear();  // the nodes moved: the same selection is a new problem
    const bool progress = (invalid_before > 0 && invalid_before - invalid >= std::max(1.0, params.min_fixed_rel * invalid_before)) ||
                          after >= before + params.min_gain || (tri_gain && best.tri >= tri_before + params.min_gain) ||
                          (rest_gain && best.rest >= before_rest + params.min_gain);
    if (!progress || (mode.until_valid && all_valid())) return;
  }
}

// The worst sampled figure and the count of elements not certified valid.
void summarize(const std::vector<Quality>& q, double* worst, int* invalid) {
  *worst = std::numeric_limits<double>::infinity(), *invalid = 0;
  for (const auto& x : q) *worst = std::min(*worst, x.scaled), *invalid += x.valid ? 0 : 1;
}

// Certified-valid elements whose field dips between their samples (OptimizeParams::check_points,
// check_tolerance) are sampled on the check grid from then on; returns how many were switched.
// `checked` (per element, its Bézier points when last checked and not switched) skips the
// elements no move has touched since: the same points give the same figures (a cycle's sliding
// rounds move a few percent of them; the check grid is most of a cycle's cost on the eight).
int sample_dips_densely(const Spline& s, std::vector<Quality>& q, std::vector<std::vector<Eigen::Matrix3d>>& samples, core::ThreadPool& pool,
                        const OptimizeParams& params, std::vector<std::vector<Eigen::Vector3d>>& checked) {
  if (params.check_points < 2) return 0;
  std::vector<std::vector<Eigen::Matrix3d>> dense(s.size());
  std::vector<double> figure(s.size(), std::numeric_limits<double>::infinity());
  checked.resize(s.size());
  pool.for_each(s.size(), [&](std::size_t e) {
    if (!q[e].valid || q[e].grid >= params.check_points) return;
    bezier::BezierHex h = s.hex(e);
    if (h.points == checked[e]) return;
    std::vector<Eigen::Matrix3d> js = bezier::jacobian_samples(h, params.gauss_points, params.check_points);
    checked[e] = std::move(h.points);
    const double m = bezier::summarize_jacobians(js).min_scaled;
    if (m < params.target && m < q[e].scaled - params.check_tolerance) figure[e] = m, dense[e] = std::move(js);
  });
  int switched = 0;
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < s.size(); ++e) {
    if (dense[e].empty()) continue;
    q[e].sampled = q[e].scaled;  // its usual sample's
    q[e].grid = params.check_points, q[e].scaled = figure[e], samples[e] = std::move(dense[e]);
    ++switched, lowest = std::min(lowest, figure[e]);
  }
  if (switched > 0)
    core::log(std::to_string(switched) + " elements dip between their samples (down to " + std::to_string(lowest) + " on " +
              std::to_string(params.check_points) + "^3 points): sampled there from now on");
  return switched;
}

// The per-node sweeps (OptimizeParams::sweeps, max_nodes_per_sweep, min_gain, patience): worst
// elements first, each interior node moved where it raises the worst figure of its elements.
void sweep_phase(Spline& s, std::vector<Quality>& q, std::vector<std::vector<Eigen::Matrix3d>>& samples, std::vector<XRowSamples>& x_rows,
                 core::ThreadPool& pool, const OptimizeParams& params, const SlideSurface* surface, OptimizeResult& r) {
  const bool slide = params.sweep_slide && surface != nullptr;
  const bezier::CertifyParams cp;
  auto summary = [&](double* worst, int* invalid) { summarize(q, worst, invalid); };
  double last_worst = 0;
  int last_invalid = 0, stalled = 0;
  summary(&last_worst, &last_invalid);
  std::optional<core::LogSection> sweeps_phase;
  if (params.sweeps > 0) sweeps_phase.emplace("per-node sweeps");
  for (int sweep = 0; sweep < params.sweeps; ++sweep) {
    std::vector<std::size_t> bad;
    for (std::size_t e = 0; e < s.size(); ++e)
      if (q[e].scaled < params.target || !q[e].valid) bad.push_back(e);
    // Elements not certified valid first (a sample can miss their fold), then worst first.
    std::sort(bad.begin(), bad.end(), [&](std::size_t a, std::size_t b) {
      return q[a].valid != q[b].valid ? !q[a].valid : q[a].scaled < q[b].scaled;
    });
    if (bad.empty()) {
      r.stop_reason = "no_element_below_target";
      break;
    }
    if (q[bad.front()].valid && q[bad.front()].scaled >= params.stop_at) {  // the worst first: every element valid and above it
      r.stop_reason = "reached_stop_at";
      break;
    }
    int moved = 0;
    std::set<int> visited;  // a node is moved once per sweep, for the worst element it supports
    int tried = 0;
    for (const std::size_t e : bad) {
      if (q[e].scaled >= params.target && q[e].valid) continue;  // improved by an earlier move this sweep
      const std::vector<int> nodes = fresh_nodes(s, e, visited, slide);
      for (const int id : nodes) {
        // OptimizeParams::sweep_slide: a surface node searches its tangent plane (two coordinates,
        // within its reach; the sampled Jacobians stay affine in them), the move checked below is
        // projected back onto the surface at its offset. Nodes that may not slide (near a sharp
        // edge) and those along sharp curves (one coordinate) stay.
        SlideFrame frame;
        if (slide && s.on_surface(id) && !(slide_frame(s, *surface, id, false, frame) && frame.dims == 2)) continue;
        if (++tried > params.max_nodes_per_sweep) break;
        const std::vector<int>& els = s.elements_of(id);
        const auto x0 = s.position(id);
        const double h = frame.dims == 2 ? frame.reach : 0.5 * s.neighbour_distance(id);
        if (!std::isfinite(h) || h <= 0) continue;
        // The displacement of search point d (three coordinates, or two along the tangent plane).
        const auto displacement = [&](const std::vector<double>& d) -> std::array<double, 3> {
          if (frame.dims == 0) return {d[0], d[1], d[2]};
          const Eigen::Vector3d v = d[0] * frame.t1 + d[1] * frame.t2;
          return {v.x(), v.y(), v.z()};
        };
        // Elements not certified valid also count with their certified lower bound of det J
        // relative to its mean: a sample can miss the fold. The search looks only at the node's
        // elements within `margin` of the target (the others are far from being the worst);
        // the move is then checked on all of them.
        std::vector<int> near;
        for (const int x : els)
          if (q[static_cast<std::size_t>(x)].scaled < params.target + params.margin || !q[static_cast<std::size_t>(x)].valid) near.push_back(x);
        auto objective_on = [&](const std::vector<double>& d0, const auto& set) {
          const std::array<double, 3> d = displacement(d0);
          s.set_position(id, {x0[0] + d[0], x0[1] + d[1], x0[2] + d[2]});
          // Per element on the pool (sampled figure, then the certified one), reduced in order.
          std::vector<std::array<double, 2>> v(set.size(), {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()});
          pool.for_each(set.size(), [&](std::size_t i) {
            const bezier::BezierHex hx = s.hex(static_cast<std::size_t>(set[i]));
            v[i][0] = bezier::sample_jacobian(hx, params.gauss_points, q[static_cast<std::size_t>(set[i])].grid).min_scaled;
            if (!q[static_cast<std::size_t>(set[i])].valid) {
              const bezier::CertifyResult c = bezier::certify(hx, cp);
              if (c.mean_detj > 0) v[i][1] = c.min_detj_lower / c.mean_detj;
            }
          }, 1);
          double worst = std::numeric_limits<double>::infinity();
          for (const auto& [sampled, certified] : v) worst = std::min(std::min(worst, sampled), certified);
          return worst;
        };
        // The search's objective on certified-valid elements without re-evaluating them: J is
        // linear in the node's position, J(x0 + δ) = J(x0) + δ ∇N(u)ᵀ at every sample point u
        // (∇N: gradient of the node's basis function there), so each element's sampled J(x0) and
        // ∇N are taken once per node. Most of the optimization's time was these re-evaluations.
        AffineSamples linear;
        std::vector<int> direct;  // elements not certified valid: re-evaluated and certified per call
        std::vector<int> linearized;
        // (x_rows hold the usual sample layout: elements sampled on the check grid are direct too.)
        for (const int x : near) (q[static_cast<std::size_t>(x)].valid && q[static_cast<std::size_t>(x)].grid == params.grid_points ? linearized : direct).push_back(x);
        // Row x of the samples with the node moved by h along x, per element (in parallel), then
        // added in element order.
        // Samples refresh() did not keep: the same grid on the same points (the sampled figure's).
        pool.for_each(linearized.size(), [&](std::size_t k) {
          const std::size_t x = static_cast<std::size_t>(linearized[k]);
          if (samples[x].empty()) samples[x] = bezier::jacobian_samples(s.hex(x), params.gauss_points, params.grid_points);
        }, 4);
        std::vector<std::vector<Eigen::RowVector3d>> J1(linearized.size());
        s.set_position(id, {x0[0] + h, x0[1], x0[2]});
        pool.for_each(linearized.size(), [&](std::size_t k) {
          const std::size_t x = static_cast<std::size_t>(linearized[k]);
          x_rows[static_cast<std::size_t>(s.block_of(x))](s.hex_x(x), J1[k]);
        }, 4);
        s.set_position(id, x0);
        for (std::size_t k = 0; k < linearized.size(); ++k) {
          const std::vector<Eigen::Matrix3d>& J0 = samples[static_cast<std::size_t>(linearized[k])];
          for (std::size_t i = 0; i < J1[k].size(); ++i) linear.add(J0[i], (J1[k][i] - J0[i].row(0)) / h);
        }
        auto objective = [&](const std::vector<double>& d) {
          const double worst = linear.min_scaled(displacement(d).data());
          return direct.empty() ? worst : std::min(worst, objective_on(d, direct));
        };
        std::vector<double> d(frame.dims == 2 ? 2 : 3, 0.0);
        // The objective over all the node's elements at x0: sampled figures from q, certified
        // ones of the elements not certified valid.
        std::vector<int> not_valid;
        double before = std::numeric_limits<double>::infinity();
        for (const int x : els) {
          if (q[static_cast<std::size_t>(x)].valid) before = std::min(before, q[static_cast<std::size_t>(x)].scaled);
          else not_valid.push_back(x);
        }
        if (!not_valid.empty()) before = std::min(before, objective_on(d, not_valid));
        double best = objective(d);
        maximize_in_box(objective, h, params.max_evaluations, d, best);
        // Accept only a real gain (the objective over all the node's elements, evaluated anew)
        // that keeps every certified-valid element valid. At d = 0 the objective is `before`
        // exactly: no gain. The sampled figures decide first, so moves without a gain (most of
        // them) cost no certification of the valid elements.
        if (std::all_of(d.begin(), d.end(), [](double x) { return x == 0; })) {
          s.set_position(id, x0);
          continue;
        }
        {
          const std::array<double, 3> dx = displacement(d);
          Eigen::Vector3d y(x0[0] + dx[0], x0[1] + dx[1], x0[2] + dx[2]);
          if (frame.dims == 2) y = onto_surface(frame, *surface, y);
          s.set_position(id, {y.x(), y.y(), y.z()});
        }
        const double before_sampled = worst_figures(q, els).second;
        std::vector<std::vector<Eigen::Matrix3d>> js(els.size());
        std::vector<Quality> now(els.size());
        // Accepted iff every element's new figure exceeds `before` and its usual sample's stays at
        // least the lowest of its neighbours' before (and, for elements not certified
        // valid, its certified lower bound relative to its mean det J) and every certified-valid
        // element stays certified valid. Evaluated on the pool, worst elements first; the first
        // element that fails stops the others (the decision and, when accepted, every element's
        // new figures are those of a serial pass).
        std::vector<std::size_t> order(els.size());
        for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
          return q[static_cast<std::size_t>(els[a])].scaled < q[static_cast<std::size_t>(els[b])].scaled;
        });
        std::atomic<bool> refused{false};
        pool.for_each(order.size(), [&](std::size_t i) {
          if (refused) return;
          const std::size_t k = order[i];
          const std::size_t x = static_cast<std::size_t>(els[k]);
          const bezier::BezierHex hex = s.hex(x);
          now[k].grid = q[x].grid;
          sample_figures(hex, params, now[k], js[k]);
          now[k].trilinear = corner_hex_scaled_jacobian(hex);
          if (trilinear_falls(params, q[x], now[k])) {
            refused = true;
            return;
          }
          double value = now[k].scaled;
          if (!q[x].valid) {  // judged as `before` (sample and certified bound); the stored figure adds the witness's points
            const bezier::CertifyResult c = certify_figure(hex, cp, now[k]);
            if (c.mean_detj > 0) value = std::min(value, c.min_detj_lower / c.mean_detj);
          }
          if (!(value > before + 1e-9) || now[k].sampled < before_sampled) {
            refused = true;
            return;
          }
          // A gain so far: certify the valid elements (the sampled figures refuse most moves
          // before any of these certifications).
          if (q[x].valid && !(now[k].valid = bezier::certify(hex, cp).status == bezier::Validity::valid)) refused = true;
        }, 4);
        const bool ok = !refused;
        if (!ok) {
          s.set_position(id, x0);
          continue;
        }
        for (std::size_t k = 0; k < els.size(); ++k) {
          q[static_cast<std::size_t>(els[k])] = now[k];
          samples[static_cast<std::size_t>(els[k])] = std::move(js[k]);
        }
        ++moved;
        r.surface_nodes_slid += frame.dims == 2 ? 1 : 0;
      }
    }
    ++r.sweeps;  // over all cycles
    r.nodes_moved += moved;
    double worst = 0;
    int invalid = 0;
    summary(&worst, &invalid);
    core::log("optimization sweep " + std::to_string(sweep + 1) + ": " + std::to_string(moved) + " of " + std::to_string(std::min(tried, params.max_nodes_per_sweep)) +
              " nodes searched moved, worst scaled Jacobian " +
              std::to_string(worst) + ", " + std::to_string(invalid) + " elements not certified valid");
    if (tried > params.max_nodes_per_sweep) {
      ++r.sweeps_cut_at_node_bound;
      core::log_warning("optimization sweep " + std::to_string(sweep + 1) + " stopped at its bound of " +
                        std::to_string(params.max_nodes_per_sweep) + " node moves; elements below the target were left unvisited");
    }
    if (moved == 0) {
      r.stop_reason = "no_move";
      break;
    }
    const bool progress = last_invalid > 0
                              ? last_invalid - invalid >= std::max(1.0, params.min_fixed_rel * last_invalid)
                              : worst >= last_worst + params.min_gain;
    stalled = progress ? 0 : stalled + 1;
    last_worst = std::max(last_worst, worst), last_invalid = std::min(last_invalid, invalid);
    if (stalled >= params.patience) {
      r.stop_reason = "stalled";
      core::log("optimization stalled: " + std::to_string(stalled) + " sweeps in a row made too little progress (fewer than " +
                std::to_string(params.min_fixed_rel * 100) + " % of the invalid elements fixed, or a gain below " +
                std::to_string(params.min_gain) + " in the worst scaled Jacobian)");
      break;
    }
  }
}

// Throws core::ConfigError for parameters out of range.
void check(const OptimizeParams& params) {
  if (params.sweeps < 0 || params.sweeps > 100) throw core::ConfigError("tmesh.optimize_sweeps must be in [0, 100], got " + std::to_string(params.sweeps));
  if (params.gauss_points < 1 || params.gauss_points > 10 || params.max_evaluations < 1 || params.grid_points < 2 || params.grid_points > 8)
    throw core::ConfigError("tmesh optimization: gauss_points must be in [1, 10], grid_points in [2, 8] and max_evaluations >= 1");
  if (!(params.min_gain >= 0 && params.min_gain <= 1) || !(params.min_fixed_rel >= 0 && params.min_fixed_rel <= 1) ||
      params.patience < 1 || params.patience > 100)
    throw core::ConfigError("tmesh optimization: min_gain and min_fixed_rel must be in [0, 1] and patience in [1, 100]");
  if (!(params.cycle_min_gain >= 0 && params.cycle_min_gain <= 1))
    throw core::ConfigError("tmesh optimization: cycle_min_gain must be in [0, 1], got " + std::to_string(params.cycle_min_gain));
  if ((params.check_points != 0 && (params.check_points < 2 || params.check_points > 32)) || !(params.check_tolerance >= 0 && params.check_tolerance <= 1))
    throw core::ConfigError("tmesh optimization: check_points must be 0 or in [2, 32] and check_tolerance in [0, 1]");
  if (params.cycles < 1 || params.cycles > 100) throw core::ConfigError("tmesh.optimize_cycles must be in [1, 100], got " + std::to_string(params.cycles));
  if (!(params.stop_at >= 0 && params.stop_at <= 1)) throw core::ConfigError("tmesh.stop_at must be in [0, 1], got " + std::to_string(params.stop_at));
  if (params.trilinear_sweeps < 0 || params.trilinear_sweeps > 100 || !(params.trilinear_target >= -1 && params.trilinear_target <= 1))
    throw core::ConfigError("tmesh optimization: trilinear_sweeps must be in [0, 100] and trilinear_target in [-1, 1]");
  if (params.joint_rounds < 0 || params.joint_rounds > 100 || params.joint_evaluations < 1 || params.joint_evaluations > 100000 ||
      !(params.joint_sharpness > 0 && params.joint_sharpness <= 1000) || params.joint_dense_points < 2 || params.joint_dense_points > 32 ||
      !(params.joint_window >= 0 && params.joint_window <= 1))
    throw core::ConfigError(
        "tmesh optimization: joint_rounds must be in [0, 100], joint_evaluations in [1, 100000], joint_sharpness in (0, 1000], "
        "joint_dense_points in [2, 32] and joint_window in [0, 1]");
  if (!(params.max_boundary_deviation >= 0 && std::isfinite(params.max_boundary_deviation)) || params.deviation_points < 2 || params.deviation_points > 64)
    throw core::ConfigError("tmesh optimization: max_boundary_deviation must be finite and >= 0 and deviation_points in [2, 64]");
}

// The optimizer's state: the spline and per element its figures and sampled Jacobians at the
// current control points (kept up to date with every accepted move, so a node's search does not
// re-evaluate them), the folds joint steps made, and the threads (started once: the per-node
// batches, ~64 elements, are too small to start threads for each; every item writes its own
// slot, so results do not depend on the count). Records the figures before into r.
struct State {
  Spline s;
  std::vector<Quality> q;
  std::vector<std::vector<Eigen::Matrix3d>> samples;
  core::ThreadPool pool;
  Folds folds;
  State(std::vector<TMesh>& blocks, const OptimizeParams& params, OptimizeResult& r) : s(blocks), q(s.size()), samples(s.size()), folds(s.size()) {
    for (Quality& x : q) x.grid = params.grid_points;
    refresh(params);
    summarize(q, &r.min_before, &r.invalid_before);
    r.min_before = worst_figures(q).second;  // the usual sample's, as min_after (a fold's witness counts in `scaled` only)
    for (const Quality& x : q) r.element_before.push_back(x.sampled);
  }
  // Every element's figures from its points, each on its own sample grid. Its samples are not
  // kept: only the sweeps read them, on the few elements they reach, and compute them there
  // (sweep_phase); kept for all they were most of tmesh's memory (the assembly: ~0.45 GB).
  void refresh(const OptimizeParams& params) {
    const bezier::CertifyParams cp;
    pool.for_each(s.size(), [&](std::size_t e) {
      const bezier::BezierHex h = s.hex(e);
      thread_local std::vector<Eigen::Matrix3d> js;
      sample_figures(h, params, q[e], js);
      std::vector<Eigen::Matrix3d>().swap(samples[e]);
      certify_figure(h, cp, q[e]);
      q[e].trilinear = corner_hex_scaled_jacobian(h);
    });
  }
  // The figures after into r.
  void finish(OptimizeResult& r) const {
    summarize(q, &r.min_after_checked, &r.invalid_after);
    r.min_after = worst_figures(q).second;
    for (const Quality& x : q) r.element_after.push_back(x.sampled);
    for (const auto& f : folds) r.folds_between_samples += static_cast<int>(f.size());
    if (r.folds_between_samples > 0)
      core::log(std::to_string(r.folds_between_samples) + " folds between the samples (found by the certifier) were sampled around in the joint rounds");
  }
};

// repair_folds' rounds: joint rounds on the nodes of the elements not certified valid and of two
// rings of their neighbours (one ring fixed 2 of the rod's 6 refined folds, two all 6), until a
// round fixes none. Its own floor: no element certified valid falls below the worst figure of the
// valid ones at the start (the full rounds bound them by the worst figure, a fold's).
void repair_phase(State& st, const OptimizeParams& params, const SlideSurface* surface, OptimizeResult& r) {
  double worst = 0;
  int start = 0;
  summarize(st.q, &worst, &start);
  JointMode mode;
  mode.until_valid = true, mode.folded_only = true, mode.rings = 2;
  mode.valid_floor = std::numeric_limits<double>::infinity();
  for (const Quality& x : st.q)
    if (x.valid) mode.valid_floor = std::min(mode.valid_floor, x.scaled);
  for (int round = 0, before = start, after = start; before > 0; ++round, before = after) {
    {
      core::LogSection phase("repair " + std::to_string(round + 1) + " of the folds" + (surface ? ": joint rounds sliding" : ": joint rounds"));
      joint_phase(st.s, st.q, st.samples, st.folds, st.pool, params, surface, r, mode);
    }
    summarize(st.q, &worst, &after);
    core::log("repair " + std::to_string(round + 1) + ": not certified valid " + std::to_string(before) + " -> " + std::to_string(after) +
              ", the valid elements kept at or above " + std::to_string(mode.valid_floor));
    if (after >= before) break;
  }
}

}  // namespace

namespace {

// Every block's control points, to put back later (a kept cycle end, a retry's start).
using NetPoints = std::vector<std::vector<std::array<double, 3>>>;
NetPoints net_points(const std::vector<TMesh>& blocks) {
  NetPoints p;
  for (const TMesh& t : blocks) p.push_back(t.control_points);
  return p;
}
void set_net_points(std::vector<TMesh>& blocks, const NetPoints& p) {
  for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b].control_points = p[b];
}

// One run of the optimization (optimize() retries it, OptimizeParams::fold_retry).
OptimizeResult optimize_once(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface, const std::vector<TMesh>* settled) {
  OptimizeResult r;
  State st(blocks, params, r);
  Spline& s = st.s;
  std::vector<Quality>& q = st.q;
  std::vector<std::vector<Eigen::Matrix3d>>& samples = st.samples;
  core::ThreadPool& pool = st.pool;
  Folds& folds = st.folds;
  std::vector<XRowSamples> x_rows;  // per block (its degree)
  for (const TMesh& t : blocks) x_rows.emplace_back(t.degree, params.gauss_points, params.grid_points);
  auto summary = [&](double* worst, int* invalid) { summarize(q, worst, invalid); };
  std::vector<std::vector<Eigen::Vector3d>> checked;  // sample_dips_densely's: elements checked and not moved since
  if (settled) {  // optimize_moved: the elements the move left as they were count as checked
    bool same = settled->size() == blocks.size();
    for (std::size_t b = 0; same && b < blocks.size(); ++b) same = (*settled)[b].control_points.size() == blocks[b].control_points.size();
    if (!same) throw core::InvalidInputError("optimize_moved: the settled net's blocks are not the net's");
    checked.resize(s.size());
    std::size_t moved = 0;
    for (std::size_t e = 0; e < s.size(); ++e) {
      const auto& now = blocks[static_cast<std::size_t>(s.block_of(e))].control_points;
      const auto& then = (*settled)[static_cast<std::size_t>(s.block_of(e))].control_points;
      const std::vector<int>& pts = s.points_of(e);
      if (std::all_of(pts.begin(), pts.end(), [&](int i) { return now[static_cast<std::size_t>(i)] == then[static_cast<std::size_t>(i)]; }))
        checked[e] = s.hex(e).points;
      else
        ++moved;
    }
    core::log(std::to_string(moved) + " of " + std::to_string(s.size()) + " elements moved since the net was optimized: checked between their samples");
  }
  // The nodes at the best cycle end, judged once that end's dips are on the check grid: within a
  // cycle no figure falls, but the dips a cycle's moves open between the samples are only found
  // at its end, and a last cycle may open deeper ones than it raised (the pillowed twist 0.8:
  // 0.51 on the 9³ check grid after cycle 1, 0.26 after cycle 3).
  struct Kept {
    NetPoints points;
    double worst = -std::numeric_limits<double>::infinity();
    int invalid = std::numeric_limits<int>::max();
    int cycle = 0;
    bool better_than(double w, int inv) const { return invalid < inv || (invalid == inv && worst > w); }
  } kept;
  // Cycles: joint rounds, then per-node sweeps, again from where they stopped (OptimizeParams::cycles).
  for (int cycle = 0; cycle < params.cycles; ++cycle) {
    double cycle_start = 0;
    int cycle_invalid = 0;
    summary(&cycle_start, &cycle_invalid);
    // With folds left, a cycle that raised the certified elements' worst figure is progress too.
    auto worst_valid = [&q] {
      double w = std::numeric_limits<double>::infinity();
      for (const Quality& x : q)
        if (x.valid) w = std::min(w, x.scaled);
      return w;
    };
    const double rest_start = worst_valid();
    r.stop_reason.clear();
    if (params.sweeps > 0 && cycle > 0) {
      core::LogSection phase("cycle " + std::to_string(cycle + 1) + ": joint rounds" + (surface ? " sliding" : ""));
      joint_phase(s, q, samples, folds, pool, params, surface, r);
    }
    if (params.sweeps > 0 && cycle == 0) {
      // Surface nodes fixed first, then (given the surface) sliding from where those rounds stopped:
      // every kept round raises the worst figure, so sliding can only add to the fixed result.
      if (!surface || params.slide_from != OptimizeParams::SlideFrom::start) {
        core::LogSection phase("joint rounds");
        JointMode mode;
        mode.until_valid = surface && params.slide_from == OptimizeParams::SlideFrom::valid;
        joint_phase(s, q, samples, folds, pool, params, nullptr, r, mode);
      }
      if (surface) {
        core::LogSection phase("sliding rounds (joint rounds with surface nodes along the surface)");
        joint_phase(s, q, samples, folds, pool, params, surface, r);
      }
    }
    sweep_phase(s, q, samples, x_rows, pool, params, surface, r);
    r.cycles = cycle + 1;
    double cycle_end = 0;
    int cycle_invalid_end = 0;
    summary(&cycle_end, &cycle_invalid_end);
    if (params.cycles > 1)
      core::log("cycle " + std::to_string(cycle + 1) + ": worst scaled Jacobian " + std::to_string(cycle_start) + " -> " + std::to_string(cycle_end) +
                ", not certified valid " + std::to_string(cycle_invalid) + " -> " + std::to_string(cycle_invalid_end));
    if (r.stop_reason == "disabled") break;
    // Dips found: the next cycle raises them (if there is one).
    const int dips = params.sweeps > 0 ? sample_dips_densely(s, q, samples, pool, params, checked) : 0;
    r.elements_on_check_grid += dips;
    double w = 0;  // the figures with the dips among them
    int inv = 0;
    summary(&w, &inv);
    if (params.check_points >= 2 && params.cycles > 1 && (inv < kept.invalid || (inv == kept.invalid && w > kept.worst)))
      kept = {net_points(blocks), w, inv, cycle + 1};
    if (dips > 0) {
      // When none of them is below stop_at, the run has reached it.
      if (inv == 0 && w >= params.stop_at) {
        r.stop_reason = "reached_stop_at";
        break;
      }
      if (cycle + 1 == params.cycles) {
        r.stop_reason = "cycle_bound";
        core::log_warning("optimization stopped at its bound of " + std::to_string(params.cycles) +
                          " cycles (optimize_cycles) with elements just found to dip between the samples");
      }
      continue;
    }
    if (r.stop_reason == "no_element_below_target") break;
    if (cycle_invalid_end == 0 && cycle_end >= params.stop_at) {
      r.stop_reason = "reached_stop_at";
      break;
    }
    if (cycle_invalid_end >= cycle_invalid && cycle_end < cycle_start + params.cycle_min_gain &&
        !(cycle_invalid_end > 0 && worst_valid() >= rest_start + params.cycle_min_gain))
      break;
  }
  if (kept.cycle > 0 && kept.cycle < r.cycles) {
    double w = 0;
    int inv = 0;
    summary(&w, &inv);
    if (kept.better_than(w, inv)) {
      // Its figures again, on the grids as they are now: an element put on the check grid since
      // did not dip there by more than check_tolerance, so the kept end may come out a little lower.
      const NetPoints last = net_points(blocks);
      set_net_points(blocks, kept.points);
      st.refresh(params);
      double kw = 0;
      int kinv = 0;
      summary(&kw, &kinv);
      if (kinv < inv || (kinv == inv && kw > w)) {
        r.cycle_kept = kept.cycle;
        core::log("the nodes of cycle " + std::to_string(kept.cycle) + "'s end are kept: worst scaled Jacobian on every element's own sample " +
                  std::to_string(kw) + ", the last cycle's end " + std::to_string(w) + " (dips it opened between the samples)");
      } else {
        set_net_points(blocks, last);
        st.refresh(params);
      }
    }
  }
  if (r.stop_reason.empty()) {
    r.stop_reason = params.sweeps == 0 ? "disabled" : "sweep_bound";
    if (params.sweeps > 0)
      core::log_warning("optimization stopped at its bound of " + std::to_string(params.sweeps) +
                        " sweeps (tmesh.optimize_sweeps) while moves still raised the worst scaled Jacobian");
  }
  {
    core::LogSection phase("trilinear pass");
    trilinear_phase(s, q, samples, pool, params, r);
  }
  st.finish(r);
  return r;
}

}  // namespace

namespace {
OptimizeResult optimize_with(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface, const std::vector<TMesh>* settled);
}  // namespace

OptimizeResult optimize(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface) {
  return optimize_with(blocks, params, surface, nullptr);
}

OptimizeResult optimize_moved(std::vector<TMesh>& blocks, const std::vector<TMesh>& settled, const OptimizeParams& params, const SlideSurface* surface) {
  return optimize_with(blocks, params, surface, &settled);
}

namespace {

OptimizeResult optimize_with(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface, const std::vector<TMesh>* settled) {
  check(params);
  const bool may_retry = surface && params.fold_retry && params.sweeps > 0 && params.slide_from != OptimizeParams::SlideFrom::start;
  NetPoints start;
  if (may_retry) start = net_points(blocks);
  OptimizeResult first = optimize_once(blocks, params, surface, settled);
  if (!may_retry || first.invalid_after == 0) return first;
  core::log_warning(std::to_string(first.invalid_after) +
                    " elements are left not certified valid: the optimization runs again from the start with surface nodes sliding from "
                    "the first round (tmesh.slide_from: start; tmesh.fold_retry)");
  const NetPoints first_end = net_points(blocks);
  set_net_points(blocks, start);
  OptimizeParams again = params;
  again.slide_from = OptimizeParams::SlideFrom::start;
  core::Stopwatch watch;
  OptimizeResult second;
  {
    core::LogSection phase("optimization again, sliding from the start");
    second = optimize_once(blocks, again, surface, settled);
  }
  const bool better = second.invalid_after < first.invalid_after ||
                      (second.invalid_after == first.invalid_after && second.min_after_checked > first.min_after_checked);
  OptimizeResult::Retry retry{true, better, second.invalid_after, second.min_after, watch.seconds()};
  core::log("the second run ends with " + std::to_string(second.invalid_after) + " elements not certified valid, worst " +
            std::to_string(second.min_after) + " (the first: " + std::to_string(first.invalid_after) + ", " + std::to_string(first.min_after) +
            "): the " + (better ? "second" : "first") + " run's end is kept");
  if (!better) set_net_points(blocks, first_end);
  OptimizeResult& r = better ? second : first;
  r.retry = retry;
  return r;
}

}  // namespace

OptimizeResult repair_folds(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface) {
  check(params);
  OptimizeResult r;
  State st(blocks, params, r);
  repair_phase(st, params, surface, r);
  st.finish(r);
  r.stop_reason = r.invalid_after == 0 ? "all_valid" : "stalled";
  return r;
}

}  // namespace volts::tmesh
