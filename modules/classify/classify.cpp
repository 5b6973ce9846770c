#include "classify/classify.h"

#include <CGAL/Polygon_mesh_processing/compute_normal.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/errors.h"
#include "surface/mesh_json.h"
#include "viz/viz.h"

namespace PMP = CGAL::Polygon_mesh_processing;

namespace volts::classify {

using surface::Mesh;
using Vector = surface::Kernel::Vector_3;
using HalfedgeIndex = Mesh::Halfedge_index;
using VertexIndex = Mesh::Vertex_index;

const char* to_string(CurveKind kind) { return kind == CurveKind::feature ? "feature" : "difference"; }

int Classification::feature_curves() const {
  return static_cast<int>(std::count_if(curves.begin(), curves.end(), [](const Curve& c) { return c.kind == CurveKind::feature; }));
}
int Classification::difference_curves() const { return static_cast<int>(curves.size()) - feature_curves(); }

namespace {

constexpr double kPi = 3.14159265358979323846;

double angle_deg(const Vector& a, const Vector& b) {
  const double la = std::sqrt(a.squared_length()), lb = std::sqrt(b.squared_length());
  if (la == 0 || lb == 0) return 0;
  return std::acos(std::clamp(a * b / (la * lb), -1.0, 1.0)) * 180.0 / kPi;
}

// State of one classification run, hidden here (PMP style: the header only has free functions).
struct Classifier {
  const Mesh& mesh;
  const Params& params;
  std::vector<char> sharp;                     // per edge
  std::vector<std::vector<HalfedgeIndex>> out;  // per vertex: outgoing halfedges of sharp edges
  std::vector<char> is_corner;
  std::vector<int> edge_curve;                 // per edge: curve id or -1
  Classification result;

  Classifier(const Mesh& m, const Params& p) : mesh(m), params(p) {}

  void find_sharp_edges() {
    std::vector<Vector> normal(mesh.number_of_faces());
    for (auto f : mesh.faces()) normal[f] = PMP::compute_face_normal(f, mesh);
    sharp.assign(mesh.number_of_edges(), 0);
    out.assign(mesh.number_of_vertices(), {});
    for (auto e : mesh.edges()) {
      const HalfedgeIndex h = mesh.halfedge(e);
      const double a = angle_deg(normal[mesh.face(h)], normal[mesh.face(mesh.opposite(h))]);
      if (a > params.sharp_angle_deg) {
        sharp[e] = 1;
        out[mesh.source(h)].push_back(h);
        out[mesh.target(h)].push_back(mesh.opposite(h));
        const int a0 = static_cast<int>(mesh.source(h)), b0 = static_cast<int>(mesh.target(h));
        result.sharp_edge_vertices.push_back(std::min(a0, b0));
        result.sharp_edge_vertices.push_back(std::max(a0, b0));
      }
    }
  }

  Vector dir(HalfedgeIndex h) const { return mesh.point(mesh.target(h)) - mesh.point(mesh.source(h)); }

  void find_corners() {
    is_corner.assign(mesh.number_of_vertices(), 0);
    for (auto v : mesh.vertices()) {
      const auto& o = out[v];
      bool corner = o.size() == 1 || o.size() >= 3;  // curve end, or three or more curves meet
      if (o.size() == 2) {
        // Turning angle between the incoming and the outgoing edge of the chain.
        const Vector in = -dir(o[0]);
        corner = angle_deg(in, dir(o[1])) > params.corner_angle_deg;
      }
      if (corner) {
        is_corner[v] = 1;
        result.corners.push_back(static_cast<int>(v));
      }
    }
  }

  // Walks from halfedge h along sharp edges until a corner or back to the start.
  void trace(HalfedgeIndex h) {
    Curve c;
    const int id = static_cast<int>(result.curves.size());
    const VertexIndex start = mesh.source(h);
    c.vertices.push_back(static_cast<int>(start));
    c.patch_left = result.face_patch[mesh.face(h)];
    c.patch_right = result.face_patch[mesh.face(mesh.opposite(h))];
    for (;;) {
      edge_curve[mesh.edge(h)] = id;
      const VertexIndex t = mesh.target(h);
      if (is_corner[t] || t == start) {
        if (t == start && !is_corner[t]) c.closed = true;
        else c.vertices.push_back(static_cast<int>(t));
        break;
      }
      c.vertices.push_back(static_cast<int>(t));
      // Not a corner, so exactly two sharp edges meet here: take the other one.
      const auto& o = out[t];
      h = (mesh.edge(o[0]) == mesh.edge(h)) ? o[1] : o[0];
    }
    result.curves.push_back(std::move(c));
  }

  void find_curves() {
    edge_curve.assign(mesh.number_of_edges(), -1);
    for (int v : result.corners)
      for (HalfedgeIndex h : out[VertexIndex(v)])
        if (edge_curve[mesh.edge(h)] < 0) trace(h);
    // What is left are loops without corners: closed curves, started at their lowest vertex.
    for (auto v : mesh.vertices())
      for (HalfedgeIndex h : out[v])
        if (edge_curve[mesh.edge(h)] < 0) trace(h);
  }

  void find_patches() {
    result.face_patch.assign(mesh.number_of_faces(), -1);
    std::vector<Mesh::Face_index> stack;
    for (auto f0 : mesh.faces()) {
      if (result.face_patch[f0] >= 0) continue;
      const int id = result.patches++;
      result.face_patch[f0] = id;
      stack.push_back(f0);
      while (!stack.empty()) {
        const auto f = stack.back();
        stack.pop_back();
        for (HalfedgeIndex h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
          if (sharp[mesh.edge(h)]) continue;
          const auto g = mesh.face(mesh.opposite(h));
          if (result.face_patch[g] < 0) {
            result.face_patch[g] = id;
            stack.push_back(g);
          }
        }
      }
    }
  }

  // A curve bounding a hole of a patch is a difference curve: the patch has several boundary loops
  // and the loop's vector area points against the patch's normal (a hole runs clockwise).
  void classify_difference_curves() {
    const int np = result.patches;
    std::vector<Vector> patch_normal(np, Vector(0, 0, 0));
    std::vector<double> patch_area(np, 0.0);
    for (auto f : mesh.faces()) {
      const auto h = mesh.halfedge(f);
      const Vector n = CGAL::cross_product(mesh.point(mesh.target(h)) - mesh.point(mesh.source(h)),
                                           mesh.point(mesh.target(mesh.next(h))) - mesh.point(mesh.source(h))) / 2.0;
      patch_normal[result.face_patch[f]] += n;
      patch_area[result.face_patch[f]] += std::sqrt(n.squared_length());
    }
    auto on_boundary = [&](HalfedgeIndex h) {
      return sharp[mesh.edge(h)] && result.face_patch[mesh.face(h)] != result.face_patch[mesh.face(mesh.opposite(h))];
    };
    std::vector<char> seen(mesh.number_of_halfedges(), 0);
    std::vector<std::vector<std::pair<double, std::vector<int>>>> loops(np);  // per patch: (signed area, curves)
    for (auto h0 : mesh.halfedges()) {
      if (seen[h0] || !on_boundary(h0)) continue;
      const int p = result.face_patch[mesh.face(h0)];
      Vector area(0, 0, 0);
      std::vector<int> curves;
      HalfedgeIndex h = h0;
      do {
        seen[h] = 1;
        area = area + CGAL::cross_product(mesh.point(mesh.source(h)) - CGAL::ORIGIN, mesh.point(mesh.target(h)) - CGAL::ORIGIN) / 2.0;
        const int c = edge_curve[mesh.edge(h)];
        if (curves.empty() || curves.back() != c) curves.push_back(c);
        // Next boundary halfedge of the same patch: turn around the target inside the patch.
        HalfedgeIndex g = mesh.next(h);
        while (!on_boundary(g)) g = mesh.next(mesh.opposite(g));
        h = g;
      } while (h != h0);
      const double len = std::sqrt(patch_normal[p].squared_length());
      loops[p].push_back({len > 0 ? area * patch_normal[p] / len : 0.0, curves});
    }
    for (int p = 0; p < np; ++p) {
      auto& ls = loops[p];
      // A tube (cylinder wall) has no meaningful normal: its loops are rims, classified from the caps.
      if (ls.size() < 2 || std::sqrt(patch_normal[p].squared_length()) < 0.1 * patch_area[p]) continue;
      const auto outer = std::max_element(ls.begin(), ls.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      for (auto it = ls.begin(); it != ls.end(); ++it)
        if (it != outer)
          for (int c : it->second) result.curves[c].kind = CurveKind::difference;
    }
  }

  void find_genus() {
    const long chi = static_cast<long>(mesh.number_of_vertices()) - static_cast<long>(mesh.number_of_edges()) +
                     static_cast<long>(mesh.number_of_faces());
    result.genus = static_cast<int>((2 - chi) / 2);
  }
};

}  // namespace

Classification classify(const Mesh& mesh, const Params& params) {
  if (!(params.sharp_angle_deg > 0 && params.sharp_angle_deg < 180))
    throw core::ConfigError("classify.sharp_angle_deg must be in (0, 180)");
  if (!(params.corner_angle_deg > 0 && params.corner_angle_deg < 180))
    throw core::ConfigError("classify.corner_angle_deg must be in (0, 180)");
  Classifier c(mesh, params);
  c.find_sharp_edges();
  c.find_corners();
  c.find_patches();
  c.find_curves();
  c.classify_difference_curves();
  c.find_genus();
  return std::move(c.result);
}

core::Json to_json(const Classification& c) {
  core::Json curves = core::Json::array();
  for (const Curve& k : c.curves)
    curves.push_back({{"vertices", k.vertices}, {"closed", k.closed}, {"kind", to_string(k.kind)},
                      {"patches", {k.patch_left, k.patch_right}}});
  return core::Json{{"corners", c.corners}, {"curves", curves}, {"face_patch", c.face_patch},
                    {"patches", c.patches}, {"sharp_edges", c.sharp_edge_vertices}, {"genus", c.genus}};
}

Classification from_json(const core::Json& j, const std::string& file) {
  Classification c;
  try {
    c.corners = core::require(j, "corners", file).get<std::vector<int>>();
    c.face_patch = core::require(j, "face_patch", file).get<std::vector<int>>();
    c.patches = core::require(j, "patches", file).get<int>();
    c.sharp_edge_vertices = core::require(j, "sharp_edges", file).get<std::vector<int>>();
    c.genus = core::require(j, "genus", file).get<int>();
    for (const auto& k : core::require(j, "curves", file)) {
      Curve cv;
      cv.vertices = core::require(k, "vertices", file).get<std::vector<int>>();
      cv.closed = core::require(k, "closed", file).get<bool>();
      const std::string kind = core::require(k, "kind", file).get<std::string>();
      if (kind != "feature" && kind != "difference") throw core::InvalidInputError(file + ": unknown curve kind '" + kind + "'");
      cv.kind = kind == "feature" ? CurveKind::feature : CurveKind::difference;
      const auto pp = core::require(k, "patches", file).get<std::vector<int>>();
      if (pp.size() != 2) throw core::InvalidInputError(file + ": curve patches must be a pair");
      cv.patch_left = pp[0];
      cv.patch_right = pp[1];
      c.curves.push_back(std::move(cv));
    }
  } catch (const core::Json::exception& e) {
    throw core::InvalidInputError(file + ": malformed classification: " + e.what());
  }
  return c;
}

core::Json report_figures(const Classification& c) {
  return core::Json{{"corners", c.corners.size()},
                    {"curves", c.curves.size()},
                    {"feature_curves", c.feature_curves()},
                    {"difference_curves", c.difference_curves()},
                    {"patches", c.patches},
                    {"sharp_edges", c.sharp_edge_vertices.size() / 2},
                    {"genus", c.genus}};
}

void write_vtp(const std::string& path, const Mesh& mesh, const Classification& c) {
  viz::PolyData d;
  d.points = surface::vertex_array(mesh);
  viz::Field patch{"patch_id", 1, {}}, curve{"curve_id", 1, {}}, kind{"curve_kind", 1, {}}, corner{"corner_id", 1, {}};
  auto push = [&](double p, double cu, double k, double co) {
    patch.values.push_back(p);
    curve.values.push_back(cu);
    kind.values.push_back(k);
    corner.values.push_back(co);
  };
  for (std::size_t i = 0; i < c.corners.size(); ++i) {
    d.verts.push_back({c.corners[i]});
    push(-1, -1, -1, double(i));
  }
  for (std::size_t i = 0; i < c.curves.size(); ++i) {
    auto line = c.curves[i].vertices;
    if (c.curves[i].closed) line.push_back(line.front());
    d.lines.push_back(line);
    push(-1, double(i), c.curves[i].kind == CurveKind::feature ? 0 : 1, -1);
  }
  d.polys = surface::triangle_array(mesh);
  for (auto f : mesh.faces()) push(c.face_patch[f], -1, -1, -1);
  d.cell_fields = {patch, curve, kind, corner};
  viz::write_vtp(path, d);
}

}  // namespace volts::classify
