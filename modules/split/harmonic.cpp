#include "split/harmonic.h"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <map>

#include "core/errors.h"

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
