#include "fit/gfd.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "bezier/bezier_hex.h"
#include "bezier/bspline.h"
#include "bezier/certify.h"
#include "core/errors.h"
#include "core/log.h"
#include "fit/net.h"
#include "fit/validity.h"
#include "tmesh/pillow.h"

namespace volts::fit {
namespace {

using Eigen::Vector3d;
using Map = std::function<tmesh::Vec3(const tmesh::Vec3&)>;

constexpr double kPi = 3.14159265358979323846;

Vector3d vec(const tmesh::Vec3& x) { return {x[0], x[1], x[2]}; }

struct Ref {
  int block = 0;
  int local = 0;
  std::array<int, 3> ijk{0, 0, 0};
};

// The control points of all solids, each shared point once, and the nets the validity checks see.
struct State {
  const std::vector<tmesh::TMesh>* solids = nullptr;
  int degree = 3;
  std::vector<Vector3d> pos;            // per function id
  std::vector<std::vector<Ref>> refs;   // per function id: every solid holding it
  std::vector<SolidNet> nets;           // per solid
  std::vector<char> all_valid;          // per solid: its net satisfied Proposition 3 initially (then moves keep it)
  std::vector<double> tolerance;        // per such solid: the margin its moves keep (ValidityParams::tolerance)
  double margin_floor = 1e-3;           // GfdParams::min_margin
  const std::function<void(const std::vector<SolidNet>&)>* observer = nullptr;
  // Solids whose net fails Proposition 3: extraction operators per axis and the certified result
  // of every element (index element_index()).
  std::vector<std::array<std::vector<Eigen::MatrixXd>, 3>> extraction;
  std::vector<std::vector<bezier::CertifyResult>> certified;
  bezier::CertifyParams certify;

  void set(int id, const Vector3d& x) {
    pos[static_cast<std::size_t>(id)] = x;
    for (const Ref& r : refs[static_cast<std::size_t>(id)]) nets[static_cast<std::size_t>(r.block)].points[static_cast<std::size_t>(r.local)] = x;
  }
};

State make_state(const std::vector<tmesh::TMesh>& solids) {
  State s;
  s.solids = &solids;
  s.degree = solids.front().degree;
  for (std::size_t b = 0; b < solids.size(); ++b) {
    const auto& t = solids[b];
    if (t.degree != s.degree) throw core::InvalidInputError("fit: solids of mixed degree");
    if (t.function_ids.size() != t.control_points.size()) throw core::InvalidInputError("fit: a solid has no function ids");
    SolidNet net;
    net.size = t.size;
    net.degree = {t.degree, t.degree, t.degree};
    for (std::size_t i = 0; i < t.control_points.size(); ++i) {
      net.points.push_back(vec(t.control_points[i]));
      const auto id = static_cast<std::size_t>(t.function_ids[i]);
      if (id >= s.pos.size()) s.pos.resize(id + 1, Vector3d::Zero()), s.refs.resize(id + 1);
      Ref r;
      r.block = static_cast<int>(b);
      r.local = static_cast<int>(i);
      const int n0 = t.size[0], n1 = t.size[1];
      r.ijk = {static_cast<int>(i) % n0, (static_cast<int>(i) / n0) % n1, static_cast<int>(i) / (n0 * n1)};
      s.refs[id].push_back(r);
      s.pos[id] = vec(t.control_points[i]);
    }
    s.nets.push_back(std::move(net));
  }
  return s;
}

// Bézier element e (per-axis element indices) of solid b: C^T·P per direction (bspline.h).
bezier::BezierHex element(const State& s, int b, const std::array<int, 3>& e) {
  const auto& net = s.nets[static_cast<std::size_t>(b)];
  const auto& ops = s.extraction[static_cast<std::size_t>(b)];
  const int p = s.degree, n = p + 1;
  bezier::BezierHex h;
  h.degree = {p, p, p};
  h.points.assign(static_cast<std::size_t>(n * n * n), Vector3d::Zero());
  const Eigen::MatrixXd& C0 = ops[0][static_cast<std::size_t>(e[0])];
  const Eigen::MatrixXd& C1 = ops[1][static_cast<std::size_t>(e[1])];
  const Eigen::MatrixXd& C2 = ops[2][static_cast<std::size_t>(e[2])];
  // Open uniform knots: element e is supported by control points e..e+p along each axis.
  for (int c = 0; c <= p; ++c)
    for (int bb = 0; bb <= p; ++bb)
      for (int a = 0; a <= p; ++a) {
        const Vector3d& x = net.at(e[0] + a, e[1] + bb, e[2] + c);
        for (int k = 0; k <= p; ++k) {
          const double wk = C2(c, k);
          if (wk == 0) continue;
          for (int j = 0; j <= p; ++j) {
            const double wj = wk * C1(bb, j);
            if (wj == 0) continue;
            for (int i = 0; i <= p; ++i) {
              const double w = wj * C0(a, i);
              if (w != 0) h.points[static_cast<std::size_t>(h.index(i, j, k))] += w * x;
            }
          }
        }
      }
  return h;
}

// Elements of solid b whose support holds control point ijk (per axis e in [ijk − p, ijk]).
std::vector<std::array<int, 3>> elements_at(const State& s, int b, const std::array<int, 3>& ijk) {
  const auto& net = s.nets[static_cast<std::size_t>(b)];
  std::array<std::pair<int, int>, 3> range;
  for (int a = 0; a < 3; ++a) range[a] = {std::max(0, ijk[a] - s.degree), std::min(net.size[a] - s.degree - 1, ijk[a])};
  std::vector<std::array<int, 3>> out;
  for (int k = range[2].first; k <= range[2].second; ++k)
    for (int j = range[1].first; j <= range[1].second; ++j)
      for (int i = range[0].first; i <= range[0].second; ++i) out.push_back({i, j, k});
  return out;
}

int element_index(const State& s, int b, const std::array<int, 3>& e) {
  const auto& net = s.nets[static_cast<std::size_t>(b)];
  const int n0 = net.size[0] - s.degree, n1 = net.size[1] - s.degree;
  return e[0] + n0 * (e[1] + n1 * e[2]);
}

// Moves point `id` by up to `delta` inside the feasible region: μ = 1, 1/2, ... Returns the
// applied displacement's length, or -1 if every trial was refused. The region, per solid holding
// the point: Proposition 3 on the sub-grids around it if the solid's net satisfied it initially;
// else every element around it certified valid stays so and no other element's certified lower
// bound of det J falls.
double feasible_move(State& s, int id, const Vector3d& delta, int halvings, bool* shortened) {
  const auto& refs = s.refs[static_cast<std::size_t>(id)];
  const Vector3d start = s.pos[static_cast<std::size_t>(id)];
  std::vector<std::vector<bezier::CertifyResult>> trial(refs.size());
  double mu = 1;
  for (int h = 0; h <= halvings; ++h, mu *= 0.5) {
    s.set(id, start + mu * delta);
    bool ok = true;
    for (std::size_t r = 0; r < refs.size() && ok; ++r) {
      const int b = refs[r].block;
      if (s.all_valid[static_cast<std::size_t>(b)]) {
        ValidityParams p;
        p.stop_at_first_failure = true;
        p.tolerance = s.tolerance[static_cast<std::size_t>(b)];
        ok = check_solid_near(s.nets[static_cast<std::size_t>(b)], refs[r].ijk, p).valid;
        continue;
      }
      trial[r].clear();
      for (const auto& e : elements_at(s, b, refs[r].ijk)) {
        const bezier::CertifyResult& old = s.certified[static_cast<std::size_t>(b)][static_cast<std::size_t>(element_index(s, b, e))];
        const bezier::CertifyResult now = bezier::certify(element(s, b, e), s.certify);
        ok = old.status == bezier::Validity::valid
                 ? now.status == bezier::Validity::valid &&
                       now.min_detj_lower >= std::min(old.min_detj_lower, s.margin_floor * std::abs(now.mean_detj))
                 : now.min_detj_lower >= old.min_detj_lower;
        if (!ok) break;
        trial[r].push_back(now);
      }
    }
    if (ok) {
      for (std::size_t r = 0; r < refs.size(); ++r) {
        const int b = refs[r].block;
        if (s.all_valid[static_cast<std::size_t>(b)]) continue;
        std::size_t i = 0;
        for (const auto& e : elements_at(s, b, refs[r].ijk))
          s.certified[static_cast<std::size_t>(b)][static_cast<std::size_t>(element_index(s, b, e))] = trial[r][i++];
      }
      if (s.observer) (*s.observer)(s.nets);
      *shortened = h > 0;
      return (mu * delta).norm();
    }
  }
  s.set(id, start);
  return -1;
}

// One phase move of point id by delta, counted in the phase's report: skipped below the stop
// distance, refused outside the feasible region. Returns the distance moved (0 if none).
double phase_move(State& s, PhaseReport& ph, int id, const Vector3d& delta, const GfdParams& params, double diag) {
  if (delta.norm() <= params.stop_rel * diag) return 0;
  bool shortened = false;
  const double moved = feasible_move(s, id, delta, params.halvings, &shortened);
  if (moved < 0) {
    ++ph.refused;
    return 0;
  }
  ++ph.moves, ph.shortened += shortened;
  return moved;
}

// A curve, face or interior of one solid: axes with state -1 are free, 0 / 1 fixed at the start / end.
struct Entity {
  int block = 0;
  std::array<int, 3> state{-1, -1, -1};
  std::vector<int> free_local;  // control points it moves (local indices of the block)
  // Data: parameter points and the map there, with each point's basis per axis.
  std::vector<Vector3d> q;
  std::vector<std::array<bezier::BasisValues, 3>> basis;
};

int dimension(const std::array<int, 3>& st) { return static_cast<int>(std::count(st.begin(), st.end(), -1)); }

// Every curve (dim 1), face (2) or interior (3) of the solids, each once (a face shared by two
// solids belongs to the first).
std::vector<Entity> entities(const State& s, int dim, const Map& map, int samples) {
  const auto& solids = *s.solids;
  std::vector<Entity> out;
  std::set<std::vector<int>> seen;
  for (std::size_t b = 0; b < solids.size(); ++b) {
    const auto& t = solids[b];
    for (int code = 0; code < 27; ++code) {
      std::array<int, 3> st{code % 3 - 1, (code / 3) % 3 - 1, code / 9 - 1};
      if (dimension(st) != dim) continue;
      Entity e;
      e.block = static_cast<int>(b);
      e.state = st;
      std::vector<int> ids;
      for (int k = 0; k < t.size[2]; ++k)
        for (int j = 0; j < t.size[1]; ++j)
          for (int i = 0; i < t.size[0]; ++i) {
            const std::array<int, 3> ijk{i, j, k};
            bool in = true;
            for (int a = 0; a < 3 && in; ++a)
              in = st[a] == -1 ? ijk[a] > 0 && ijk[a] < t.size[a] - 1 : ijk[a] == (st[a] == 0 ? 0 : t.size[a] - 1);
            if (!in) continue;
            const int local = i + t.size[0] * (j + t.size[1] * k);
            e.free_local.push_back(local);
            ids.push_back(t.function_ids[static_cast<std::size_t>(local)]);
          }
      if (ids.empty()) continue;
      std::sort(ids.begin(), ids.end());
      if (!seen.insert(ids).second) continue;
      std::array<std::vector<double>, 3> ts;
      for (int a = 0; a < 3; ++a) {
        if (st[a] != -1) {
          ts[a] = {st[a] == 0 ? 0.0 : 1.0};
          continue;
        }
        const int m = samples * (t.size[a] - t.degree);
        for (int k = 0; k < m; ++k) ts[a].push_back((k + 0.5) / m);
      }
      for (const double w : ts[2])
        for (const double v : ts[1])
          for (const double u : ts[0]) {
            e.q.push_back(vec(map(tmesh::block_point(t.corners, {u, v, w}))));
            e.basis.push_back({bezier::basis_functions(t.knots[0], t.degree, u), bezier::basis_functions(t.knots[1], t.degree, v),
                               bezier::basis_functions(t.knots[2], t.degree, w)});
          }
      out.push_back(std::move(e));
    }
  }
  return out;
}

// Calls f(local index, weight) for every control point of solid t whose basis function is
// non-zero at the data point with per-axis basis B.
template <class F>
void for_each_support(const tmesh::TMesh& t, const std::array<bezier::BasisValues, 3>& B, F&& f) {
  const int p = t.degree;
  for (int c = 0; c <= p; ++c)
    for (int b = 0; b <= p; ++b)
      for (int a = 0; a <= p; ++a) {
        const double w = B[0].values[a] * B[1].values[b] * B[2].values[c];
        if (w != 0) f((B[0].span - p + a) + t.size[0] * ((B[1].span - p + b) + t.size[1] * (B[2].span - p + c)), w);
      }
}

// Residuals of one entity at its data points with the current control points.
std::vector<Vector3d> residuals(const State& s, const Entity& e) {
  const auto& t = (*s.solids)[static_cast<std::size_t>(e.block)];
  const auto& net = s.nets[static_cast<std::size_t>(e.block)];
  std::vector<Vector3d> r(e.q.size());
  for (std::size_t j = 0; j < e.q.size(); ++j) {
    Vector3d x = Vector3d::Zero();
    for_each_support(t, e.basis[j], [&](int local, double w) { x += w * net.points[static_cast<std::size_t>(local)]; });
    r[j] = e.q[j] - x;
  }
  return r;
}

// LSPIA directions of the entity's free points (indexed like free_local): Δ_i = Σ_j N_i(t_j) r_j / Σ_j N_i(t_j).
std::vector<Vector3d> lspia_directions(const State& s, const Entity& e) {
  const auto& t = (*s.solids)[static_cast<std::size_t>(e.block)];
  const std::vector<Vector3d> r = residuals(s, e);
  std::vector<Vector3d> num(t.control_points.size(), Vector3d::Zero());
  std::vector<double> den(t.control_points.size(), 0.0);
  for (std::size_t j = 0; j < e.q.size(); ++j)
    for_each_support(t, e.basis[j], [&](int local, double w) {
      num[static_cast<std::size_t>(local)] += w * r[j];
      den[static_cast<std::size_t>(local)] += w;
    });
  std::vector<Vector3d> d;
  for (const int l : e.free_local) {
    const auto i = static_cast<std::size_t>(l);
    d.push_back(den[i] > 0 ? Vector3d(num[i] / den[i]) : Vector3d::Zero());
  }
  return d;
}

// Directions of the entity's free points (indexed like free_local): toward the least-squares fit
// of its data with every other control point where it is, P* = argmin Σ_j |Q_j − X(t_j)|² (a
// Tikhonov term 1e-10·mean diagonal keeps the normal matrix definite where data is sparse).
std::vector<Vector3d> least_squares_directions(const State& s, const Entity& e) {
  const auto& t = (*s.solids)[static_cast<std::size_t>(e.block)];
  const auto& net = s.nets[static_cast<std::size_t>(e.block)];
  std::vector<int> column(t.control_points.size(), -1);
  for (std::size_t i = 0; i < e.free_local.size(); ++i) column[static_cast<std::size_t>(e.free_local[i])] = static_cast<int>(i);
  const auto m = static_cast<Eigen::Index>(e.free_local.size());
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::MatrixXd rhs(static_cast<Eigen::Index>(e.q.size()), 3);
  for (std::size_t j = 0; j < e.q.size(); ++j) {
    Vector3d fixed = Vector3d::Zero();
    for_each_support(t, e.basis[j], [&](int local, double w) {
      const int col = column[static_cast<std::size_t>(local)];
      if (col >= 0) trip.emplace_back(static_cast<Eigen::Index>(j), col, w);
      else fixed += w * net.points[static_cast<std::size_t>(local)];
    });
    rhs.row(static_cast<Eigen::Index>(j)) = (e.q[j] - fixed).transpose();
  }
  Eigen::SparseMatrix<double> N(static_cast<Eigen::Index>(e.q.size()), m);
  N.setFromTriplets(trip.begin(), trip.end());
  Eigen::SparseMatrix<double> A = N.transpose() * N;
  double mean_diag = 0;
  for (Eigen::Index i = 0; i < m; ++i) mean_diag += A.coeff(i, i);
  mean_diag = m ? mean_diag / static_cast<double>(m) : 1;
  const double lambda = 1e-10 * std::max(mean_diag, 1e-300);
  Eigen::MatrixXd current(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) current.row(i) = net.points[static_cast<std::size_t>(e.free_local[static_cast<std::size_t>(i)])].transpose();
  Eigen::SparseMatrix<double> I(m, m);
  I.setIdentity();
  A += lambda * I;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  if (ldlt.info() != Eigen::Success) throw core::NumericalError("fit: the least-squares system of a curve, face or solid is singular");
  const Eigen::MatrixXd target = ldlt.solve(Eigen::MatrixXd(N.transpose() * rhs + lambda * current));
  std::vector<Vector3d> d;
  for (Eigen::Index i = 0; i < m; ++i) d.push_back((target.row(i) - current.row(i)).transpose());
  return d;
}

void error_figures(const State& s, const std::vector<Entity>& es, double diag, double* rms, double* max) {
  double sum = 0, mx = 0;
  std::size_t n = 0;
  for (const auto& e : es)
    for (const auto& r : residuals(s, e)) sum += r.squaredNorm(), mx = std::max(mx, r.norm()), ++n;
  *rms = n ? std::sqrt(sum / static_cast<double>(n)) / diag : 0;
  *max = mx / diag;
}

PhaseReport fit_phase(State& s, const std::vector<Entity>& es, const char* name, double diag, const GfdParams& params) {
  PhaseReport ph;
  ph.name = name;
  for (const auto& e : es) ph.points += static_cast<int>(e.free_local.size());
  error_figures(s, es, diag, &ph.rms_before, &ph.max_before);
  const auto& solids = *s.solids;
  for (ph.sweeps = 0; ph.sweeps < params.sweeps;) {
    ++ph.sweeps;
    double largest = 0;
    for (const auto& e : es) {
      const auto d = dimension(e.state) == 3 ? lspia_directions(s, e) : least_squares_directions(s, e);
      for (std::size_t i = 0; i < e.free_local.size(); ++i) {
        const int id = solids[static_cast<std::size_t>(e.block)].function_ids[static_cast<std::size_t>(e.free_local[i])];
        largest = std::max(largest, phase_move(s, ph, id, d[i], params, diag));
      }
    }
    if (largest <= params.stop_rel * diag) break;
  }
  error_figures(s, es, diag, &ph.rms_after, &ph.max_after);
  return ph;
}

// Inner control points of the common faces of two solids (off the face's edges), with their
// neighbours one row inside on both sides.
struct FacePoint {
  int id = -1;         // P0
  int a = -1, b = -1;  // neighbours one row inside the first and the second solid
};
struct Face {
  int first = -1, second = -1;
  std::vector<FacePoint> points;
};

std::vector<Face> common_faces(const State& s) {
  const auto& solids = *s.solids;
  std::map<std::pair<int, int>, Face> faces;
  for (std::size_t id = 0; id < s.refs.size(); ++id) {
    const auto& refs = s.refs[id];
    if (refs.size() != 2) continue;
    FacePoint fp;
    fp.id = static_cast<int>(id);
    int other[2] = {-1, -1};
    for (int side = 0; side < 2; ++side) {
      const Ref& r = refs[static_cast<std::size_t>(side)];
      const auto& t = solids[static_cast<std::size_t>(r.block)];
      int fixed = -1, count = 0;
      for (int a = 0; a < 3; ++a)
        if (r.ijk[a] == 0 || r.ijk[a] == t.size[a] - 1) fixed = a, ++count;
      if (count != 1) break;  // on a face's edge: the cube's edges and where three or more solids meet
      std::array<int, 3> n = r.ijk;
      n[fixed] += r.ijk[fixed] == 0 ? 1 : -1;
      other[side] = t.function_ids[static_cast<std::size_t>(n[0] + t.size[0] * (n[1] + t.size[1] * n[2]))];
    }
    if (other[0] < 0 || other[1] < 0) continue;
    fp.a = other[0], fp.b = other[1];
    Face& f = faces[{refs[0].block, refs[1].block}];
    f.first = refs[0].block, f.second = refs[1].block;
    f.points.push_back(fp);
  }
  std::vector<Face> out;
  for (auto& [k, f] : faces) out.push_back(std::move(f));
  return out;
}

double angle_deg(const Vector3d& u, const Vector3d& w) {
  const double c = u.normalized().dot(w.normalized());
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / kPi;
}

std::vector<Interface> measure(const State& s, const std::vector<Face>& faces) {
  std::vector<Interface> out;
  for (const Face& f : faces) {
    Interface it;
    it.first = f.first, it.second = f.second;
    double su = 0, sw = 0, sum = 0;
    for (const FacePoint& p : f.points) {
      const Vector3d u = s.pos[static_cast<std::size_t>(p.id)] - s.pos[static_cast<std::size_t>(p.a)];
      const Vector3d w = s.pos[static_cast<std::size_t>(p.b)] - s.pos[static_cast<std::size_t>(p.id)];
      const double ang = angle_deg(u, w);
      it.max_angle_deg = std::max(it.max_angle_deg, ang);
      sum += ang, su += u.norm(), sw += w.norm();
      ++it.points;
    }
    it.mean_angle_deg = it.points ? sum / it.points : 0;
    it.alpha = sw > 0 ? su / sw : 0;
    out.push_back(it);
  }
  return out;
}

// Moves the rows beside each common face toward Proposition 4 (P0 − a = α (b − P0), one α per
// face): the nearest such pair to (a, b) is a' = P0 − α v, b' = P0 + v with v = (α u + w)/(α² + 1).
// Only solid-interior points move (the others carry the boundary fit).
PhaseReport g1_phase(State& s, const std::vector<Face>& faces, const GfdParams& params, double diag) {
  PhaseReport ph;
  ph.name = "g1";
  auto interior = [&](int id) {
    for (const Ref& r : s.refs[static_cast<std::size_t>(id)]) {
      const auto& t = (*s.solids)[static_cast<std::size_t>(r.block)];
      for (int a = 0; a < 3; ++a)
        if (r.ijk[a] == 0 || r.ijk[a] == t.size[a] - 1) return false;
    }
    return true;
  };
  std::set<int> movable;
  for (const Face& f : faces)
    for (const FacePoint& p : f.points) {
      if (interior(p.a)) movable.insert(p.a);
      if (interior(p.b)) movable.insert(p.b);
    }
  ph.points = static_cast<int>(movable.size());
  auto defect = [&]() {
    double sum = 0, mx = 0;
    int n = 0;
    for (const auto& it : measure(s, faces)) mx = std::max(mx, it.max_angle_deg), sum += it.mean_angle_deg, ++n;
    return std::array<double, 2>{n ? sum / n : 0, mx};
  };
  // For g1 the "errors" are angles in degrees: mean of the faces' mean angles, and the max.
  const auto d0 = defect();
  ph.rms_before = d0[0], ph.max_before = d0[1];
  for (ph.sweeps = 0; ph.sweeps < params.g1_sweeps;) {
    ++ph.sweeps;
    const auto m = measure(s, faces);
    // Targets of each movable point, averaged over the faces it is beside.
    std::map<int, std::pair<Vector3d, int>> target;
    for (std::size_t fi = 0; fi < faces.size(); ++fi) {
      const double al = m[fi].alpha;
      if (!(al > 0)) continue;
      for (const FacePoint& p : faces[fi].points) {
        const Vector3d P0 = s.pos[static_cast<std::size_t>(p.id)];
        const Vector3d u = P0 - s.pos[static_cast<std::size_t>(p.a)], w = s.pos[static_cast<std::size_t>(p.b)] - P0;
        const Vector3d v = (al * u + w) / (al * al + 1);
        for (const auto& [id, x] : {std::pair<int, Vector3d>{p.a, P0 - al * v}, std::pair<int, Vector3d>{p.b, P0 + v}}) {
          if (!movable.count(id)) continue;
          auto& t = target[id];
          if (t.second == 0) t.first = Vector3d::Zero();
          t.first += x, ++t.second;
        }
      }
    }
    double largest = 0;
    for (const auto& [id, t] : target) {
      largest = std::max(largest, phase_move(s, ph, id, t.first / t.second - s.pos[static_cast<std::size_t>(id)], params, diag));
    }
    if (largest <= params.stop_rel * diag) break;
  }
  const auto d1 = defect();
  ph.rms_after = d1[0], ph.max_after = d1[1];
  return ph;
}

// Greville abscissae of solid b along axis a (where the control points sit in parameter space).
std::vector<double> greville(const State& s, int b, int a) {
  const auto& t = (*s.solids)[static_cast<std::size_t>(b)];
  const auto& knots = t.knots[static_cast<std::size_t>(a)];
  std::vector<double> g(static_cast<std::size_t>(t.size[a]));
  for (std::size_t i = 0; i < g.size(); ++i) {
    double sum = 0;
    for (int k = 1; k <= t.degree; ++k) sum += knots[i + static_cast<std::size_t>(k)];
    g[i] = sum / t.degree;
  }
  return g;
}

// Second divided difference of a grid line at index j, D_j = w[0] P_{j−1} + w[1] P_j + w[2] P_{j+1}
// over the Greville abscissae g: zero on nets of maps that are linear along the line (the nets of
// trilinear and affine maps), so fairness leaves exact fits alone.
std::array<double, 3> divided_difference(const std::vector<double>& g, int j) {
  const auto u = static_cast<std::size_t>(j);
  const double h0 = g[u] - g[u - 1], h1 = g[u + 1] - g[u], h = g[u + 1] - g[u - 1];
  const double a = 2 / (h0 * h), c = 2 / (h1 * h);
  return {a, -(a + c), c};
}

// Fairness of the nets: the second divided differences along every grid line of every solid (a
// discrete thin-plate energy of the control net), rms and max relative to the diagonal.
std::array<double, 2> second_differences(const State& s, double diag) {
  double sum = 0, mx = 0;
  long n = 0;
  for (std::size_t b = 0; b < s.nets.size(); ++b) {
    const SolidNet& net = s.nets[b];
    std::array<std::vector<double>, 3> g;
    for (int a = 0; a < 3; ++a) g[static_cast<std::size_t>(a)] = greville(s, static_cast<int>(b), a);
    for (int k = 0; k < net.size[2]; ++k)
      for (int j = 0; j < net.size[1]; ++j)
        for (int i = 0; i < net.size[0]; ++i)
          for (int a = 0; a < 3; ++a) {
            std::array<int, 3> m{i, j, k}, p{i, j, k};
            --m[a], ++p[a];
            if (m[a] < 0 || p[a] >= net.size[a]) continue;
            const auto w = divided_difference(g[static_cast<std::size_t>(a)], (std::array<int, 3>{i, j, k})[static_cast<std::size_t>(a)]);
            const double d = (w[0] * net.at(m[0], m[1], m[2]) + w[1] * net.at(i, j, k) + w[2] * net.at(p[0], p[1], p[2])).norm() / diag;
            sum += d * d, mx = std::max(mx, d), ++n;
          }
  }
  return {n ? std::sqrt(sum / static_cast<double>(n)) : 0.0, mx};
}

// The paper's last step improves "the fairness of each TBS". Points deep inside a solid (off its
// faces and off the rows beside them, which carry the boundary fit and Proposition 4's G1
// condition) move by Gauss–Seidel on the thin-plate energy of the net: P_i appears in the second
// divided differences D_{i−1}, D_i, D_{i+1} of its three grid lines, D = c P_i + r, and the
// minimiser is −Σ c r / Σ c². Each move is feasible (gfd's region).
PhaseReport fairness_phase(State& s, const GfdParams& params, double diag) {
  PhaseReport ph;
  ph.name = "fairness";
  const auto e0 = second_differences(s, diag);
  ph.rms_before = e0[0], ph.max_before = e0[1];
  struct Point {
    int id, block;
    std::array<int, 3> ijk;
  };
  std::vector<Point> free;
  std::vector<std::array<std::vector<double>, 3>> g(s.nets.size());
  for (std::size_t b = 0; b < s.nets.size(); ++b)
    for (int a = 0; a < 3; ++a) g[b][static_cast<std::size_t>(a)] = greville(s, static_cast<int>(b), a);
  for (std::size_t id = 0; id < s.refs.size(); ++id) {
    if (s.refs[id].size() != 1) continue;  // shared by solids: on a common face
    const Ref& r = s.refs[id][0];
    const auto& net = s.nets[static_cast<std::size_t>(r.block)];
    bool deep = true;
    for (int a = 0; a < 3; ++a) deep = deep && r.ijk[a] >= 2 && r.ijk[a] <= net.size[a] - 3;
    if (deep) free.push_back({static_cast<int>(id), r.block, r.ijk});
  }
  ph.points = static_cast<int>(free.size());
  for (ph.sweeps = 0; ph.sweeps < params.fairness_sweeps;) {
    ++ph.sweeps;
    double largest = 0;
    for (const Point& q : free) {
      const auto& net = s.nets[static_cast<std::size_t>(q.block)];
      const Vector3d here = s.pos[static_cast<std::size_t>(q.id)];
      Vector3d num = Vector3d::Zero();
      double den = 0;
      for (int a = 0; a < 3; ++a) {
        const auto& ga = g[static_cast<std::size_t>(q.block)][static_cast<std::size_t>(a)];
        auto at = [&](int step) {
          std::array<int, 3> x = q.ijk;
          x[static_cast<std::size_t>(a)] += step;
          return net.at(x[0], x[1], x[2]);
        };
        for (int j = -1; j <= 1; ++j) {  // D at index i + j; P_i is its neighbour −j
          const auto w = divided_difference(ga, q.ijk[static_cast<std::size_t>(a)] + j);
          const double c = w[static_cast<std::size_t>(1 - j)];
          const Vector3d d = w[0] * at(j - 1) + w[1] * at(j) + w[2] * at(j + 1);
          num += c * (d - c * here);
          den += c * c;
        }
      }
      largest = std::max(largest, phase_move(s, ph, q.id, -num / den - here, params, diag));
    }
    if (largest <= params.stop_rel * diag) break;
  }
  const auto e1 = second_differences(s, diag);
  ph.rms_after = e1[0], ph.max_after = e1[1];
  return ph;
}

// True if control point `id` lies on a block face marked boundary (the input surface).
bool on_surface(const State& s, int id) {
  for (const Ref& r : s.refs[static_cast<std::size_t>(id)]) {
    const auto& t = (*s.solids)[static_cast<std::size_t>(r.block)];
    for (int a = 0; a < 3; ++a)
      if ((r.ijk[a] == 0 && t.boundary[2 * a]) || (r.ijk[a] == t.size[a] - 1 && t.boundary[2 * a + 1])) return true;
  }
  return false;
}

// Elements of the solids guarded by certification that are not certified valid: their control
// points (block corners and points on the surface excepted: moving those cost the boundary fit,
// measured on the fandisk: hausdorff_rel 0.029 -> 0.063) move toward the mean of their neighbours along the free axes of
// their curve, face or interior (Laplacian smoothing untangles; face and curve points stay on
// their face or curve's net), each move in the feasible region: raising the element's certified
// lower bound of det J or leaving every bound where it was (the feasible
// region never lets one fall). Stops after a sweep without progress on an element.
PhaseReport repair_phase(State& s, const GfdParams& params) {
  PhaseReport ph;
  ph.name = "repair";
  const auto invalid = [&]() {
    int n = 0;
    for (const auto& list : s.certified)
      for (const auto& c : list) n += c.status != bezier::Validity::valid;
    return n;
  };
  ph.rms_before = ph.max_before = invalid();
  for (ph.sweeps = 0; ph.sweeps < params.repair_sweeps && invalid() > 0;) {
    ++ph.sweeps;
    int moved = 0;
    for (std::size_t b = 0; b < s.certified.size(); ++b) {
      const auto& net = s.nets[b];
      const int n0 = net.size[0] - s.degree, n1 = net.size[1] - s.degree;
      for (std::size_t ei = 0; ei < s.certified[b].size(); ++ei) {
        if (s.certified[b][ei].status == bezier::Validity::valid) continue;
        const std::array<int, 3> e{static_cast<int>(ei) % n0, (static_cast<int>(ei) / n0) % n1, static_cast<int>(ei) / (n0 * n1)};
        for (int c = 0; c <= s.degree; ++c)
          for (int bb = 0; bb <= s.degree; ++bb)
            for (int a = 0; a <= s.degree; ++a) {
              const std::array<int, 3> ijk{e[0] + a, e[1] + bb, e[2] + c};
              const int id = (*s.solids)[b].function_ids[static_cast<std::size_t>(net.index(ijk[0], ijk[1], ijk[2]))];
              Vector3d mean = Vector3d::Zero();
              int count = 0;
              for (int ax = 0; ax < 3; ++ax) {
                if (ijk[ax] == 0 || ijk[ax] == net.size[ax] - 1) continue;  // fixed axis: stay on the face or curve
                for (const int step : {-1, 1}) {
                  std::array<int, 3> nb = ijk;
                  nb[ax] += step;
                  mean += net.at(nb[0], nb[1], nb[2]), ++count;
                }
              }
              if (count == 0 || on_surface(s, id)) continue;  // block corners and the boundary fit stay
              const double before = s.certified[b][ei].min_detj_lower;
              bool shortened = false;
              if (feasible_move(s, id, mean / count - s.pos[static_cast<std::size_t>(id)], params.halvings, &shortened) < 0) {
                ++ph.refused;
                continue;
              }
              ++ph.moves, ph.shortened += shortened;
              if (s.certified[b][ei].min_detj_lower > before) ++moved;  // progress on this element
            }
      }
    }
    if (moved == 0) break;
  }
  ph.rms_after = ph.max_after = invalid();
  return ph;
}

// The certified results of every element of solid b (extraction operators computed on first use).
std::vector<bezier::CertifyResult> certify_solid(State& s, int b) {
  const auto& t = (*s.solids)[static_cast<std::size_t>(b)];
  auto& ops = s.extraction[static_cast<std::size_t>(b)];
  if (ops[0].empty())
    for (int a = 0; a < 3; ++a) ops[static_cast<std::size_t>(a)] = bezier::extraction_operators(t.knots[static_cast<std::size_t>(a)], t.degree);
  std::vector<bezier::CertifyResult> out;
  const int n0 = t.size[0] - t.degree, n1 = t.size[1] - t.degree, n2 = t.size[2] - t.degree;
  for (int k = 0; k < n2; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i) out.push_back(bezier::certify(element(s, b, {i, j, k}), s.certify));
  return out;
}

// GFD keeps validity; it cannot create it, and a net sampled from a distorted map can start with
// elements that are not valid. Their control points are pulled toward the affine least-squares
// fit of the whole net (cube coordinates → physical), x = t·sampled + (1 − t)·affine with t halved
// per round for every point of an element still not certified valid. The affine net is valid (an
// affine map with positive determinant of the valid pillow partition), so after `rounds` rounds
// the points still in such elements go onto it (t = 0), and if that leaves one (a transition), the
// whole net does: the start is certified valid in every case. (Targets from local affine fits of
// the elements around each point were tried: on the fandisk they stalled at 23 elements not valid
// and the fit ended no closer to the surface.)
void valid_start(State& s, int rounds, GfdReport* rep) {
  const auto& solids = *s.solids;
  const auto all_not_valid = [&]() {
    std::vector<std::pair<int, std::array<int, 3>>> out;
    for (std::size_t b = 0; b < solids.size(); ++b) {
      const auto cert = certify_solid(s, static_cast<int>(b));
      const auto& t = solids[b];
      const int n0 = t.size[0] - t.degree, n1 = t.size[1] - t.degree;
      for (std::size_t e = 0; e < cert.size(); ++e)
        if (cert[e].status != bezier::Validity::valid)
          out.push_back({static_cast<int>(b), {static_cast<int>(e) % n0, (static_cast<int>(e) / n0) % n1, static_cast<int>(e) / (n0 * n1)}});
    }
    return out;
  };
  auto bad = all_not_valid();
  rep->start_not_valid = static_cast<int>(bad.size());
  if (bad.empty() || rounds == 0) return;
  const std::size_t n = s.pos.size();
  Eigen::MatrixXd X(static_cast<Eigen::Index>(n), 4), Y(static_cast<Eigen::Index>(n), 3);
  for (std::size_t id = 0; id < n; ++id) {
    const Ref& r = s.refs[id].front();
    const auto& t = solids[static_cast<std::size_t>(r.block)];
    const tmesh::Vec3 u = tmesh::block_point(t.corners, t.parameters[static_cast<std::size_t>(r.local)]);
    X.row(static_cast<Eigen::Index>(id)) << u[0], u[1], u[2], 1;
    Y.row(static_cast<Eigen::Index>(id)) = s.pos[id].transpose();
  }
  const Eigen::MatrixXd B = X.colPivHouseholderQr().solve(Y);  // 4 x 3
  if (!(B.topRows(3).determinant() > 0)) {
    core::log_warning("fit: the affine fit of the initial net reverses orientation; elements not certified valid stay");
    return;
  }
  const Eigen::MatrixXd affine = X * B;
  const std::vector<Vector3d> sampled = s.pos;
  std::vector<double> share(n, 1.0);
  const auto apply = [&]() {
    for (std::size_t id = 0; id < n; ++id)
      s.set(static_cast<int>(id), share[id] * sampled[id] + (1 - share[id]) * Vector3d(affine.row(static_cast<Eigen::Index>(id)).transpose()));
  };
  for (int round = 1; !bad.empty(); ++round) {
    rep->start_rounds = round;
    if (round > rounds + 1) {  // a transition between blended and sampled points stayed not valid
      std::fill(share.begin(), share.end(), 0.0);
      apply();
      bad = all_not_valid();
      break;
    }
    std::set<int> ids;
    for (const auto& [b, e] : bad) {
      const auto& t = solids[static_cast<std::size_t>(b)];
      for (int c = 0; c <= s.degree; ++c)
        for (int bb = 0; bb <= s.degree; ++bb)
          for (int a = 0; a <= s.degree; ++a)
            ids.insert(t.function_ids[static_cast<std::size_t>((e[0] + a) + t.size[0] * ((e[1] + bb) + t.size[1] * (e[2] + c)))]);
    }
    for (const int id : ids) share[static_cast<std::size_t>(id)] = round > rounds ? 0.0 : 0.5 * share[static_cast<std::size_t>(id)];
    apply();
    bad = all_not_valid();
  }
  if (!bad.empty()) throw core::NumericalError("fit: the affine fit of the initial net is not certified valid");
  for (std::size_t id = 0; id < n; ++id) {
    if (share[id] == 1) continue;
    ++rep->start_blended_points;
    rep->start_max_shift = std::max(rep->start_max_shift, (s.pos[id] - sampled[id]).norm());
  }
}

void totals(const State& s, int* failures, double* margin) {
  *failures = 0;
  *margin = std::numeric_limits<double>::infinity();
  for (const auto& net : s.nets) {
    const Validity v = check_solid(net);
    *failures += v.failures;
    *margin = std::min(*margin, v.margin);
  }
}

}  // namespace

GfdReport fit_solids(std::vector<tmesh::TMesh>& solids, const Map& map, const GfdParams& params) {
  if (params.samples < 1 || params.samples > 16) throw core::ConfigError("fit.samples must be in [1, 16]");
  if (params.sweeps < 0 || params.sweeps > 1000) throw core::ConfigError("fit.sweeps must be in [0, 1000]");
  if (!(params.stop_rel >= 0 && params.stop_rel < 1)) throw core::ConfigError("fit.stop_rel must be in [0, 1)");
  if (params.halvings < 0 || params.halvings > 30) throw core::ConfigError("fit.halvings must be in [0, 30]");
  if (params.g1_sweeps < 0 || params.g1_sweeps > 1000) throw core::ConfigError("fit.g1_sweeps must be in [0, 1000]");
  if (!(params.min_margin >= 0 && params.min_margin < 1)) throw core::ConfigError("fit: min_margin must be in [0, 1)");
  if (params.repair_sweeps < 0 || params.repair_sweeps > 1000) throw core::ConfigError("fit.repair_sweeps must be in [0, 1000]");
  if (params.start_rounds < 0 || params.start_rounds > 60) throw core::ConfigError("fit.start_rounds must be in [0, 60]");
  if (params.fairness_sweeps < 0 || params.fairness_sweeps > 1000) throw core::ConfigError("fit.fairness_sweeps must be in [0, 1000]");
  if (solids.empty()) throw core::InvalidInputError("fit: no solids");
  GfdReport rep;
  State s = make_state(solids);
  if (params.observer) s.observer = &params.observer;
  Eigen::AlignedBox3d box;
  for (const auto& x : s.pos) box.extend(x);
  const double diag = std::max(box.diagonal().norm(), 1e-300);
  s.extraction.resize(s.nets.size());
  s.certified.resize(s.nets.size());
  s.margin_floor = params.min_margin;
  {
    core::LogSection sec("valid start");
    valid_start(s, params.start_rounds, &rep);
    rep.start_max_shift /= diag;
    if (rep.start_not_valid > 0)
      core::log(std::to_string(rep.start_not_valid) + " elements of the sampled nets not certified valid; " +
                std::to_string(rep.start_blended_points) + " control points pulled toward the affine fit in " +
                std::to_string(rep.start_rounds) + " rounds (largest shift " + std::to_string(rep.start_max_shift) + " of the diagonal)");
  }
  for (std::size_t b = 0; b < s.nets.size(); ++b) {
    const Validity v = check_solid(s.nets[b]);
    s.all_valid.push_back(v.valid);
    // A margin, not just validity: moves would otherwise drive the triple products to the
    // rounding tolerance, where a re-export of the points could flip the verdict.
    s.tolerance.push_back(v.valid ? std::max(ValidityParams{}.tolerance, std::min(params.min_margin, 0.5 * v.margin)) : 0.0);
    if (v.valid) continue;
    // Proposition 3 is only sufficient; where it fails the certified Bernstein check of det J
    // (bezier::certify) guards the moves instead.
    s.certified[b] = certify_solid(s, static_cast<int>(b));
    int valid = 0;
    for (const auto& c : s.certified[b]) valid += c.status == bezier::Validity::valid;
    core::log_warning("fit: the initial net of solid " + std::to_string(b) + " fails the validity condition (Prop. 3) on " +
                      std::to_string(v.failures) + " of " + std::to_string(v.checked) + " sub-grids; its moves keep the " +
                      std::to_string(valid) + " of " + std::to_string(s.certified[b].size()) +
                      " elements certified valid (det J > 0 by Bernstein coefficients) valid instead");
  }
  totals(s, &rep.initial_failing_subgrids, &rep.initial_margin);
  const std::vector<Face> faces = common_faces(s);
  rep.g1_before = measure(s, faces);
  const char* names[] = {"", "curves", "surfaces", "solids"};
  for (int dim = 1; dim <= 3; ++dim) {
    core::LogSection sec(std::string("fit ") + names[dim]);
    const auto es = entities(s, dim, map, params.samples);
    rep.phases.push_back(fit_phase(s, es, names[dim], diag, params));
    const auto& ph = rep.phases.back();
    core::log(std::to_string(ph.points) + " points, " + std::to_string(ph.sweeps) + " sweeps, " + std::to_string(ph.moves) + " moves (" +
              std::to_string(ph.shortened) + " shortened, " + std::to_string(ph.refused) + " refused), max error " +
              std::to_string(ph.max_before) + " -> " + std::to_string(ph.max_after) + " of the diagonal");
  }
  {
    core::LogSection sec("fit g1");
    rep.phases.push_back(g1_phase(s, faces, params, diag));
    const auto& ph = rep.phases.back();
    core::log("max angle across common faces (inner points) " + std::to_string(ph.max_before) + " -> " + std::to_string(ph.max_after) +
              " degrees, " + std::to_string(ph.moves) + " moves, " + std::to_string(ph.refused) + " refused");
  }
  rep.g1_after = measure(s, faces);
  if (params.fairness_sweeps > 0) {
    core::LogSection sec("fit fairness");
    rep.phases.push_back(fairness_phase(s, params, diag));
    const auto& ph = rep.phases.back();
    core::log(std::to_string(ph.points) + " points deep inside the solids, rms second difference of the nets " +
              std::to_string(ph.rms_before) + " -> " + std::to_string(ph.rms_after) + " of the diagonal, " + std::to_string(ph.moves) +
              " moves, " + std::to_string(ph.refused) + " refused");
  }
  if (params.repair_sweeps > 0) {
    core::LogSection sec("fit repair");
    rep.phases.push_back(repair_phase(s, params));
    const auto& ph = rep.phases.back();
    if (ph.max_before > 0)
      core::log("elements not certified valid " + std::to_string(static_cast<int>(ph.max_before)) + " -> " +
                std::to_string(static_cast<int>(ph.max_after)) + ", " + std::to_string(ph.moves) + " moves");
  }
  totals(s, &rep.final_failing_subgrids, &rep.final_margin);
  for (auto& t : solids)
    for (std::size_t i = 0; i < t.control_points.size(); ++i) {
      const Vector3d& x = s.pos[static_cast<std::size_t>(t.function_ids[i])];
      t.control_points[i] = {x[0], x[1], x[2]};
    }
  return rep;
}

std::vector<Interface> g1_defects(const std::vector<tmesh::TMesh>& solids) {
  const State s = make_state(solids);
  return measure(s, common_faces(s));
}

}  // namespace volts::fit
