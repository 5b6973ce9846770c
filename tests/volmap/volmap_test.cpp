// Volume map (Liu et al. 2013 §4.3): harmonic tet map onto a polycube embedding, untangling, point
// location. Cases the polycube stage meets: box-like solids onto the unit cube (boundary from
// polycube::map_surface), a sphere onto the cube, tori onto a square ring (non-convex).
#include <gtest/gtest.h>

#include <CGAL/Side_of_triangle_mesh.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <random>

#include "classify/classify.h"
#include "common/test_util.h"
#include "core/errors.h"
#include "polycube/polycube.h"
#include "split/split.h"
#include "volmap/volmap.h"

using namespace volts;
using volmap::VolumeMap;
using UVW = std::array<double, 3>;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Square ring: outer [-2,2]^2, inner [-1,1]^2, height [0,1].
bool in_ring(const UVW& p) {
  return std::abs(p[0]) <= 2 && std::abs(p[1]) <= 2 && p[2] >= 0 && p[2] <= 1 && !(std::abs(p[0]) < 1 && std::abs(p[1]) < 1);
}

// Position s in [0,1) along a closed square loop with corners c[0..3] at s = 0, 1/4, 1/2, 3/4.
std::array<double, 2> on_loop(double s, const std::array<std::array<double, 2>, 4>& c) {
  const int k = std::min(3, static_cast<int>(std::floor(4 * s)));
  const double f = 4 * s - k;
  const auto &a = c[k], &b = c[(k + 1) % 4];
  return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])};
}

// Angle in [0,1) turns, measured from 45 degrees and snapped to 1/5760 turn (both tori's grid
// angles are multiples of it), so the ring's corners fall exactly on grid lines.
double turns_from_45(double angle) {
  double s = angle / (2 * kPi) - 0.125;
  s -= std::floor(s);
  s = std::round(s * 5760) / 5760;
  return s >= 1 ? s - 1 : s;
}

// Bijection of a grid torus about z (major radius R) onto the square ring's boundary: the angle
// around z runs along the ring's loop, the angle around the tube around the ring's cross-section
// (outer-top corner at 45 degrees), both with corners on grid lines.
std::vector<UVW> ring_boundary_map(const surface::Mesh& s, double R) {
  std::vector<UVW> r(s.number_of_vertices());
  for (auto v : s.vertices()) {
    const auto& p = s.point(v);
    const double theta = std::atan2(p.y(), p.x());
    const double phi = std::atan2(p.z(), std::hypot(p.x(), p.y()) - R);
    const auto hz = on_loop(turns_from_45(phi), {{{2, 1}, {1, 1}, {1, 0}, {2, 0}}});
    const double h = hz[0];
    const auto xy = on_loop(turns_from_45(theta), {{{h, h}, {-h, h}, {-h, -h}, {h, -h}}});
    r[static_cast<int>(v)] = {xy[0], xy[1], hz[1]};
  }
  return r;
}

// Radial projection of the (cube-grid) sphere onto the cube [0,1]^3; grid vertices land exactly on
// the cube's faces and edges.
std::vector<UVW> cube_boundary_map(const surface::Mesh& s) {
  std::vector<UVW> r(s.number_of_vertices());
  for (auto v : s.vertices()) {
    const auto& p = s.point(v);
    const double m = std::max({std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
    UVW q{p.x() / m, p.y() / m, p.z() / m};
    for (double& c : q) {
      if (std::abs(std::abs(c) - 1) < 1e-9) c = c > 0 ? 1 : -1;
      c = (c + 1) / 2;
    }
    r[static_cast<int>(v)] = q;
  }
  return r;
}

// Box-like solid: the polycube stage's own surface map onto the unit cube.
std::vector<UVW> polycube_boundary_map(const surface::Mesh& s) {
  const auto c = classify::classify(s, {});
  const auto d = split::split(s, c, {});
  const auto p = polycube::map_surface(s, c, d, {});
  EXPECT_EQ(p.flipped_surface_triangles, 0);
  return p.vertex_uvw;
}

// Each mapped surface triangle lies in one face of the domain (it shares a coordinate plane), so the
// parameter domain is exactly the cube or ring (a sanity check of the boundary maps above).
void expect_triangles_on_faces(const surface::Mesh& s, const std::vector<UVW>& sp) {
  int off = 0;
  for (auto f : s.faces()) {
    std::vector<UVW> q;
    for (auto v : vertices_around_face(s.halfedge(f), s)) q.push_back(sp[static_cast<int>(v)]);
    bool on = false;
    for (int a = 0; a < 3; ++a) on = on || (q[0][a] == q[1][a] && q[1][a] == q[2][a]);
    off += !on;
  }
  EXPECT_EQ(off, 0);
}

struct Case {
  std::string name;
  surface::Mesh mesh;
  std::vector<UVW> sp;
  bool ring = false;  // else the unit cube
  volmap::Params params;
};

Case make_case(const std::string& name) {
  Case c;
  c.name = name;
  if (name == "box" || name == "bulged-box") {
    c.mesh = test::generated_model(name, 12);
    c.sp = polycube_boundary_map(c.mesh);
  } else if (name == "sphere") {
    c.mesh = test::generated_model("sphere", 32);
    c.sp = cube_boundary_map(c.mesh);
  } else if (name == "torus" || name == "torus-fine" || name == "torus-48") {
    // 64 x 24 (128 x 48) grid: corners on grid lines
    c.mesh = test::generated_model("torus", name == "torus-48" ? 48 : 24);
    c.sp = ring_boundary_map(c.mesh, 2.0);
    c.ring = true;
    if (name == "torus-fine") c.params.tetgen.max_volume_rel = 1e-4;  // ~18,000 tets, more interior points
  } else {
    c.mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/cinolib_torus.obj");  // R = 3, r = 1.25, 48 x 16 grid
    c.sp = ring_boundary_map(c.mesh, 3.0);
    c.ring = true;
  }
  return c;
}

UVW random_point(std::mt19937& rng, bool ring) {
  if (!ring) {
    std::uniform_real_distribution<double> u(0, 1);
    return {u(rng), u(rng), u(rng)};
  }
  std::uniform_real_distribution<double> xy(-2, 2), z(0, 1);
  for (;;) {
    UVW p{xy(rng), xy(rng), z(rng)};
    if (in_ring(p)) return p;
  }
}

class VolumeMapCase : public ::testing::TestWithParam<std::string> {};

}  // namespace

// 0 flipped tets after untangling; the map is one-to-one: 10,000 random parameter points each lie
// in exactly one mapped tet and map into the physical solid; the mapped tets fill the domain.
TEST_P(VolumeMapCase, UntangledAndOneToOne) {
  const Case c = make_case(GetParam());
  expect_triangles_on_faces(c.mesh, c.sp);
  const VolumeMap m = volmap::harmonic_volume_map(c.mesh, c.sp, c.params);
  std::cout << "[ figures  ] " << c.name << ": " << volmap::report_figures(m).dump() << "\n";
  RecordProperty("flipped_before", m.flipped_tets_before_untangling);
  EXPECT_EQ(m.flipped_tets, 0);
  EXPECT_GT(m.min_volume_ratio, 0);
  double vol = 0;
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) vol += volmap::parameter_volume(m, t);
  EXPECT_NEAR(vol, c.ring ? 12.0 : 1.0, 1e-9);
  EXPECT_NEAR(m.parameter_volume, c.ring ? 12.0 : 1.0, 1e-9);

  // Boundary vertices keep their ids, physical positions and parameters exactly.
  ASSERT_EQ(m.surface_vertices, static_cast<int>(c.mesh.number_of_vertices()));
  for (auto v : c.mesh.vertices()) {
    const int i = static_cast<int>(v);
    const auto& p = c.mesh.point(v);
    EXPECT_TRUE(m.physical[i] == Eigen::Vector3d(p.x(), p.y(), p.z())) << i;
    EXPECT_TRUE(m.parameter[i] == Eigen::Vector3d(c.sp[i][0], c.sp[i][1], c.sp[i][2])) << i;
  }

  const volmap::Locator loc(m);
  CGAL::Side_of_triangle_mesh<surface::Mesh, surface::Kernel> inside(c.mesh);
  std::mt19937 rng(7);
  int not_one = 0, outside = 0;
  for (int k = 0; k < 10000; ++k) {
    const UVW u = random_point(rng, c.ring);
    const auto tets = loc.tets_containing(u, 1e-12);
    not_one += tets.size() != 1;
    const auto x = loc.physical(u);
    ASSERT_TRUE(x.has_value());
    outside += inside(surface::Point((*x)[0], (*x)[1], (*x)[2])) == CGAL::ON_UNBOUNDED_SIDE;
  }
  EXPECT_EQ(not_one, 0);
  EXPECT_EQ(outside, 0);
}

INSTANTIATE_TEST_SUITE_P(Models, VolumeMapCase, ::testing::Values("box", "bulged-box", "sphere", "torus", "torus-fine", "torus-48", "cinolib-torus"),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

// A linear boundary condition is reproduced exactly inside: the cotangent Laplacian is the P1
// stiffness matrix, whose harmonic functions include the affine ones.
TEST(HarmonicVolumeMap, ReproducesAffineMaps) {
  const surface::Mesh s = test::generated_model("torus", 12);
  Eigen::Matrix3d A;
  A << 1.0, 0.3, -0.2, 0.1, 0.8, 0.4, -0.3, 0.2, 1.5;
  const Eigen::Vector3d b(0.5, -1.0, 2.0);
  std::vector<UVW> sp;
  for (auto v : s.vertices()) {
    const auto& p = s.point(v);
    const Eigen::Vector3d q = A * Eigen::Vector3d(p.x(), p.y(), p.z()) + b;
    sp.push_back({q[0], q[1], q[2]});
  }
  const VolumeMap m = volmap::harmonic_volume_map(s, sp, {});
  EXPECT_EQ(m.flipped_tets_before_untangling, 0);
  EXPECT_EQ(m.flipped_tets, 0);
  ASSERT_GT(m.physical.size(), static_cast<std::size_t>(m.surface_vertices));
  double err = 0;
  for (std::size_t i = 0; i < m.physical.size(); ++i) err = std::max(err, (m.parameter[i] - (A * m.physical[i] + b)).norm());
  EXPECT_LE(err, 1e-9);
  EXPECT_NEAR(m.min_volume_ratio, 1.0, 1e-9);
}

// The harmonic map folds tets at the ring's concave inner edges; untangling is what unfolds them.
TEST(HarmonicVolumeMap, UntanglingUnfoldsTheRingsInnerEdges) {
  Case c = make_case("torus-fine");
  const VolumeMap m = volmap::harmonic_volume_map(c.mesh, c.sp, c.params);
  EXPECT_GT(m.flipped_tets_before_untangling, 0);
  EXPECT_EQ(m.flipped_tets, 0);
  c.params.untangle_max_sweeps = 0;
  const VolumeMap raw = volmap::harmonic_volume_map(c.mesh, c.sp, c.params);
  EXPECT_EQ(raw.flipped_tets, m.flipped_tets_before_untangling);
  EXPECT_LE(raw.min_volume_ratio, 0);
  // Both say why untangling stopped: the bound of 0 sweeps left the folds.
  EXPECT_EQ(raw.untangle_stop, "sweep_bound");
  EXPECT_TRUE(m.untangle_stop == "done" || m.untangle_stop == "stalled") << m.untangle_stop;
  // Untangling moves interior points only.
  ASSERT_EQ(raw.parameter.size(), m.parameter.size());
  for (int i = 0; i < m.surface_vertices; ++i) EXPECT_TRUE(raw.parameter[i] == m.parameter[i]);
  // Uniform weights fold more, and are untangled too.
  c.params = {};
  c.params.laplacian = "uniform";
  const VolumeMap u = volmap::harmonic_volume_map(c.mesh, c.sp, c.params);
  std::cout << "[ figures  ] torus, uniform weights: " << volmap::report_figures(u).dump() << "\n";
  EXPECT_EQ(u.flipped_tets, 0);
}

// Untangling leaves the map barely positive where it unfolded tets; smoothing (per-vertex descent
// of the foldover-free energy as a barrier) spreads that distortion without flipping anything or
// moving the surface. Figure: tets whose volume ratio (relative to the mean) is below 0.05.
TEST(HarmonicVolumeMap, SmoothingSpreadsTheDistortionOfAnUntangledMap) {
  Case c = make_case("torus-48");
  c.params.smooth_below_ratio = 0.5;  // whatever untangling leaves, so the test does not hang on its figure
  c.params.smooth_sweeps = 10;        // enough to show it
  const VolumeMap smooth = volmap::harmonic_volume_map(c.mesh, c.sp, c.params);
  c.params.smooth_sweeps = 0;
  const VolumeMap raw = volmap::harmonic_volume_map(c.mesh, c.sp, c.params);
  ASSERT_GT(raw.flipped_tets_before_untangling, 0);
  EXPECT_EQ(raw.flipped_tets, 0);
  EXPECT_EQ(smooth.flipped_tets, 0);
  EXPECT_EQ(smooth.min_volume_ratio_before_smoothing, raw.min_volume_ratio);
  EXPECT_GE(smooth.min_volume_ratio, raw.min_volume_ratio);
  EXPECT_EQ(raw.smooth_sweeps, 0);
  EXPECT_GT(smooth.smooth_sweeps, 0);
  ASSERT_EQ(raw.parameter.size(), smooth.parameter.size());
  for (int i = 0; i < smooth.surface_vertices; ++i) EXPECT_TRUE(raw.parameter[i] == smooth.parameter[i]) << i;
  const auto thin = [](const VolumeMap& m) {
    double phys = 0;
    std::vector<double> pv;
    for (const auto& t : m.tets) {
      pv.push_back(tetmesh::signed_volume6(m.physical[t[0]], m.physical[t[1]], m.physical[t[2]], m.physical[t[3]]) / 6);
      phys += pv.back();
    }
    int n = 0;
    for (int t = 0; t < static_cast<int>(m.tets.size()); ++t)
      n += volmap::parameter_volume(m, t) / pv[t] * (phys / m.parameter_volume) < 0.05;
    return n;
  };
  const int before = thin(raw), after = thin(smooth);
  std::cout << "[ figures  ] torus-48: tets with volume ratio < 0.05: " << before << " -> " << after << " of " << raw.tets.size()
            << "; min volume ratio " << raw.min_volume_ratio << " -> " << smooth.min_volume_ratio << "\n";
  EXPECT_LT(after, before);
}

TEST(HarmonicVolumeMap, UniformWeightsAlsoUntangle) {
  const Case c = make_case("box");
  volmap::Params p;
  p.laplacian = "uniform";
  const VolumeMap m = volmap::harmonic_volume_map(c.mesh, c.sp, p);
  EXPECT_EQ(m.flipped_tets, 0);
}

TEST(HarmonicVolumeMap, BadInputIsATypedError) {
  const Case c = make_case("sphere");
  auto sp = c.sp;
  sp.pop_back();
  try {
    volmap::harmonic_volume_map(c.mesh, sp, {});
    FAIL();
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("surface_parameter has"), std::string::npos) << e.what();
  }
  sp = c.sp;
  sp[3][1] = std::nan("");
  try {
    volmap::harmonic_volume_map(c.mesh, sp, {});
    FAIL();
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("surface_parameter[3] is not finite"), std::string::npos) << e.what();
  }
  sp = c.sp;
  for (auto& u : sp) u[0] = -u[0];  // mirrored: encloses negative volume
  EXPECT_THROW(volmap::harmonic_volume_map(c.mesh, sp, {}), core::InvalidInputError);
  volmap::Params p;
  p.laplacian = "cotan";
  EXPECT_THROW(volmap::harmonic_volume_map(c.mesh, c.sp, p), core::ConfigError);
  p = {};
  p.tetgen.keep_boundary = false;
  EXPECT_THROW(volmap::harmonic_volume_map(c.mesh, c.sp, p), core::ConfigError);
  p = {};
  p.untangle_max_sweeps = -1;
  EXPECT_THROW(volmap::harmonic_volume_map(c.mesh, c.sp, p), core::ConfigError);
}

// Surface vertices locate onto their own positions; points just outside snap, far ones do not; a
// point on a shared face always gets the lowest-index tet.
TEST(Locator, ExactAtVerticesSnapsNearAndRefusesFar) {
  const Case c = make_case("sphere");
  const VolumeMap m = volmap::harmonic_volume_map(c.mesh, c.sp, {});
  const volmap::Locator loc(m);
  double err = 0;
  for (std::size_t i = 0; i < m.parameter.size(); ++i) {
    const auto x = loc.physical({m.parameter[i][0], m.parameter[i][1], m.parameter[i][2]});
    ASSERT_TRUE(x.has_value()) << i;
    err = std::max(err, (Eigen::Vector3d((*x)[0], (*x)[1], (*x)[2]) - m.physical[i]).norm());
  }
  EXPECT_LE(err, 1e-9);
  // Points given by barycentric coordinates in a known tet come back at the same combination of its
  // physical corners (the inverse of the piecewise-linear map).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u01(0, 1);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(m.tets.size()) - 1);
  err = 0;
  for (int k = 0; k < 2000; ++k) {
    const auto& t = m.tets[pick(rng)];
    double b[4], sum = 0;
    for (double& x : b) sum += (x = u01(rng) + 1e-3);
    Eigen::Vector3d uvw = Eigen::Vector3d::Zero(), xyz = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) uvw += b[j] / sum * m.parameter[t[j]], xyz += b[j] / sum * m.physical[t[j]];
    const auto x = loc.physical({uvw[0], uvw[1], uvw[2]});
    ASSERT_TRUE(x.has_value());
    err = std::max(err, (Eigen::Vector3d((*x)[0], (*x)[1], (*x)[2]) - xyz).norm());
  }
  EXPECT_LE(err, 1e-9);
  EXPECT_TRUE(loc.physical({0.5, 0.5, 1 + 1e-9}).has_value());
  EXPECT_TRUE(loc.physical({-1e-8, 0.3, 0.7}).has_value());
  EXPECT_FALSE(loc.physical({0.5, 0.5, 1.01}).has_value());
  EXPECT_FALSE(loc.physical({3, 3, 3}).has_value());
  EXPECT_EQ(loc.containing_tet({5, 0, 0}), -1);
  // Centroid of the face shared by two tets: both contain it; the lower index is chosen.
  const auto& t = m.tets[0];
  const Eigen::Vector3d f = (m.parameter[t[0]] + m.parameter[t[1]] + m.parameter[t[2]]) / 3;
  const UVW u{f[0], f[1], f[2]};
  const auto all = loc.tets_containing(u, 1e-10);
  ASSERT_FALSE(all.empty());
  std::array<double, 4> bary;
  EXPECT_EQ(loc.containing_tet(u, &bary), all.front());
  EXPECT_NEAR(bary[0] + bary[1] + bary[2] + bary[3], 1.0, 1e-12);
}

TEST(VolumeMapFiles, JsonRoundTripAndVtu) {
  const Case c = make_case("sphere");
  const VolumeMap m = volmap::harmonic_volume_map(c.mesh, c.sp, {});
  const VolumeMap back = volmap::from_json(core::Json::parse(volmap::to_json(m).dump()), "x.json");
  EXPECT_EQ(back.tets, m.tets);
  EXPECT_EQ(back.parameter, m.parameter);
  EXPECT_EQ(back.physical, m.physical);
  EXPECT_EQ(back.surface_vertices, m.surface_vertices);
  EXPECT_EQ(back.flipped_tets_before_untangling, m.flipped_tets_before_untangling);
  EXPECT_EQ(back.min_volume_ratio, m.min_volume_ratio);
  EXPECT_EQ(back.untangle_joint, m.untangle_joint);
  EXPECT_EQ(back.untangle_stop, m.untangle_stop);
  EXPECT_EQ(back.smooth_sweeps, m.smooth_sweeps);
  core::Json bad = volmap::to_json(m);
  bad["tets"][5] = 1 << 30;
  try {
    volmap::from_json(bad, "x.json");
    FAIL();
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.json: tets: tet 1"), std::string::npos) << e.what();
  }
  bad = volmap::to_json(m);
  bad.erase("parameter");
  EXPECT_THROW(volmap::from_json(bad, "x.json"), core::InvalidInputError);
  // The repair counts are optional (older files lack them) but checked when present.
  bad = volmap::to_json(m);
  bad.erase("flips");
  bad.erase("collapsed_edges");
  bad.erase("smooth_sweeps");
  EXPECT_EQ(volmap::from_json(bad, "x.json").flips, 0);
  EXPECT_EQ(volmap::from_json(bad, "x.json").smooth_sweeps, 0);
  for (const char* key : {"flips", "collapsed_edges", "smooth_sweeps"}) {
    bad = volmap::to_json(m);
    bad[key] = "two";
    try {
      volmap::from_json(bad, "x.json");
      FAIL() << key;
    } catch (const core::InvalidInputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("x.json: ") + key + " must be an integer"), std::string::npos) << e.what();
    }
  }

  const auto dir = test::fresh_dir("volmap", "files");
  volmap::write_vtu((dir / "map.vtu").string(), m, std::vector<int>(m.tets.size(), 0));
  volmap::write_parameter_vtu((dir / "map_parameter.vtu").string(), m);
  EXPECT_GT(std::filesystem::file_size(dir / "map.vtu"), 1000u);
  EXPECT_GT(std::filesystem::file_size(dir / "map_parameter.vtu"), 1000u);
  EXPECT_THROW(volmap::write_vtu((dir / "x.vtu").string(), m, {1, 2}), core::InvalidInputError);
  std::filesystem::remove_all(dir);
}
