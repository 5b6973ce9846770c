// Decomposition into cube components (Liu et al. §4.1, §4.3): on every model, every patch is a disk
// bounded by four sides, the patches cover the surface once (hole fills twice: once for the cube,
// once for the virtual component), and every component is bounded like a cube — six faces whose
// corners meet as a cube's do.
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "classify/classify.h"
#include "common/test_util.h"
#include "core/errors.h"
#include "models/models.h"
#include "split/split.h"

using namespace volts;

namespace {

surface::Mesh shared(const std::string& f) { return surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + f); }

surface::Mesh generated(const std::string& name, int resolution) { return test::generated_model(name, resolution); }

split::Decomposition run_split(const surface::Mesh& m, const split::Params& p = {}) {
  return split::split(m, classify::classify(m, {}), p);
}

using Edge = std::pair<int, int>;
Edge edge(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// A set of triangles is a disk: V - E + F = 1 and its boundary edges form one loop. Returns the
// boundary vertices.
std::set<int> check_disk(const split::Layout& L, const std::vector<int>& tris, const std::string& what) {
  std::map<Edge, int> count;
  std::set<int> verts;
  for (int t : tris)
    for (int k = 0; k < 3; ++k) {
      ++count[edge(L.triangles[t][k], L.triangles[t][(k + 1) % 3])];
      verts.insert(L.triangles[t][k]);
    }
  EXPECT_EQ(static_cast<int>(verts.size()) - static_cast<int>(count.size()) + static_cast<int>(tris.size()), 1) << what << " is not a disk";
  std::map<int, std::vector<int>> adj;
  for (const auto& [e, n] : count) {
    EXPECT_LE(n, 2) << what;
    if (n == 1) adj[e.first].push_back(e.second), adj[e.second].push_back(e.first);
  }
  std::set<int> boundary;
  for (const auto& [v, n] : adj) {
    EXPECT_EQ(n.size(), 2u) << what << ": boundary is not a simple loop at vertex " << v;
    boundary.insert(v);
  }
  // One loop: walk it.
  if (!adj.empty()) {
    int start = adj.begin()->first, prev = start, cur = adj.begin()->second[0];
    std::size_t steps = 1;
    while (cur != start && steps <= adj.size()) {
      const auto& n = adj[cur];
      const int next = n[0] == prev ? n[1] : n[0];
      prev = cur, cur = next, ++steps;
    }
    EXPECT_EQ(steps, adj.size()) << what << " has more than one boundary loop";
  }
  return boundary;
}

// The properties every decomposition must have; returns the number of components.
void check_decomposition(const split::Decomposition& d) {
  const split::Layout& L = d.layout;
  ASSERT_EQ(L.filled.size(), L.triangles.size());
  std::set<Edge> mesh_edges;
  for (const auto& t : L.triangles)
    for (int k = 0; k < 3; ++k) mesh_edges.insert(edge(t[k], t[(k + 1) % 3]));
  // Patches: disks with four corners joined by four sides along their boundary.
  for (std::size_t p = 0; p < L.patches.size(); ++p) {
    const auto& P = L.patches[p];
    const auto boundary = check_disk(L, P.triangles, "patch " + std::to_string(p));
    std::set<int> corners(P.corners.begin(), P.corners.end());
    EXPECT_EQ(corners.size(), 4u);
    std::size_t side_vertices = 0;
    for (int k = 0; k < 4; ++k) {
      const auto& s = P.sides[k];
      ASSERT_GE(s.size(), 2u);
      EXPECT_EQ(s.front(), P.corners[k]);
      EXPECT_EQ(s.back(), P.corners[(k + 1) % 4]);
      for (std::size_t i = 0; i + 1 < s.size(); ++i) EXPECT_TRUE(mesh_edges.count(edge(s[i], s[i + 1]))) << "side is not along edges";
      for (int v : s) EXPECT_TRUE(boundary.count(v)) << "side vertex off the patch boundary";
      side_vertices += s.size() - 1;
    }
    EXPECT_EQ(side_vertices, boundary.size()) << "the four sides do not make up the whole boundary of patch " << p;
  }
  // Coverage: input triangles in exactly one patch, fill triangles in exactly two.
  std::vector<int> cover(L.triangles.size(), 0);
  for (const auto& P : L.patches)
    for (int t : P.triangles) ++cover[t];
  for (std::size_t t = 0; t < cover.size(); ++t) EXPECT_EQ(cover[t], L.filled[t] ? 2 : 1) << "triangle " << t;
  // Every patch in exactly one component.
  std::vector<int> owner(L.patches.size(), 0);
  for (const auto& c : d.components)
    for (int p : c.patches) ++owner[p];
  for (std::size_t p = 0; p < owner.size(); ++p) EXPECT_EQ(owner[p], 1) << "patch " << p;
  // Internal faces: closed loops along edges through their four corners.
  for (const auto& f : L.internal_faces) {
    ASSERT_GE(f.loop.size(), 4u);
    for (std::size_t i = 0; i < f.loop.size(); ++i) EXPECT_TRUE(mesh_edges.count(edge(f.loop[i], f.loop[(i + 1) % f.loop.size()])));
    for (int c : f.corners) EXPECT_NE(std::find(f.loop.begin(), f.loop.end(), c), f.loop.end());
  }
  // Components: six faces meeting like a cube's.
  for (std::size_t ci = 0; ci < d.components.size(); ++ci) {
    const auto& c = d.components[ci];
    ASSERT_EQ(c.faces.size(), 6u) << "component " << ci;
    std::map<int, int> faces_at;
    std::vector<int> patches;
    for (const auto& f : c.faces) {
      EXPECT_NE(f.patches.empty(), f.internal_face < 0) << "a face is either patches or one internal face";
      for (int v : f.corners) ++faces_at[v];
      if (!f.patches.empty()) {
        std::vector<int> tris;
        for (int p : f.patches) tris.insert(tris.end(), L.patches[p].triangles.begin(), L.patches[p].triangles.end()), patches.push_back(p);
        const auto boundary = check_disk(L, tris, "face of component " + std::to_string(ci));
        for (int v : f.corners) EXPECT_TRUE(boundary.count(v)) << "face corner off the face boundary";
      }
    }
    EXPECT_EQ(faces_at.size(), 8u) << "component " << ci << " has not 8 corners";
    for (const auto& [v, n] : faces_at) EXPECT_EQ(n, 3) << "corner " << v << " of component " << ci;
    int adjacent = 0, opposite = 0;
    for (int a = 0; a < 6; ++a)
      for (int b = a + 1; b < 6; ++b) {
        std::set<int> ca(c.faces[a].corners.begin(), c.faces[a].corners.end());
        int shared_corners = 0;
        for (int v : c.faces[b].corners) shared_corners += ca.count(v);
        adjacent += shared_corners == 2, opposite += shared_corners == 0;
      }
    EXPECT_EQ(adjacent, 12) << "component " << ci;
    EXPECT_EQ(opposite, 3) << "component " << ci;
    std::sort(patches.begin(), patches.end());
    EXPECT_EQ(patches, c.patches) << "the faces' patches are the component's patches";
  }
  EXPECT_EQ(d.quad_patches, static_cast<int>(L.patches.size()));
}

void check_torus(const split::Decomposition& d, int cubes) {
  check_decomposition(d);
  EXPECT_EQ(d.genus, 1);
  ASSERT_EQ(d.tori.size(), 1u);
  EXPECT_EQ(d.tori[0].components.size(), static_cast<std::size_t>(cubes));
  EXPECT_EQ(d.tori[0].cross_sections.size(), static_cast<std::size_t>(cubes));
  ASSERT_EQ(d.components.size(), static_cast<std::size_t>(cubes));
  for (const auto& c : d.components) EXPECT_EQ(c.type, split::ComponentType::torus_cube);
  // Neighbours in the ring share their cross section.
  for (int k = 0; k < cubes; ++k) {
    const int cs = d.tori[0].cross_sections[k];
    auto has = [&](int comp) {
      for (const auto& f : d.components[comp].faces)
        if (f.internal_face == cs) return true;
      return false;
    };
    EXPECT_TRUE(has(d.tori[0].components[k]));
    EXPECT_TRUE(has(d.tori[0].components[(k + 1) % cubes]));
  }
  EXPECT_EQ(d.critical_saddle == 0 || d.critical_max - d.critical_saddle + d.critical_min == 0, true)
      << "Morse counts of the first field on a torus";
}

}  // namespace

TEST(Split, BoxIsOneCubeOfItsSixPatches) {
  for (const char* name : {"box", "bulged-box"}) {
    const auto d = run_split(generated(name, 8));
    check_decomposition(d);
    ASSERT_EQ(d.components.size(), 1u) << name;
    EXPECT_EQ(d.components[0].type, split::ComponentType::cube);
    EXPECT_EQ(d.layout.patches.size(), 6u);
    EXPECT_EQ(d.genus, 0);
  }
}

TEST(Split, GeneratedTorusIsARingOfFourCubes) {
  for (int res : {12, 24}) {
    const auto d = run_split(generated("torus", res));
    check_torus(d, 4);
    EXPECT_EQ(d.critical_min, 1);
    EXPECT_EQ(d.critical_max, 1);
    EXPECT_EQ(d.critical_saddle, 2);
  }
}

TEST(Split, LongitudesOfATorusOfRevolutionDoNotTwist) {
  // Generated torus: axis z, major radius 2. A longitudinal line keeps its angle around the tube
  // (a twisted one would sweep all 360 degrees); a cross section keeps its angle around the axis.
  const auto d = run_split(generated("torus", 16));
  ASSERT_EQ(d.longitude_lines.size(), 4u);
  auto spread = [](const std::vector<double>& angles) {
    double lo = 1e9, hi = -1e9;
    for (double a : angles) {
      const double r = std::remainder(a - angles[0], 2 * 3.14159265358979);
      lo = std::min(lo, r), hi = std::max(hi, r);
    }
    return (hi - lo) * 180 / 3.14159265358979;
  };
  for (const auto& line : d.longitude_lines) {
    std::vector<double> phi;
    for (int v : line) {
      const auto& p = d.layout.points[v];
      phi.push_back(std::atan2(p[2], std::hypot(p[0], p[1]) - 2.0));
    }
    EXPECT_LT(spread(phi), 20.0);
  }
  for (const auto& line : d.cross_section_lines) {
    std::vector<double> theta;
    for (int v : line) theta.push_back(std::atan2(d.layout.points[v][1], d.layout.points[v][0]));
    EXPECT_LT(spread(theta), 20.0);
  }
}

TEST(Split, CinolibTorusIsARingOfFourCubes) {
  const auto d = run_split(shared("cinolib_torus.obj"));
  check_torus(d, 4);
}

TEST(Split, TorusCubesPerRingFromTheConfig) {
  split::Params p;
  p.torus_cubes = 6;
  check_torus(run_split(generated("torus", 16), p), 6);
}

TEST(Split, WasherWithSmoothRimsIsATorusAlongItsSharpCurves) {
  const auto m = shared("loopycuts_mechanical08_rem.obj");
  const auto c = classify::classify(m, {});
  const auto d = split::split(m, c, {});
  check_torus(d, 4);
  // Every sharp curve is a longitudinal line: none of its edges is crossed by a patch interior.
  EXPECT_EQ(d.longitude_lines.size(), c.curves.size());
}

TEST(Split, ExtremePointsOnOneVertexAreAClearError) {
  split::Params p;
  p.extreme_points = {{2.75, 0, 0}, {2.75, 0, 0}};
  try {
    run_split(generated("torus", 12), p);
    FAIL() << "no error";
  } catch (const core::TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("split.extreme_points"), std::string::npos) << e.what();
  }
}

TEST(Split, CrossSectionFromAPlane) {
  split::Params p;
  p.cross_section_plane = {0, 0, 0, 1, 0, 0};  // x = 0 crosses the generated torus's ring twice
  check_torus(run_split(generated("torus", 12), p), 4);
}

TEST(Split, StageJsonRoundTrips) {
  const auto d = run_split(generated("torus", 12));
  const auto e = split::from_json(split::to_json(d), "x.json");
  EXPECT_EQ(split::to_json(e), split::to_json(d));
  check_torus(e, 4);
}

namespace {

// A cube minus `holes` virtual components: each with six patches, two of them fills (its contacts
// with the cube).
void check_difference(const split::Decomposition& d, int holes = 1) {
  check_decomposition(d);
  ASSERT_EQ(d.components.size(), static_cast<std::size_t>(1 + holes));
  EXPECT_EQ(d.components[0].type, split::ComponentType::cube);
  for (int h = 1; h <= holes; ++h) {
    EXPECT_EQ(d.components[h].type, split::ComponentType::virtual_component);
    EXPECT_EQ(d.components[h].patches.size(), 6u);
  }
  EXPECT_TRUE(d.tori.empty());
  const auto filled = std::count(d.layout.filled.begin(), d.layout.filled.end(), 1);
  EXPECT_GT(filled, 0);
  EXPECT_EQ(d.contacts.size(), static_cast<std::size_t>(2 * holes));
  std::map<int, int> per_hole;
  for (const auto& c : d.contacts) {
    EXPECT_EQ(c.via, "filled_patch");
    EXPECT_EQ(c.a, 0);
    ++per_hole[c.b];
    for (int t : d.layout.patches[c.index].triangles) EXPECT_EQ(d.layout.filled[t], 1);
  }
  for (int h = 1; h <= holes; ++h) EXPECT_EQ(per_hole[h], 2) << "hole " << h;
}

}  // namespace

TEST(Split, SquareRingWithSharpRimsIsACubeMinusAVirtualCube) {
  const auto d = run_split(shared("vhacd_tube1.off"));
  check_difference(d);
  EXPECT_EQ(d.genus, 1);
}

TEST(Split, CubeWithHoleIsACubeMinusAVirtualCylinder) {
  for (int res : {16, 32}) {
    const auto d = run_split(generated("cube-with-hole", res));
    check_difference(d);
  }
}

// The assembly's base (Liu et al. 2013, Fig. 1(d)): one cube minus four virtual cylinders. Each
// hole's component lies around its own hole (radius 0.3 about (+-1.5, +-1)), its fills in the
// plate's top and bottom planes, and its four wall cuts at the diagonals of the plate's faces.
TEST(Split, PlateIsACubeMinusFourVirtualCylinders) {
  for (int res : {16, 24}) {
    SCOPED_TRACE("resolution " + std::to_string(res));
    const auto d = run_split(generated("plate", res));
    check_difference(d, 4);
    EXPECT_EQ(d.genus, 4);
    std::set<std::pair<int, int>> centres;
    for (int h = 1; h <= 4; ++h) {
      double sx = 0, sy = 0, far = 0;
      int n = 0;
      std::vector<std::array<double, 3>> pts;
      for (const int p : d.components[static_cast<std::size_t>(h)].patches)
        for (const int t : d.layout.patches[static_cast<std::size_t>(p)].triangles)
          for (const int v : d.layout.triangles[static_cast<std::size_t>(t)]) pts.push_back(d.layout.points[static_cast<std::size_t>(v)]);
      for (const auto& q : pts) sx += q[0], sy += q[1], ++n;
      sx /= n, sy /= n;
      for (const auto& q : pts) far = std::max(far, std::hypot(q[0] - std::copysign(1.5, sx), q[1] - std::copysign(1.0, sy)));
      EXPECT_NEAR(std::abs(sx), 1.5, 0.05);
      EXPECT_NEAR(std::abs(sy), 1.0, 0.05);
      EXPECT_LT(far, 0.3 + 1e-9);  // the prism is inscribed in the cylinder
      centres.insert({sx > 0 ? 1 : -1, sy > 0 ? 1 : -1});
    }
    EXPECT_EQ(centres.size(), 4u);  // one component per hole
    for (const auto& c : d.contacts) {
      const auto& patch = d.layout.patches[static_cast<std::size_t>(c.index)];
      for (const int t : patch.triangles)
        for (const int v : d.layout.triangles[static_cast<std::size_t>(t)]) EXPECT_NEAR(std::abs(d.layout.points[static_cast<std::size_t>(v)][2]), 0.25, 1e-9);
      // The fill's corners, where the wall cuts meet the rim: on the diagonals seen from the hole.
      for (const int v : patch.corners) {
        const auto& q = d.layout.points[static_cast<std::size_t>(v)];
        const double deg = std::atan2(q[1] - (q[1] > 0 ? 1.0 : -1.0), q[0] - (q[0] > 0 ? 1.5 : -1.5)) * 180 / 3.14159265358979323846;
        EXPECT_NEAR(std::fmod(deg + 360, 90.0), 45.0, 1.0) << "corner at " << q[0] << ", " << q[1];
      }
    }
  }
}

// The assembly (Liu et al. 2013, Fig. 1): the union of the plate minus four holes and a ring
// standing on it. The ring meets the plate along its foot (the closed difference curve in the
// plate's top plane z = 0.25 that alone separates the surface); the foot's fill is one whole face
// of one ring cube and lies inside the plate cube's top face. Every input triangle is in one
// patch (check_decomposition), so the layout's input triangles have the input's area.
TEST(Split, AssemblyIsAPlateMinusFourHolesWithARingStandingOnItsFoot) {
  for (int res : {16, 32}) {
    SCOPED_TRACE("resolution " + std::to_string(res));
    const surface::Mesh input = generated("assembly", res);
    const auto d = run_split(input);
    check_decomposition(d);
    EXPECT_EQ(d.genus, 5);
    ASSERT_EQ(d.components.size(), 9u);
    EXPECT_EQ(d.components[0].type, split::ComponentType::cube);
    for (int c = 1; c <= 4; ++c) EXPECT_EQ(d.components[c].type, split::ComponentType::virtual_component);
    ASSERT_EQ(d.tori.size(), 1u);
    EXPECT_EQ(d.tori[0].components, (std::vector<int>{5, 6, 7, 8}));
    const auto& L = d.layout;
    auto area = [&](const std::array<int, 3>& t) {
      auto p = [&](int k) { const auto& q = L.points[t[k]]; return Eigen::Vector3d(q[0], q[1], q[2]); };
      return 0.5 * (p(1) - p(0)).cross(p(2) - p(0)).norm();
    };
    double layout_area = 0, input_area = 0;
    for (std::size_t t = 0; t < L.triangles.size(); ++t)
      if (!L.filled[t]) layout_area += area(L.triangles[t]);
    for (auto f : input.faces()) {
      std::array<Eigen::Vector3d, 3> q;
      int k = 0;
      for (auto v : CGAL::vertices_around_face(input.halfedge(f), input)) q[k++] = {input.point(v).x(), input.point(v).y(), input.point(v).z()};
      input_area += 0.5 * (q[1] - q[0]).cross(q[2] - q[0]).norm();
    }
    EXPECT_NEAR(layout_area, input_area, 1e-9 * input_area);
    // The foot: one contact between the plate cube and a ring cube.
    std::vector<split::Contact> feet;
    for (const auto& c : d.contacts)
      if (c.via == "filled_patch" && d.components[c.b].type == split::ComponentType::torus_cube) feet.push_back(c);
    ASSERT_EQ(feet.size(), 1u);
    EXPECT_EQ(feet[0].a, 0);
    const auto& foot = L.patches[feet[0].index];
    double x_max = 0, y_max = 0;
    for (int t : foot.triangles) {
      EXPECT_EQ(L.filled[t], 1);
      for (int v : L.triangles[t]) {
        EXPECT_NEAR(L.points[v][2], 0.25, 1e-9);
        x_max = std::max(x_max, std::abs(L.points[v][0])), y_max = std::max(y_max, std::abs(L.points[v][1]));
      }
    }
    // The torus (radii 0.8, 0.3 about the y axis at z = 0.95) cut by z = 0.25: |x| <= 0.85, |y| <= 0.3.
    EXPECT_GT(x_max, 0.8);
    EXPECT_LT(x_max, 0.85 + 1e-9);
    EXPECT_LT(y_max, 0.3 + 1e-9);
    int whole_faces = 0;
    for (const auto& f : d.components[feet[0].b].faces) whole_faces += f.patches == std::vector<int>{feet[0].index};
    EXPECT_EQ(whole_faces, 1) << "the foot is one whole face of its ring cube";
    // The plate's top face (its corners at z = 0.25) holds the foot's triangles.
    int top_faces = 0;
    for (const auto& f : d.components[0].faces) {
      bool top = true;
      for (int v : f.corners) top &= std::abs(L.points[v][2] - 0.25) < 1e-9;
      if (!top) continue;
      ++top_faces;
      std::set<int> tris;
      for (int p : f.patches) tris.insert(L.patches[p].triangles.begin(), L.patches[p].triangles.end());
      for (int t : foot.triangles) EXPECT_TRUE(tris.count(t)) << "foot triangle " << t << " is not in the plate's top face";
    }
    EXPECT_EQ(top_faces, 1);
    // The ring's other patches stand on the plate, the plate's lie in it.
    for (int c = 0; c < 9; ++c)
      for (int p : d.components[c].patches) {
        if (p == feet[0].index) continue;
        for (int t : L.patches[p].triangles)
          for (int v : L.triangles[t]) {
            if (c >= 5) EXPECT_GT(L.points[v][2], 0.25 - 1e-9) << "ring patch " << p;
            else EXPECT_LT(L.points[v][2], 0.25 + 1e-9) << "plate patch " << p;
          }
      }
  }
}

TEST(Split, HoleForcedToTorusWithCornersIsAClearError) {
  split::Params p;
  p.hole = "torus";
  try {
    run_split(shared("vhacd_tube1.off"), p);
    FAIL() << "no error";
  } catch (const core::TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("split.hole"), std::string::npos) << e.what();
  }
}

TEST(Split, EightIsTwoToriOfFourCubesMeetingOnAFilledDisk) {
  split::Params p;
  p.genus2 = "disk";
  const auto d = run_split(shared("cfwen_eight.off"), p);
  EXPECT_EQ(d.genus2, "disk");
  check_decomposition(d);
  EXPECT_EQ(d.genus, 2);
  ASSERT_EQ(d.tori.size(), 2u);
  ASSERT_EQ(d.components.size(), 8u);
  for (const auto& c : d.components) EXPECT_EQ(c.type, split::ComponentType::torus_cube);
  EXPECT_EQ(d.critical_saddle, 4);
  // The tori meet on the filled disk: one contact through a filled patch, between the two tori.
  int meets = 0;
  for (const auto& c : d.contacts)
    if (c.via == "filled_patch") {
      ++meets;
      EXPECT_NE(d.components[c.a].torus, d.components[c.b].torus);
    }
  EXPECT_EQ(meets, 1);
}

// split.genus2 auto (the default): a connector where split can cut the neck at connector_cut (the
// eight: the same decomposition as genus2 connector), else at auto_connector_cut (the rod: at
// 0.5 a cross section crosses a longitudinal line more than once; the same decomposition as
// genus2 connector at 0.85), else the disk, with a warning (the rod at 0.95, past the second try:
// the planar fill of its small end crosses the surface).
TEST(Split, Genus2AutoIsAConnectorWhereTheNeckCanBeCutElseTheDisk) {
  split::Params c;
  c.genus2 = "connector";
  const auto eight = run_split(shared("cfwen_eight.off"));
  EXPECT_EQ(eight.genus2, "connector");
  EXPECT_EQ(split::to_json(eight).dump(), split::to_json(run_split(shared("cfwen_eight.off"), c)).dump());
  EXPECT_THROW(run_split(shared("loopycuts_rod_rem.obj"), c), core::TopologyError);
  const auto rod = run_split(shared("loopycuts_rod_rem.obj"));
  EXPECT_EQ(rod.genus2, "connector");
  EXPECT_EQ(rod.components.size(), 9u);
  c.connector_cut = split::auto_connector_cut;
  EXPECT_EQ(split::to_json(rod).dump(), split::to_json(run_split(shared("loopycuts_rod_rem.obj"), c)).dump());
  split::Params far;
  far.connector_cut = 0.95;
  const auto disk = run_split(shared("loopycuts_rod_rem.obj"), far);
  EXPECT_EQ(disk.genus2, "disk");
  EXPECT_EQ(disk.tori.size(), 2u);
  split::Params d;
  d.genus2 = "disk";
  EXPECT_EQ(split::to_json(disk).dump(), split::to_json(run_split(shared("loopycuts_rod_rem.obj"), d)).dump());
}

// The closed surface of each torus (its cubes' patches: ring and disk) and of the neck cube (its
// six patches, both disks among them), as meshes.
std::vector<surface::Mesh> primitive_surfaces(const split::Decomposition& d) {
  std::map<int, std::set<int>> of;  // torus id (or -1 - component for a cube) -> layout triangles
  for (std::size_t c = 0; c < d.components.size(); ++c) {
    const int key = d.components[c].torus >= 0 ? d.components[c].torus : -1 - static_cast<int>(c);
    for (int q : d.components[c].patches)
      for (int t : d.layout.patches[static_cast<std::size_t>(q)].triangles) of[key].insert(t);
  }
  std::vector<surface::Mesh> out;
  for (const auto& [key, tris] : of) {
    std::vector<surface::Point> points;
    std::map<int, std::size_t> local;
    std::vector<std::vector<std::size_t>> polygons;
    for (int t : tris) {
      std::vector<std::size_t> poly;
      for (int v : d.layout.triangles[static_cast<std::size_t>(t)]) {
        auto [it, fresh] = local.emplace(v, points.size());
        if (fresh) {
          const auto& x = d.layout.points[static_cast<std::size_t>(v)];
          points.emplace_back(x[0], x[1], x[2]);
        }
        poly.push_back(it->second);
      }
      polygons.push_back(poly);
    }
    CGAL::Polygon_mesh_processing::orient_polygon_soup(points, polygons);
    surface::Mesh m;
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, m);
    out.push_back(std::move(m));
  }
  return out;
}

TEST(Split, RodCutNearItsEyesIsTwoToriAndAConnectorWhoseSurfacesDoNotCrossThemselves) {
  // At 0.85 of the way to the saddles CGAL's hole filling crosses ring 1 and the neck (triangles
  // bridging the rims' notches); the fills are then made in the rims' planes.
  split::Params p;
  p.connector_cut = 0.85;
  p.connector_end = "level";
  const auto rod = run_split(shared("loopycuts_rod_rem.obj"), p);
  EXPECT_EQ(rod.genus2, "connector");
  EXPECT_EQ(rod.planar_fills, 2);  // both disks: CGAL's fill crossed ring 1, then the neck
  EXPECT_EQ(split::report_figures(rod).at("planar_fills"), 2);
  check_decomposition(rod);
  ASSERT_EQ(rod.components.size(), 9u);
  const auto surfaces = primitive_surfaces(rod);
  ASSERT_EQ(surfaces.size(), 3u);  // two tori and the neck
  for (const auto& m : surfaces) EXPECT_FALSE(CGAL::Polygon_mesh_processing::does_self_intersect(m));
  // The eight's fills (CGAL's, kept) clear its surface too.
  const auto eight = run_split(shared("cfwen_eight.off"));
  EXPECT_EQ(eight.planar_fills, 0);
  for (const auto& m : primitive_surfaces(eight)) EXPECT_FALSE(CGAL::Polygon_mesh_processing::does_self_intersect(m));
  // A cut along the shoulder's flat face (0.8): its fill lies in that face's plane; split says so.
  p.genus2 = "connector";
  p.connector_cut = 0.8;
  try {
    run_split(shared("loopycuts_rod_rem.obj"), p);
    ADD_FAILURE() << "the cut at 0.8 should not split";
  } catch (const core::TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("crosses the surface"), std::string::npos) << e.what();
  }
}

// split.connector_end: shoulder (work in progress, docs/status.md "Session 20", "Session 21"): the rod's small
// end is cut along the shoulder's two concave sharp curves (where the shank, z in [0.094, 0.228],
// ends at x ~ 0.826 on the thinner eye, z in [0.129, 0.192]) and across the sides between them,
// so its disk is the eye's cross section in the shoulder's plane; the level set at 0.85 crosses
// the shoulder obliquely.
TEST(Split, RodConnectorEndsOnTheShoulderOfItsSmallEye) {
  split::Params p;
  p.connector_cut = 0.85;
  p.connector_end = "level";
  auto small_fill = [](const split::Decomposition& d) {
    std::array<double, 4> r{1e9, -1e9, 1e9, -1e9};  // x range, z range of the fill at x > 0.5
    for (std::size_t t = 0; t < d.layout.triangles.size(); ++t) {
      if (!d.layout.filled[t]) continue;
      for (const int v : d.layout.triangles[t]) {
        const auto& x = d.layout.points[static_cast<std::size_t>(v)];
        if (x[0] < 0.5) continue;
        r[0] = std::min(r[0], x[0]), r[1] = std::max(r[1], x[0]), r[2] = std::min(r[2], x[2]), r[3] = std::max(r[3], x[2]);
      }
    }
    return r;
  };
  const auto level = small_fill(run_split(shared("loopycuts_rod_rem.obj"), p));
  EXPECT_GT(level[1] - level[0], 0.01);
  p.connector_end = "shoulder";
  const auto rod = run_split(shared("loopycuts_rod_rem.obj"), p);
  EXPECT_EQ(rod.genus2, "connector");
  check_decomposition(rod);
  ASSERT_EQ(rod.components.size(), 9u);
  for (const auto& m : primitive_surfaces(rod)) EXPECT_FALSE(CGAL::Polygon_mesh_processing::does_self_intersect(m));
  const auto shoulder = small_fill(rod);
  EXPECT_GT(shoulder[0], 0.824);
  EXPECT_LT(shoulder[1], 0.829);
  EXPECT_GT(shoulder[2], 0.125);  // the eye's cross section, not the shank's
  EXPECT_LT(shoulder[3], 0.197);
  // The neck's end face there is its disk and the shoulder's two faces (lenses between the concave
  // curves and the shank's convex ones): three patches, its corners on the convex curves, above and
  // below the eye (z outside [0.129, 0.192]), and every lens in the shoulder's plane.
  int ends = 0;
  for (const auto& c : rod.components) {
    if (c.type != split::ComponentType::cube) continue;
    for (const auto& f : c.faces) {
      if (f.patches.size() != 3) continue;
      ++ends;
      int above = 0, below = 0, fills = 0;
      for (const int v : f.corners) {
        const auto& x = rod.layout.points[static_cast<std::size_t>(v)];
        EXPECT_NEAR(x[0], 0.8265, 0.005);
        above += x[2] > 0.197, below += x[2] < 0.125;
      }
      EXPECT_EQ(above, 2);
      EXPECT_EQ(below, 2);
      for (const int p : f.patches) {
        const auto& P = rod.layout.patches[static_cast<std::size_t>(p)];
        fills += rod.layout.filled[static_cast<std::size_t>(P.triangles[0])];
        for (const int t : P.triangles)
          for (const int v : rod.layout.triangles[static_cast<std::size_t>(t)]) EXPECT_NEAR(rod.layout.points[static_cast<std::size_t>(v)][0], 0.8265, 0.005);
      }
      EXPECT_EQ(fills, 1);
    }
  }
  EXPECT_EQ(ends, 1);
  // The eight has no shoulder: its ends stay on the level sets (the same decomposition).
  split::Params q;
  q.connector_end = "level";
  EXPECT_EQ(run_split(shared("cfwen_eight.off")).layout.points, run_split(shared("cfwen_eight.off"), q).layout.points);
  p.connector_end = "elsewhere";
  EXPECT_THROW(run_split(shared("cfwen_eight.off"), p), core::ConfigError);
}

// The rod's small eye is a box with a hole: with the connector on its shoulder, the eye's disk
// rim arcs are closed around the ring by the eye's outer sharp edges and the other two corner
// lines are the hole's sharp rims, so every sharp edge of the eye's cross section is a cube edge
// (split without them, the lines ran up to 0.014 inside the outer edge and inside the hole wall).
// The big eye's disk is a level cut (no sharp ends): its rim lines stay levels, its hole's rims
// are the other two lines.
TEST(Split, RodSmallEyesCornerLinesAreItsSharpEdges) {
  const surface::Mesh mesh = shared("loopycuts_rod_rem.obj");
  const classify::Classification c = classify::classify(mesh, {});
  std::set<Edge> sharp;
  for (std::size_t i = 0; i + 1 < c.sharp_edge_vertices.size(); i += 2) sharp.insert(edge(c.sharp_edge_vertices[i], c.sharp_edge_vertices[i + 1]));
  split::Params p;
  p.connector_cut = 0.85;
  p.connector_end = "shoulder";
  const split::Decomposition d = split::split(mesh, c, p);
  check_decomposition(d);
  const int n_input = static_cast<int>(mesh.number_of_vertices());
  // Vertices of a line not on a sharp input edge (a vertex split has put on the line, where a cut
  // crossed it, lies on one).
  auto off_sharp = [&](const std::vector<int>& line) {
    int off = 0;
    for (std::size_t k = 0; k < line.size(); ++k) {
      const int a = line[k], b = line[(k + 1) % line.size()];
      if (a < n_input && b < n_input) off += !sharp.count(edge(a, b));
    }
    for (const int v : line) {
      if (v < n_input) continue;
      const auto& x = d.layout.points[static_cast<std::size_t>(v)];
      double best = 1e300;
      for (const auto& [a, b] : sharp) {
        const auto &pa = d.layout.points[static_cast<std::size_t>(a)], &pb = d.layout.points[static_cast<std::size_t>(b)];
        double t = 0, len = 0;
        for (int q = 0; q < 3; ++q) t += (x[q] - pa[q]) * (pb[q] - pa[q]), len += (pb[q] - pa[q]) * (pb[q] - pa[q]);
        t = std::clamp(t / len, 0.0, 1.0);
        double dd = 0;
        for (int q = 0; q < 3; ++q) dd += (pa[q] + t * (pb[q] - pa[q]) - x[q]) * (pa[q] + t * (pb[q] - pa[q]) - x[q]);
        best = std::min(best, std::sqrt(dd));
      }
      off += best > 1e-9;
    }
    return off;
  };
  int small_eye = 0, big_eye = 0, big_eye_sharp = 0;
  for (const auto& line : d.longitude_lines) {
    bool small = true, big = true;
    for (const int v : line) small = small && d.layout.points[static_cast<std::size_t>(v)][0] > 0.82, big = big && d.layout.points[static_cast<std::size_t>(v)][0] < 0.3;
    if (small) {
      ++small_eye;
      EXPECT_EQ(off_sharp(line), 0) << "small eye line " << small_eye;
    }
    if (big) ++big_eye, big_eye_sharp += off_sharp(line) == 0;
  }
  EXPECT_EQ(small_eye, 4);
  EXPECT_EQ(big_eye, 4);
  EXPECT_EQ(big_eye_sharp, 2);
}

TEST(Split, EightWithAConnectorIsTwoToriAndANeckCubeOnTheirDisks) {
  // split.genus2: connector (Liu et al. §6): the neck between two cut levels is one cube whose
  // ends are the tori's disks, each a whole patch of its torus.
  split::Params p;
  p.genus2 = "connector";
  const auto d = run_split(shared("cfwen_eight.off"), p);
  check_decomposition(d);
  ASSERT_EQ(d.tori.size(), 2u);
  ASSERT_EQ(d.components.size(), 9u);
  int cubes = 0, neck = -1;
  for (std::size_t c = 0; c < d.components.size(); ++c)
    if (d.components[c].type == split::ComponentType::cube) ++cubes, neck = static_cast<int>(c);
  EXPECT_EQ(cubes, 1);
  // Two contacts through filled patches, each between the neck and a different torus; each such
  // patch of a torus holds fill triangles only (the disk is a whole patch).
  std::set<int> tori;
  for (const auto& c : d.contacts) {
    if (c.via != "filled_patch") continue;
    ASSERT_TRUE(c.a == neck || c.b == neck);
    tori.insert(d.components[c.a == neck ? c.b : c.a].torus);
  }
  EXPECT_EQ(tori, (std::set<int>{0, 1}));
  for (const auto& comp : d.components) {
    if (comp.torus < 0) continue;
    for (int q : comp.patches) {
      const auto& tris = d.layout.patches[static_cast<std::size_t>(q)].triangles;
      const auto fills = std::count_if(tris.begin(), tris.end(), [&](int t) { return d.layout.filled[static_cast<std::size_t>(t)] != 0; });
      EXPECT_TRUE(fills == 0 || fills == static_cast<long>(tris.size())) << "patch " << q << " mixes disk and surface";
      if (fills == 0) continue;
      // The disk's corners lie on its rim's roundings: in the rim's principal frame, each corner is
      // at least half way out along both axes (on the eight, corners chosen by the ring and tube
      // fields sat 0.43 of the way out along the neck, and the pillow folded there).
      const auto& P = d.layout.patches[static_cast<std::size_t>(q)];
      std::vector<Eigen::Vector3d> rim;
      for (const auto& side : P.sides)
        for (std::size_t i = 0; i + 1 < side.size(); ++i) {
          const auto& x = d.layout.points[static_cast<std::size_t>(side[i])];
          rim.emplace_back(x[0], x[1], x[2]);
        }
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const auto& x : rim) centre += x;
      centre /= static_cast<double>(rim.size());
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const auto& x : rim) cov += (x - centre) * (x - centre).transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
      for (int axis : {2, 1}) {
        const Eigen::Vector3d e = eig.eigenvectors().col(axis);
        double extent = 0;
        for (const auto& x : rim) extent = std::max(extent, std::abs((x - centre).dot(e)));
        for (const int v : P.corners) {
          const auto& x = d.layout.points[static_cast<std::size_t>(v)];
          EXPECT_GE(std::abs((Eigen::Vector3d(x[0], x[1], x[2]) - centre).dot(e)), 0.5 * extent) << "disk patch " << q << ", axis " << axis;
        }
      }
    }
  }
  p.connector_cut = 0.01;
  EXPECT_THROW(run_split(shared("cfwen_eight.off"), p), core::ConfigError);
}

TEST(Split, ConnectorSideCurvesLeaveTheDisksAcrossTheirRims) {
  // The neck's four side curves leave each disk corner across the rim, not along it: each side
  // patch's angle at a disk corner is at least 40° (the surface angle there is ~180°, 90° each
  // when the curve is square to the rim). Shortest edge paths on the coarse eight left one corner
  // at 21°, and that corner's element stayed at a scaled Jacobian of 0.09.
  split::Params p;
  p.genus2 = "connector";
  const auto d = run_split(shared("cfwen_eight.off"), p);
  const auto& pts = d.layout.points;
  auto at = [&](int v) { return Eigen::Vector3d(pts[static_cast<std::size_t>(v)][0], pts[static_cast<std::size_t>(v)][1], pts[static_cast<std::size_t>(v)][2]); };
  int checked = 0;
  for (const auto& comp : d.components) {
    if (comp.type != split::ComponentType::cube) continue;
    std::set<int> disk_corners;
    std::vector<int> sides;
    for (int q : comp.patches) {
      const auto& P = d.layout.patches[static_cast<std::size_t>(q)];
      if (d.layout.filled[static_cast<std::size_t>(P.triangles.at(0))]) disk_corners.insert(P.corners.begin(), P.corners.end());
      else sides.push_back(q);
    }
    ASSERT_EQ(disk_corners.size(), 8u);
    ASSERT_EQ(sides.size(), 4u);
    for (int q : sides) {
      const auto& P = d.layout.patches[static_cast<std::size_t>(q)];
      for (int c : P.corners) {
        ASSERT_TRUE(disk_corners.count(c)) << "side patch " << q << " has a corner off the disks";
        double angle = 0;
        for (int t : P.triangles) {
          const auto& tr = d.layout.triangles[static_cast<std::size_t>(t)];
          for (int k = 0; k < 3; ++k) {
            if (tr[static_cast<std::size_t>(k)] != c) continue;
            const Eigen::Vector3d a = at(tr[static_cast<std::size_t>((k + 1) % 3)]) - at(c), b = at(tr[static_cast<std::size_t>((k + 2) % 3)]) - at(c);
            angle += std::acos(std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0));
          }
        }
        EXPECT_GE(angle * 180 / M_PI, 40.0) << "side patch " << q << " at disk corner " << c;
        EXPECT_LE(angle * 180 / M_PI, 140.0) << "side patch " << q << " at disk corner " << c;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 16);
}

TEST(Split, RodIsTwoToriAndAConnectorWithDefaults) {
  // A CAD part of genus 2 (an eye and a small hole): with the defaults, two tori of four cubes
  // and the shank's cube between them, its small end on the shoulder (examples/rod.yaml).
  const auto d = run_split(shared("loopycuts_rod_rem.obj"));
  check_decomposition(d);
  EXPECT_EQ(d.genus, 2);
  EXPECT_EQ(d.genus2, "connector");
  EXPECT_EQ(d.tori.size(), 2u);
  EXPECT_EQ(d.components.size(), 9u);
}

TEST(Split, CrossSectionThroughAGivenPoint) {
  // Generated torus (axis z, R = 2, r = 0.75): the first cross section through the outermost point
  // on +y passes within one edge of it.
  split::Params p;
  p.cross_section_point = {{0, 2.75, 0}};
  const auto d = run_split(generated("torus", 16), p);
  check_torus(d, 4);
  double best = 1e9;
  for (int v : d.cross_section_lines[0]) {
    const auto& q = d.layout.points[v];
    best = std::min(best, std::hypot(q[0], q[1] - 2.75, q[2]));
  }
  EXPECT_LT(best, 2 * 3.14159265 * 2.75 / 16 / 2 + 1e-9);
}
