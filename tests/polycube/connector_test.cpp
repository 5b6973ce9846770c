// The connector cube of two tori (polycube/connector.h; split.genus2: connector): on the eight,
// each torus is closed by its own disk and the neck is one cube whose ends are those disks; it
// maps onto the unit cube with its surface on the cube's boundary, its ends at a = 0 (ring 0's
// disk) and a = 1, no flipped triangle, the same parameterization of each end as the ring's patch
// map of that disk (up to a symmetry of the square), and a volume map without flipped tets.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "classify/classify.h"
#include "core/errors.h"
#include "polycube/connector.h"
#include "polycube/patch_map.h"
#include "polycube/rings.h"
#include "split/split.h"
#include "surface/surface.h"
#include "volmap/volmap.h"

using namespace volts;

namespace {

struct Eight {
  split::Decomposition d;
  std::vector<polycube::Ring> rings;
  polycube::Ring neck;
  polycube::ConnectorMap map;
};

const Eight& eight() {
  static const Eight e = [] {
    Eight x;
    const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/cfwen_eight.off");
    split::Params sp;
    sp.genus2 = "connector";
    x.d = split::split(mesh, classify::classify(mesh, {}), sp);
    x.rings = polycube::rings(x.d);
    x.neck = polycube::connector(x.d).value();
    x.map = polycube::map_connector(x.neck, x.rings[0], {});
    return x;
  }();
  return e;
}

// The layout patch of `piece` whose triangles are fills (its disk), as the piece's patch index.
int disk_patch(const polycube::Ring& piece, const std::set<int>& fills) {
  const auto& L = piece.decomposition.layout;
  for (std::size_t p = 0; p < L.patches.size(); ++p) {
    const int t = L.patches[p].triangles.at(0);
    if (L.filled[static_cast<std::size_t>(t)] && fills.count(piece.layout_triangle[static_cast<std::size_t>(t)])) return static_cast<int>(p);
  }
  return -1;
}

// Patch p of `piece`'s map_patches map, by whole-decomposition vertex id.
std::map<int, std::array<double, 2>> by_layout_vertex(const polycube::Ring& piece, const std::vector<polycube::PatchMap>& maps, int p) {
  std::map<int, std::array<double, 2>> out;
  const auto& pm = maps.at(static_cast<std::size_t>(p));
  for (std::size_t i = 0; i < pm.vertices.size(); ++i) out[piece.layout_vertex[static_cast<std::size_t>(pm.vertices[i])]] = pm.st[i];
  return out;
}

// The largest distance between two maps of one vertex set onto the unit square, under the best of
// the square's eight symmetries applied to `a` (1e300 if the vertex sets differ).
double distance_up_to_symmetry(const std::map<int, std::array<double, 2>>& a, const std::map<int, std::array<double, 2>>& b) {
  if (a.size() != b.size()) return 1e300;
  double best = 1e300;
  for (int sym = 0; sym < 8; ++sym) {
    double worst = 0;
    for (const auto& [v, st] : a) {
      std::array<double, 2> x = st;
      if (sym & 1) x[0] = 1 - x[0];
      if (sym & 2) x[1] = 1 - x[1];
      if (sym & 4) std::swap(x[0], x[1]);
      const auto it = b.find(v);
      if (it == b.end()) return 1e300;
      worst = std::max(worst, std::hypot(x[0] - it->second[0], x[1] - it->second[1]));
    }
    best = std::min(best, worst);
  }
  return best;
}

}  // namespace

TEST(Connector, EightSplitsIntoTwoClosedToriAndANeckCube) {
  const Eight& e = eight();
  ASSERT_EQ(e.rings.size(), 2u);
  EXPECT_EQ(e.neck.decomposition.components.size(), 1u);
  EXPECT_EQ(e.neck.decomposition.layout.patches.size(), 6u);
  // Every fill triangle closes exactly one torus and is an end of the neck.
  const std::set<int> neck(e.neck.layout_triangle.begin(), e.neck.layout_triangle.end());
  int fills = 0;
  for (std::size_t t = 0; t < e.d.layout.triangles.size(); ++t) {
    if (!e.d.layout.filled[t]) continue;
    ++fills;
    int in = 0;
    for (const auto& r : e.rings) in += std::count(r.layout_triangle.begin(), r.layout_triangle.end(), static_cast<int>(t));
    EXPECT_EQ(in, 1) << "fill triangle " << t;
    EXPECT_TRUE(neck.count(static_cast<int>(t))) << "fill triangle " << t;
  }
  EXPECT_GT(fills, 0);
}

TEST(Connector, NeckMapsOntoTheUnitCubeWithItsEndsOnTheRingsDisks) {
  const Eight& e = eight();
  const polycube::ConnectorMap& m = e.map;
  EXPECT_EQ(std::set<int>(m.corner_vertex.begin(), m.corner_vertex.end()).size(), 8u);
  EXPECT_EQ(m.flipped_surface_triangles, 0);
  EXPECT_LT(m.max_mismatch, 1e-9);
  for (const auto& p : m.points) {
    int on = 0;
    for (const double x : p) {
      EXPECT_GE(x, -1e-12);
      EXPECT_LE(x, 1 + 1e-12);
      on += std::abs(x) < 1e-12 || std::abs(x - 1) < 1e-12;
    }
    EXPECT_GE(on, 1) << "a surface point inside the cube";
  }
  // Ring r's disk lies on the face a = r.
  const auto& L = e.neck.decomposition.layout;
  for (int r = 0; r < 2; ++r) {
    const std::set<int> ring(e.rings[r].layout_triangle.begin(), e.rings[r].layout_triangle.end());
    const int p = disk_patch(e.neck, ring);
    ASSERT_GE(p, 0);
    for (int t : L.patches[static_cast<std::size_t>(p)].triangles)
      for (int v : L.triangles[static_cast<std::size_t>(t)]) EXPECT_NEAR(m.points[static_cast<std::size_t>(v)][0], r, 1e-12);
  }
}

TEST(Connector, EachEndIsParameterizedAsItsRingParameterizesTheDisk) {
  const Eight& e = eight();
  const auto neck_maps = polycube::map_patches(e.neck.decomposition, {});
  for (int r = 0; r < 2; ++r) {
    const polycube::Ring& ring = e.rings[static_cast<std::size_t>(r)];
    const std::set<int> fills(ring.layout_triangle.begin(), ring.layout_triangle.end());
    const int pn = disk_patch(e.neck, fills), pr = disk_patch(ring, fills);
    ASSERT_GE(pn, 0);
    ASSERT_GE(pr, 0);
    const auto ring_maps = polycube::map_patches(ring.decomposition, {});
    EXPECT_LT(distance_up_to_symmetry(by_layout_vertex(e.neck, neck_maps, pn), by_layout_vertex(ring, ring_maps, pr)), 1e-8) << "ring " << r;
  }
}

TEST(Connector, NeckVolumeMapHasNoFlippedTets) {
  const Eight& e = eight();
  const volmap::VolumeMap vm = polycube::connector_volume_map(e.neck, e.map, {});
  EXPECT_EQ(vm.flipped_tets, 0);
  EXPECT_GT(vm.min_volume_ratio, 0);
  EXPECT_EQ(vm.surface_vertices, static_cast<int>(e.neck.layout_vertex.size()));
  double volume = 0;
  for (const auto& t : vm.tets) {
    const auto& p = vm.parameter;
    volume += (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).dot(p[t[3]] - p[t[0]]) / 6;
  }
  EXPECT_NEAR(volume, 1.0, 1e-9);  // the tets fill the unit cube
}

// The rod cut near its eyes (split.connector_cut 0.85): CGAL's fills crossed ring 1 and the neck
// there, so TetGen refused the neck; with the planar fills its volume map has no flipped tet, with
// the maps smoothed as the pipeline smooths a connector split's.
TEST(Connector, RodCutNearItsEyesMapsItsNeckWithoutFlippedTets) {
  const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/loopycuts_rod_rem.obj");
  split::Params sp;
  sp.genus2 = "connector";
  sp.connector_cut = 0.85;
  sp.connector_end = "level";
  const split::Decomposition d = split::split(mesh, classify::classify(mesh, {}), sp);
  const auto rings = polycube::rings(d);
  const polycube::Ring neck = polycube::connector(d).value();
  polycube::Params pp;
  pp.smooth_below_ratio = pp.connector_smooth_below_ratio;
  const polycube::ConnectorMap map = polycube::map_connector(neck, rings[0], {});
  const volmap::VolumeMap vm = polycube::connector_volume_map(neck, map, pp);
  EXPECT_EQ(vm.flipped_tets, 0);
  EXPECT_GT(vm.min_volume_ratio, 0);
  EXPECT_EQ(vm.surface_vertices, static_cast<int>(neck.layout_vertex.size()));
}

// split.connector_end: shoulder makes the rod's small end face its disk and the shoulder's two
// lenses (docs/status.md, Session 21): that face is mapped as three strips across the eye, lens |
// disk | lens, with straight lines between them; the disk's strip is ring 1's map of the disk
// scaled onto it (so ring 1's face can cover it exactly), the lenses lie beyond the lines, and
// the whole surface map is one-to-one with every patch agreeing on shared sides.
TEST(Connector, RodShoulderEndFaceIsMappedAsLensDiskLensStrips) {
  const auto mesh = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/loopycuts_rod_rem.obj");
  split::Params sp;
  sp.genus2 = "connector";
  sp.connector_cut = 0.85;
  sp.connector_end = "shoulder";
  const split::Decomposition d = split::split(mesh, classify::classify(mesh, {}), sp);
  const auto rings = polycube::rings(d);
  ASSERT_EQ(rings.size(), 2u);
  const polycube::Ring neck = polycube::connector(d).value();
  const polycube::ConnectorMap m = polycube::map_connector(neck, rings[0], {});
  EXPECT_EQ(std::set<int>(m.corner_vertex.begin(), m.corner_vertex.end()).size(), 8u);
  EXPECT_EQ(m.flipped_surface_triangles, 0);
  EXPECT_LT(m.max_mismatch, 1e-9);
  ASSERT_TRUE(m.strip_axis == 1 || m.strip_axis == 2) << m.strip_axis;
  EXPECT_EQ(m.strip_end, 1);  // the small eye is ring 1
  const double lo = m.strip[0], hi = m.strip[1];
  EXPECT_GT(lo, 0.05);
  EXPECT_LT(hi, 0.95);
  EXPECT_GT(hi - lo, 0.2);
  const int other = 3 - m.strip_axis;
  // The end face's three patches: the disk in [lo, hi] (within rounding), the lenses outside.
  const auto& L = neck.decomposition.layout;
  const std::set<int> ring1(rings[1].layout_triangle.begin(), rings[1].layout_triangle.end());
  const int pn = disk_patch(neck, ring1);
  ASSERT_GE(pn, 0);
  const auto& faces = neck.decomposition.components.at(0).faces;
  int lensed = 0;
  for (const auto& f : faces) {
    if (f.patches.size() != 3) continue;
    ++lensed;
    for (const int p : f.patches) {
      int in = 0, out = 0;
      for (int t : L.patches[static_cast<std::size_t>(p)].triangles)
        for (int v : L.triangles[static_cast<std::size_t>(t)]) {
          const auto& x = m.points[static_cast<std::size_t>(v)];
          EXPECT_NEAR(x[0], 1.0, 1e-12);
          const double c = x[static_cast<std::size_t>(m.strip_axis)];
          in += c > lo + 1e-12 && c < hi - 1e-12, out += c < lo - 1e-12 || c > hi + 1e-12;
        }
      if (p == pn) EXPECT_EQ(out, 0) << "a vertex of the disk outside its strip";
      else EXPECT_EQ(in, 0) << "a vertex of lens patch " << p << " inside the disk's strip";
    }
  }
  EXPECT_EQ(lensed, 1);
  // The disk's strip, rescaled to the unit square, is ring 1's own map of the disk.
  std::map<int, std::array<double, 2>> strip;
  for (int t : L.patches[static_cast<std::size_t>(pn)].triangles)
    for (int v : L.triangles[static_cast<std::size_t>(t)]) {
      const auto& x = m.points[static_cast<std::size_t>(v)];
      strip[neck.layout_vertex[static_cast<std::size_t>(v)]] = {x[static_cast<std::size_t>(other)],
                                                                (x[static_cast<std::size_t>(m.strip_axis)] - lo) / (hi - lo)};
    }
  const int pr = disk_patch(rings[1], ring1);
  ASSERT_GE(pr, 0);
  EXPECT_LT(distance_up_to_symmetry(strip, by_layout_vertex(rings[1], polycube::map_patches(rings[1].decomposition, {}), pr)), 1e-9);
  // And the neck's volume map, with the maps smoothed as the pipeline smooths a connector's.
  polycube::Params pp;
  pp.smooth_below_ratio = pp.connector_smooth_below_ratio;
  const volmap::VolumeMap vm = polycube::connector_volume_map(neck, m, pp);
  EXPECT_EQ(vm.flipped_tets, 0);
  EXPECT_GT(vm.min_volume_ratio, 0);
}

TEST(Connector, StageFileCornersAreCheckedAndNameTheFile) {
  const Eight& e = eight();
  const volmap::VolumeMap vm = polycube::connector_volume_map(e.neck, e.map, {});
  const core::Json good = polycube::to_json(e.neck, e.map, vm);
  const std::array<int, 8> corners = polycube::connector_corners(good, "p.json");
  for (int i = 0; i < 8; ++i)
    EXPECT_EQ(corners[static_cast<std::size_t>(i)], e.neck.layout_vertex[static_cast<std::size_t>(e.map.corner_vertex[static_cast<std::size_t>(i)])]);
  auto refused = [](core::Json j, const std::string& part) {
    try {
      polycube::connector_corners(j, "p.json");
      ADD_FAILURE() << "no error for " << part;
    } catch (const core::InvalidInputError& x) {
      const std::string what = x.what();
      EXPECT_NE(what.find("p.json"), std::string::npos) << what;
      EXPECT_NE(what.find(part), std::string::npos) << what;
    }
  };
  core::Json j = good;
  j.erase("corner_vertex");
  refused(j, "corner_vertex");
  j = good;
  j["corner_vertex"][3] = 1 << 30;
  refused(j, "out of range");
  j = good;
  j["corner_vertex"][3] = j["corner_vertex"][4];
  refused(j, "repeats");
  j = good;
  j["corner_vertex"] = "eight";
  refused(j, "malformed");
}
