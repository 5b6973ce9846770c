// What volts-tmesh reads from a ring's polycube.stage.json (pipeline/polycube_input.h): the
// physical point of every parameter point on a cube's round faces is the surface map's, so it
// lies on the input surface whatever the interior of the volume map looks like.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "../common/test_util.h"
#include "core/errors.h"
#include "polycube_input.h"
#include "surface/mesh_json.h"
#include "surface/surface.h"

namespace volts {
namespace {

namespace fs = std::filesystem;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<surface::Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<surface::Kernel, Primitive>>;

// The generated torus at resolution 16 run through stage polycube in a fresh directory: its
// polycube.stage.json ("" and a test failure if the run failed).
std::string torus_polycube_file(const std::string& name) {
  const fs::path d = test::fresh_dir("pipeline", name);
  test::write_text(d / "run.yaml", "input: {generate: torus, resolution: 16}\n");
  const test::Outcome r = test::run(test::bin("volts") + " run " + (d / "run.yaml").string() + " --workdir " + (d / "w").string() + " --to polycube");
  EXPECT_EQ(r.code, 0) << r.output;
  return r.code == 0 ? (d / "w" / "polycube.stage.json").string() : std::string();
}

// read_polycube_input refuses `file` (written with one corruption, `what`) with an
// InvalidInputError naming the file and `member`.
void expect_refused(const std::string& file, const std::string& member, const std::string& what) {
  try {
    pipeline::read_polycube_input(file, tmesh::Params{});
    ADD_FAILURE() << what << " accepted";
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(member), std::string::npos) << e.what();
  }
}

TEST(PolycubeInput, RingPointsOnTheRoundFacesLieOnTheSurface) {
  // The generated torus at resolution 16 (coarse: the chords of the round ring's faces are long).
  // Through the tets, the inner round face's points lay up to the chords' sagitta inside the
  // surface (measured 1e-2 off for some), and smoothing the interior moved them.
  const std::string file = torus_polycube_file("polycube_input_ring");
  ASSERT_FALSE(file.empty());
  const pipeline::PolycubeInput in = pipeline::read_polycube_input(file, tmesh::Params{});
  ASSERT_EQ(in.kind, "torus");
  const surface::Mesh mesh = surface::mesh_from_json(in.surface, file);
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  const double diag = surface::bbox_diagonal(mesh);
  const int cubes = static_cast<int>(in.maps.boundary.size());
  ASSERT_EQ(cubes, 4);
  double worst = 0, seam = 0;
  int samples = 0;
  for (int c = 0; c < cubes; ++c) {
    EXPECT_EQ(in.maps.boundary[c], (std::array<int, 6>{0, 0, 1, 1, 1, 1}));
    for (int axis = 1; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side)
        for (int i = 0; i <= 12; ++i)
          for (int j = 0; j <= 12; ++j) {
            tmesh::Vec3 abc{i / 12.0, 0, 0};
            abc[axis] = side;
            abc[3 - axis] = j / 12.0;
            const tmesh::Vec3 p = in.maps.physical(c, abc);
            worst = std::max(worst, std::sqrt(CGAL::to_double(tree.squared_distance(surface::Point(p[0], p[1], p[2])))));
            ++samples;
            if (i == 12) {  // the same point as the next cube's a = 0
              tmesh::Vec3 next = abc;
              next[0] = 0;
              const tmesh::Vec3 q = in.maps.physical((c + 1) % cubes, next);
              seam = std::max(seam, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
            }
          }
  }
  EXPECT_EQ(samples, 4 * 4 * 13 * 13);
  EXPECT_LT(worst, 1e-9 * diag);
  EXPECT_LT(seam, 1e-9 * diag);
  // And a point inside is not on the surface (the check above is not vacuous).
  const tmesh::Vec3 centre = in.maps.physical(0, {0.5, 0.5, 0.5});
  EXPECT_GT(std::sqrt(CGAL::to_double(tree.squared_distance(surface::Point(centre[0], centre[1], centre[2])))), 0.05 * diag);
}

TEST(PolycubeInput, RingCutsBecomeBlockFacesAndBadCutsNameTheFile) {
  // polycube.cuts (sharp curves inside faces, polycube.sharp_lines) cut every ring cube's blocks
  // there (tmesh::cube_blocks): the C0 block faces of the paper's repeated knots.
  const std::string file = torus_polycube_file("polycube_input_cuts");
  ASSERT_FALSE(file.empty());
  core::Json j = core::read_stage_file(file, "volts-polycube", 2);
  EXPECT_EQ(j["polycube"]["cuts"], core::Json::parse("[[], [], []]"));  // sharp_lines is off by default
  EXPECT_TRUE(pipeline::read_polycube_input(file, tmesh::Params{}).maps.blocks.empty());
  j["polycube"]["cuts"] = core::Json::parse("[[], [0.3], [0.6, 0.8]]");
  const std::string cut = (fs::path(file).parent_path() / "cut.json").string();
  test::write_text(cut, j.dump());
  const pipeline::PolycubeInput in = pipeline::read_polycube_input(cut, tmesh::Params{});
  ASSERT_EQ(in.maps.blocks.size(), 4u);
  for (const auto& blocks : in.maps.blocks) {
    // core 2 x 3, the slabs under the faces across b cut twice, across c once: 6 + 2 * 3 + 2 * 2.
    EXPECT_EQ(blocks.size(), 16u);
    // The cut heights appear as block corners on the surface faces (in the cube's axes, which may
    // swap b and c to keep the map right-handed).
    std::set<double> b_at_c0, c_at_b0;
    for (const auto& b : blocks)
      for (const auto& x : b.corners) {
        if (x[2] == 0) b_at_c0.insert(x[1]);
        if (x[1] == 0) c_at_b0.insert(x[2]);
      }
    const bool straight = b_at_c0.count(0.3) && c_at_b0.count(0.6) && c_at_b0.count(0.8);
    const bool swapped = c_at_b0.count(0.3) && b_at_c0.count(0.6) && b_at_c0.count(0.8);
    EXPECT_TRUE(straight != swapped);
  }
  for (const char* bad : {"[[0.5], [], []]", "[[], [0.6, 0.3], []]", "[[], [1.2], []]", "{\"b\": 1}"}) {
    j["polycube"]["cuts"] = core::Json::parse(bad);
    test::write_text(cut, j.dump());
    expect_refused(cut, "cuts", bad);
  }
}

TEST(PolycubeInput, ProfileRingsHaveACubePerCellAndSectorAndBadProfilesNameTheFile) {
  // polycube.profile (a rectilinear cross section, embedding.h): one cube per grid cell and
  // sector, blocks from tmesh::profile_blocks. A plus profile injected into the torus's file lies
  // inside its square ring, so every point still has an image: the centre cell's centre is the
  // square sector's centre.
  const std::string file = torus_polycube_file("polycube_input_profile");
  ASSERT_FALSE(file.empty());
  core::Json j = core::read_stage_file(file, "volts-polycube", 2);
  EXPECT_TRUE(j["polycube"]["profile"].is_null());  // the torus keeps the square
  const pipeline::PolycubeInput square = pipeline::read_polycube_input(file, tmesh::Params{});
  j["polycube"]["profile"] = core::Json::parse(R"({"b": [0, 0.3, 0.7, 1], "c": [0, 0.25, 0.75, 1],
                                                   "cells": [[1, 0], [0, 1], [1, 1], [2, 1], [1, 2]]})");
  const std::string plus = (fs::path(file).parent_path() / "plus.json").string();
  test::write_text(plus, j.dump());
  const pipeline::PolycubeInput in = pipeline::read_polycube_input(plus, tmesh::Params{});
  ASSERT_EQ(in.maps.blocks.size(), 20u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(in.maps.blocks[static_cast<std::size_t>(5 * k + 2)].size(), 9u);  // the centre: 3 x 3 columns
    EXPECT_EQ(in.maps.blocks[static_cast<std::size_t>(5 * k)].size(), 4u);      // an arm: core + 3 slabs
    const tmesh::Vec3 a = in.maps.physical(5 * k + 2, {0.5, 0.5, 0.5}), b = square.maps.physical(k, {0.5, 0.5, 0.5});
    EXPECT_LT(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), 1e-12);
    // Neighbouring cells meet: the centre's face toward an arm is the arm's face toward it.
    const tmesh::Vec3 p = in.maps.polycube(5 * k + 2, {0.5, 0, 0.5}), q = in.maps.polycube(5 * k + 2, {0.5, 1, 0.5});
    bool met_p = false, met_q = false;
    for (const int arm : {0, 1, 3, 4})
      for (const tmesh::Vec3 x : {tmesh::Vec3{0.5, 0, 0.5}, tmesh::Vec3{0.5, 1, 0.5}, tmesh::Vec3{0.5, 0.5, 0}, tmesh::Vec3{0.5, 0.5, 1}}) {
        const tmesh::Vec3 y = in.maps.polycube(5 * k + arm, x);
        met_p = met_p || std::hypot(y[0] - p[0], y[1] - p[1], y[2] - p[2]) < 1e-12;
        met_q = met_q || std::hypot(y[0] - q[0], y[1] - q[1], y[2] - q[2]) < 1e-12;
      }
    EXPECT_TRUE(met_p && met_q);
  }
  for (const char* bad : {R"({"b": [0, 0.5, 1], "c": [0, 1], "cells": [[2, 0]]})", R"({"b": [0, 0.5], "c": [0, 1], "cells": [[0, 0]]})",
                          R"({"b": [0, 1], "c": [0, 1], "cells": []})", R"({"b": 1})"}) {
    j["polycube"]["profile"] = core::Json::parse(bad);
    test::write_text(plus, j.dump());
    expect_refused(plus, "profile", bad);
  }
}


// Every block face of `in`'s complex evaluated at its corners: inner faces keyed by their corners'
// polycube points (a conforming complex has each exactly twice: `unmatched` counts the others),
// surface faces' corners measured against `tree` (`off_surface`, the largest distance) and handed
// to `on_surface` (cube, the corners' parameters, polycube and physical points).
struct FaceWalk {
  int unmatched = 0, inner = 0, surface = 0;
  double off_surface = 0;
};
using SurfaceFace = std::function<void(int, const std::vector<tmesh::Vec3>&, const std::vector<tmesh::Vec3>&, const std::vector<tmesh::Vec3>&)>;
FaceWalk walk_faces(const pipeline::PolycubeInput& in, const Tree& tree, const SurfaceFace& on_surface) {
  FaceWalk w;
  std::map<std::array<std::array<long long, 3>, 4>, int> inner;
  for (std::size_t c = 0; c < in.maps.blocks.size(); ++c)
    for (const tmesh::Block& b : in.maps.blocks[c])
      for (int f = 0; f < 6; ++f) {
        const int dd = f / 2, side = f % 2;
        std::array<std::array<long long, 3>, 4> key{};
        std::vector<tmesh::Vec3> uvw, poly, phys;
        for (int i = 0; i < 8; ++i) {
          if (((i >> dd) & 1) != side) continue;
          const tmesh::Vec3& x = b.corners[static_cast<std::size_t>(i)];
          const tmesh::Vec3 q = in.maps.polycube(static_cast<int>(c), x);
          for (int e = 0; e < 3; ++e) key[uvw.size()][static_cast<std::size_t>(e)] = std::llround(q[e] * 1e7);
          uvw.push_back(x), poly.push_back(q);
          if (!b.boundary[f]) continue;
          const tmesh::Vec3 p = in.maps.physical(static_cast<int>(c), x);
          phys.push_back(p);
          w.off_surface = std::max(w.off_surface, std::sqrt(CGAL::to_double(tree.squared_distance(surface::Point(p[0], p[1], p[2])))));
        }
        if (b.boundary[f]) {
          ++w.surface;
          on_surface(static_cast<int>(c), uvw, poly, phys);
          continue;
        }
        std::sort(key.begin(), key.end());
        ++inner[key];
      }
  for (const auto& [key, n] : inner) w.unmatched += n != 2;
  w.inner = static_cast<int>(inner.size());
  return w;
}

// The rod with its small end on the shoulder (examples/rod.yaml): the connector's end face is
// the eye's disk between two lenses, and the eye's ring stands on the disk's strip only. Every
// block corner of the complex is evaluated, the blocks conform in polycube space across that
// partial gluing (each inner block face is exactly one other block's), and every corner of a
// surface block face lies on the input surface — the lenses' too, which lie on the connector's
// end face outside the eye.
TEST(PolycubeInput, RodsEyeStandsOnTheDisksStripOfTheConnectorsLensedEnd) {
  const fs::path d = test::fresh_dir("pipeline", "polycube_input_lensed");
  test::write_text(d / "run.yaml", "input: {file: " + std::string(VOLTS_SHARED_MODELS) +
                                       "/loopycuts_rod_rem.obj}\nsplit: {connector_cut: 0.85, connector_end: shoulder}\n");
  const test::Outcome r = test::run(test::bin("volts") + " run " + (d / "run.yaml").string() + " --workdir " + (d / "w").string() + " --to polycube");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string file = (d / "w" / "polycube.stage.json").string();
  const core::Json j = core::read_stage_file(file, "volts-polycube", 2);
  ASSERT_TRUE(j["connectors"][0].contains("end_strip"));
  const core::Json strip = j["connectors"][0]["end_strip"];
  const int axis = strip["axis"].get<int>(), end = strip["end"].get<int>();
  const double lo = strip["lo"].get<double>(), hi = strip["hi"].get<double>();
  const pipeline::PolycubeInput in = pipeline::read_polycube_input(file, tmesh::Params{});
  ASSERT_EQ(in.kind, "tori");
  ASSERT_EQ(in.maps.blocks.size(), 9u);  // four cubes per ring, then the connector
  const surface::Mesh mesh = surface::mesh_from_json(in.surface, file);
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  const double diag = surface::bbox_diagonal(mesh);
  int lens_faces = 0;
  const FaceWalk w = walk_faces(in, tree, [&](int c, const std::vector<tmesh::Vec3>& uvw, const std::vector<tmesh::Vec3>&, const std::vector<tmesh::Vec3>&) {
    bool lens = c == 8;
    for (const auto& x : uvw)
      lens = lens && std::abs(x[0] - end) < 1e-12 && (x[static_cast<std::size_t>(axis)] < lo + 1e-9 || x[static_cast<std::size_t>(axis)] > hi - 1e-9);
    lens_faces += lens;
  });
  EXPECT_EQ(w.unmatched, 0) << "of " << w.inner << " inner block faces";
  EXPECT_GT(w.surface, 0);
  EXPECT_GT(lens_faces, 0) << "no pillow under the lenses";
  EXPECT_LT(w.off_surface, 1e-6 * diag);
  // A corrupt end_strip is refused naming the file and the member.
  const std::string bad = (d / "bad.json").string();
  for (const char* edit : {R"({"lo": 0.9})", R"({"axis": 0})", R"({"corner_vertex": [0, 1, 2, 1000000000]})", R"({"hi": "top"})"}) {
    core::Json k = j;
    const core::Json change = core::Json::parse(edit);
    for (auto it = change.begin(); it != change.end(); ++it) k["connectors"][0]["end_strip"][it.key()] = *it;
    test::write_text(bad, k.dump());
    expect_refused(bad, "end_strip", edit);
  }
}


// The assembly's stage file `j` with its base's parameters flipped (x -> 1 - x) along the axes
// `flip` says: its surface map's points, its volume map's parameters, its holes' and its foot's
// boxes and the structure's boxes.
core::Json flip_base(core::Json k, const std::array<bool, 3>& flip) {
  auto points = [&](core::Json& a) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (flip[i % 3]) a[i] = 1 - a[i].get<double>();
  };
  auto box = [&](core::Json& lo, core::Json& hi) {
    for (std::size_t d = 0; d < 3; ++d) {
      if (!flip[d]) continue;
      const double l = lo[d].get<double>(), h = hi[d].get<double>();
      lo[d] = 1 - h, hi[d] = 1 - l;
    }
  };
  core::Json& pc = k["base"]["polycube"];
  points(pc["points"]), points(k["base"]["volume_map"]["parameter"]);
  for (auto& h : pc["holes"]) box(h["hole_lo"], h["hole_hi"]);
  box(pc["foot"]["lo"], pc["foot"]["hi"]);
  for (auto& v : k["structure"]["virtual_components"])
    for (auto& b : v["boxes"]) box(b["lo"], b["hi"]);
  return k;
}

// The assembly (kind torus_on_cube, examples/assembly.yaml): the plate's boxes and the ring's
// cubes as one complex (foot_maps). Every block corner is evaluated; the blocks conform in
// polycube space (each inner block face is exactly one other block's: across the foot, the ring's
// closures and the cuts near the foot's ends), every corner of a surface block face lies on the
// input surface, the ring's cubes have blocks on the crack where the ring leaves its foot — the
// same with the base's parameters turned half a turn (the foot on the other face, the ring's row
// the other way) —, and a base without its foot, with foreign corner vertices or mirrored against
// the ring is refused naming the member.
TEST(PolycubeInput, AssemblysRingStandsOnItsFootAndTheComplexConforms) {
  const fs::path d = test::fresh_dir("pipeline", "polycube_input_assembly");
  test::write_text(d / "run.yaml", "input: {generate: assembly, resolution: 16}\n");
  const test::Outcome r = test::run(test::bin("volts") + " run " + (d / "run.yaml").string() + " --workdir " + (d / "w").string() + " --to polycube");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string file = (d / "w" / "polycube.stage.json").string();
  const core::Json j = core::read_stage_file(file, "volts-polycube", 2);
  tmesh::Params params;
  params.level = 2;
  const pipeline::PolycubeInput in = pipeline::read_polycube_input(file, params);
  ASSERT_EQ(in.kind, "torus_on_cube");
  // 45 grid boxes of the plate and 4 ring cubes, cut near the foot's ends: more sub-boxes.
  EXPECT_GT(in.maps.blocks.size(), 49u);
  const surface::Mesh mesh = surface::mesh_from_json(in.surface, file);
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  const double diag = surface::bbox_diagonal(mesh);
  // Counts the ring's surface faces down on the plate's top (z = 0.25): the ring's slabs on the
  // cracks where it leaves its foot.
  auto count_cracks = [](int& count) -> SurfaceFace {
    return [&count](int, const std::vector<tmesh::Vec3>&, const std::vector<tmesh::Vec3>& poly, const std::vector<tmesh::Vec3>& phys) {
      bool ring = true, low = false;
      for (const auto& q : poly) ring = ring && q[0] < 10;  // the ring's annulus; the plate's points lie at x >= 30
      for (const auto& p : phys) low = low || p[2] < 0.25 + 1e-6;
      count += ring && low;
    };
  };
  int crack_faces = 0;
  const FaceWalk w = walk_faces(in, tree, count_cracks(crack_faces));
  EXPECT_EQ(w.unmatched, 0) << "of " << w.inner << " inner block faces";
  EXPECT_GT(w.surface, 0);
  EXPECT_GT(crack_faces, 0) << "no ring slab reaches the foot's ends";
  EXPECT_LT(w.off_surface, 1e-6 * diag);
  // The base's parameters turned half a turn about their third axis, (u, v, w) -> (1 - u, 1 - v,
  // w): the foot on the face u = 0 and the ring's row the other way along v (stage polycube
  // always puts it on u = 1). The same solid, so the same checks.
  {
    const core::Json k = flip_base(j, {true, true, false});
    const std::string turned = (d / "turned.json").string();
    test::write_text(turned, k.dump());
    const pipeline::PolycubeInput t = pipeline::read_polycube_input(turned, params);
    int cracks = 0;
    const FaceWalk tw = walk_faces(t, tree, count_cracks(cracks));
    EXPECT_EQ(tw.unmatched, 0) << "turned: of " << tw.inner << " inner block faces";
    EXPECT_EQ(tw.inner, w.inner);
    EXPECT_EQ(cracks, crack_faces);
    EXPECT_LT(tw.off_surface, 1e-6 * diag);
  }
  const std::string bad = (d / "bad.json").string();
  test::write_text(bad, flip_base(j, {false, true, false}).dump());  // one axis: the base mirrored against the ring
  expect_refused(bad, "mirrored", "a base mirrored against the ring");
  core::Json k = j;
  k["base"]["polycube"].erase("foot");
  test::write_text(bad, k.dump());
  expect_refused(bad, "foot", "a base without its foot");
  k = j;
  for (auto& v : k["base"]["layout_vertex"]) v = v.get<int>() + 1;
  test::write_text(bad, k.dump());
  expect_refused(bad, "layout_vertex", "foreign corner vertices");
}

}  // namespace
}  // namespace volts
