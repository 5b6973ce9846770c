// Tests of volts::models: every model at several resolutions is a valid closed surface of the right
// genus whose volume converges to the analytic one, with exactly the sharp edges it should have.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numeric>

#include "core/errors.h"
#include "models/models.h"

namespace {

using volts::models::make_model;
using volts::models::ModelParams;
using volts::surface::Mesh;
using Vector = volts::surface::Kernel::Vector_3;
namespace PMP = CGAL::Polygon_mesh_processing;

const double kPi = std::acos(-1.0);
const int kResolutions[] = {4, 8, 16};

Mesh make(const std::string& name, int resolution) {
  ModelParams p;
  p.name = name;
  p.resolution = resolution;
  return make_model(p);
}

// --- What the header promises about each model --------------------------------------------------

const std::array<double, 3> kBoxHalf = {1.0, 0.75, 0.5};

double bulged_box_volume(double bulge) {
  // Each face (sides 2h_b x 2h_c) adds the integral of a sin(pi s) sin(pi t): a * area * (2/pi)^2.
  double v = 8 * kBoxHalf[0] * kBoxHalf[1] * kBoxHalf[2];
  for (int a = 0; a < 3; ++a) {
    const double hb = kBoxHalf[(a + 1) % 3], hc = kBoxHalf[(a + 2) % 3];
    v += 2 * bulge * std::min(hb, hc) * (4 * hb * hc) * 4 / (kPi * kPi);
  }
  return v;
}

double analytic_volume(const std::string& name) {
  if (name == "box") return bulged_box_volume(0.0);
  if (name == "bulged-box") return bulged_box_volume(ModelParams().bulge);
  if (name == "torus") return 2 * kPi * kPi * 2.0 * 0.75 * 0.75;
  if (name == "cube-with-hole") return 8.0 - kPi * 0.7 * 0.7 * 2.0;
  if (name == "sphere") return 4.0 / 3.0 * kPi;
  if (name == "tetrahedron") return 8.0 / 3.0;
  if (name == "cone") return kPi * 1.0 * 1.5 / 3.0;
  ADD_FAILURE() << "no analytic volume for " << name;
  return 0.0;
}

int expected_genus(const std::string& name) { return name == "torus" || name == "cube-with-hole" ? 1 : 0; }

// --- Measures --------------------------------------------------------------------------------------

/// Angle in degrees between the normals of the two faces of an edge (0 = flat).
double dihedral_deviation(const Mesh& mesh, Mesh::Edge_index e) {
  const auto h = mesh.halfedge(e);
  const Vector n0 = PMP::compute_face_normal(mesh.face(h), mesh);
  const Vector n1 = PMP::compute_face_normal(mesh.face(mesh.opposite(h)), mesh);
  return std::acos(std::clamp(n0 * n1, -1.0, 1.0)) * 180.0 / kPi;
}

std::vector<Mesh::Edge_index> sharp_edges(const Mesh& mesh) {
  std::vector<Mesh::Edge_index> sharp;
  for (const auto e : mesh.edges())
    if (dihedral_deviation(mesh, e) > 30.0) sharp.push_back(e);
  return sharp;
}

double edge_length(const Mesh& mesh, Mesh::Edge_index e) {
  return std::sqrt(CGAL::squared_distance(mesh.point(mesh.vertex(e, 0)), mesh.point(mesh.vertex(e, 1))));
}

double min_angle_deg(const Mesh& mesh) {
  double smallest = 180.0;
  for (const auto f : mesh.faces()) {
    std::vector<volts::surface::Point> p;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) p.push_back(mesh.point(v));
    for (int k = 0; k < 3; ++k)
      smallest = std::min(smallest, CGAL::approximate_angle(p[(k + 1) % 3], p[k], p[(k + 2) % 3]));
  }
  return smallest;
}

std::filesystem::path temp_dir() {
  const auto dir = std::filesystem::path(VOLTS_BINARY_DIR) / "test_models_tmp";
  std::filesystem::create_directories(dir);
  return dir;
}

// --- Tests -----------------------------------------------------------------------------------------

TEST(Models, EveryModelIsAValidClosedSurfaceOfItsGenus) {
  for (const auto& name : volts::models::model_names())
    for (const int r : kResolutions) {
      SCOPED_TRACE(name + " at resolution " + std::to_string(r));
      const Mesh mesh = make(name, r);
      // Written and read back: read_surface validates (closed, manifold, oriented, no degenerate faces).
      const auto path = (temp_dir() / (name + "-" + std::to_string(r) + ".off")).string();
      volts::surface::write_surface(path, mesh);
      volts::surface::ReadInfo info;
      const Mesh back = volts::surface::read_surface(path, &info);
      EXPECT_FALSE(info.flipped) << "inward";
      EXPECT_EQ(info.welded_vertices, 0u) << "coincident vertices";
      EXPECT_EQ(back.number_of_vertices(), mesh.number_of_vertices());
      EXPECT_EQ(back.number_of_faces(), mesh.number_of_faces());
      EXPECT_TRUE(CGAL::is_closed(mesh));
      EXPECT_TRUE(CGAL::is_triangle_mesh(mesh));
      EXPECT_EQ(volts::surface::genus(mesh), expected_genus(name));
      EXPECT_GT(volts::surface::signed_volume(mesh), 0.0) << "not outward";
      EXPECT_FALSE(PMP::does_self_intersect(mesh));
    }
}

TEST(Models, VolumeConvergesToTheAnalyticVolume) {
  for (const auto& name : volts::models::model_names()) {
    SCOPED_TRACE(name);
    const double exact = analytic_volume(name);
    std::map<int, double> err;
    for (const int r : {4, 8, 16, 32}) {
      const double v = volts::surface::signed_volume(make(name, r));
      err[r] = std::abs(v - exact) / exact;
      // Vertices lie on the exact surface: a convex solid's polyhedron is inscribed (smaller); the hole's
      // prism is inscribed in its cylinder, so the cube with a hole is larger.
      if (name == "bulged-box" || name == "sphere" || name == "cone") {
        EXPECT_LT(v, exact) << r;
      } else if (name == "cube-with-hole") {
        EXPECT_GT(v, exact) << r;
      } else if (name == "box" || name == "tetrahedron") {
        EXPECT_LT(err[r], 1e-12) << r;  // polyhedra are exact
      }
      EXPECT_LT(err[r], 20.0 / (r * r)) << r;  // second order in the segment length
    }
    if (name != "box" && name != "tetrahedron") {
      EXPECT_LT(err[32], err[8] / 8) << "not converging";
    }
  }
}

TEST(Models, BulgeIsRelativeToHalfTheShorterSideOfEachFace) {
  ModelParams p;
  p.bulge = 0.3;
  const Mesh mesh = make_model(p);  // resolution 16: every face has a centre vertex
  std::array<double, 3> extent{};
  for (const auto v : mesh.vertices())
    for (int a = 0; a < 3; ++a) extent[a] = std::max(extent[a], std::abs(mesh.point(v)[a]));
  for (int a = 0; a < 3; ++a) {
    const double shorter = std::min(kBoxHalf[(a + 1) % 3], kBoxHalf[(a + 2) % 3]);
    EXPECT_DOUBLE_EQ(extent[a], kBoxHalf[a] + p.bulge * shorter) << "axis " << a;
  }
}

TEST(Models, BoxLikeModelsAreSharpExactlyAlongTheirEdges) {
  // Sharp edges = total edge length / segment length: box 4 (2 + 1.5 + 1) / (2 / r) = 9 r;
  // tetrahedron 6 r. Every other edge is clearly smooth.
  const std::map<std::string, int> sharp_per_resolution = {{"box", 9}, {"bulged-box", 9}, {"tetrahedron", 6}};
  for (const auto& [name, per_r] : sharp_per_resolution)
    for (const int r : kResolutions) {
      SCOPED_TRACE(name + " at resolution " + std::to_string(r));
      const Mesh mesh = make(name, r);
      double min_sharp = 180.0, max_smooth = 0.0;
      int sharp = 0;
      for (const auto e : mesh.edges()) {
        const double d = dihedral_deviation(mesh, e);
        if (d > 30.0) {
          ++sharp;
          min_sharp = std::min(min_sharp, d);
        } else {
          max_smooth = std::max(max_smooth, d);
        }
      }
      EXPECT_EQ(sharp, per_r * r);
      EXPECT_GT(min_sharp, 45.0);
      EXPECT_LT(max_smooth, 20.0);
    }
}

TEST(Models, BoxEdgesAreExactlyStraight) {
  for (const std::string name : {"box", "bulged-box"}) {
    const Mesh mesh = make(name, 16);
    for (const auto e : sharp_edges(mesh))
      for (int k = 0; k < 2; ++k) {
        const auto& p = mesh.point(mesh.vertex(e, k));
        int on_faces = 0;
        for (int a = 0; a < 3; ++a) on_faces += std::abs(p[a]) == kBoxHalf[a];
        EXPECT_GE(on_faces, 2) << name << ": sharp edge vertex " << p << " off the box edges";
      }
  }
}

TEST(Models, SmoothModelsTurnAboutOneSegmentAngleAtMost) {
  // The tightest circle has r segments: no edge turns much more than 360 / r degrees (a little more
  // across the diagonals of non-planar quads), so from r = 16 on nothing is sharp.
  for (const std::string name : {"torus", "sphere"})
    for (const int r : kResolutions) {
      const Mesh mesh = make(name, r);
      double max_dev = 0.0;
      for (const auto e : mesh.edges()) max_dev = std::max(max_dev, dihedral_deviation(mesh, e));
      EXPECT_LE(max_dev, 360.0 / r * 1.05) << name << " at resolution " << r;
      if (r >= 16) {
        EXPECT_TRUE(sharp_edges(mesh).empty()) << name << " at resolution " << r;
      }
    }
}

TEST(Models, CubeWithHoleHasTheSharpFeaturesOfFig3) {
  const double radius = 0.7;
  for (const int r : {4, 8, 12, 16}) {
    SCOPED_TRACE("resolution " + std::to_string(r));
    const Mesh mesh = make("cube-with-hole", r);
    const auto sharp = sharp_edges(mesh);

    std::map<Mesh::Vertex_index, int> degree;
    for (const auto e : sharp) ++degree[mesh.vertex(e, 0)], ++degree[mesh.vertex(e, 1)];
    int corners = 0;
    for (const auto& [v, d] : degree) {
      if (d == 2) continue;
      ++corners;
      EXPECT_EQ(d, 3);
      const auto& p = mesh.point(v);
      EXPECT_TRUE(std::abs(p.x()) == 1 && std::abs(p.y()) == 1 && std::abs(p.z()) == 1) << "corner at " << p;
    }
    EXPECT_EQ(corners, 8);

    // Each sharp edge lies on a cube edge or on a rim (the inscribed polygon of the hole's circle).
    double cube_length = 0.0, rim_length = 0.0;
    int cube_segments = 0;
    for (const auto e : sharp) {
      const auto& p = mesh.point(mesh.vertex(e, 0));
      const auto& q = mesh.point(mesh.vertex(e, 1));
      int on_faces = 0;
      for (int a = 0; a < 3; ++a) on_faces += std::abs(p[a]) == 1 && p[a] == q[a];
      if (on_faces >= 2) {
        cube_length += edge_length(mesh, e);
        ++cube_segments;
        continue;
      }
      for (const auto& x : {p, q}) {  // the rim has at least 2 r segments
        EXPECT_EQ(std::abs(x.z()), 1.0) << "rim vertex " << x << " off the cube's faces";
        EXPECT_GE(std::hypot(x.x(), x.y()), radius * std::cos(kPi / (2 * r)) - 1e-12) << x;
        EXPECT_LE(std::hypot(x.x(), x.y()), radius + 1e-12) << x;
      }
      rim_length += edge_length(mesh, e);
    }
    EXPECT_NEAR(cube_length, 24.0, 1e-9);
    EXPECT_EQ(cube_segments, 12 * r);  // r segments along each cube edge, as in the box
    EXPECT_NEAR(rim_length, 2 * 2 * kPi * radius, 2 * 2 * kPi * radius * 0.01);

    // 14 curves (Fig. 3): 12 cube edges between corners and 2 closed rims. Count the components of the
    // sharp edges joined at non-corner vertices (union-find over edges).
    std::vector<std::size_t> up(sharp.size());
    std::iota(up.begin(), up.end(), 0);
    const std::function<std::size_t(std::size_t)> find = [&](std::size_t i) {
      return up[i] == i ? i : up[i] = find(up[i]);
    };
    std::map<Mesh::Vertex_index, std::size_t> first_edge;
    for (std::size_t i = 0; i < sharp.size(); ++i)
      for (int k = 0; k < 2; ++k) {
        const auto v = mesh.vertex(sharp[i], k);
        if (degree[v] != 2) continue;
        const auto [it, inserted] = first_edge.try_emplace(v, i);
        if (!inserted) up[find(i)] = find(it->second);
      }
    int curves = 0;
    for (std::size_t i = 0; i < sharp.size(); ++i) curves += find(i) == i;
    EXPECT_EQ(curves, 14);
  }
}

TEST(Models, TrianglesAreReasonablyShaped) {
  for (const auto& name : volts::models::model_names())
    for (const int r : kResolutions) EXPECT_GT(min_angle_deg(make(name, r)), 20.0) << name << " at " << r;
}

TEST(Models, SameParametersGiveTheSameMesh) {
  // Built again after other models (allocator state differs: the Boolean's output order depends on it).
  const auto names = volts::models::model_names();
  std::vector<Mesh> first;
  for (const auto& name : names) first.push_back(make(name, 8));
  for (std::size_t k = names.size(); k-- > 0;) {
    const Mesh& a = first[k];
    make(names[k], 4);
    const Mesh b = make(names[k], 8);
    ASSERT_EQ(a.number_of_vertices(), b.number_of_vertices()) << names[k];
    ASSERT_EQ(a.number_of_faces(), b.number_of_faces()) << names[k];
    for (const auto v : a.vertices()) ASSERT_EQ(a.point(v), b.point(v)) << names[k];
    for (const auto f : a.faces()) {
      const auto va = CGAL::vertices_around_face(a.halfedge(f), a);
      const auto vb = CGAL::vertices_around_face(b.halfedge(f), b);
      ASSERT_TRUE(std::equal(va.begin(), va.end(), vb.begin(), vb.end())) << names[k];
    }
  }
}

TEST(Models, BadParametersAreConfigErrors) {
  ModelParams p;
  p.name = "klein-bottle";
  try {
    make_model(p);
    FAIL() << "no error";
  } catch (const volts::core::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown model 'klein-bottle'"), std::string::npos) << what;
    for (const auto& name : volts::models::model_names()) EXPECT_NE(what.find(name), std::string::npos) << what;
  }
  EXPECT_THROW(volts::models::model_description("klein-bottle"), volts::core::ConfigError);
  for (const int r : {-1, 0, 3, 513}) {
    ModelParams q;
    q.resolution = r;
    EXPECT_THROW(make_model(q), volts::core::ConfigError) << r;
  }
  for (const double b : {-0.1, 0.5, std::nan("")}) {
    ModelParams q;
    q.bulge = b;
    EXPECT_THROW(make_model(q), volts::core::ConfigError) << b;
  }
  for (const auto& name : volts::models::model_names()) EXPECT_FALSE(volts::models::model_description(name).empty());
}

}  // namespace
