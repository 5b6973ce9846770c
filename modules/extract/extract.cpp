#include "extract/extract.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <limits>
#include <string>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "bezier/certify.h"
#include "bezier/vtk_bezier.h"
#include "core/errors.h"
#include "core/log.h"
#include "core/parallel.h"
#include "extract/point_index.h"
#include "quality/quality.h"

namespace volts::extract {

using surface::Mesh;

namespace {

// Global function id of every control point of every block: TMesh::function_ids, or the next
// free ids where a block has none.
std::vector<std::vector<int>> function_ids(const std::vector<tmesh::TMesh>& ts) {
  std::vector<std::vector<int>> ids(ts.size());
  std::size_t total = 0;
  for (const auto& t : ts) total += t.control_points.size();
  int next = 0;
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (const int id : ts[b].function_ids) {
      // Every id must be used, so none reaches the number of control points (nor allocates it).
      if (id < 0 || static_cast<std::size_t>(id) >= total)
        throw core::InvalidInputError("extract: block " + std::to_string(b) + " has function id " + std::to_string(id) + ", outside [0, " +
                                      std::to_string(total) + ") (the control points of all blocks)");
      next = std::max(next, id + 1);
    }
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const std::size_t n = ts[b].control_points.size();
    if (ts[b].function_ids.empty()) {
      for (std::size_t i = 0; i < n; ++i) ids[b].push_back(next++);
    } else {
      if (ts[b].function_ids.size() != n)
        throw core::InvalidInputError("extract: block " + std::to_string(b) + " has " + std::to_string(ts[b].function_ids.size()) +
                                      " function ids for " + std::to_string(n) + " control points");
      ids[b] = ts[b].function_ids;
    }
  }
  return ids;
}

// Makes 1-D operator rows equal within kSame identical to the first such row seen, so that
// analytically equal rows (uniform knots) are bit-identical and exporters can share them.
class RowCanon {
 public:
  Eigen::MatrixXd canonical(const Eigen::MatrixXd& m) {
    Eigen::MatrixXd r = m;
    for (int i = 0; i < m.rows(); ++i) {
      const Eigen::RowVectorXd row = m.row(i);
      auto it = std::find_if(rows_.begin(), rows_.end(), [&](const Eigen::RowVectorXd& x) {
        return x.size() == row.size() && (x - row).cwiseAbs().maxCoeff() <= kSame;
      });
      if (it == rows_.end()) rows_.push_back(row);
      else r.row(i) = *it;
    }
    return r;
  }

 private:
  static constexpr double kSame = 1e-14;
  std::vector<Eigen::RowVectorXd> rows_;
};

}  // namespace

double point_tolerance(const Eigen::AlignedBox3d& box, double rel) {
  if (box.isEmpty()) return 0.0;
  const double magnitude = std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
  return rel * box.diagonal().norm() + 64 * std::numeric_limits<double>::epsilon() * magnitude;
}

GlobalBasis global_basis(const std::vector<tmesh::TMesh>& ts, const std::vector<bezier::BezierHex>& hexes, bool keep_operators) {
  const std::vector<std::vector<int>> ids = function_ids(ts);
  GlobalBasis g;
  int nodes = 0;
  Eigen::AlignedBox3d box;
  for (std::size_t b = 0; b < ts.size(); ++b) {
    for (std::size_t i = 0; i < ids[b].size(); ++i) {
      nodes = std::max(nodes, ids[b][i] + 1);
      box.extend(Eigen::Vector3d(ts[b].control_points[i][0], ts[b].control_points[i][1], ts[b].control_points[i][2]));
    }
    for (const auto& f : ts[b].free_nodes) nodes = std::max(nodes, f.id + 1);  // no block's point (continuity.h)
  }
  const double diagonal = box.isEmpty() ? 0.0 : box.diagonal().norm();
  const double tol = point_tolerance(box, 1e-12);
  // T-junctions (TMesh::constraints) carry no function: their rows name the nodes that do.
  std::vector<const tmesh::TMesh::Constraint*> row(static_cast<std::size_t>(nodes), nullptr);
  std::vector<int> row_block(static_cast<std::size_t>(nodes), -1);
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (const auto& k : ts[b].constraints) {
      if (k.point < 0 || static_cast<std::size_t>(k.point) >= ids[b].size() || k.ids.size() != k.weights.size() || k.ids.empty())
        throw core::InvalidInputError("extract: block " + std::to_string(b) + " has a malformed T-junction (point " + std::to_string(k.point) + ")");
      const int id = ids[b][static_cast<std::size_t>(k.point)];
      const auto*& r = row[static_cast<std::size_t>(id)];
      if (!r) {
        r = &k, row_block[static_cast<std::size_t>(id)] = static_cast<int>(b);
      } else if (r->ids != k.ids || r->weights != k.weights) {
        throw core::InvalidInputError("extract: node " + std::to_string(id) + " is a T-junction with different rows in blocks " +
                                      std::to_string(row_block[static_cast<std::size_t>(id)]) + " and " + std::to_string(b));
      }
    }
  // Functions: the nodes that are no T-junction, numbered in node order.
  std::vector<int> function_of(static_cast<std::size_t>(nodes), -1);
  int count = 0;
  for (int id = 0; id < nodes; ++id)
    if (!row[static_cast<std::size_t>(id)]) function_of[static_cast<std::size_t>(id)] = count++;
  for (std::size_t id = 0; id < row.size(); ++id)
    if (row[id])
      for (const int m : row[id]->ids)
        if (m < 0 || m >= nodes || row[static_cast<std::size_t>(m)])
          throw core::InvalidInputError("extract: T-junction " + std::to_string(id) + " names node " + std::to_string(m) + ", which is no function");
  g.points.assign(count, Eigen::Vector3d::Zero());
  g.weights.assign(count, 1.0);
  std::vector<int> owner(nodes, -1);  // block that first gave the node its point
  std::vector<Eigen::Vector3d> node_point(static_cast<std::size_t>(nodes), Eigen::Vector3d::Zero());
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (std::size_t i = 0; i < ids[b].size(); ++i) {
      const int id = ids[b][i];
      const Eigen::Vector3d p(ts[b].control_points[i][0], ts[b].control_points[i][1], ts[b].control_points[i][2]);
      if (owner[id] < 0) {
        owner[id] = static_cast<int>(b), node_point[static_cast<std::size_t>(id)] = p;
      } else if ((node_point[static_cast<std::size_t>(id)] - p).norm() > tol) {
        throw core::InvalidInputError("extract: function " + std::to_string(id) + " has different control points in blocks " +
                                      std::to_string(owner[id]) + " and " + std::to_string(b));
      }
    }
  for (std::size_t b = 0; b < ts.size(); ++b)
    for (const auto& f : ts[b].free_nodes) {
      const Eigen::Vector3d p(f.point[0], f.point[1], f.point[2]);
      if (owner[f.id] < 0) {
        owner[f.id] = static_cast<int>(b), node_point[static_cast<std::size_t>(f.id)] = p;
      } else if ((node_point[static_cast<std::size_t>(f.id)] - p).norm() > tol) {
        throw core::InvalidInputError("extract: free node " + std::to_string(f.id) + " has different points in blocks " + std::to_string(owner[f.id]) + " and " +
                                      std::to_string(b) + " (or is a block's control point elsewhere)");
      }
    }
  for (int id = 0; id < nodes; ++id) {
    if (owner[id] < 0) throw core::InvalidInputError("extract: function id " + std::to_string(id) + " belongs to no control point");
    if (function_of[static_cast<std::size_t>(id)] >= 0) g.points[function_of[static_cast<std::size_t>(id)]] = node_point[static_cast<std::size_t>(id)];
  }
  for (int id = 0; id < nodes; ++id) {
    const auto* r = row[static_cast<std::size_t>(id)];
    if (!r) continue;
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < r->ids.size(); ++k) x += r->weights[k] * node_point[static_cast<std::size_t>(r->ids[k])];
    if (!((x - node_point[static_cast<std::size_t>(id)]).norm() <= tol))
      throw core::InvalidInputError("extract: T-junction " + std::to_string(id) + " is not where its row puts it (off by " +
                                    std::to_string((x - node_point[static_cast<std::size_t>(id)]).norm()) + ")");
  }

  // 1-D operators per block (canonical rows: serial, the first row seen wins), then the block
  // and spans of every element.
  RowCanon canon;
  std::vector<std::array<std::vector<Eigen::MatrixXd>, 3>> block_ops;
  std::vector<std::array<std::vector<int>, 3>> block_spans;
  std::vector<std::pair<std::size_t, std::array<std::size_t, 3>>> spans_of;
  std::size_t e = 0;
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const tmesh::TMesh& t = ts[b];
    const int p = t.degree;
    std::array<std::vector<int>, 3> spans;
    std::array<std::vector<Eigen::MatrixXd>, 3> ops;
    for (int d = 0; d < 3; ++d) {
      spans[d] = bezier::element_spans(t.knots[d], p);
      ops[d] = bezier::extraction_operators(t.knots[d], p);
      for (auto& m : ops[d]) m = canon.canonical(m);
    }
    for (std::size_t ec = 0; ec < spans[2].size(); ++ec)
      for (std::size_t eb = 0; eb < spans[1].size(); ++eb)
        for (std::size_t ea = 0; ea < spans[0].size(); ++ea, ++e) {
          if (e >= hexes.size()) throw core::NumericalError("extract: more elements in the blocks than Bézier hexes");
          spans_of.push_back({b, {ea, eb, ec}});
        }
    block_ops.push_back(std::move(ops));
    block_spans.push_back(std::move(spans));
  }
  if (e != hexes.size()) throw core::NumericalError("extract: fewer elements in the blocks than Bézier hexes");
  // Every element's operator and checks in parallel; the first failing element (in element
  // order) is reported, as a serial loop would.
  std::vector<ExtractionElement> elements(keep_operators ? hexes.size() : 0);
  std::vector<double> pous(hexes.size(), 0.0), mins(hexes.size(), 0.0);
  std::vector<std::string> errors(hexes.size());
  core::parallel_for(hexes.size(), [&](std::size_t e) {
    const auto& [b, span] = spans_of[e];
    const auto& [ea, eb, ec] = span;
    const tmesh::TMesh& t = ts[b];
    const int p = t.degree, q = p + 1;
    const auto& spans = block_spans[b];
    const auto& ops = block_ops[b];
    const auto name = [&] {
      return "extract: element " + std::to_string(e) + " (block " + std::to_string(b) + ", span " + std::to_string(ea) + "," +
             std::to_string(eb) + "," + std::to_string(ec) + ")";
    };
    // Global ids of the element's (p+1)^3 local functions, index a + q(b + q c).
    std::vector<int> local(q * q * q);
    for (int c = 0; c < q; ++c)
      for (int bb = 0; bb < q; ++bb)
        for (int a = 0; a < q; ++a) {
          const int i = spans[0][ea] - p + a, j = spans[1][eb] - p + bb, k = spans[2][ec] - p + c;
          local[a + q * (bb + q * c)] = ids[b][i + t.size[0] * (j + t.size[1] * k)];
        }
    ExtractionElement el;
    const Eigen::MatrixXd& Cu = ops[0][ea];
    const Eigen::MatrixXd& Cv = ops[1][eb];
    const Eigen::MatrixXd& Cw = ops[2][ec];
    // Columns of the nonzero entries of every 1-D operator row: a product with a zero factor is
    // zero, so only these products are formed (a tenth of all (p+1)^3 columns).
    std::array<std::vector<std::vector<int>>, 3> nonzero;
    for (int d = 0; d < 3; ++d) {
      const Eigen::MatrixXd& C = d == 0 ? Cu : d == 1 ? Cv : Cw;
      nonzero[d].resize(static_cast<std::size_t>(q));
      for (int r = 0; r < q; ++r)
        for (int col = 0; col < q; ++col)
          if (C(r, col) != 0.0) nonzero[d][static_cast<std::size_t>(r)].push_back(col);
    }
    // Local function l adds its Bernstein row Cu(a,:)⊗Cv(b,:)⊗Cw(c,:) to the row of its global
    // function, or with a T-junction's weights to the rows its node's row names. The terms are
    // grouped by global row, local order kept within each (stable sort), and summed one row at a
    // time: each entry sums its terms in local order, as the dense functions × (p+1)^3 matrix
    // used before did (same values bit for bit; with the column bits below, the assembly's phase
    // 0.42 -> 0.33 s).
    struct Term {
      int row;  // index in el.functions
      int l;    // local function
      double w;
    };
    thread_local std::vector<Term> terms;
    terms.clear();
    const bool rows = std::any_of(local.begin(), local.end(), [&](int id) { return row[static_cast<std::size_t>(id)] != nullptr; });
    for (const int id : local)
      if (const auto* r = row[static_cast<std::size_t>(id)]) {
        for (const int m : r->ids) el.functions.push_back(function_of[static_cast<std::size_t>(m)]);
      } else {
        el.functions.push_back(function_of[static_cast<std::size_t>(id)]);
      }
    std::sort(el.functions.begin(), el.functions.end());
    el.functions.erase(std::unique(el.functions.begin(), el.functions.end()), el.functions.end());
    auto index = [&](int f) { return static_cast<int>(std::lower_bound(el.functions.begin(), el.functions.end(), f) - el.functions.begin()); };
    const int nb = q * q * q;
    for (int l = 0; l < nb; ++l) {
      const int id = local[static_cast<std::size_t>(l)];
      if (const auto* r = row[static_cast<std::size_t>(id)]) {
        for (std::size_t k = 0; k < r->ids.size(); ++k) terms.push_back({index(function_of[static_cast<std::size_t>(r->ids[k])]), l, r->weights[k]});
      } else {
        terms.push_back({index(function_of[static_cast<std::size_t>(id)]), l, 1.0});
      }
    }
    std::stable_sort(terms.begin(), terms.end(), [](const Term& x, const Term& y) { return x.row < y.row; });
    // Without rows an entry is kept where a nonzero product reached it, even if the sum cancels
    // (as setFromTriplets did); with rows where the sum is nonzero (as the dense matrix's
    // nonzeros were): both as before, bit for bit.
    // `used` is a bit per column: a row's entries are then read in column order from its set bits
    // alone (scanning all (p+1)^3 columns per row cost as much as the products).
    thread_local std::vector<double> sum;
    thread_local std::vector<std::uint64_t> used;
    sum.assign(static_cast<std::size_t>(nb), 0.0), used.assign(static_cast<std::size_t>(nb + 63) / 64, 0);
    double* const acc = sum.data();
    std::uint64_t* const bits = used.data();
    std::size_t products = 0;
    for (const Term& t : terms) {
      const std::size_t uq = static_cast<std::size_t>(q), ul = static_cast<std::size_t>(t.l);
      products += nonzero[0][ul % uq].size() * nonzero[1][(ul / uq) % uq].size() * nonzero[2][ul / (uq * uq)].size();
    }
    el.op.resize(static_cast<int>(el.functions.size()), nb);
    el.op.reserve(static_cast<Eigen::Index>(products));
    for (std::size_t at = 0; at < terms.size();) {
      const int r = terms[at].row;
      el.op.startVec(r);
      for (; at < terms.size() && terms[at].row == r; ++at) {
        const int l = terms[at].l;
        const double w = terms[at].w;
        const int a = l % q, bb = (l / q) % q, c = l / (q * q);
        for (const int cw : nonzero[2][static_cast<std::size_t>(c)])
          for (const int cv : nonzero[1][static_cast<std::size_t>(bb)])
            for (const int cu : nonzero[0][static_cast<std::size_t>(a)]) {
              const double v = Cu(a, cu) * Cv(bb, cv) * Cw(c, cw);
              if (!rows && v == 0.0) continue;
              const std::size_t col = static_cast<std::size_t>(cu + q * (cv + q * cw));
              acc[col] += rows ? w * v : v, bits[col / 64] |= std::uint64_t{1} << (col % 64);
            }
      }
      for (std::size_t word = 0; word < used.size(); ++word)
        for (std::uint64_t m = bits[word]; m; m &= m - 1) {
          const std::size_t col = 64 * word + static_cast<std::size_t>(__builtin_ctzll(m));
          if (!rows || acc[col] != 0.0) el.op.insertBack(r, static_cast<int>(col)) = acc[col];
          acc[col] = 0.0;
        }
      std::fill(used.begin(), used.end(), 0);
    }
    el.op.finalize();
    // Partition of unity and reproduction of the extracted hex.
    const bezier::BezierHex& h = hexes[e];
    if (h.num_points() != q * q * q) {
      errors[e] = name() + ": its Bézier hex has another degree";
      return;
    }
    Eigen::RowVectorXd sums = Eigen::RowVectorXd::Zero(q * q * q);
    Eigen::MatrixXd bez = Eigen::MatrixXd::Zero(q * q * q, 3);
    for (int r = 0; r < el.op.outerSize(); ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(el.op, r); it; ++it) {
        sums[it.col()] += it.value();
        bez.row(it.col()) += it.value() * g.points[el.functions[r]].transpose();
      }
    const double pou = (sums.array() - 1.0).abs().maxCoeff();
    pous[e] = pou;
    double lowest = 0.0;
    for (Eigen::Index k = 0; k < el.op.nonZeros(); ++k) lowest = std::min(lowest, el.op.valuePtr()[k]);
    mins[e] = lowest;
    if (!(pou <= 1e-12)) {
      char msg[64];
      std::snprintf(msg, sizeof msg, "%.1e, allowed 1e-12)", pou);
      errors[e] = name() + ": its extraction operator is no partition of unity (a column sum is off 1 by " + msg;
      return;
    }
    double dev = 0;
    for (int i = 0; i < q * q * q; ++i) dev = std::max(dev, (bez.row(i).transpose() - h.points[i]).norm());
    if (!(dev <= tol)) {
      char msg[96];
      std::snprintf(msg, sizeof msg, " by %.1e (%.1e of the bounding-box diagonal; allowed %.1e)", dev, dev / std::max(diagonal, 1e-300), tol);
      errors[e] = name() + ": Cᵀ·P misses its Bézier control points" + msg;
      return;
    }
    if (keep_operators) elements[e] = std::move(el);
  });
  for (std::size_t e = 0; e < hexes.size(); ++e) {
    if (!errors[e].empty()) throw core::NumericalError(errors[e]);
    g.partition_of_unity_error = std::max(g.partition_of_unity_error, pous[e]);
    g.min_coefficient = std::min(g.min_coefficient, mins[e]);
  }
  g.elements = std::move(elements);

  return g;
}

Result extract(const std::vector<tmesh::TMesh>& ts, const Mesh& surface, const Params& params) {
  if (params.gauss_points < 0 || params.gauss_points > 10) throw core::ConfigError("extract.gauss_points must be in [0, 10]");
  if (params.dense_points < 0 || params.dense_points == 1 || params.dense_points > 16) throw core::ConfigError("extract.dense_points must be 0 or in [2, 16]");
  if (params.boundary_samples < 2 || params.boundary_samples > 64) throw core::ConfigError("extract.boundary_samples must be in [2, 64]");
  if (ts.empty()) throw core::InvalidInputError("extract: no T-mesh");
  Result r;
  r.degree = ts[0].degree;
  std::vector<quality::BoundaryFace> boundary;
  std::vector<int> block;  // per element
  {
    core::LogSection s("Bézier extraction");
    for (const auto& t : ts) {
      if (t.degree != r.degree) throw core::InvalidInputError("extract: the cubes' T-meshes have different degrees");
      bezier::TensorBSplineVolume vol;
      vol.degree = {t.degree, t.degree, t.degree};
      vol.knots = t.knots;
      for (const auto& p : t.control_points) vol.points.emplace_back(p[0], p[1], p[2]);
      auto hexes = bezier::extract_bezier_hexes(vol);
      // Elements are ordered i fastest over the tensor grid of knot spans; boundary faces are those
      // on the first or last span in some direction, on a cube face that is on the surface.
      const int n[3] = {static_cast<int>(bezier::element_spans(t.knots[0], t.degree).size()),
                        static_cast<int>(bezier::element_spans(t.knots[1], t.degree).size()),
                        static_cast<int>(bezier::element_spans(t.knots[2], t.degree).size())};
      const int ne = static_cast<int>(hexes.size());
      if (n[0] * n[1] * n[2] != ne) throw core::NumericalError("extract: element count does not match the knot spans");
      const int offset = static_cast<int>(r.hexes.size());
      for (int e = 0; e < ne; ++e) {
        const int idx[3] = {e % n[0], (e / n[0]) % n[1], e / (n[0] * n[1])};
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side)
            if (t.boundary[2 * axis + side] && idx[axis] == (side ? n[axis] - 1 : 0)) boundary.push_back({offset + e, axis, side});
      }
      r.grids.push_back({offset, {n[0], n[1], n[2]}});
      r.hexes.insert(r.hexes.end(), std::make_move_iterator(hexes.begin()), std::make_move_iterator(hexes.end()));
      block.insert(block.end(), hexes.size(), static_cast<int>(&t - ts.data()));
    }
  }
  {
    core::LogSection s("global basis and extraction operators");
    const auto& x = params.exports;
    const bool operators = std::find(x.begin(), x.end(), "bext") != x.end() || std::find(x.begin(), x.end(), "json") != x.end();
    r.basis = global_basis(ts, r.hexes, operators);
    char pou[32];
    std::snprintf(pou, sizeof pou, "%.1e", r.basis.partition_of_unity_error);
    core::log(std::to_string(r.basis.points.size()) + " global functions, partition of unity within " + pou);
    if (r.basis.min_coefficient < 0)
      core::log_warning("some global functions have negative Bernstein coefficients (down to " + std::to_string(r.basis.min_coefficient) +
                        "; tmesh.continuity c2's smooth rows): they sum to one but are not B-splines, so masses lumped by row sums "
                        "can be negative on some elements");
  }
  const int gp = params.gauss_points > 0 ? params.gauss_points : r.degree + 1;
  auto located = [&](const quality::WorstSample& w) {
    const tmesh::TMesh& t = ts[static_cast<std::size_t>(block[static_cast<std::size_t>(w.element)])];
    return Result::Worst{w, block[static_cast<std::size_t>(w.element)], t.component, t.kind};
  };
  {
    core::LogSection s("scaled Jacobian at corners and Gauss points");
    quality::ScaledJacobian sj = quality::scaled_jacobian(r.hexes, gp);
    for (const quality::WorstSample& w : quality::worst_samples(r.hexes, sj, boundary, gp, 10)) r.worst.push_back(located(w));
    r.min_scaled_jacobian = std::move(sj.min_per_element);
    r.max_scaled_jacobian = std::move(sj.max_per_element);
    r.min_scaled = sj.min, r.max_scaled = sj.max;
    r.volume_frac_scaled_jacobian_above_0_5 = quality::volume_fraction_scaled_jacobian_above(r.hexes, gp, 0.5);
  }
  if (params.dense_points > 0) {
    // The field between the samples above: the optimizer raises those, which can leave it low
    // on element edges and faces (the generated torus: 0.507 there, 0.234 on the grid).
    core::LogSection s("scaled Jacobian on a uniform grid");
    quality::ScaledJacobian d = quality::scaled_jacobian_on_grid(r.hexes, params.dense_points);
    for (const quality::WorstSample& w : quality::worst_grid_samples(r.hexes, d, boundary, params.dense_points, 10)) r.worst_dense.push_back(located(w));
    r.min_scaled_jacobian_dense = std::move(d.min_per_element);
    r.min_scaled_dense = r.hexes.empty() ? 0.0 : d.min;
    core::log("worst on " + std::to_string(params.dense_points) + "^3 points per element: " + std::to_string(r.min_scaled_dense));
  }
  {
    // Certified sign of det J (Randrianarivony 2008 §4): the sampled figures above can miss a fold.
    core::LogSection s("certified Jacobian validity");
    r.certified_min_detj_rel = std::numeric_limits<double>::infinity();
    std::vector<bezier::CertifyResult> cs(r.hexes.size());
    core::parallel_for(r.hexes.size(), [&](std::size_t e) { cs[e] = bezier::certify(r.hexes[e], params.certify); });
    for (const bezier::CertifyResult& c : cs) {
      r.status.push_back(static_cast<int>(c.status));
      r.certified_min_detj.push_back(c.min_detj_lower);
      if (c.mean_detj != 0) r.certified_min_detj_rel = std::min(r.certified_min_detj_rel, c.min_detj_lower / std::abs(c.mean_detj));
    }
    if (r.hexes.empty()) r.certified_min_detj_rel = 0;
    const quality::ValidityCounts counts = quality::count_validity(r.status);
    r.certified_valid = counts.valid, r.certified_invalid = counts.invalid, r.undecided = counts.undecided;
  }
  {
    core::LogSection s("boundary deviation and volume");
    quality::BoundaryDeviation dev = quality::boundary_deviation(r.hexes, boundary, surface, params.boundary_samples);
    r.boundary_distance = std::move(dev.per_element);
    r.hausdorff_rel = dev.rel;
    const quality::Volume v = quality::volume(r.hexes, surface, std::max({r.degree, 1}) + 2);
    r.spline_volume = v.elements, r.surface_volume = v.surface, r.volume_rel_error = v.rel_error;
  }
  return r;
}

namespace {

double frac_above(const std::vector<double>& v, double x) {
  if (v.empty()) return 0.0;
  return static_cast<double>(std::count_if(v.begin(), v.end(), [x](double y) { return y > x; })) / static_cast<double>(v.size());
}

}  // namespace

core::Json report_figures(const Result& r) {
  auto listed = [](const std::vector<Result::Worst>& list) {
    core::Json worst = core::Json::array();
    for (const Result::Worst& x : list) {
      const quality::WorstSample& w = x.sample;
      worst.push_back({{"element", w.element}, {"block", x.block}, {"component", x.component}, {"block_kind", x.block_kind},
                       {"scaled_jacobian", w.scaled_jacobian}, {"sample", w.at_corner ? "corner" : w.on_grid ? "grid" : "gauss"},
                       {"uvw", {w.uvw[0], w.uvw[1], w.uvw[2]}}, {"position", {w.position[0], w.position[1], w.position[2]}},
                       {"boundary_faces", w.boundary_faces}, {"surface_bound", w.surface_bound}});
    }
    return worst;
  };
  return core::Json{{"worst_elements", listed(r.worst)}, {"worst_elements_dense", listed(r.worst_dense)},
                    {"bezier_elements", r.hexes.size()},   {"degree", r.degree},
                    {"min_scaled_jacobian", r.min_scaled}, {"max_scaled_jacobian", r.max_scaled},
                    {"min_scaled_jacobian_dense", r.min_scaled_dense},
                    {"hausdorff_rel", r.hausdorff_rel},    {"volume_rel_error", r.volume_rel_error},
                    {"spline_volume", r.spline_volume},    {"surface_volume", r.surface_volume},
                    {"certified_valid", r.certified_valid}, {"certified_invalid", r.certified_invalid},
                    {"undecided", r.undecided},            {"certified_min_detj_rel", r.certified_min_detj_rel},
                    {"global_functions", r.basis.points.size()},
                    {"partition_of_unity_error", r.basis.partition_of_unity_error},
                    {"min_extraction_coefficient", r.basis.min_coefficient},
                    {"frac_scaled_jacobian_above_0_5", frac_above(r.min_scaled_jacobian, 0.5)},
                    {"volume_frac_scaled_jacobian_above_0_5", r.volume_frac_scaled_jacobian_above_0_5}};
}

void write_bezier_vtu(const std::string& path, const Result& r) {
  std::vector<bezier::CellArray> cells = {{"min_scaled_jacobian", 1, r.min_scaled_jacobian},
                                          {"max_scaled_jacobian", 1, r.max_scaled_jacobian},
                                          {"boundary_distance", 1, r.boundary_distance},
                                          {"status", 1, std::vector<double>(r.status.begin(), r.status.end())},
                                          {"certified_min_detj", 1, r.certified_min_detj}};
  if (!r.min_scaled_jacobian_dense.empty()) cells.push_back({"min_scaled_jacobian_dense", 1, r.min_scaled_jacobian_dense});
  bezier::write_bezier_vtu(path, r.hexes, cells, r.grids.empty() ? shared_points(r.hexes) : shared_points(r.hexes, r.grids));
}

namespace {

// shared_points' numbering: points in order of first sight; a point within the tolerance of an
// earlier one of equal weight (1e-12 relative) is that one, one of another weight a point of its own.
class PointMerger {
 public:
  explicit PointMerger(const std::vector<bezier::BezierHex>& hexes) {
    Eigen::AlignedBox3d box;
    std::size_t total = 0;
    for (const auto& h : hexes) {
      for (const auto& x : h.points) box.extend(x);
      total += h.points.size();
    }
    tol_ = std::max(point_tolerance(box, 1e-12), std::numeric_limits<double>::min());
    index_ = PointIndex(box, tol_);
    index_.reserve(total / 2);
    total_ = total;
  }
  double tolerance() const { return tol_; }
  std::size_t total() const { return total_; }  ///< control points of all hexes
  /// The point's number by its position (the index holds every point given here).
  int by_position(const Eigen::Vector3d& x, double w) {
    const int p = index_.find_or_add(x);
    if (p == static_cast<int>(file_point_.size())) {
      file_point_.push_back(next_), weight_.push_back(w);
      return next_++;
    }
    if (std::abs(weight_[static_cast<std::size_t>(p)] - w) <= 1e-12 * std::abs(w)) return file_point_[static_cast<std::size_t>(p)];
    return next_++;  // a second weight at one position: a point of its own, outside the index
  }
  /// A new number, for a point no other may be (not indexed).
  int fresh() { return next_++; }

 private:
  double tol_ = 0;
  std::size_t total_ = 0;
  PointIndex index_{Eigen::AlignedBox3d(), 0.0};
  std::vector<int> file_point_;  // per index point: its number
  std::vector<double> weight_;   // per index point
  int next_ = 0;
};

}  // namespace

std::vector<int> shared_points(const std::vector<bezier::BezierHex>& hexes) {
  PointMerger merge(hexes);
  std::vector<int> ids;
  ids.reserve(merge.total());
  for (const auto& h : hexes)
    for (int n = 0; n < h.num_points(); ++n) ids.push_back(merge.by_position(h.points[static_cast<std::size_t>(n)], h.weight(n)));
  return ids;
}

std::vector<int> shared_points(const std::vector<bezier::BezierHex>& hexes, const std::vector<ElementGrid>& grids) {
  PointMerger merge(hexes);  // the grids' sides only: the points a neighbour may share
  const double tol = merge.tolerance();
  std::vector<Eigen::Vector3d> first_at;  // per number: where it was first seen, and its weight
  std::vector<double> first_weight;
  std::vector<int> ids;
  ids.reserve(merge.total());
  std::size_t e = 0;
  for (const ElementGrid& g : grids) {
    const long long count = static_cast<long long>(g.n[0]) * g.n[1] * g.n[2];
    if (g.first != static_cast<int>(e) || g.n[0] < 1 || g.n[1] < 1 || g.n[2] < 1 || count > static_cast<long long>(hexes.size() - e))
      throw core::InvalidInputError("shared_points: the element grids do not cover the hexes in order (grid at " + std::to_string(g.first) + ")");
    const std::array<int, 3> p = hexes[e].degree;
    const std::array<int, 3> m{p[0] * g.n[0] + 1, p[1] * g.n[1] + 1, p[2] * g.n[2] + 1};
    std::vector<int> net(static_cast<std::size_t>(m[0]) * m[1] * m[2], -1);  // net point -> its number
    for (int ec = 0; ec < g.n[2]; ++ec)
      for (int eb = 0; eb < g.n[1]; ++eb)
        for (int ea = 0; ea < g.n[0]; ++ea, ++e) {
          const bezier::BezierHex& h = hexes[e];
          if (h.degree != p) throw core::InvalidInputError("shared_points: hex " + std::to_string(e) + " has another degree than its grid's first");
          for (int n = 0; n < h.num_points(); ++n) {
            const auto [i, j, k] = h.ijk(n);
            const std::array<int, 3> at{p[0] * ea + i, p[1] * eb + j, p[2] * ec + k};
            int& slot = net[static_cast<std::size_t>(at[0] + m[0] * (at[1] + m[1] * at[2]))];
            const Eigen::Vector3d& x = h.points[static_cast<std::size_t>(n)];
            const double w = h.weight(n);
            if (slot >= 0 && (first_at[static_cast<std::size_t>(slot)] - x).norm() <= tol &&
                std::abs(first_weight[static_cast<std::size_t>(slot)] - w) <= 1e-12 * std::abs(w)) {
              ids.push_back(slot);
              continue;
            }
            const bool side = at[0] == 0 || at[1] == 0 || at[2] == 0 || at[0] == m[0] - 1 || at[1] == m[1] - 1 || at[2] == m[2] - 1;
            const int id = side || slot >= 0 ? merge.by_position(x, w) : merge.fresh();
            if (id == static_cast<int>(first_at.size())) first_at.push_back(x), first_weight.push_back(w);
            if (slot < 0) slot = id;
            ids.push_back(id);
          }
        }
  }
  if (e != hexes.size()) throw core::InvalidInputError("shared_points: the element grids cover " + std::to_string(e) + " of " + std::to_string(hexes.size()) + " hexes");
  return ids;
}

GlobalBasis bezier_basis(const std::vector<bezier::BezierHex>& hexes, bool keep_operators) {
  Eigen::AlignedBox3d box;
  for (const auto& h : hexes) {
    bezier::check(h);
    for (const auto& x : h.points) box.extend(x);
  }
  PointIndex index(box, std::max(point_tolerance(box, 1e-12), std::numeric_limits<double>::min()));
  // About half of the points are shared (cubic tet-route hexes: 0.49 distinct per point).
  index.reserve(hexes.empty() ? 0 : hexes.size() * hexes[0].points.size() / 2);
  GlobalBasis g;
  if (keep_operators) g.elements.resize(hexes.size());
  for (std::size_t e = 0; e < hexes.size(); ++e) {
    const bezier::BezierHex& h = hexes[e];
    const int nb = h.num_points();
    std::vector<int> local(static_cast<std::size_t>(nb));
    for (int l = 0; l < nb; ++l) {
      const int f = index.find_or_add(h.points[static_cast<std::size_t>(l)]);
      if (f == static_cast<int>(g.weights.size())) {
        g.weights.push_back(h.weight(l));
      } else if (std::abs(g.weights[static_cast<std::size_t>(f)] - h.weight(l)) > 1e-12 * g.weights[static_cast<std::size_t>(f)]) {
        throw core::InvalidInputError("extract: element " + std::to_string(e) + " shares a control point with another element but not its weight (" +
                                      std::to_string(h.weight(l)) + " against " + std::to_string(g.weights[static_cast<std::size_t>(f)]) +
                                      "): the elements are not C0 there");
      }
      local[static_cast<std::size_t>(l)] = f;
    }
    std::vector<int> sorted = local;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      throw core::InvalidInputError("extract: element " + std::to_string(e) + " has two control points closer than the tolerance (a degenerate element)");
    if (!keep_operators) continue;
    ExtractionElement& el = g.elements[e];
    el.functions = sorted;
    // Row r (function sorted[r]) has its one 1 in the column of its Bernstein function.
    std::vector<int> column(static_cast<std::size_t>(nb));
    for (int l = 0; l < nb; ++l)
      column[static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), local[static_cast<std::size_t>(l)]) - sorted.begin())] = l;
    el.op.resize(nb, nb);
    el.op.reserve(nb);
    for (int r = 0; r < nb; ++r) {
      el.op.startVec(r);
      el.op.insertBack(r, column[static_cast<std::size_t>(r)]) = 1.0;
    }
    el.op.finalize();
  }
  g.points = index.points();
  g.partition_of_unity_error = 0.0;  // one 1 per column
  return g;
}

}  // namespace volts::extract
