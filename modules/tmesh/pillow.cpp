#include "tmesh/pillow.h"

#include <string>

#include "core/errors.h"

namespace volts::tmesh {

Vec3 block_point(const std::array<Vec3, 8>& c, const Vec3& uvw) {
  Vec3 x{0, 0, 0};
  for (int i = 0; i < 8; ++i) {
    const double w = (i & 1 ? uvw[0] : 1 - uvw[0]) * (i & 2 ? uvw[1] : 1 - uvw[1]) * (i & 4 ? uvw[2] : 1 - uvw[2]);
    for (int d = 0; d < 3; ++d) x[d] += w * c[i][d];
  }
  return x;
}

std::vector<Block> cube_blocks(const std::array<int, 6>& boundary, const std::array<int, 3>& elements, int layers) {
  if (layers < 0) throw core::ConfigError("tmesh.pillow_layers must be >= 0, got " + std::to_string(layers));
  for (const int n : elements)
    if (n < 1) throw core::ConfigError("tmesh: a cube needs at least one element per direction");
  auto box = [](const Vec3& lo, const Vec3& hi) {
    std::array<Vec3, 8> c;
    for (int i = 0; i < 8; ++i)
      for (int d = 0; d < 3; ++d) c[i][d] = (i >> d) & 1 ? hi[d] : lo[d];
    return c;
  };
  if (layers == 0) {
    Block b;
    b.corners = box({0, 0, 0}, {1, 1, 1});
    b.elements = elements;
    b.boundary = boundary;
    return {b};
  }
  // Core extent: pulled in from every surface face by `layers` elements of the cube's spacing.
  Vec3 lo{0, 0, 0}, hi{1, 1, 1};
  for (int d = 0; d < 3; ++d) {
    const int sides = boundary[2 * d] + boundary[2 * d + 1];
    const double h = 1.0 / (elements[d] + sides * layers);
    if (boundary[2 * d]) lo[d] = layers * h;
    if (boundary[2 * d + 1]) hi[d] = 1 - layers * h;
  }
  std::vector<Block> blocks;
  Block core;
  core.corners = box(lo, hi);
  core.elements = elements;
  blocks.push_back(core);
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      if (!boundary[2 * a + s]) continue;
      Block slab;
      slab.pillow = true;
      slab.elements = elements;
      slab.elements[a] = layers;
      slab.boundary[2 * a + s] = 1;
      // Local axes are the cube's (orientation kept); along a, the side toward the face is the
      // cube face, the other the core face. The outer face spans the whole cube face, the inner
      // face the core's, so the slab's sides are diagonal where the next face is a surface face
      // too and flat (on the cube face) where it is not.
      for (int i = 0; i < 8; ++i) {
        const bool outer = ((i >> a) & 1) == s;
        Vec3 x;
        for (int d = 0; d < 3; ++d) {
          const int bit = (i >> d) & 1;
          if (d == a) x[d] = outer ? s : (s ? hi[d] : lo[d]);
          else x[d] = outer ? bit : (bit ? hi[d] : lo[d]);
        }
        slab.corners[i] = x;
      }
      blocks.push_back(slab);
    }
  return blocks;
}

}  // namespace volts::tmesh
