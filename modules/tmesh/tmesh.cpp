#include "tmesh/tmesh.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "bezier/bspline.h"
#include "core/errors.h"
#include "core/log.h"
#include "viz/viz.h"

namespace volts::tmesh {

using Vec3 = std::array<double, 3>;

int TMesh::elements() const {
  int n = 1;
  for (int a = 0; a < 3; ++a) n *= static_cast<int>(bezier::element_spans(knots[a], degree).size());
  return n;
}

namespace {

// Collocation matrix of the B-spline basis at the Greville points (square, non-singular by
// Schoenberg–Whitney).
Eigen::MatrixXd collocation(const std::vector<double>& knots, int degree, const std::vector<double>& g) {
  const int n = static_cast<int>(g.size());
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, n);
  for (int a = 0; a < n; ++a) {
    const auto b = bezier::basis_functions(knots, degree, g[a]);
    for (int k = 0; k <= degree; ++k) N(a, b.span - degree + k) = b.values[k];
  }
  return N;
}

}  // namespace

TMesh build(const polycube::VolumeMap& map, const Params& params) {
  return build(PointMap([&](const Vec3& x) { return map(x); }), params);
}

TMesh build(const PointMap& map, const Params& params) {
  if (params.level < 1 || params.level > 7) throw core::ConfigError("tmesh.level must be in [1, 7], got " + std::to_string(params.level));
  if (params.degree < 1 || params.degree > 5) throw core::ConfigError("tmesh.degree must be in [1, 5], got " + std::to_string(params.degree));
  TMesh t;
  t.level = params.level;
  t.degree = params.degree;
  const int elems = 1 << params.level;
  const auto knots = bezier::open_uniform_knots(elems, params.degree);
  const auto g = bezier::greville_abscissae(knots, params.degree);
  const int m = static_cast<int>(g.size());
  t.knots = {knots, knots, knots};
  t.size = {m, m, m};

  // Sample the volume map at the Greville points, then solve N ⊗ N ⊗ N · P = D one axis at a time.
  const std::size_t total = static_cast<std::size_t>(m) * m * m;
  Eigen::MatrixXd data(total, 3);
  t.parameters.resize(total);
  core::Progress progress("sampling the volume map", total);
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const std::size_t idx = i + static_cast<std::size_t>(m) * (j + static_cast<std::size_t>(m) * k);
        t.parameters[idx] = {g[i], g[j], g[k]};
        const Vec3 x = map(t.parameters[idx]);
        data.row(idx) << x[0], x[1], x[2];
        progress.step(idx);
      }
  progress.finish();
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(collocation(knots, params.degree, g));
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t stride = axis == 0 ? 1 : axis == 1 ? m : static_cast<std::size_t>(m) * m;
    Eigen::MatrixXd line(m, 3);
    for (std::size_t base = 0; base < total; ++base) {
      // base runs over the lines' first points: those with index 0 along `axis`.
      if ((base / stride) % m != 0) continue;
      for (int a = 0; a < m; ++a) line.row(a) = data.row(base + a * stride);
      const Eigen::MatrixXd solved = lu.solve(line);
      for (int a = 0; a < m; ++a) data.row(base + a * stride) = solved.row(a);
    }
  }
  t.control_points.resize(total);
  for (std::size_t i = 0; i < total; ++i) t.control_points[i] = {data(i, 0), data(i, 1), data(i, 2)};
  return t;
}

double trilinear_min_scaled_jacobian(const std::array<Vec3, 8>& x) {
  // Corner c with its three edge neighbours in VTK hexahedron order, right-handed.
  static const int nb[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7}, {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};
  double worst = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    Eigen::Matrix3d J;
    for (int e = 0; e < 3; ++e)
      for (int k = 0; k < 3; ++k) J(k, e) = x[nb[c][e]][k] - x[c][k];
    const double l = J.col(0).norm() * J.col(1).norm() * J.col(2).norm();
    worst = std::min(worst, l > 0 ? J.determinant() / l : 0.0);
  }
  return worst;
}

core::Json to_json(const TMesh& t) {
  std::vector<double> cp, par;
  for (const auto& p : t.control_points) cp.insert(cp.end(), p.begin(), p.end());
  for (const auto& p : t.parameters) par.insert(par.end(), p.begin(), p.end());
  return core::Json{{"level", t.level}, {"degree", t.degree}, {"knots", t.knots}, {"size", t.size},
                    {"control_points", cp}, {"parameters", par}, {"boundary", t.boundary}, {"component", t.component},
                    {"function_ids", t.function_ids}};
}

TMesh from_json(const core::Json& j, const std::string& file) {
  TMesh t;
  try {
    t.level = core::require(j, "level", file).get<int>();
    t.degree = core::require(j, "degree", file).get<int>();
    t.knots = core::require(j, "knots", file).get<std::array<std::vector<double>, 3>>();
    t.size = core::require(j, "size", file).get<std::array<int, 3>>();
    // The ranges of the config (tmesh.level, tmesh.degree): larger values would overflow 1 << level.
    if (t.level < 1 || t.level > 7 || t.degree < 1 || t.degree > 5)
      throw core::InvalidInputError(file + ": tmesh level " + std::to_string(t.level) + " or degree " +
                                    std::to_string(t.degree) + " out of range (level 1..7, degree 1..5)");
    for (int a = 0; a < 3; ++a) bezier::check_knot_vector(t.knots[a], t.degree, "tmesh knot vector");
    // One control point per B-spline function: the sizes follow from the knots, so their product
    // is bounded by the file's length.
    for (int a = 0; a < 3; ++a)
      if (t.size[a] != static_cast<int>(t.knots[a].size()) - t.degree - 1)
        throw core::InvalidInputError(file + ": tmesh size " + std::to_string(t.size[a]) + " does not match its " +
                                      std::to_string(t.knots[a].size()) + " knots of degree " + std::to_string(t.degree));
    if (j.contains("boundary")) t.boundary = j["boundary"].get<std::array<int, 6>>();
    if (j.contains("component")) t.component = j["component"].get<int>();
    if (j.contains("function_ids")) t.function_ids = j["function_ids"].get<std::vector<int>>();
    const auto cp = core::require(j, "control_points", file).get<std::vector<double>>();
    const auto par = core::require(j, "parameters", file).get<std::vector<double>>();
    const std::size_t n = static_cast<std::size_t>(t.size[0]) * t.size[1] * t.size[2];
    if (cp.size() != 3 * n || par.size() != 3 * n)
      throw core::InvalidInputError(file + ": control point count does not match size");
    if (!t.function_ids.empty() && t.function_ids.size() != n)
      throw core::InvalidInputError(file + ": tmesh function_ids has " + std::to_string(t.function_ids.size()) +
                                    " entries for " + std::to_string(n) + " control points");
    for (const int id : t.function_ids)
      if (id < 0) throw core::InvalidInputError(file + ": tmesh function_ids holds a negative id");
    for (const double x : cp)
      if (!std::isfinite(x)) throw core::InvalidInputError(file + ": a tmesh control point is not finite");
    for (std::size_t i = 0; i < n; ++i) {
      t.control_points.push_back({cp[3 * i], cp[3 * i + 1], cp[3 * i + 2]});
      t.parameters.push_back({par[3 * i], par[3 * i + 1], par[3 * i + 2]});
    }
  } catch (const core::Json::exception& e) {
    throw core::InvalidInputError(file + ": malformed tmesh: " + e.what());
  }
  return t;
}

core::Json report_figures(const std::vector<TMesh>& ts, double min_sj) {
  std::size_t nodes = 0, octree_nodes = 0;
  int elements = 0, level = 0;
  for (const auto& t : ts) {
    const std::size_t n = static_cast<std::size_t>(1) << t.level;
    nodes += t.control_points.size();
    octree_nodes += (n + 1) * (n + 1) * (n + 1);
    elements += t.elements();
    level = std::max(level, t.level);
  }
  return core::Json{{"nodes", nodes},
                    {"octree_nodes", octree_nodes},
                    {"cubes", ts.size()},
                    {"elements", elements},
                    {"max_level", level},
                    {"irregular_nodes_surface", 0},
                    {"irregular_nodes_interior", 0},
                    {"min_scaled_jacobian_before", min_sj},
                    {"min_scaled_jacobian_after", min_sj}};
}

double write_vtu(const std::string& path, const TMesh& t, const polycube::VolumeMap& map) {
  return write_vtu(path, std::vector<TMesh>{t}, {PointMap([&](const Vec3& x) { return map(x); })});
}

double write_vtu(const std::string& path, const std::vector<TMesh>& ts, const std::vector<PointMap>& maps) {
  viz::UnstructuredGrid g;
  viz::Field level{"level", 1, {}}, sj{"scaled_jacobian", 1, {}}, comp{"component", 1, {}};
  double worst = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < ts.size(); ++c) {
    const TMesh& t = ts[c];
    const int n = 1 << t.level;
    const int base = static_cast<int>(g.points.size());
    auto node = [&](int i, int j, int k) { return base + i + (n + 1) * (j + (n + 1) * k); };
    for (int k = 0; k <= n; ++k)
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) g.points.push_back(maps[c]({double(i) / n, double(j) / n, double(k) / n}));
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          std::vector<int> cell = {node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                                   node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)};
          std::array<Vec3, 8> x;
          for (int a = 0; a < 8; ++a) x[a] = g.points[cell[a]];
          const double s = trilinear_min_scaled_jacobian(x);
          worst = std::min(worst, s);
          g.cells.push_back(cell);
          g.cell_types.push_back(12);  // VTK_HEXAHEDRON
          level.values.push_back(t.level);
          sj.values.push_back(s);
          comp.values.push_back(t.component);
        }
  }
  g.cell_fields = {level, sj, comp};
  viz::write_vtu(path, g);
  return worst;
}

}  // namespace volts::tmesh
