// Tests of fit/cube_map.h: which surfaces are box-like, the six segmented patches as a
// classification, and the map of the solid onto the unit cube (Lin, Huang & Hu 2018, Fig. 1(a)–(b)).
#include "fit/cube_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>

#include "classify/classify.h"
#include "common/test_util.h"
#include "core/errors.h"

using namespace volts;
using namespace volts::fit;
using Eigen::Vector3d;
using Mesh = surface::Mesh;

namespace {

Vector3d point(const Mesh& m, int v) {
  const auto& p = m.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(v)));
  return {p.x(), p.y(), p.z()};
}

classify::Classification classified(const Mesh& m) { return classify::classify(m, classify::Params{}); }

std::array<int, 3> face_vertices(const Mesh& m, Mesh::Face_index f) {
  std::array<int, 3> v{};
  int i = 0;
  for (auto u : m.vertices_around_face(m.halfedge(f))) v[i++] = static_cast<int>(u.idx());
  return v;
}

// Per vertex: 1 if it lies on an edge between two faces of different patches.
std::vector<char> patch_boundary_vertices(const Mesh& m, const std::vector<int>& face_patch) {
  std::vector<char> on(m.number_of_vertices(), 0);
  for (auto e : m.edges()) {
    const auto h = m.halfedge(e);
    if (face_patch[m.face(h).idx()] != face_patch[m.face(m.opposite(h)).idx()])
      on[m.source(h).idx()] = on[m.target(h).idx()] = 1;
  }
  return on;
}

// Triangles whose three vertices all lie on their patch's boundary (flat on the cube after an
// arc-length boundary map: the triangles the chord splitting removes).
int flat_triangles(const Mesh& m, const std::vector<int>& face_patch) {
  const auto on = patch_boundary_vertices(m, face_patch);
  int n = 0;
  for (auto f : m.faces()) {
    const auto v = face_vertices(m, f);
    n += on[v[0]] && on[v[1]] && on[v[2]];
  }
  return n;
}

double enclosed_volume(const Mesh& m) {
  double vol = 0;
  for (auto f : m.faces()) {
    const auto v = face_vertices(m, f);
    vol += point(m, v[0]).dot(point(m, v[1]).cross(point(m, v[2]))) / 6;
  }
  return vol;
}

double area(const Mesh& m) {
  double a = 0;
  for (auto f : m.faces()) {
    const auto v = face_vertices(m, f);
    a += (point(m, v[1]) - point(m, v[0])).cross(point(m, v[2]) - point(m, v[0])).norm() / 2;
  }
  return a;
}

double tet_volume(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6;
}

// The surfaces map_to_cube is tested on, mapped once per test program: the smooth sphere (no sharp
// curves: classify finds one patch, so the six patches come from the segmentation), the bulged box
// (its twelve sharp edges make classify's patches box-like) and the box.
struct Mapped {
  Mesh input;
  classify::Classification c;
  CubeMap cube;
};

const Mapped& mapped(const std::string& name) {
  static std::map<std::string, Mapped> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    Mapped m;
    m.input = test::generated_model(name, name == "sphere" ? 32 : 16);
    m.c = classified(m.input);
    m.cube = map_to_cube(m.input, m.c, CubeMapParams{});
    it = cache.emplace(name, std::move(m)).first;
  }
  return it->second;
}

const char* const kMapped[] = {"sphere", "bulged-box"};

}  // namespace

// ---- box_like ----

TEST(BoxLike, AcceptsTheBoxsSixFacesTwelveEdgesEightCorners) {
  const Mesh m = test::generated_model("box", 16);
  const auto c = classified(m);
  EXPECT_TRUE(box_like(c)) << c.patches << " patches, " << c.curves.size() << " curves, " << c.corners.size() << " corners";
}

TEST(BoxLike, RejectsSurfacesWithoutSixQuadPatches) {
  // The sphere has no sharp edge at this resolution (one patch); the torus is genus 1.
  EXPECT_FALSE(box_like(classified(test::generated_model("sphere", 32))));
  const auto torus = classified(test::generated_model("torus", 16));
  EXPECT_EQ(torus.genus, 1);
  EXPECT_FALSE(box_like(torus));
}

TEST(BoxLike, RejectsEveryBrokenPartOfTheBoxStructure) {
  const auto box = classified(test::generated_model("box", 16));
  ASSERT_TRUE(box_like(box));
  auto genus = box;
  genus.genus = 1;
  EXPECT_FALSE(box_like(genus));
  auto missing_curve = box;
  missing_curve.curves.pop_back();
  EXPECT_FALSE(box_like(missing_curve));
  auto missing_corner = box;
  missing_corner.corners.pop_back();
  EXPECT_FALSE(box_like(missing_corner));
  auto closed = box;
  closed.curves[3].closed = true;
  EXPECT_FALSE(box_like(closed));
  auto same_side = box;  // a curve with one patch on both sides: its patches then have 3 and 5 curves
  same_side.curves[0].patch_right = same_side.curves[0].patch_left;
  EXPECT_FALSE(box_like(same_side));
}

// ---- classification_of ----

TEST(ClassificationOf, TwelveCurvesRunFromCornerToCornerAlongLabelBoundaries) {
  const Mesh m = test::generated_model("sphere", 16);
  const SixPatches s = six_patches(m);
  ASSERT_TRUE(s.layout.ok()) << s.layout.summary();
  const classify::Classification c = classification_of(m, s);
  EXPECT_TRUE(box_like(c));
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.patches, 6);
  EXPECT_EQ(c.face_patch, s.label);
  std::vector<int> corners(s.corners.begin(), s.corners.end());
  std::sort(corners.begin(), corners.end());
  EXPECT_EQ(c.corners, corners);
  const std::set<int> corner_set(corners.begin(), corners.end());
  ASSERT_EQ(corner_set.size(), 8u);

  const auto label = [&](Mesh::Halfedge_index h) { return s.label[m.face(h).idx()]; };
  std::map<std::pair<int, int>, int> in_curves;  // boundary edge (a < b) -> curves holding it
  std::set<std::pair<int, int>> patch_pairs;
  ASSERT_EQ(c.curves.size(), 12u);
  for (std::size_t k = 0; k < c.curves.size(); ++k) {
    const auto& curve = c.curves[k];
    ASSERT_GE(curve.vertices.size(), 2u) << k;
    EXPECT_FALSE(curve.closed) << k;
    EXPECT_TRUE(corner_set.count(curve.vertices.front())) << k;
    EXPECT_TRUE(corner_set.count(curve.vertices.back())) << k;
    EXPECT_NE(curve.vertices.front(), curve.vertices.back()) << k;
    for (std::size_t i = 1; i + 1 < curve.vertices.size(); ++i) EXPECT_FALSE(corner_set.count(curve.vertices[i])) << k << " " << i;
    // The two patches are neighbouring cube faces (different axes), never opposite ones.
    EXPECT_NE(curve.patch_left / 2, curve.patch_right / 2) << k;
    patch_pairs.insert({std::min(curve.patch_left, curve.patch_right), std::max(curve.patch_left, curve.patch_right)});
    for (std::size_t i = 0; i + 1 < curve.vertices.size(); ++i) {
      const int a = curve.vertices[i], b = curve.vertices[i + 1];
      const auto h = m.halfedge(Mesh::Vertex_index(static_cast<Mesh::size_type>(a)), Mesh::Vertex_index(static_cast<Mesh::size_type>(b)));
      ASSERT_NE(h, Mesh::null_halfedge()) << "curve " << k << ": " << a << "-" << b << " is not a mesh edge";
      EXPECT_EQ(label(h), curve.patch_left) << k << " " << i;
      EXPECT_EQ(label(m.opposite(h)), curve.patch_right) << k << " " << i;
      ++in_curves[{std::min(a, b), std::max(a, b)}];
    }
  }
  EXPECT_EQ(patch_pairs.size(), 12u);  // each pair of neighbouring faces shares exactly one curve

  std::set<std::pair<int, int>> boundary, sharp;
  for (auto e : m.edges()) {
    const auto h = m.halfedge(e);
    if (label(h) == label(m.opposite(h))) continue;
    const int a = static_cast<int>(m.source(h).idx()), b = static_cast<int>(m.target(h).idx());
    boundary.insert({std::min(a, b), std::max(a, b)});
  }
  for (const auto& e : boundary) EXPECT_EQ(in_curves[e], 1) << e.first << "-" << e.second;
  EXPECT_EQ(in_curves.size(), boundary.size());  // and no curve edge is off the boundary
  ASSERT_EQ(c.sharp_edge_vertices.size() % 2, 0u);
  for (std::size_t i = 0; i < c.sharp_edge_vertices.size(); i += 2) {
    EXPECT_LT(c.sharp_edge_vertices[i], c.sharp_edge_vertices[i + 1]);
    sharp.insert({c.sharp_edge_vertices[i], c.sharp_edge_vertices[i + 1]});
  }
  EXPECT_EQ(sharp, boundary);
}

TEST(ClassificationOf, RejectsLabelsThatAreNotCubeLike) {
  const Mesh m = test::generated_model("sphere", 16);
  SixPatches s = six_patches(m);
  // The face with the highest centroid (middle of +z) relabelled -x: -x gets a second component.
  int top = 0;
  double best = -1;
  for (auto f : m.faces()) {
    double z = 0;
    for (int v : face_vertices(m, f)) z += point(m, v).z();
    if (z > best) best = z, top = static_cast<int>(f.idx());
  }
  s.label[static_cast<std::size_t>(top)] = 1;
  s.layout = cube_layout(m, s.label);
  ASSERT_FALSE(s.layout.ok());
  EXPECT_THROW(classification_of(m, s), core::TopologyError);
}

// ---- map_to_cube ----

TEST(MapToCube, PatchesComeFromClassifyWhenBoxLikeElseFromTheSegmentation) {
  const Mapped& sphere = mapped("sphere");
  EXPECT_FALSE(box_like(sphere.c));
  EXPECT_EQ(sphere.cube.patch_source, "segmentation");
  EXPECT_TRUE(sphere.cube.segmentation.layout.ok());
  const Mapped& box = mapped("bulged-box");
  ASSERT_TRUE(box_like(box.c));
  EXPECT_EQ(box.cube.patch_source, "classify");
  EXPECT_EQ(box.cube.patches.corners, box.c.corners);
  ASSERT_EQ(box.cube.patches.curves.size(), box.c.curves.size());
  for (std::size_t k = 0; k < box.c.curves.size(); ++k) EXPECT_EQ(box.cube.patches.curves[k].vertices, box.c.curves[k].vertices);
  for (const char* name : kMapped) {
    const CubeMap& cube = mapped(name).cube;
    EXPECT_TRUE(box_like(cube.patches)) << name;
    EXPECT_EQ(cube.patches.face_patch.size(), cube.mesh.number_of_faces()) << name;
  }
}

// Flips counted by map_to_cube and recomputed here: a surface triangle on cube face (axis a, side s)
// must wind counter-clockwise seen along the outward normal, as the input's outward-oriented
// triangle does; every tet must have positive volume in both spaces.
TEST(MapToCube, NoSurfaceTriangleOrTetIsFlipped) {
  for (const char* name : kMapped) {
    const CubeMap& cube = mapped(name).cube;
    EXPECT_EQ(cube.surface.flipped_surface_triangles, 0) << name;
    EXPECT_EQ(cube.volume.flipped_tets, 0) << name;
    const auto& uvw = cube.surface.vertex_uvw;
    int flipped_triangles = 0;
    for (auto f : cube.mesh.faces()) {
      const int face = cube.surface.patch_face[static_cast<std::size_t>(cube.patches.face_patch[f.idx()])];
      Vector3d normal = Vector3d::Zero();
      normal[face / 2] = face % 2 ? 1 : -1;
      const auto v = face_vertices(cube.mesh, f);
      const Vector3d a(uvw[v[0]].data()), b(uvw[v[1]].data()), c(uvw[v[2]].data());
      flipped_triangles += (b - a).cross(c - a).dot(normal) <= 0;
    }
    EXPECT_EQ(flipped_triangles, 0) << name;
    int flipped_tets = 0;
    const auto& vm = cube.volume;
    for (std::size_t t = 0; t < vm.tets.size(); ++t) {
      const auto& q = vm.tets[t];
      flipped_tets += volmap::parameter_volume(vm, static_cast<int>(t)) <= 0;
      flipped_tets += tet_volume(vm.physical[q[0]], vm.physical[q[1]], vm.physical[q[2]], vm.physical[q[3]]) <= 0;
    }
    EXPECT_EQ(flipped_tets, 0) << name;
  }
}

TEST(MapToCube, SurfaceVerticesLieOnTheirPatchsFaceOfTheUnitCube) {
  for (const char* name : kMapped) {
    const CubeMap& cube = mapped(name).cube;
    const auto& uvw = cube.surface.vertex_uvw;
    ASSERT_EQ(uvw.size(), cube.mesh.number_of_vertices()) << name;
    for (std::size_t v = 0; v < uvw.size(); ++v) {
      int on_side = 0;
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(uvw[v][a], -1e-12) << name << " vertex " << v;
        EXPECT_LE(uvw[v][a], 1 + 1e-12) << name << " vertex " << v;
        on_side += std::abs(uvw[v][a]) <= 1e-12 || std::abs(uvw[v][a] - 1) <= 1e-12;
      }
      EXPECT_GE(on_side, 1) << name << " vertex " << v << " is inside the cube";
    }
    // Every vertex of a patch's triangles on that patch's face; the six faces distinct.
    std::set<int> faces;
    for (int f : cube.surface.patch_face) faces.insert(f);
    EXPECT_EQ(faces.size(), 6u) << name;
    int off = 0;
    for (auto f : cube.mesh.faces()) {
      const int face = cube.surface.patch_face[static_cast<std::size_t>(cube.patches.face_patch[f.idx()])];
      for (int v : face_vertices(cube.mesh, f)) off += std::abs(uvw[v][face / 2] - face % 2) > 1e-12;
    }
    EXPECT_EQ(off, 0) << name;
    // The volume map's boundary condition is this surface map.
    ASSERT_EQ(cube.volume.surface_vertices, static_cast<int>(uvw.size())) << name;
    double worst = 0;
    for (std::size_t v = 0; v < uvw.size(); ++v) worst = std::max(worst, (cube.volume.parameter[v] - Vector3d(uvw[v].data())).norm());
    EXPECT_LT(worst, 1e-12) << name;
  }
}

TEST(MapToCube, KeepsTheInputVertexPositionsForTheInputIds) {
  for (const char* name : kMapped) {
    const Mapped& mp = mapped(name);
    ASSERT_GE(mp.cube.mesh.number_of_vertices(), mp.input.number_of_vertices()) << name;
    int moved = 0;
    double worst_tet_point = 0;
    for (int v = 0; v < static_cast<int>(mp.input.number_of_vertices()); ++v) {
      moved += point(mp.cube.mesh, v) != point(mp.input, v);
      worst_tet_point = std::max(worst_tet_point, (mp.cube.volume.physical[static_cast<std::size_t>(v)] - point(mp.input, v)).norm());
    }
    EXPECT_EQ(moved, 0) << name;
    EXPECT_LT(worst_tet_point, 1e-12) << name;
  }
}

// The parameter domain is bounded by the surface triangles at their cube positions, all on the
// cube's faces (tested above), so it is [0,1]^3: volume 1 up to rounding. Rounding: ~10^4 tet
// volumes, each a triple product of O(1) differences with relative error ~1e-16, summed: well
// below 1e-10. The physical tets fill the solid: their volumes sum to the volume the surface encloses.
TEST(MapToCube, ParameterDomainIsTheUnitCubeAndTheTetsFillTheSolid) {
  for (const char* name : kMapped) {
    const CubeMap& cube = mapped(name).cube;
    EXPECT_NEAR(cube.volume.parameter_volume, 1.0, 1e-10) << name;
    double param = 0, phys = 0;
    const auto& vm = cube.volume;
    for (std::size_t t = 0; t < vm.tets.size(); ++t) {
      const auto& q = vm.tets[t];
      param += volmap::parameter_volume(vm, static_cast<int>(t));
      phys += tet_volume(vm.physical[q[0]], vm.physical[q[1]], vm.physical[q[2]], vm.physical[q[3]]);
    }
    EXPECT_NEAR(param, 1.0, 1e-10) << name;
    const double enclosed = enclosed_volume(cube.mesh);
    EXPECT_NEAR(phys / enclosed, 1.0, 1e-10) << name;
  }
}

// The map is onto the cube: every point of [0,1]^3 has a physical point, and the cube's corners go
// to the surface's corners (classify's or the segmentation's).
TEST(MapToCube, VolumeMapCoversTheCubeAndSendsCubeCornersToCornerVertices) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const char* name : kMapped) {
    const CubeMap& cube = mapped(name).cube;
    const volmap::Locator locate(cube.volume);
    int missing = 0;
    for (int i = 0; i < 300; ++i) missing += !locate.physical({unit(rng), unit(rng), unit(rng)}).has_value();
    EXPECT_EQ(missing, 0) << name;
    ASSERT_EQ(cube.surface.corner_cube_coords.size(), cube.patches.corners.size()) << name;
    std::set<std::array<int, 3>> codes;
    for (std::size_t k = 0; k < cube.patches.corners.size(); ++k) {
      const auto& code = cube.surface.corner_cube_coords[k];
      codes.insert(code);
      const auto x = locate.physical({double(code[0]), double(code[1]), double(code[2])});
      ASSERT_TRUE(x.has_value()) << name << " corner " << k;
      EXPECT_LT((Vector3d(x->data()) - point(cube.mesh, cube.patches.corners[k])).norm(), 1e-12) << name << " corner " << k;
    }
    EXPECT_EQ(codes.size(), 8u) << name;
  }
}

TEST(MapToCube, RejectsGenusOne) {
  const Mesh torus = test::generated_model("torus", 16);
  EXPECT_THROW(map_to_cube(torus, classified(torus), CubeMapParams{}), core::TopologyError);
}

// The chord splitting: the box's faces are grids of squares split in two, so at some patch corners a
// triangle has all three vertices on the patch boundary (flat on the cube after the arc-length
// boundary map). After map_to_cube none is left, and the splits (midpoints, centroids) keep the
// surface: same area, same enclosed volume.
TEST(MapToCube, NoTriangleHasAllThreeVerticesOnItsPatchBoundary) {
  for (const char* name : {"box", "bulged-box", "sphere"}) {
    const Mapped& mp = mapped(name);
    if (mp.cube.patch_source == "classify") {
      // The input as classified has such triangles (else the test would not test the splitting).
      EXPECT_GT(flat_triangles(mp.input, mp.c.face_patch), 0) << name;
      EXPECT_GT(mp.cube.splits, 0) << name;
    }
    EXPECT_EQ(flat_triangles(mp.cube.mesh, mp.cube.patches.face_patch), 0) << name;
    EXPECT_NEAR(area(mp.cube.mesh) / area(mp.input), 1.0, 1e-12) << name;
    EXPECT_NEAR(enclosed_volume(mp.cube.mesh) / enclosed_volume(mp.input), 1.0, 1e-12) << name;
  }
}
