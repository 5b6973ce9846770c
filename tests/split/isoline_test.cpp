// Level sets inserted into the mesh (cross sections of Liu et al. §4.1): the mesh stays a valid
// closed triangle surface of the same area, no triangle is crossed by the level any more, and the
// loops have the topology the field predicts.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <set>

#include "core/errors.h"
#include "models/models.h"
#include "split/harmonic.h"
#include "split/isoline.h"

using namespace volts;
namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

surface::Mesh shared(const std::string& f) { return surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + f); }

std::vector<double> x_field(const surface::Mesh& m) {
  std::vector<double> f;
  for (auto v : m.vertices()) f.push_back(m.point(v).x());
  return f;
}

void check_mesh_and_level(const surface::Mesh& m, const std::vector<double>& f, double c) {
  ASSERT_TRUE(m.is_valid(false));
  ASSERT_EQ(f.size(), m.number_of_vertices());
  for (auto fc : m.faces()) {
    ASSERT_EQ(m.degree(fc), 3u);
    bool above = false, below = false;
    for (auto v : CGAL::vertices_around_face(m.halfedge(fc), m)) above |= f[v] > c, below |= f[v] < c;
    EXPECT_FALSE(above && below) << "a triangle is still crossed by the level";
  }
  for (auto h : m.halfedges()) ASSERT_FALSE(m.is_border(h));
}

}  // namespace

TEST(Isoline, LevelSetsOfXOnATorus) {
  // Generated torus: axis z, major radius 2, minor 0.75; f = x has its saddles at x = ±1.25.
  models::ModelParams p;
  p.name = "torus";
  p.resolution = 24;
  auto mesh = models::make_model(p);
  const double area = PMP::area(mesh);
  auto f = x_field(mesh);
  // Below the first saddle the sublevel set is a disk: one loop that separates a cap.
  const auto cap = split::insert_isoline(mesh, f, -2.0);
  check_mesh_and_level(mesh, f, -2.0);
  ASSERT_EQ(cap.size(), 1u);
  for (int v : cap[0]) {
    EXPECT_EQ(f[v], -2.0);
    EXPECT_NEAR(mesh.point(surface::Mesh::Vertex_index(v)).x(), -2.0, 1e-12);
  }
  const auto single = split::regions_cut_by(mesh, cap);
  EXPECT_EQ(*std::max_element(single.begin(), single.end()), 1);
  // Between the saddles: two meridians (around the tube), which together cut the torus in two.
  const auto meridians = split::insert_isoline(mesh, f, 0.3);
  check_mesh_and_level(mesh, f, 0.3);
  ASSERT_EQ(meridians.size(), 2u);
  const auto label = split::regions_cut_by(mesh, meridians);
  EXPECT_EQ(std::set<int>(label.begin(), label.end()).size(), 2u);
  const auto one = split::regions_cut_by(mesh, {meridians[0]});
  EXPECT_EQ(std::set<int>(one.begin(), one.end()).size(), 1u) << "one meridian does not separate a torus";
  EXPECT_NEAR(PMP::area(mesh), area, 1e-9 * area);
}

TEST(Isoline, HarmonicCrossSectionsOfARealTorus) {
  auto mesh = shared("cinolib_torus.obj");
  const double area = PMP::area(mesh);
  // Height-like harmonic field between the extreme points along x.
  int lo = 0, hi = 0;
  for (auto v : mesh.vertices()) {
    if (mesh.point(v).x() < mesh.point(surface::Mesh::Vertex_index(lo)).x()) lo = static_cast<int>(v);
    if (mesh.point(v).x() > mesh.point(surface::Mesh::Vertex_index(hi)).x()) hi = static_cast<int>(v);
  }
  auto f = split::harmonic_field(mesh, {{lo, 0.0}, {hi, 1.0}});
  const auto cp = split::critical_points(mesh, f);
  ASSERT_EQ(cp.saddles.size(), 2u);
  const double s1 = std::min(f[cp.saddles[0].first], f[cp.saddles[1].first]);
  const double s2 = std::max(f[cp.saddles[0].first], f[cp.saddles[1].first]);
  // Between min and the first saddle one loop, between the saddles two, above the second one.
  EXPECT_EQ(split::insert_isoline(mesh, f, s1 / 2).size(), 1u);
  EXPECT_EQ(split::insert_isoline(mesh, f, (s1 + s2) / 2).size(), 2u);
  EXPECT_EQ(split::insert_isoline(mesh, f, (s2 + 1) / 2).size(), 1u);
  check_mesh_and_level(mesh, f, (s2 + 1) / 2);
  EXPECT_NEAR(PMP::area(mesh), area, 1e-9 * area);
}

TEST(Isoline, FieldOfWrongSizeIsAnError) {
  auto mesh = shared("vhacd_tube1.off");
  std::vector<double> f(3, 0.0);
  EXPECT_THROW(split::insert_isoline(mesh, f, 0.5), core::InvalidInputError);
}
