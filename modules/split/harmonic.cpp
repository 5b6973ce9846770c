#include "split/harmonic.h"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <limits>
#include <map>

#include "core/errors.h"
#include "split/isoline.h"

namespace volts::split {

using surface::Mesh;

namespace {

// Cotangent weight of each edge: (cot α + cot β) / 2 over the two opposite angles.
std::vector<double> cotangent_weights(const Mesh& mesh) {
  std::vector<double> w(mesh.number_of_edges(), 0.0);
  for (auto h : mesh.halfedges()) {
    if (mesh.is_border(h)) continue;
    const auto& a = mesh.point(mesh.source(h));
    const auto& b = mesh.point(mesh.target(h));
    const auto& c = mesh.point(mesh.target(mesh.next(h)));
    const auto u = a - c, v = b - c;
    const double cross = std::sqrt(CGAL::cross_product(u, v).squared_length());
    if (cross > 0) w[mesh.edge(h)] += 0.5 * (u * v) / cross;
  }
  return w;
}

bool less(const std::vector<double>& f, int a, int b) { return f[a] < f[b] || (f[a] == f[b] && a < b); }

}  // namespace

struct HarmonicSolver::Impl {
  std::vector<int> constrained;
  std::vector<int> free_index;  // per vertex: index among the free vertices, or -1
  Eigen::SparseMatrix<double> coupling;  // free x constrained block (moved to the right-hand side)
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

HarmonicSolver::HarmonicSolver(const Mesh& mesh, const std::vector<int>& constrained) : impl_(std::make_unique<Impl>()) {
  const int nv = static_cast<int>(mesh.number_of_vertices());
  if (constrained.empty()) throw core::InvalidInputError("harmonic field: no constrained vertex");
  std::vector<int> cindex(nv, -1);
  for (std::size_t i = 0; i < constrained.size(); ++i) {
    const int v = constrained[i];
    if (v < 0 || v >= nv) throw core::InvalidInputError("harmonic field: vertex " + std::to_string(v) + " out of range");
    if (cindex[v] >= 0) throw core::InvalidInputError("harmonic field: vertex " + std::to_string(v) + " is constrained twice");
    cindex[v] = static_cast<int>(i);
  }
  impl_->constrained = constrained;
  impl_->free_index.assign(nv, -1);
  int nf = 0;
  for (int v = 0; v < nv; ++v)
    if (cindex[v] < 0) impl_->free_index[v] = nf++;
  const auto w = cotangent_weights(mesh);
  std::vector<Eigen::Triplet<double>> lap, cpl;
  std::vector<double> diag(nf, 0.0);
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    const int a = static_cast<int>(mesh.source(h)), b = static_cast<int>(mesh.target(h));
    for (auto [p, q] : {std::pair{a, b}, std::pair{b, a}}) {
      const int fp = impl_->free_index[p];
      if (fp < 0) continue;
      diag[fp] += w[e];
      if (impl_->free_index[q] >= 0) lap.emplace_back(fp, impl_->free_index[q], -w[e]);
      else cpl.emplace_back(fp, cindex[q], w[e]);
    }
  }
  for (int i = 0; i < nf; ++i) lap.emplace_back(i, i, diag[i]);
  Eigen::SparseMatrix<double> L(nf, nf);
  L.setFromTriplets(lap.begin(), lap.end());
  impl_->coupling.resize(nf, static_cast<int>(constrained.size()));
  impl_->coupling.setFromTriplets(cpl.begin(), cpl.end());
  if (nf > 0) {
    impl_->ldlt.compute(L);
    if (impl_->ldlt.info() != Eigen::Success)
      throw core::NumericalError("harmonic field: Cholesky factorization of the cotangent Laplacian failed");
  }
}

HarmonicSolver::~HarmonicSolver() = default;
HarmonicSolver::HarmonicSolver(HarmonicSolver&&) noexcept = default;

std::vector<double> HarmonicSolver::solve(const std::vector<double>& values) const {
  if (values.size() != impl_->constrained.size())
    throw core::InvalidInputError("harmonic field: " + std::to_string(values.size()) + " values for " +
                                  std::to_string(impl_->constrained.size()) + " constrained vertices");
  const Eigen::VectorXd c = Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  std::vector<double> f(impl_->free_index.size());
  for (std::size_t i = 0; i < impl_->constrained.size(); ++i) f[impl_->constrained[i]] = values[i];
  if (impl_->coupling.rows() > 0) {
    const Eigen::VectorXd x = impl_->ldlt.solve(impl_->coupling * c);
    if (impl_->ldlt.info() != Eigen::Success) throw core::NumericalError("harmonic field: solve failed");
    for (std::size_t v = 0; v < f.size(); ++v)
      if (impl_->free_index[v] >= 0) f[v] = x[impl_->free_index[v]];
  }
  return f;
}

std::vector<double> harmonic_field(const Mesh& mesh, const std::vector<Constraint>& constraints) {
  std::vector<int> vs;
  std::vector<double> vals;
  for (const auto& c : constraints) vs.push_back(c.vertex), vals.push_back(c.value);
  return HarmonicSolver(mesh, vs).solve(vals);
}

std::vector<double> periodic_harmonic_field(const Mesh& mesh, const std::vector<int>& cut, const std::vector<Constraint>& constraints) {
  const int nv = static_cast<int>(mesh.number_of_vertices());
  const int n = static_cast<int>(cut.size());
  if (n < 3) throw core::InvalidInputError("periodic harmonic field: a cut loop needs at least 3 vertices");
  std::vector<int> pos(nv, -1);
  for (int i = 0; i < n; ++i) {
    if (cut[i] < 0 || cut[i] >= nv) throw core::InvalidInputError("periodic harmonic field: cut vertex out of range");
    if (pos[cut[i]] >= 0) throw core::InvalidInputError("periodic harmonic field: the cut passes twice through vertex " + std::to_string(cut[i]));
    pos[cut[i]] = i;
  }
  using VI = Mesh::Vertex_index;
  // shift[h] = 1 for the halfedges leaving a cut vertex into its right-hand fan: the values of
  // the cut vertex seen from that side are one period higher.
  std::vector<char> right(mesh.number_of_halfedges(), 0);
  for (int i = 0; i < n; ++i) {
    const VI c(cut[i]), next(cut[(i + 1) % n]), prev(cut[(i + n - 1) % n]);
    const auto hn = mesh.halfedge(c, next), hp = mesh.halfedge(c, prev);
    if (hn == Mesh::null_halfedge() || hp == Mesh::null_halfedge())
      throw core::InvalidInputError("periodic harmonic field: consecutive cut vertices " + std::to_string(cut[i]) +
                                    " and " + std::to_string(cut[(i + 1) % n]) + " are not joined by an edge");
    for (auto h = mesh.opposite(mesh.prev(hn)); h != hp; h = mesh.opposite(mesh.prev(h))) right[h] = 1;
  }
  const auto w = cotangent_weights(mesh);
  // Minimize sum_e w_e (u_b + s_b - u_a - s_a)^2, s = the shift of each end on that edge; u_pin = 0
  // without constraints, else the constrained values (Dirichlet rows).
  std::vector<double> fixed(nv, std::numeric_limits<double>::quiet_NaN());
  for (const auto& c : constraints) {
    if (c.vertex < 0 || c.vertex >= nv) throw core::InvalidInputError("periodic harmonic field: constrained vertex out of range");
    if (pos[c.vertex] >= 0) throw core::InvalidInputError("periodic harmonic field: vertex " + std::to_string(c.vertex) + " is on the cut and constrained");
    if (!std::isnan(fixed[c.vertex])) throw core::InvalidInputError("periodic harmonic field: vertex " + std::to_string(c.vertex) + " is constrained twice");
    fixed[c.vertex] = c.value;
  }
  const int pin = 0;
  if (constraints.empty()) fixed[pin] = 0.0;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nv);
  std::vector<double> diag(nv, 0.0);
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e), g = mesh.opposite(h);
    const int a = static_cast<int>(mesh.source(h)), b = static_cast<int>(mesh.target(h));
    const double t = static_cast<double>(right[g]) - static_cast<double>(right[h]);  // s_b - s_a
    diag[a] += w[e], diag[b] += w[e];
    trip.emplace_back(a, b, -w[e]);
    trip.emplace_back(b, a, -w[e]);
    rhs[a] += w[e] * t;
    rhs[b] -= w[e] * t;
  }
  for (int v = 0; v < nv; ++v) trip.emplace_back(v, v, diag[v]);
  // Fixed vertices: rows and columns replaced by the identity, their columns moved to the right.
  std::vector<Eigen::Triplet<double>> kept;
  for (const auto& tr : trip) {
    const bool row_fixed = !std::isnan(fixed[tr.row()]), col_fixed = !std::isnan(fixed[tr.col()]);
    if (!row_fixed && !col_fixed) kept.push_back(tr);
    else if (!row_fixed) rhs[tr.row()] -= tr.value() * fixed[tr.col()];
  }
  for (int v = 0; v < nv; ++v)
    if (!std::isnan(fixed[v])) kept.emplace_back(v, v, 1.0), rhs[v] = fixed[v];
  Eigen::SparseMatrix<double> L(nv, nv);
  L.setFromTriplets(kept.begin(), kept.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(L);
  if (ldlt.info() != Eigen::Success) throw core::NumericalError("periodic harmonic field: factorization failed");
  const Eigen::VectorXd u = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !u.allFinite()) throw core::NumericalError("periodic harmonic field: solve failed");
  std::vector<double> out(nv);
  double spread = 0;
  for (int v = 0; v < nv; ++v) {
    out[v] = u[v] - std::floor(u[v]);
    spread = std::max(spread, std::abs(circle_difference(out[v], out[pin], 1.0)));
  }
  for (const auto& c : constraints) out[c.vertex] = c.value - std::floor(c.value);  // exactly, for level sets through them
  if (spread < 1e-6) throw core::TopologyError("periodic harmonic field: the cut loop separates the surface (no period around it)");
  return out;
}

int CriticalPoints::saddle_count() const {
  int n = 0;
  for (const auto& s : saddles) n += s.second;
  return n;
}

CriticalPoints critical_points(const Mesh& mesh, const std::vector<double>& f) {
  if (f.size() != mesh.number_of_vertices()) throw core::InvalidInputError("critical points: field size does not match the mesh");
  CriticalPoints cp;
  for (auto v : mesh.vertices()) {
    const int vi = static_cast<int>(v);
    int changes = 0, above = 0, n = 0;
    bool first = true, first_up = false, prev_up = false;
    for (auto h : CGAL::halfedges_around_source(v, mesh)) {  // the link, in cyclic order
      const bool up = less(f, vi, static_cast<int>(mesh.target(h)));
      if (first) first_up = up, first = false;
      else changes += (up != prev_up);
      prev_up = up;
      above += up;
      ++n;
    }
    changes += (prev_up != first_up);
    if (changes == 0) (above == n ? cp.minima : cp.maxima).push_back(vi);
    else if (changes >= 4) cp.saddles.push_back({vi, changes / 2 - 1});
  }
  return cp;
}

}  // namespace volts::split
