// Liu et al. 2013 §4.3 volume map: TetGen tets, chord splitting, harmonic map, untangling (single-vertex
// LPs, then a joint foldover-free energy of Garanzha et al. 2021 if needed).
#include "volmap/volmap.h"
#include "volmap/foldover_energy.h"
#include "volmap/repair.h"

#include <nlopt.hpp>

#include <Eigen/Sparse>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "core/errors.h"
#include "core/log.h"

namespace volts::volmap {
namespace {

using Vec = Eigen::Vector3d;
using Tet = std::array<int, 4>;

void check(const surface::Mesh& surface, const std::vector<std::array<double, 3>>& sp, const Params& p) {
  if (p.laplacian != "cotangent" && p.laplacian != "uniform")
    throw core::ConfigError("volmap laplacian must be \"cotangent\" or \"uniform\", not \"" + p.laplacian + "\"");
  if (p.untangle_max_sweeps < 0 || p.untangle_max_sweeps > 100000)
    throw core::ConfigError("volmap untangle_max_sweeps must be in [0, 100000]");
  if (!(p.untangle_min_volume_rel >= 0 && p.untangle_min_volume_rel < 1))
    throw core::ConfigError("volmap untangle_min_volume_rel must be in [0, 1)");
  if (!(p.smooth_below_ratio >= 0 && p.smooth_below_ratio <= 1) || p.smooth_sweeps < 0 || p.smooth_sweeps > 10000)
    throw core::ConfigError("volmap smooth_below_ratio must be in [0, 1] and smooth_sweeps in [0, 10000]");
  if (!p.tetgen.keep_boundary)
    throw core::ConfigError("volmap needs tetgen keep_boundary = true: the boundary condition is given per surface vertex");
  if (surface.has_garbage())
    throw core::InvalidInputError("volmap: the surface has removed vertices or faces (collect_garbage first)");
  if (sp.size() != surface.number_of_vertices())
    throw core::InvalidInputError("volmap: surface_parameter has " + std::to_string(sp.size()) + " entries for " +
                                  std::to_string(surface.number_of_vertices()) + " surface vertices");
  for (std::size_t i = 0; i < sp.size(); ++i)
    if (!(std::isfinite(sp[i][0]) && std::isfinite(sp[i][1]) && std::isfinite(sp[i][2])))
      throw core::InvalidInputError("volmap: surface_parameter[" + std::to_string(i) + "] is not finite");
}

// Vertex -> incident tets, kept up to date by the splits.
struct Incidence {
  std::vector<std::vector<int>> of;
  void add(int t, const Tet& tet) {
    for (int v : tet) of[v].push_back(t);
  }
  void remove(int t, int v) { of[v].erase(std::find(of[v].begin(), of[v].end(), t)); }
  std::vector<int> sharing(const std::vector<int>& vs) const {
    std::vector<int> r = of[vs[0]];
    std::sort(r.begin(), r.end());
    for (std::size_t k = 1; k < vs.size(); ++k) {
      std::vector<int> o = of[vs[k]], x;
      std::sort(o.begin(), o.end());
      std::set_intersection(r.begin(), r.end(), o.begin(), o.end(), std::back_inserter(x));
      r.swap(x);
    }
    return r;
  }
};

// Inserts point m on the simplex `vs` (an edge or a face): every tet containing it becomes one tet
// per vertex of `vs`, with that vertex replaced by m (orientation kept: m lies on the simplex).
void split_simplex(VolumeMap& vm, Incidence& inc, const std::vector<int>& vs, const Vec& m) {
  const int mid = static_cast<int>(vm.physical.size());
  vm.physical.push_back(m);
  inc.of.emplace_back();
  for (int t : inc.sharing(vs)) {
    const Tet old = vm.tets[t];
    for (std::size_t k = 0; k < vs.size(); ++k) {
      Tet nt = old;
      *std::find(nt.begin(), nt.end(), vs[k]) = mid;
      if (k == 0) {
        vm.tets[t] = nt;
        inc.remove(t, vs[0]);
        inc.of[mid].push_back(t);
      } else {
        vm.tets.push_back(nt);
        inc.add(static_cast<int>(vm.tets.size()) - 1, nt);
      }
    }
  }
}

// An interior edge or face whose vertices are all on the surface is a chord of the solid; in a
// polycube it would run along a face or outside a concave edge, so its tets could not all stay
// positive. Splitting gives each such simplex a free vertex.
void split_chords(VolumeMap& vm, const surface::Mesh& surface) {
  const int n = vm.surface_vertices;
  std::set<std::pair<int, int>> surface_edges;
  for (auto e : surface.edges()) {
    int a = surface.vertex(e, 0), b = surface.vertex(e, 1);
    surface_edges.insert({std::min(a, b), std::max(a, b)});
  }
  Incidence inc;
  inc.of.resize(vm.physical.size());
  for (int t = 0; t < static_cast<int>(vm.tets.size()); ++t) inc.add(t, vm.tets[t]);

  std::set<std::pair<int, int>> chords;
  for (const Tet& t : vm.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const int a = std::min(t[i], t[j]), b = std::max(t[i], t[j]);
        if (b < n && !surface_edges.count({a, b})) chords.insert({a, b});
      }
  for (const auto& [a, b] : chords) split_simplex(vm, inc, {a, b}, 0.5 * (vm.physical[a] + vm.physical[b]));
  vm.split_edges = static_cast<int>(chords.size());

  std::set<std::array<int, 3>> surface_faces;
  for (auto f : surface.faces()) {
    std::array<int, 3> k;
    int m = 0;
    for (auto v : vertices_around_face(surface.halfedge(f), surface)) k[m++] = v;
    std::sort(k.begin(), k.end());
    surface_faces.insert(k);
  }
  std::set<std::array<int, 3>> faces;
  for (const Tet& t : vm.tets)
    for (const auto& f : tetmesh::kOutwardFace) {
      std::array<int, 3> k{t[f[0]], t[f[1]], t[f[2]]};
      std::sort(k.begin(), k.end());
      if (k[2] < n && !surface_faces.count(k)) faces.insert(k);
    }
  for (const auto& k : faces)
    split_simplex(vm, inc, {k[0], k[1], k[2]}, (vm.physical[k[0]] + vm.physical[k[1]] + vm.physical[k[2]]) / 3.0);
  vm.split_faces = static_cast<int>(faces.size());
}

// Harmonic map with the surface vertices fixed: K_II x_I = -K_IB x_B, K the Laplacian.
void harmonic(VolumeMap& vm, const std::string& laplacian) {
  const int np = static_cast<int>(vm.physical.size()), n = vm.surface_vertices, ni = np - n;
  if (ni == 0) return;
  std::vector<Eigen::Triplet<double>> trip;
  if (laplacian == "cotangent") {
    // P1 stiffness: K_ij = sum over tets of vol * grad(lambda_i) . grad(lambda_j) (the cotangent formula).
    for (const Tet& t : vm.tets) {
      Eigen::Matrix3d E;
      for (int j = 0; j < 3; ++j) E.col(j) = vm.physical[t[j + 1]] - vm.physical[t[0]];
      const double vol = E.determinant() / 6;
      const Eigen::Matrix3d Ei = E.inverse();  // rows: gradients of lambda_1..3
      Eigen::Matrix<double, 4, 3> G;
      G.row(0) = -(Ei.row(0) + Ei.row(1) + Ei.row(2));
      G.bottomRows(3) = Ei;
      const Eigen::Matrix4d Kt = vol * G * G.transpose();
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) trip.emplace_back(t[a], t[b], Kt(a, b));
    }
  } else {
    std::set<std::pair<int, int>> edges;
    for (const Tet& t : vm.tets)
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) edges.insert({std::min(t[a], t[b]), std::max(t[a], t[b])});
    for (const auto& [a, b] : edges) {
      trip.emplace_back(a, b, -1.0), trip.emplace_back(b, a, -1.0);
      trip.emplace_back(a, a, 1.0), trip.emplace_back(b, b, 1.0);
    }
  }
  Eigen::SparseMatrix<double> K(np, np);
  K.setFromTriplets(trip.begin(), trip.end());
  const Eigen::SparseMatrix<double> KII = K.bottomRightCorner(ni, ni), KIB = K.bottomLeftCorner(ni, n);
  Eigen::MatrixXd xb(n, 3);
  for (int i = 0; i < n; ++i) xb.row(i) = vm.parameter[i].transpose();
  const Eigen::MatrixXd rhs = -(KIB * xb);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(KII);
  if (solver.info() != Eigen::Success) throw core::NumericalError("volmap: the Laplacian could not be factorized");
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) throw core::NumericalError("volmap: the harmonic map solve failed");
  for (int i = 0; i < ni; ++i) vm.parameter[n + i] = x.row(i).transpose();
}

double volume6(const std::vector<Vec>& p, const Tet& t) { return tetmesh::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]); }

// 6 × volume of tet t as a function of the position x of its local vertex j: g . x + h.
void linear_volume(const std::vector<Vec>& p, const Tet& t, int j, Vec& g, double& h) {
  const auto& f = tetmesh::kOutwardFace[j];
  const Vec &a = p[t[f[0]]], &b = p[t[f[1]]], &c = p[t[f[2]]];
  const Vec nout = (b - a).cross(c - a);  // outward for a positive tet: x on the inner side gives > 0
  g = -nout;
  h = nout.dot(a);
}

struct LpData {
  std::vector<Vec> b;  // scaled gradients
  std::vector<double> a;
};

// Constraints t - a_k - b_k . y <= 0 for the unknowns (y, t).
void lp_constraints(unsigned m, double* result, unsigned nv, const double* x, double* grad, void* data) {
  const auto* d = static_cast<const LpData*>(data);
  for (unsigned k = 0; k < m; ++k) {
    result[k] = x[3] - d->a[k] - d->b[k].dot(Vec(x[0], x[1], x[2]));
    if (grad) {
      for (int i = 0; i < 3; ++i) grad[k * nv + i] = -d->b[k][i];
      grad[k * nv + 3] = 1.0;
    }
  }
}

double lp_objective(unsigned, const double* x, double* grad, void*) {
  if (grad) grad[0] = grad[1] = grad[2] = 0, grad[3] = -1;
  return -x[3];
}

// Moves free vertex v to maximize the smallest 6×volume of its tets (parameter space); returns
// whether it moved (only if that smallest volume grows).
bool optimize_vertex(VolumeMap& vm, const std::vector<int>& tets_of_v, const std::vector<std::vector<int>>& nbrs, int v) {
  auto& p = vm.parameter;
  const Vec x0 = p[v];
  double scale = 0;
  Vec lo = x0, hi = x0;
  for (int u : nbrs[v]) {
    scale += (p[u] - x0).norm();
    lo = lo.cwiseMin(p[u]), hi = hi.cwiseMax(p[u]);
  }
  scale /= std::max<std::size_t>(1, nbrs[v].size());
  if (!(scale > 0)) return false;
  LpData d;
  double m0 = HUGE_VAL;
  for (int t : tets_of_v) {
    const Tet& tet = vm.tets[t];
    const int j = static_cast<int>(std::find(tet.begin(), tet.end(), v) - tet.begin());
    Vec g;
    double h;
    linear_volume(p, tet, j, g, h);
    const double v0 = g.dot(x0) + h;
    m0 = std::min(m0, v0);
    d.a.push_back(v0 / (scale * scale * scale));
    d.b.push_back(g / (scale * scale));
  }
  const unsigned m = static_cast<unsigned>(d.a.size());
  nlopt::opt opt(nlopt::LD_SLSQP, 4);
  std::vector<double> lb(4), ub(4);
  for (int i = 0; i < 3; ++i) lb[i] = (lo[i] - x0[i]) / scale, ub[i] = (hi[i] - x0[i]) / scale;
  const double t0 = m0 / (scale * scale * scale);
  lb[3] = t0 - 1, ub[3] = HUGE_VAL;
  opt.set_lower_bounds(lb);
  opt.set_upper_bounds(ub);
  opt.set_min_objective(lp_objective, nullptr);
  opt.add_inequality_mconstraint(lp_constraints, &d, std::vector<double>(m, 1e-14));
  opt.set_xtol_abs(1e-10);
  opt.set_maxeval(200);
  std::vector<double> y{0, 0, 0, t0};
  double f = 0;
  try {
    opt.optimize(y, f);
  } catch (const std::exception&) {
    // Round-off or iteration limits: y still holds the last iterate, judged below like any other.
  }
  const Vec x1 = x0 + scale * Vec(y[0], y[1], y[2]);
  if (!x1.allFinite()) return false;
  p[v] = x1;
  double m1 = HUGE_VAL;
  for (int t : tets_of_v) m1 = std::min(m1, volume6(p, vm.tets[t]));
  if (m1 > m0) return true;
  p[v] = x0;
  return false;
}

// Fallback when single-vertex moves stall (a tangle that needs several vertices to move together):
// the free vertices within a few rings of the inverted tets minimize the regularized foldover-free
// energy of Garanzha et al. 2021 ("Foldover-free maps in 50 lines of code"), jointly, by L-BFGS
// (NLopt), with the regularization eps lowered until every tet is positive.
struct GlobalData {
  VolumeMap* vm;
  std::vector<int> vars;                // vertex of each variable block (3 doubles)
  std::vector<int> var_of;              // vertex -> variable block or -1
  std::vector<int> tets;                // tets touching a variable vertex
  std::vector<Eigen::Matrix3d> s_inv;   // per tet in `tets`: (physical shape matrix)^-1 * scale
  std::vector<double> weight;           // per tet: physical volume
  std::vector<Vec> origin;              // per variable block: its position at the start
  std::vector<double> unit;             // per variable block: position = origin + unit * x
  double eps = 1;
  double det_min = 0;
};

// Gradient of a tet's energy in its 4 vertices' parameter positions, from dE/dJ (P = edge matrix).
std::array<Vec, 4> vertex_gradients(const Eigen::Matrix3d& dJ, const Eigen::Matrix3d& s_inv, double weight) {
  const Eigen::Matrix3d dP = weight * dJ * s_inv.transpose();
  return {Vec(-dP.col(0) - dP.col(1) - dP.col(2)), Vec(dP.col(0)), Vec(dP.col(1)), Vec(dP.col(2))};
}

Eigen::Matrix3d tet_jacobian(const std::vector<Vec>& p, const Tet& t, const Eigen::Matrix3d& s_inv) {
  Eigen::Matrix3d P;
  for (int j = 0; j < 3; ++j) P.col(j) = p[t[j + 1]] - p[t[0]];
  return P * s_inv;
}

double global_energy(unsigned nx, const double* x, double* grad, void* data) {
  auto* d = static_cast<GlobalData*>(data);
  auto& p = d->vm->parameter;
  for (std::size_t k = 0; k < d->vars.size(); ++k) p[d->vars[k]] = d->origin[k] + d->unit[k] * Vec(x[3 * k], x[3 * k + 1], x[3 * k + 2]);
  if (grad) std::fill(grad, grad + nx, 0.0);
  double e = 0;
  d->det_min = HUGE_VAL;
  for (std::size_t i = 0; i < d->tets.size(); ++i) {
    const Tet& t = d->vm->tets[d->tets[i]];
    Eigen::Matrix3d dJ;
    double D = 0;
    e += d->weight[i] * tet_energy(tet_jacobian(p, t, d->s_inv[i]), d->eps, &D, grad ? &dJ : nullptr);
    d->det_min = std::min(d->det_min, D);
    if (!grad) continue;
    const std::array<Vec, 4> g = vertex_gradients(dJ, d->s_inv[i], d->weight[i]);
    for (int j = 0; j < 4; ++j) {
      const int k = d->var_of[t[j]];
      if (k < 0) continue;
      for (int c = 0; c < 3; ++c) grad[3 * k + c] += d->unit[k] * g[j][c];
    }
  }
  return e;
}

// Minimizes the energy over the parameter positions of `active` (free vertices), the others fixed.
// The free (interior) vertices of `tets` and those within `rings` rings of them.
std::set<int> free_vertices_near(const VolumeMap& vm, const std::vector<int>& tets, const std::vector<std::vector<int>>& nbrs, int rings) {
  const int n = vm.surface_vertices;
  std::set<int> active;
  for (int t : tets)
    for (int v : vm.tets[t])
      if (v >= n) active.insert(v);
  for (int r = 0; r < rings; ++r) {
    std::set<int> grown = active;
    for (int v : active)
      for (int u : nbrs[v])
        if (u >= n) grown.insert(u);
    active.swap(grown);
  }
  return active;
}

void minimize_energy(VolumeMap& vm, const std::set<int>& active, const std::vector<std::vector<int>>& tets_of, int max_rounds) {
  if (active.empty()) return;
  GlobalData d;
  d.vm = &vm;
  d.var_of.assign(vm.parameter.size(), -1);
  std::set<int> tets;
  for (int v : active) {
    d.var_of[v] = static_cast<int>(d.vars.size());
    d.vars.push_back(v);
    tets.insert(tets_of[v].begin(), tets_of[v].end());
  }
  d.tets.assign(tets.begin(), tets.end());
  // J is scaled so that det J averages 1 over the whole map (the volume term prefers det J = 1).
  double phys = 0;
  for (const Tet& t : vm.tets) phys += volume6(vm.physical, t) / 6;
  const double scale = std::cbrt(phys / vm.parameter_volume);
  for (int t : d.tets) {
    Eigen::Matrix3d S;
    for (int j = 0; j < 3; ++j) S.col(j) = vm.physical[vm.tets[t][j + 1]] - vm.physical[vm.tets[t][0]];
    d.s_inv.push_back(S.inverse() * scale);
    d.weight.push_back(S.determinant() / 6);
  }
  // Variables scaled per vertex by 1/sqrt of the energy's stiffness there (Jacobi): sliver tets
  // make some vertices ~1e8 times stiffer than others, and unscaled, L-BFGS's line search failed
  // at its first step (measured on the washer).
  std::vector<double> stiff(d.vars.size(), 0.0);
  for (std::size_t i = 0; i < d.tets.size(); ++i) {
    const Tet& t = vm.tets[d.tets[i]];
    for (int j = 0; j < 4; ++j) {
      const int k = d.var_of[t[j]];
      if (k < 0) continue;
      const Vec row = j == 0 ? Vec(-(d.s_inv[i].row(0) + d.s_inv[i].row(1) + d.s_inv[i].row(2)).transpose())
                             : Vec(d.s_inv[i].row(j - 1).transpose());
      stiff[k] += d.weight[i] * row.squaredNorm();
    }
  }
  for (std::size_t k = 0; k < d.vars.size(); ++k) {
    d.origin.push_back(vm.parameter[d.vars[k]]);
    d.unit.push_back(stiff[k] > 0 ? 1 / std::sqrt(stiff[k]) : 1.0);
  }
  std::vector<double> x(3 * d.vars.size(), 0.0);
  global_energy(static_cast<unsigned>(x.size()), x.data(), nullptr, &d);
  // Where no positive map exists (a connectivity the fixed surface forbids), det_min creeps toward
  // 0 and then the tiny eps lets L-BFGS diverge (measured: -3e-4, then -1e32): if the last round is
  // not positive, the best one is kept; 30 rounds without a better one end it (on the eight det_min
  // falls for a few rounds before it turns positive).
  std::vector<double> best_x = x;  // of the rounds (the first rounds' large eps may lower det_min at first)
  double best_det = -HUGE_VAL;
  int since_best = 0;
  double e_prev = HUGE_VAL;
  for (int round = 0; round < max_rounds && since_best < 30; ++round) {
    // eps update of Garanzha et al.: small enough to make inverted tets expensive, never 0. Each
    // round lowers it by at least a fifth (their sigma 0.1 took the eight's rings ~40 rounds of
    // ~100 evaluations each) and stops at a relative energy change of 1e-6: the rounds only need to
    // end positive, smooth_map shapes the map after them (its min volume ratio measured the same).
    const double mu = 0.8 * (d.det_min + std::sqrt(d.eps * d.eps + d.det_min * d.det_min)) / 2;
    d.eps = d.det_min < mu ? std::max(1e-12, 2 * std::sqrt(mu * (mu - d.det_min))) : 1e-12;
    nlopt::opt opt(nlopt::LD_LBFGS, static_cast<unsigned>(x.size()));
    opt.set_min_objective(global_energy, &d);
    opt.set_maxeval(300);
    opt.set_ftol_rel(1e-6);
    double e = 0;
    try {
      opt.optimize(x, e);
    } catch (const std::exception&) {
      // Round-off limited: x holds the last iterate.
    }
    e = global_energy(static_cast<unsigned>(x.size()), x.data(), nullptr, &d);
    if (d.det_min > best_det) {
      best_det = d.det_min, best_x = x, since_best = 0;
    } else {
      ++since_best;
    }
    if (d.det_min > 0 && std::abs(e_prev - e) < 1e-6 * std::abs(e)) break;
    e_prev = e;
  }
  if (!(d.det_min > 0)) global_energy(static_cast<unsigned>(best_x.size()), best_x.data(), nullptr, &d);  // writes the best positions
}

void untangle_jointly(VolumeMap& vm, const std::vector<std::vector<int>>& nbrs, const std::vector<std::vector<int>>& tets_of,
                      int rings, int max_rounds) {
  std::vector<int> inverted;
  for (int t = 0; t < static_cast<int>(vm.tets.size()); ++t)
    if (!(volume6(vm.parameter, vm.tets[t]) > 0)) inverted.push_back(t);
  minimize_energy(vm, free_vertices_near(vm, inverted, nbrs, rings), tets_of, max_rounds);
}

// After untangling, a map that is positive but nearly degenerate somewhere (the untangler only lifts
// tets out of inversion, by default; measured min volume ratio 1e-8 on the eight and the washer)
// makes the T-mesh sampled from it fold. Each interior vertex in turn descends the energy of its
// tets with eps = 0 (a barrier at det J = 0): Newton steps (steepest descent where the Hessian is
// not positive) with backtracking that never lets a tet reach det J <= 0. Per vertex, not jointly: on sliver reference shapes NLopt's joint L-BFGS
// failed at its first line search (measured on the eight), a per-vertex search cannot.
// Returns the sweeps run.
int smooth_map(VolumeMap& vm, const std::vector<std::vector<int>>& tets_of, int sweeps) {
  double phys = 0;
  for (const Tet& t : vm.tets) phys += volume6(vm.physical, t) / 6;
  const double scale = std::cbrt(phys / vm.parameter_volume);  // det J averages 1, as in minimize_energy
  std::vector<Eigen::Matrix3d> s_inv(vm.tets.size());
  std::vector<double> weight(vm.tets.size());
  for (std::size_t t = 0; t < vm.tets.size(); ++t) {
    Eigen::Matrix3d S;
    for (int j = 0; j < 3; ++j) S.col(j) = vm.physical[vm.tets[t][j + 1]] - vm.physical[vm.tets[t][0]];
    s_inv[t] = S.inverse() * scale;
    weight[t] = S.determinant() / 6;
  }
  auto& p = vm.parameter;
  // Energy of v's tets, its gradient and Hessian in v; +inf if a tet is not positive.
  const auto local = [&](int v, Vec* g, Eigen::Matrix3d* H) {
    double e = 0;
    if (g) g->setZero();
    if (H) H->setZero();
    for (int t : tets_of[v]) {
      const Tet& tet = vm.tets[t];
      const Eigen::Matrix3d& S = s_inv[t];
      // J = P S with P's columns p_j - p_0: v's row of the shape gradients.
      const Vec row = tet[0] == v ? Vec(-(S.row(0) + S.row(1) + S.row(2)).transpose())
                                  : Vec(S.row(tet[1] == v ? 0 : tet[2] == v ? 1 : 2).transpose());
      double D = 0;
      Vec gt;
      Eigen::Matrix3d Ht;
      const double f = vertex_energy(tet_jacobian(p, tet, S), row, 0.0, &D, g ? &gt : nullptr, H ? &Ht : nullptr);
      if (!(D > 0)) return HUGE_VAL;
      e += weight[t] * f;
      if (g) *g += weight[t] * gt;
      if (H) *H += weight[t] * Ht;
    }
    return e;
  };
  double total = 0;  // the energy of the whole map, for the stopping rule
  for (std::size_t t = 0; t < vm.tets.size(); ++t) {
    double D = 0;
    total += weight[t] * tet_energy(tet_jacobian(p, vm.tets[t], s_inv[t]), 0.0, &D, nullptr);
  }
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    double decrease = 0;
    for (int v = vm.surface_vertices; v < static_cast<int>(p.size()); ++v) {
      for (int it = 0; it < 8; ++it) {
        Vec g;
        Eigen::Matrix3d H;
        const double e0 = local(v, &g, &H);
        if (!std::isfinite(e0) || g.squaredNorm() == 0) break;
        double h = HUGE_VAL;  // the step is at most half the shortest edge at v (parameter space)
        for (int t : tets_of[v])
          for (int u : vm.tets[t])
            if (u != v) h = std::min(h, (p[u] - p[v]).norm());
        const Vec x0 = p[v];
        // Newton's direction (the Hessian in closed form, foldover_energy.h) where it descends,
        // else the gradient's: sliver tets make the vertex's energy badly scaled, and steepest
        // descent crawled (300 sweeps, 18 s on the eight's first ring).
        Vec dir = -g.normalized();
        double first = 0.5 * h;
        const Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
        if (H.allFinite() && ldlt.info() == Eigen::Success && ldlt.isPositive() && (ldlt.vectorD().array() > 0).all()) {
          const Vec d = ldlt.solve(-g);
          if (d.allFinite() && d.dot(g) < 0 && d.norm() > 0) dir = d.normalized(), first = std::min(d.norm(), 0.5 * h);
        }
        bool moved = false;
        for (double step = first; step > 1e-6 * h; step *= 0.5) {
          p[v] = x0 + step * dir;
          const double e1 = local(v, nullptr, nullptr);
          if (e1 < e0 - 1e-4 * step * std::abs(g.dot(dir))) {
            moved = true;
            decrease += e0 - e1;
            break;
          }
        }
        if (!moved) {
          p[v] = x0;
          break;
        }
      }
    }
    total -= decrease;
    if (decrease < 1e-5 * total) return sweep + 1;  // converged: later sweeps would not change the T-mesh
  }
  return sweeps;
}

std::vector<std::vector<int>> tets_of_points(const VolumeMap& vm) {
  std::vector<std::vector<int>> tets_of(vm.parameter.size());
  for (int t = 0; t < static_cast<int>(vm.tets.size()); ++t)
    for (int v : vm.tets[t]) tets_of[v].push_back(t);
  return tets_of;
}

void untangle(VolumeMap& vm, const Params& params) {
  const int np = static_cast<int>(vm.parameter.size());
  const int nt = static_cast<int>(vm.tets.size());
  std::vector<std::vector<int>> tets_of(np), nbrs(np);
  for (int t = 0; t < nt; ++t)
    for (int a = 0; a < 4; ++a) {
      tets_of[vm.tets[t][a]].push_back(t);
      for (int b = 0; b < 4; ++b)
        if (a != b) nbrs[vm.tets[t][a]].push_back(vm.tets[t][b]);
    }
  for (auto& l : nbrs) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  // 6 × target volume; the total parameter volume does not change when interior points move.
  const double target6 = params.untangle_min_volume_rel * 6 * vm.parameter_volume / nt;
  const auto bad_tets = [&] {
    std::vector<int> b;
    for (int t = 0; t < nt; ++t)
      if (!(volume6(vm.parameter, vm.tets[t]) > target6)) b.push_back(t);
    return b;
  };
  // Gauss-Seidel sweeps of single-vertex moves over the free vertices near bad tets.
  const int budget_end = vm.untangle_sweeps + params.untangle_max_sweeps;  // per call
  const auto sweeps = [&] {
    std::vector<int> bad = bad_tets();
    int stalled = 0;
    int ring = 0;  // grown when a sweep makes no progress: a tangle may need its neighbours to move
    double worst = HUGE_VAL;
    for (int t : bad) worst = std::min(worst, volume6(vm.parameter, vm.tets[t]));
    if (bad.empty()) return;
    // Progress is measured against the best sweep so far, not the last one: sweeps can trade bad
    // tets back and forth (3 -> 4 -> 3 ...), which took the eight's second ring to the sweep bound.
    std::size_t best_count = bad.size();
    double best_worst = worst;
    vm.untangle_stop = "done";
    while (vm.untangle_sweeps < budget_end && !bad.empty()) {
      for (int v : free_vertices_near(vm, bad, nbrs, ring)) vm.untangle_moves += optimize_vertex(vm, tets_of[v], nbrs, v);
      ++vm.untangle_sweeps;
      const std::vector<int> now = bad_tets();
      double w = HUGE_VAL;
      for (int t : now) w = std::min(w, volume6(vm.parameter, vm.tets[t]));
      const bool progress = now.size() < best_count || (now.size() == best_count && w > best_worst + 1e-6 * std::abs(best_worst));
      if (progress) best_count = now.size(), best_worst = w;
      ring = progress ? 0 : std::min(ring + 1, 6);
      stalled = progress ? 0 : stalled + 1;
      bad = now;
      // Stalled once the largest neighbourhood (6 rings, reached at the 6th sweep without
      // progress) has not helped either; the joint pass takes over (12 such sweeps were 40 % of
      // the eight's untangling and never made progress there).
      if (stalled > 6) {
        vm.untangle_stop = "stalled";
        return;
      }
    }
    if (!bad.empty()) vm.untangle_stop = "sweep_bound";
  };
  sweeps();
  const auto flipped = [&] {
    int c = 0;
    for (int t = 0; t < nt; ++t) c += !(volume6(vm.parameter, vm.tets[t]) > 0);
    return c;
  };
  if (flipped() > 0 && params.untangle_max_sweeps > 0) {
    untangle_jointly(vm, nbrs, tets_of, 3, 300);
    vm.untangle_joint = true;
    sweeps();  // lifts the tets the joint pass left below the target
  }
}

}  // namespace

// Rounds of collapse + untangling while tets stay flat or inverted.
constexpr int kCollapseRounds = 4;

double parameter_volume(const VolumeMap& map, int t) { return volume6(map.parameter, map.tets[t]) / 6; }

VolumeMap harmonic_volume_map(const surface::Mesh& surface, const std::vector<std::array<double, 3>>& sp, const Params& params) {
  check(surface, sp, params);
  VolumeMap vm;
  vm.surface_vertices = static_cast<int>(surface.number_of_vertices());
  const int n = vm.surface_vertices;
  // Orientation of the boundary condition: the mapped surface must enclose a positive volume.
  double vol6 = 0;
  for (auto f : surface.faces()) {
    std::array<Vec, 3> q;
    int k = 0;
    for (auto v : vertices_around_face(surface.halfedge(f), surface)) {
      const auto& s = sp[static_cast<int>(v)];
      q[k++] = Vec(s[0], s[1], s[2]);
    }
    vol6 += q[0].dot(q[1].cross(q[2]));
  }
  if (!(vol6 > 0))
    throw core::InvalidInputError("volmap: surface_parameter maps the surface onto a region of volume " +
                                  std::to_string(vol6 / 6) + " (must be > 0: mirrored or collapsed?)");
  vm.parameter_volume = vol6 / 6;
  {
    core::LogSection s("tetrahedralize (TetGen)");
    tetmesh::TetMesh tm = tetmesh::tetrahedralize(surface, params.tetgen);
    for (const auto& bf : tetmesh::boundary_faces(tm))
      for (int j : tetmesh::kOutwardFace[bf[1]])
        if (tm.tets[bf[0]][j] >= n) throw core::NumericalError("volmap: TetGen put a Steiner point on the surface");
    vm.physical = std::move(tm.points);
    vm.tets = std::move(tm.tets);
    split_chords(vm, surface);
  }
  vm.parameter.assign(vm.physical.size(), Vec::Zero());
  for (int i = 0; i < n; ++i) vm.parameter[i] = Vec(sp[i][0], sp[i][1], sp[i][2]);
  {
    core::LogSection s("harmonic map");
    harmonic(vm, params.laplacian);
  }
  const auto flipped = [&] {
    int c = 0;
    for (const Tet& t : vm.tets) c += !(volume6(vm.parameter, t) > 0);
    return c;
  };
  vm.flipped_tets_before_untangling = flipped();
  {
    core::LogSection s("untangle");
    untangle(vm, params);
    for (int round = 0; round < kCollapseRounds && params.untangle_max_sweeps > 0 && flipped() > 0; ++round) {
      const int c = collapse_flat_tet_edges(vm);
      vm.collapsed_edges += c;
      const int f = flipped() > 0 ? flip_flat_tets(vm) : 0;
      vm.flips += f;
      if (c + f == 0) break;
      vm.untangle_stop = "done";  // unless the run below says otherwise
      untangle(vm, params);       // lifts the tets around the collapsed edges above the target
    }
  }
  vm.flipped_tets = flipped();
  double phys = 0;
  for (const Tet& t : vm.tets) phys += volume6(vm.physical, t) / 6;
  const double to_rel = phys / vm.parameter_volume;  // min_volume_ratio is relative to the mean
  const auto min_ratio = [&] {
    double m = HUGE_VAL;
    for (const Tet& t : vm.tets) m = std::min(m, volume6(vm.parameter, t) / volume6(vm.physical, t));
    return m * to_rel;
  };
  vm.min_volume_ratio = vm.min_volume_ratio_before_smoothing = min_ratio();
  if (vm.flipped_tets == 0 && vm.min_volume_ratio < params.smooth_below_ratio && params.smooth_sweeps > 0) {
    core::LogSection s("smooth");
    vm.smooth_sweeps = smooth_map(vm, tets_of_points(vm), params.smooth_sweeps);
    vm.min_volume_ratio = min_ratio();
    core::log("volmap: min volume ratio " + std::to_string(vm.min_volume_ratio_before_smoothing) + " -> " + std::to_string(vm.min_volume_ratio) +
              " after " + std::to_string(vm.smooth_sweeps) + " sweeps of smoothing" +
              (vm.smooth_sweeps == params.smooth_sweeps ? " (its bound, polycube.smooth_sweeps)" : ""));
  }
  core::log_verbose("volmap: " + std::to_string(vm.tets.size()) + " tets, " + std::to_string(vm.flipped_tets_before_untangling) +
                    " flipped by the harmonic map, " + std::to_string(vm.flipped_tets) + " after untangling");
  return vm;
}

}  // namespace volts::volmap
