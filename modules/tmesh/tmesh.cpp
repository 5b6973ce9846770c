#include "tmesh/tmesh.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "bezier/bspline.h"
#include "bezier/bspline_volume.h"
#include "core/errors.h"
#include "core/log.h"
#include "tmesh/pillow.h"
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

void check(const Params& params) {
  if (params.level < 1 || params.level > 7) throw core::ConfigError("tmesh.level must be in [1, 7], got " + std::to_string(params.level));
  if (params.degree < 1 || params.degree > 5) throw core::ConfigError("tmesh.degree must be in [1, 5], got " + std::to_string(params.degree));
  if (params.pillow_layers < 0 || params.pillow_layers > 4)
    throw core::ConfigError("tmesh.pillow_layers must be in [0, 4], got " + std::to_string(params.pillow_layers));
}

}  // namespace

TMesh build_block(const PointMap& map, int degree, const std::array<int, 3>& elements) {
  TMesh t;
  t.degree = degree;
  std::array<std::vector<double>, 3> g;
  for (int a = 0; a < 3; ++a) {
    t.knots[a] = bezier::open_uniform_knots(elements[a], degree);
    g[a] = bezier::greville_abscissae(t.knots[a], degree);
    t.size[a] = static_cast<int>(g[a].size());
  }
  const std::array<std::size_t, 3> m{static_cast<std::size_t>(t.size[0]), static_cast<std::size_t>(t.size[1]),
                                     static_cast<std::size_t>(t.size[2])};
  // Sample the volume map at the Greville points, then solve N ⊗ N ⊗ N · P = D one axis at a time.
  const std::size_t total = m[0] * m[1] * m[2];
  Eigen::MatrixXd data(total, 3);
  t.parameters.resize(total);
  for (std::size_t k = 0; k < m[2]; ++k)
    for (std::size_t j = 0; j < m[1]; ++j)
      for (std::size_t i = 0; i < m[0]; ++i) {
        const std::size_t idx = i + m[0] * (j + m[1] * k);
        t.parameters[idx] = {g[0][i], g[1][j], g[2][k]};
        const Vec3 x = map(t.parameters[idx]);
        data.row(static_cast<Eigen::Index>(idx)) << x[0], x[1], x[2];
      }
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(collocation(t.knots[axis], degree, g[axis]));
    const std::size_t stride = axis == 0 ? 1 : axis == 1 ? m[0] : m[0] * m[1];
    const std::size_t n = m[axis];
    Eigen::MatrixXd line(static_cast<Eigen::Index>(n), 3);
    for (std::size_t base = 0; base < total; ++base) {
      // base runs over the lines' first points: those with index 0 along `axis`.
      if ((base / stride) % n != 0) continue;
      for (std::size_t a = 0; a < n; ++a) line.row(static_cast<Eigen::Index>(a)) = data.row(static_cast<Eigen::Index>(base + a * stride));
      const Eigen::MatrixXd solved = lu.solve(line);
      for (std::size_t a = 0; a < n; ++a) data.row(static_cast<Eigen::Index>(base + a * stride)) = solved.row(static_cast<Eigen::Index>(a));
    }
  }
  t.control_points.resize(total);
  for (std::size_t i = 0; i < total; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    t.control_points[i] = {data(r, 0), data(r, 1), data(r, 2)};
  }
  return t;
}

TMesh build(const PointMap& map, const Params& params) {
  check(params);
  const int n = 1 << params.level;
  TMesh t = build_block(map, params.degree, {n, n, n});
  t.level = params.level;
  return t;
}

namespace {

// Points equal up to `eps` get one id: a hash grid of cell 4·eps, searched in the 27 cells around.
class PointIds {
 public:
  explicit PointIds(double eps) : eps_(eps) {}
  int id(const Vec3& x) {
    const std::array<long long, 3> c{cell(x[0]), cell(x[1]), cell(x[2])};
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = grid_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid_.end()) continue;
          for (const int i : it->second)
            if (std::abs(points_[i][0] - x[0]) <= eps_ && std::abs(points_[i][1] - x[1]) <= eps_ && std::abs(points_[i][2] - x[2]) <= eps_)
              return i;
        }
    points_.push_back(x);
    grid_[c].push_back(static_cast<int>(points_.size()) - 1);
    return static_cast<int>(points_.size()) - 1;
  }

 private:
  long long cell(double v) const { return static_cast<long long>(std::floor(v / (4 * eps_))); }
  double eps_;
  std::vector<Vec3> points_;
  std::map<std::array<long long, 3>, std::vector<int>> grid_;
};

}  // namespace

std::vector<TMesh> build(const PolycubeMaps& maps, const Params& params) {
  check(params);
  const int n = 1 << params.level;
  std::vector<TMesh> blocks;
  std::vector<std::vector<Vec3>> keys;
  double extent = 0;
  const std::size_t cubes = maps.blocks.empty() ? maps.boundary.size() : maps.blocks.size();
  core::Progress progress("blocks", cubes);
  for (std::size_t k = 0; k < cubes; ++k) {
    const int cube = static_cast<int>(k);
    for (const Block& b : maps.blocks.empty() ? cube_blocks(maps.boundary[k], {n, n, n}, params.pillow_layers) : maps.blocks[k]) {
      TMesh t = build_block([&](const Vec3& uvw) { return maps.physical(cube, block_point(b.corners, uvw)); }, params.degree, b.elements);
      t.level = params.level;
      t.boundary = b.boundary;
      t.component = cube;
      t.corners = b.corners;
      t.kind = params.pillow_layers == 0 ? "cube" : b.pillow ? "pillow" : "core";
      std::vector<Vec3> key;
      for (const auto& uvw : t.parameters) {
        key.push_back(maps.polycube(cube, block_point(b.corners, uvw)));
        for (const double v : key.back()) extent = std::max(extent, std::abs(v));
      }
      keys.push_back(std::move(key));
      blocks.push_back(std::move(t));
    }
    progress.step(k);
  }
  progress.finish();
  // Shared control points: equal polycube points. Their positions agree to rounding (the same
  // face data interpolated in another order); the first block's value is kept so that the Bézier
  // elements on both sides of a block face are exactly conforming.
  PointIds ids(1e-9 * std::max(extent, 1.0));
  std::vector<Vec3> position;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    TMesh& t = blocks[b];
    t.function_ids.resize(t.control_points.size());
    for (std::size_t i = 0; i < t.control_points.size(); ++i) {
      const int id = ids.id(keys[b][i]);
      t.function_ids[i] = id;
      if (id == static_cast<int>(position.size())) position.push_back(t.control_points[i]);
      else t.control_points[i] = position[static_cast<std::size_t>(id)];
    }
  }
  return blocks;
}

const std::array<std::array<int, 3>, 8>& hex_corner_neighbours() {
  static const std::array<std::array<int, 3>, 8> nb = {{{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7}, {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}}};
  return nb;
}

double trilinear_min_scaled_jacobian(const std::array<Vec3, 8>& x) {
  const auto& nb = hex_corner_neighbours();
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
                    {"corners", t.corners}, {"kind", t.kind}, {"function_ids", t.function_ids}};
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
    if (j.contains("corners")) t.corners = j["corners"].get<std::array<Vec3, 8>>();
    // A pillowed complex of cubes (complex.h) reaches into neighbouring cubes by less than half a cube.
    for (const auto& c : t.corners)
      for (const double x : c)
        if (!(x >= -0.5 && x <= 1.5)) throw core::InvalidInputError(file + ": tmesh block corner outside [-0.5, 1.5]^3, its cube's parameters and the pillow's reach");
    if (j.contains("kind")) t.kind = j["kind"].get<std::string>();
    if (t.kind != "cube" && t.kind != "core" && t.kind != "pillow")
      throw core::InvalidInputError(file + ": unknown tmesh block kind '" + t.kind + "'");
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

namespace {

// Global id of control point i of block b (block after block when a block has no ids).
std::vector<std::vector<int>> global_ids(const std::vector<TMesh>& ts, int* count) {
  std::vector<std::vector<int>> ids(ts.size());
  int next = 0;
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const auto& t = ts[b];
    if (t.function_ids.empty()) {
      for (std::size_t i = 0; i < t.control_points.size(); ++i) ids[b].push_back(next++);
    } else {
      ids[b] = t.function_ids;
    }
  }
  int n = next;
  for (const auto& v : ids)
    for (const int i : v) n = std::max(n, i + 1);
  *count = n;
  return ids;
}

// The spline at the knot grid of t (element corners), index i + (n0+1)*(j + (n1+1)*k), and the
// number of elements per direction.
std::vector<Vec3> corner_grid(const TMesh& t, std::array<int, 3>* n) {
  bezier::TensorBSplineVolume vol;
  vol.degree = {t.degree, t.degree, t.degree};
  vol.knots = t.knots;
  for (const auto& p : t.control_points) vol.points.emplace_back(p[0], p[1], p[2]);
  std::array<std::vector<double>, 3> g;
  for (int a = 0; a < 3; ++a) {
    for (const auto& iv : bezier::element_intervals(t.knots[a], t.degree)) g[a].push_back(iv[0]);
    g[a].push_back(bezier::element_intervals(t.knots[a], t.degree).back()[1]);
    (*n)[a] = static_cast<int>(g[a].size()) - 1;
  }
  std::vector<Vec3> x;
  for (const double w : g[2])
    for (const double v : g[1])
      for (const double u : g[0]) {
        const Eigen::Vector3d p = bezier::evaluate(vol, Eigen::Vector3d(u, v, w));
        x.push_back({p[0], p[1], p[2]});
      }
  return x;
}

// Calls f(corners in VTK order) for every element of t, as a trilinear hex of its corner points.
template <class F>
void for_each_trilinear_element(const TMesh& t, F&& f) {
  std::array<int, 3> n{};
  const std::vector<Vec3> x = corner_grid(t, &n);
  auto at = [&](int i, int j, int k) { return static_cast<std::size_t>(i + (n[0] + 1) * (j + (n[1] + 1) * k)); };
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::array<std::size_t, 8> h = {at(i, j, k), at(i + 1, j, k), at(i + 1, j + 1, k), at(i, j + 1, k),
                                              at(i, j, k + 1), at(i + 1, j, k + 1), at(i + 1, j + 1, k + 1), at(i, j + 1, k + 1)};
        std::array<Vec3, 8> c;
        for (int a = 0; a < 8; ++a) c[a] = x[h[a]];
        f(c);
      }
}

}  // namespace

NodeCounts count_nodes(const std::vector<TMesh>& ts) {
  NodeCounts c;
  const auto ids = global_ids(ts, &c.nodes);
  std::vector<char> on_surface(static_cast<std::size_t>(c.nodes), 0);
  std::vector<std::set<int>> nb(static_cast<std::size_t>(c.nodes));
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const TMesh& t = ts[b];
    for (int k = 0; k < t.size[2]; ++k)
      for (int j = 0; j < t.size[1]; ++j)
        for (int i = 0; i < t.size[0]; ++i) {
          const int idx[3] = {i, j, k};
          const auto at = static_cast<std::size_t>(i + t.size[0] * (j + t.size[1] * k));
          const int id = ids[b][at];
          for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side)
              if (t.boundary[2 * a + side] && idx[a] == (side ? t.size[a] - 1 : 0)) on_surface[static_cast<std::size_t>(id)] = 1;
          for (int a = 0; a < 3; ++a) {
            if (idx[a] + 1 >= t.size[a]) continue;
            const std::size_t stride = a == 0 ? 1 : a == 1 ? static_cast<std::size_t>(t.size[0]) : static_cast<std::size_t>(t.size[0]) * t.size[1];
            const int other = ids[b][at + stride];
            if (other == id) continue;
            nb[static_cast<std::size_t>(id)].insert(other);
            nb[static_cast<std::size_t>(other)].insert(id);
          }
        }
  }
  for (int v = 0; v < c.nodes; ++v) {
    const auto& n = nb[static_cast<std::size_t>(v)];
    if (n.empty()) continue;  // an id no block uses
    if (on_surface[static_cast<std::size_t>(v)]) {
      ++c.surface;
      int on = 0;
      for (const int w : n) on += on_surface[static_cast<std::size_t>(w)];
      if (on != 4) ++c.irregular_surface;
    } else if (n.size() != 6) {
      ++c.irregular_interior;
    }
  }
  return c;
}

double min_element_scaled_jacobian(const TMesh& t) {
  double worst = std::numeric_limits<double>::infinity();
  for_each_trilinear_element(t, [&](const std::array<Vec3, 8>& c) { worst = std::min(worst, trilinear_min_scaled_jacobian(c)); });
  return worst;
}

core::Json report_figures(const std::vector<TMesh>& ts, double before, double after) {
  const NodeCounts nc = count_nodes(ts);
  std::size_t control_points = 0;
  int elements = 0, level = 0;
  std::set<int> cubes;
  for (const auto& t : ts) {
    control_points += t.control_points.size();
    elements += t.elements();
    level = std::max(level, t.level);
    cubes.insert(t.component);
  }
  return core::Json{{"nodes", nc.nodes},
                    {"control_points", control_points},
                    {"cubes", cubes.size()},
                    {"blocks", ts.size()},
                    {"elements", elements},
                    {"max_level", level},
                    {"irregular_nodes_surface", nc.irregular_surface},
                    {"irregular_nodes_interior", nc.irregular_interior},
                    {"min_scaled_jacobian_before", before},
                    {"min_scaled_jacobian_after", after}};
}

double write_vtu(const std::string& path, const std::vector<TMesh>& ts, const std::vector<std::pair<std::string, std::vector<double>>>& extra) {
  viz::UnstructuredGrid g;
  viz::Field sj{"scaled_jacobian", 1, {}}, comp{"component", 1, {}}, block{"block", 1, {}}, pillow{"pillow", 1, {}};
  double worst = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < ts.size(); ++b) {
    const TMesh& t = ts[b];
    for_each_trilinear_element(t, [&](const std::array<Vec3, 8>& c) {
      std::vector<int> cell;
      for (const auto& p : c) cell.push_back(static_cast<int>(g.points.size())), g.points.push_back(p);
      const double s = trilinear_min_scaled_jacobian(c);
      worst = std::min(worst, s);
      g.cells.push_back(cell);
      g.cell_types.push_back(12);  // VTK_HEXAHEDRON
      sj.values.push_back(s);
      comp.values.push_back(t.component);
      block.values.push_back(static_cast<double>(b));
      pillow.values.push_back(t.kind == "pillow" ? 1 : 0);
    });
  }
  g.cell_fields = {sj, comp, block, pillow};
  for (const auto& [name, values] : extra) {
    if (values.size() != g.cells.size())
      throw std::invalid_argument("tmesh.vtu: field " + name + " has " + std::to_string(values.size()) + " values for " + std::to_string(g.cells.size()) + " elements");
    g.cell_fields.push_back(viz::Field{name, 1, values});
  }
  viz::write_vtu(path, g);
  return worst;
}

}  // namespace volts::tmesh
