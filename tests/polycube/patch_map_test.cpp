// Surface map of the quad patches onto unit squares (Liu et al. §4.2–4.3): on every model the split
// stage handles, no mapped triangle is flipped, the four corners land on the square's corners, and
// a side shared by two patches is parameterized alike from both (same arc-length fractions).
#include <gtest/gtest.h>

#include <map>

#include "classify/classify.h"
#include "models/models.h"
#include "polycube/patch_map.h"
#include "split/split.h"

using namespace volts;

namespace {

// Level ends for a connector: a shoulder end (the rod's default) is one face of three patches that
// meet the ring's face in part, whose sides are not shared whole; polycube maps that face as
// strips (Connector.RodShoulderEndFaceIsMappedAsLensDiskLensStrips).
split::Decomposition decompose(const surface::Mesh& m) {
  split::Params p;
  p.connector_end = "level";
  return split::split(m, classify::classify(m, {}), p);
}

surface::Mesh model(const std::string& name) {
  if (name.find('.') != std::string::npos) return surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + name);
  models::ModelParams p;
  p.name = name;
  p.resolution = 16;
  return models::make_model(p);
}

}  // namespace

class PatchMapOn : public ::testing::TestWithParam<const char*> {};

TEST_P(PatchMapOn, NoFlipsCornersOnCornersSharedSidesAgree) {
  const auto d = decompose(model(GetParam()));
  const auto maps = polycube::map_patches(d, {});
  ASSERT_EQ(maps.size(), d.layout.patches.size());
  std::map<std::pair<int, int>, double> side_param;  // (side's first corner, vertex) -> fraction, by undirected side
  int flips = 0;
  double distortion = 0;
  for (std::size_t p = 0; p < maps.size(); ++p) {
    const auto& m = maps[p];
    const auto& P = d.layout.patches[p];
    flips += m.flipped_triangles;
    distortion = std::max(distortion, m.max_angle_distortion_deg);
    std::map<int, std::array<double, 2>> st;
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
      st[m.vertices[i]] = m.st[i];
      EXPECT_GE(m.st[i][0], -1e-12);
      EXPECT_LE(m.st[i][0], 1 + 1e-12);
      EXPECT_GE(m.st[i][1], -1e-12);
      EXPECT_LE(m.st[i][1], 1 + 1e-12);
    }
    const double corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(st.at(P.corners[k])[0], corner[k][0]);
      EXPECT_EQ(st.at(P.corners[k])[1], corner[k][1]);
      // Shared side: the same vertices get the same fraction from the same end.
      const auto& s = P.sides[k];
      const auto frac = polycube::arc_length_fractions(d.layout, s);
      const bool forward = s.front() < s.back();
      const int key = forward ? s.front() : s.back();
      for (std::size_t i = 0; i < s.size(); ++i) {
        const double f = forward ? frac[i] : 1 - frac[i];
        const auto [it, fresh] = side_param.emplace(std::pair{key, s[i]}, f);
        if (!fresh) {
          EXPECT_NEAR(it->second, f, 1e-12) << "side from vertex " << key;
        }
      }
    }
  }
  EXPECT_EQ(flips, 0) << GetParam();
  EXPECT_LT(distortion, 180.0);
  std::printf("[ info ] %s: %zu patches, 0 flips, max angle distortion %.1f deg\n", GetParam(), maps.size(), distortion);
}

INSTANTIATE_TEST_SUITE_P(Models, PatchMapOn,
                         ::testing::Values("bulged-box", "torus", "cube-with-hole", "cinolib_torus.obj", "cfwen_eight.off", "vhacd_tube1.off",
                                           "loopycuts_mechanical08_rem.obj", "loopycuts_rod_rem.obj"),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (!isalnum(static_cast<unsigned char>(c))) c = '_';
                           return s;
                         });

// unfold_free_vertices on a square of 3 x 3 vertices whose centre (the one free vertex) is put
// past a diagonal: some of its eight triangles flip; the centre moves into the kernel of
// its link (here the square itself) and no triangle is flipped. Fixed vertices never move. A centre
// whose link has an empty kernel (its neighbours folded over) is left where it is.
TEST(UnfoldFreeVertices, MovesAFreeVertexIntoItsLinksKernel) {
  split::Layout L;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) L.points.push_back({double(i), double(j), 0.0});
  std::vector<int> tris;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i, b = a + 1, c = a + 4, d = a + 3;
      tris.push_back(static_cast<int>(L.triangles.size())), L.triangles.push_back({a, b, c});
      tris.push_back(static_cast<int>(L.triangles.size())), L.triangles.push_back({a, c, d});
    }
  L.filled.assign(L.triangles.size(), 0);
  std::map<int, std::array<double, 2>> fixed, at;
  for (int v = 0; v < 9; ++v)
    if (v != 4) fixed[v] = {L.points[v][0], L.points[v][1]};
  at = fixed;
  at[4] = {1.8, 0.3};  // inside the square but past the diagonal: some triangles flip
  EXPECT_GT(polycube::map_quality(L, tris, at).flipped_triangles, 0);
  EXPECT_EQ(polycube::unfold_free_vertices(L, tris, fixed, at, 5), 0);
  EXPECT_EQ(polycube::map_quality(L, tris, at).flipped_triangles, 0);
  EXPECT_NEAR(at[4][0], 1.0, 1e-12);  // the kernel is the square: its centroid
  EXPECT_NEAR(at[4][1], 1.0, 1e-12);
  for (const auto& [v, x] : fixed) EXPECT_EQ(at[v], x);
  // Neighbours folded over (two corners swapped): no kernel, nothing moves.
  std::map<int, std::array<double, 2>> folded = fixed;
  std::swap(folded[0], folded[8]);
  folded[4] = {1.8, 0.3};
  std::map<int, std::array<double, 2>> x = folded;
  const int left = polycube::unfold_free_vertices(L, tris, folded, x, 5);
  EXPECT_GT(left, 0);
  EXPECT_EQ(x, folded);
}
