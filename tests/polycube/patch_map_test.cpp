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
