// Tests of surface/remesh.h: isotropic remeshing keeps the solid, its sharp edges and corners, and
// reports exactly the kept sharp edges; on generated models with and without sharp features.
#include "surface/remesh.h"

#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/compute_normal.h>

#include <cmath>
#include <set>
#include <utility>

#include "common/test_util.h"
#include "core/errors.h"

using namespace volts;
using surface::Mesh;

namespace {

double dihedral_deg(const Mesh& m, Mesh::Edge_index e) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  const auto n0 = PMP::compute_face_normal(m.face(m.halfedge(e, 0)), m);
  const auto n1 = PMP::compute_face_normal(m.face(m.halfedge(e, 1)), m);
  return std::acos(std::clamp(n0 * n1, -1.0, 1.0)) * 180 / M_PI;
}

double mean_edge_length(const Mesh& m) {
  double s = 0;
  for (auto e : m.edges()) s += std::sqrt(CGAL::squared_distance(m.point(m.vertex(e, 0)), m.point(m.vertex(e, 1))));
  return s / static_cast<double>(m.number_of_edges());
}

std::set<std::pair<int, int>> pairs(const std::vector<int>& v) {
  std::set<std::pair<int, int>> s;
  for (std::size_t i = 0; i + 1 < v.size(); i += 2) s.insert({v[i], v[i + 1]});
  return s;
}

}  // namespace

// Box: the 12 edges and 8 corners are kept where they were, the reported pairs are exactly the
// edges sharper than the threshold, and the volume is the box's (flat faces: no projection error).
TEST(RemeshIsotropic, BoxKeepsItsSharpEdgesCornersAndVolume) {
  const Mesh in = test::generated_model("box", 4);
  surface::RemeshParams p;
  p.edge_length = 0.1;  // box [-1,1] x [-0.75,0.75] x [-0.5,0.5]: resolution 4 has edges of ~0.4
  const surface::Remeshed r = surface::remesh_isotropic(in, p);
  EXPECT_TRUE(CGAL::is_closed(r.mesh));
  EXPECT_EQ(surface::genus(r.mesh), 0);
  EXPECT_NEAR(surface::signed_volume(r.mesh), 2.0 * 1.5 * 1.0, 1e-9);
  EXPECT_GT(r.mesh.number_of_faces(), 4 * in.number_of_faces());
  const double mean = mean_edge_length(r.mesh);
  EXPECT_GT(mean, 0.5 * p.edge_length);
  EXPECT_LT(mean, 1.5 * p.edge_length);
  const auto sharp = pairs(r.sharp_edge_vertices);
  EXPECT_EQ(sharp.size() * 2, r.sharp_edge_vertices.size());
  double sharp_length = 0;
  for (auto e : r.mesh.edges()) {
    int a = static_cast<int>(r.mesh.vertex(e, 0).idx()), b = static_cast<int>(r.mesh.vertex(e, 1).idx());
    if (a > b) std::swap(a, b);
    const bool is_sharp = dihedral_deg(r.mesh, e) > p.sharp_angle_deg;
    EXPECT_EQ(is_sharp, sharp.count({a, b}) == 1) << a << " " << b;
    if (is_sharp) sharp_length += std::sqrt(CGAL::squared_distance(r.mesh.point(r.mesh.vertex(e, 0)), r.mesh.point(r.mesh.vertex(e, 1))));
  }
  EXPECT_NEAR(sharp_length, 4 * (2.0 + 1.5 + 1.0), 1e-9);  // the 12 edges of the box, whole
  int corners = 0;
  for (auto v : r.mesh.vertices()) {
    const auto& x = r.mesh.point(v);
    corners += std::abs(std::abs(x.x()) - 1) < 1e-12 && std::abs(std::abs(x.y()) - 0.75) < 1e-12 && std::abs(std::abs(x.z()) - 0.5) < 1e-12;
  }
  EXPECT_EQ(corners, 8);
}

// Sphere: no sharp edge, vertices stay on the input (projection), volume within the facets' error.
TEST(RemeshIsotropic, SmoothSphereHasNoSharpEdgesAndKeepsItsVolume) {
  const Mesh in = test::generated_model("sphere", 16);
  surface::RemeshParams p;
  p.edge_length = 0.05 * surface::bbox_diagonal(in);
  const surface::Remeshed r = surface::remesh_isotropic(in, p);
  EXPECT_TRUE(r.sharp_edge_vertices.empty());
  EXPECT_EQ(surface::genus(r.mesh), 0);
  const double v0 = surface::signed_volume(in), v1 = surface::signed_volume(r.mesh);
  EXPECT_NEAR(v1 / v0, 1.0, 0.02);
  for (auto v : r.mesh.vertices()) {
    const auto& x = r.mesh.point(v);
    EXPECT_LE(std::sqrt(x.x() * x.x() + x.y() * x.y() + x.z() * x.z()), 1.0 + 1e-9);  // inside the unit sphere the facets approximate
  }
}

TEST(RemeshIsotropic, RejectsBadParameters) {
  const Mesh in = test::generated_model("box", 4);
  surface::RemeshParams p;
  EXPECT_THROW(surface::remesh_isotropic(in, p), core::InvalidInputError);  // edge length 0
  p.edge_length = std::nan("");
  EXPECT_THROW(surface::remesh_isotropic(in, p), core::InvalidInputError);
  p.edge_length = 0.1;
  p.iterations = 0;
  EXPECT_THROW(surface::remesh_isotropic(in, p), core::InvalidInputError);
}
