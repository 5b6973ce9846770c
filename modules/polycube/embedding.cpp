#include "polycube/embedding.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/errors.h"
#include "core/log.h"
#include "viz/viz.h"

namespace volts::polycube {

namespace {
constexpr double kPi = 3.14159265358979323846;
using Vec3 = std::array<double, 3>;
}  // namespace

std::array<double, 3> cell_point(const Embedding& e, int k, const std::array<double, 3>& x) {
  const double theta = 2 * kPi * (k + x[0]) / e.ring, r = 1.0 + x[1];
  return {r * std::cos(theta), r * std::sin(theta), e.mirrored ? 1.0 - x[2] : x[2]};
}

void place_patches(Embedding& e, const split::Layout& L, const std::vector<PlacedPatch>& placed, const std::vector<PatchMap>& maps) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto place = [&]() {
    std::vector<Vec3> pts(L.points.size(), Vec3{nan, nan, nan});
    double mismatch = 0;
    for (const PlacedPatch& pl : placed) {
      const PatchMap& m = maps.at(static_cast<std::size_t>(pl.patch));
      const auto& X = pl.corners;
      for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        const double s = m.st[v][0], t = m.st[v][1];
        Vec3 abc{};
        for (std::size_t q = 0; q < 3; ++q)
          abc[q] = (1 - s) * (1 - t) * X[0][q] + s * (1 - t) * X[1][q] + s * t * X[2][q] + (1 - s) * t * X[3][q];
        const Vec3 y = cell_point(e, pl.component, abc);
        Vec3& slot = pts[static_cast<std::size_t>(m.vertices[v])];
        if (!std::isnan(slot[0]))
          mismatch = std::max(mismatch, std::sqrt((slot[0] - y[0]) * (slot[0] - y[0]) + (slot[1] - y[1]) * (slot[1] - y[1]) + (slot[2] - y[2]) * (slot[2] - y[2])));
        slot = y;
      }
    }
    e.max_mismatch = mismatch;
    return pts;
  };
  // Mirror if the embedded surface has the other orientation than the physical one.
  e.points = place();
  if (layout_volume(L, e.points, Fills::include) < 0) {
    e.mirrored = true;
    e.points = place();
  }
}

namespace {

// Length of the chain of patch sides of `patch` between corners u and v (adjacent corners).
double side_length(const split::Layout& L, int patch, int u, int v) {
  const split::Patch& P = L.patches.at(static_cast<std::size_t>(patch));
  for (std::size_t k = 0; k < 4; ++k) {
    const int a = P.corners[k], b = P.corners[(k + 1) % 4];
    if ((a == u && b == v) || (a == v && b == u)) return chain_length(L, P.sides[k]);
  }
  throw core::TopologyError("polycube: patch " + std::to_string(patch) + " has no side between vertices " + std::to_string(u) + " and " + std::to_string(v));
}

// The corner line (0..3, the first corners of faces[i]) that becomes (b, c) = (0, 0): chosen so
// that the two lines on the round ring's inner side (b = 0, radius 1) are the physically
// shortest around the ring. Split's corner order is arbitrary: with it, the generated torus had
// its outer side on the annulus's inner circle, and the rod's big eye its radial direction along
// the annulus's height — a harmonic volume map then turns the solid inside out.
int inner_corner_line(const split::Decomposition& d) {
  std::array<double, 4> len{};
  for (const int c : d.tori[0].components) {
    const auto& comp = d.components.at(static_cast<std::size_t>(c));
    for (int i = 0; i < 4; ++i) {
      const auto& f = comp.faces[static_cast<std::size_t>(i)];
      len[static_cast<std::size_t>(i)] += side_length(d.layout, f.patches.at(0), f.corners[0], f.corners[1]);
    }
  }
  // Line i and line i + 3 (mod 4) span the b = 0 side; keep split's order unless another side is
  // clearly (1 %) shorter.
  int best = 0;
  double best_len = len[0] + len[3];
  for (int t = 1; t < 4; ++t) {
    const double l = len[static_cast<std::size_t>(t)] + len[static_cast<std::size_t>((t + 3) % 4)];
    if (l < 0.99 * best_len) best = t, best_len = l;
  }
  return best;
}

}  // namespace

Embedding embed_torus(const split::Decomposition& d, const std::vector<PatchMap>& maps) {
  if (d.tori.size() != 1 || d.components.size() != d.tori[0].components.size())
    throw core::TopologyError("polycube: only a decomposition into one torus can be embedded yet (this one has " +
                              std::to_string(d.tori.size()) + " tori and " + std::to_string(d.components.size()) + " components)");
  const int n = static_cast<int>(d.components.size());
  Embedding e;
  e.ring = n;
  e.cells.resize(n);
  e.corner_vertex.resize(n);
  // Local corner (a, b, c) of cube k: the square corner q_i of the cross section is (b, c) =
  // (0,0), (1,0), (1,1), (0,1) for corner line (i + turn) mod 4, and faces[i].corners = {(0,q), (1,q), ...}
  // with q line i's corner.
  static const int qb[4] = {0, 1, 1, 0}, qc[4] = {0, 0, 1, 1};
  for (int k = 0; k < n; ++k) {
    const auto& comp = d.components[d.tori[0].components[k]];
    if (comp.faces.size() != 6) throw core::TopologyError("polycube: component " + std::to_string(k) + " has not six faces");
    for (int i = 0; i < 4; ++i)
      if (comp.faces[i].patches.size() != 1)
        throw core::TopologyError("polycube: a torus cube face made of " + std::to_string(comp.faces[i].patches.size()) +
                                  " patches (sharp curves inside a face) is not supported yet (issue 6); raise classify.sharp_angle_deg to ignore "
                                  "those curves, or set `route: tet`");
  }
  const int turn = inner_corner_line(d);
  for (int k = 0; k < n; ++k) {
    const auto& comp = d.components[d.tori[0].components[k]];
    for (int i = 0; i < 4; ++i)
      for (int a = 0; a < 2; ++a) {
        const int q = (i - turn + 4) % 4;
        const int corner = a + 2 * qb[q] + 4 * qc[q];
        e.corner_vertex[k][corner] = comp.faces[i].corners[a];
        e.cells[k][corner] = cell_point(e, k, {double(a), double(qb[q]), double(qc[q])});
      }
  }
  const split::Layout& L = d.layout;
  std::vector<PlacedPatch> placed;
  for (int k = 0; k < n; ++k) {
    const auto& comp = d.components[d.tori[0].components[k]];
    std::map<int, int> local_corner;  // layout vertex -> local corner index
    for (int c = 0; c < 8; ++c) local_corner[e.corner_vertex[k][c]] = c;
    for (int i = 0; i < 4; ++i) {
      PlacedPatch pl{k, comp.faces[i].patches[0], {}};
      const auto& P = L.patches[pl.patch];
      for (int j = 0; j < 4; ++j) {
        const auto it = local_corner.find(P.corners[j]);
        if (it == local_corner.end()) throw core::TopologyError("polycube: patch " + std::to_string(pl.patch) + " has a corner that is not a corner of its cube");
        pl.corners[j] = {double(it->second & 1), double((it->second >> 1) & 1), double((it->second >> 2) & 1)};
      }
      placed.push_back(pl);
    }
  }
  place_patches(e, L, placed, maps);
  if (e.mirrored)
    for (auto& cell : e.cells)
      for (auto& x : cell) x[2] = 1 - x[2];
  for (const auto& t : L.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &p = e.points[t[k]], &q = e.points[t[(k + 1) % 3]];
      const Vec3 m{(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
      const double r = std::hypot(m[0], m[1]);
      e.boundary_gap = std::max(e.boundary_gap, std::min({std::abs(r - 1), std::abs(r - 2), std::abs(m[2]), std::abs(m[2] - 1)}));
    }
  return e;
}

split::Decomposition merge_face_patches(const split::Decomposition& d) {
  split::Decomposition r = d;
  std::vector<split::Patch> patches;
  std::vector<int> new_id(d.layout.patches.size(), -1);
  for (auto& comp : r.components)
    for (auto& f : comp.faces) {
      if (f.patches.size() <= 1) continue;
      // The union's boundary, walked along the triangles' orientation (outward, so counter-
      // clockwise seen from outside), split at the face's four corners.
      split::Patch merged;
      std::map<std::pair<int, int>, int> directed;
      for (const int p : f.patches)
        for (const int t : d.layout.patches.at(static_cast<std::size_t>(p)).triangles) {
          merged.triangles.push_back(t);
          const auto& tri = d.layout.triangles.at(static_cast<std::size_t>(t));
          for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
        }
      std::map<int, int> next;
      for (const auto& [e, n] : directed)
        if (!directed.count({e.second, e.first}) && !next.emplace(e.first, e.second).second)
          throw core::TopologyError("polycube: the patches of a cube face do not form a disk (vertex " + std::to_string(e.first) + ")");
      std::vector<int> loop{f.corners[0]};
      for (std::size_t guard = 0; guard <= next.size(); ++guard) {
        const auto it = next.find(loop.back());
        if (it == next.end()) throw core::TopologyError("polycube: a cube face corner is not on the boundary of its patches");
        if (it->second == loop.front()) break;
        loop.push_back(it->second);
      }
      std::vector<std::size_t> at;
      for (std::size_t i = 0; i < loop.size(); ++i)
        if (std::find(f.corners.begin(), f.corners.end(), loop[i]) != f.corners.end()) at.push_back(i);
      if (at.size() != 4 || loop.size() != next.size())
        throw core::TopologyError("polycube: the patches of a cube face are not a disk with its four corners on the boundary");
      for (int k = 0; k < 4; ++k) {
        merged.corners[static_cast<std::size_t>(k)] = loop[at[static_cast<std::size_t>(k)]];
        const std::size_t end = k < 3 ? at[static_cast<std::size_t>(k) + 1] : loop.size();
        for (std::size_t i = at[static_cast<std::size_t>(k)]; i <= end; ++i) merged.sides[static_cast<std::size_t>(k)].push_back(loop[i % loop.size()]);
      }
      for (const int p : f.patches) new_id[static_cast<std::size_t>(p)] = static_cast<int>(patches.size());
      patches.push_back(std::move(merged));
    }
  if (patches.empty()) return r;
  for (std::size_t p = 0; p < d.layout.patches.size(); ++p)
    if (new_id[p] < 0) new_id[p] = static_cast<int>(patches.size()), patches.push_back(d.layout.patches[p]);
  r.layout.patches = std::move(patches);
  auto remap = [&](std::vector<int>& ids) {
    for (int& p : ids) p = new_id.at(static_cast<std::size_t>(p));
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  };
  for (auto& comp : r.components) {
    remap(comp.patches);
    for (auto& f : comp.faces) remap(f.patches);
  }
  for (auto& c : r.contacts)
    if (c.via == "filled_patch") c.index = new_id.at(static_cast<std::size_t>(c.index));
  r.quad_patches = static_cast<int>(r.layout.patches.size());
  return r;
}

namespace {

// Chains shared by two patches of one face: the sharp curves inside it, each from one cross side
// to the other.
std::vector<std::vector<int>> inner_chains(const split::Layout& L, const std::vector<int>& patches) {
  std::map<std::pair<int, int>, std::pair<std::size_t, const std::vector<int>*>> ends;  // (first, last) -> (patch slot, chain)
  std::vector<std::vector<int>> chains;
  for (std::size_t i = 0; i < patches.size(); ++i)
    for (const auto& side : L.patches.at(static_cast<std::size_t>(patches[i])).sides) {
      if (side.size() < 2) continue;
      const auto it = ends.find({side.back(), side.front()});
      if (it != ends.end() && it->second.first != i && std::equal(side.rbegin(), side.rend(), it->second.second->begin()))
        chains.push_back(side);
      else
        ends[{side.front(), side.back()}] = {i, &side};
    }
  return chains;
}

// Lays the sharp curves inside the faces of a torus on straight lines (see TorusSurfaceMap):
// new patch maps for those faces, and the lines' heights. `input` is the decomposition before
// merging, `d` after, `e` the embedding of the merged maps (for the corners' local coordinates).
std::array<std::vector<double>, 3> straighten_sharp_curves(const split::Decomposition& input, const split::Decomposition& d,
                                                          const Embedding& e, const PatchMapParams& params, std::vector<PatchMap>& maps) {
  const split::Layout& L = d.layout;
  const int n = static_cast<int>(d.tori.at(0).components.size());
  struct Line {
    double f0 = 0, f1 = 0;   // across-face positions (arc length) at a = 0 and a = 1
    std::vector<int> chain;  // from its a = 0 end
  };
  struct Face {
    int patch = -1;
    std::array<Vec3, 4> X;  // local coordinates of the merged patch's corners
    int across = 0;
    std::vector<Line> lines;
  };
  std::vector<std::array<Face, 4>> faces(static_cast<std::size_t>(n));
  bool any = false;
  for (int k = 0; k < n; ++k) {
    const int comp = d.tori[0].components[static_cast<std::size_t>(k)];
    std::map<int, int> local_corner;
    for (int c = 0; c < 8; ++c) local_corner[e.corner_vertex[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)]] = c;
    for (int i = 0; i < 4; ++i) {
      const auto& sub = input.components.at(static_cast<std::size_t>(comp)).faces.at(static_cast<std::size_t>(i)).patches;
      if (sub.size() < 2) continue;
      Face& F = faces[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)];
      F.patch = d.components[static_cast<std::size_t>(comp)].faces[static_cast<std::size_t>(i)].patches.at(0);
      const split::Patch& P = L.patches.at(static_cast<std::size_t>(F.patch));
      for (int j = 0; j < 4; ++j) {
        const int c = local_corner.at(P.corners[static_cast<std::size_t>(j)]);
        F.X[static_cast<std::size_t>(j)] = {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)};
      }
      F.across = F.X[0][1] != F.X[1][1] || F.X[0][1] != F.X[2][1] ? 1 : 2;
      // Position of a vertex on a cross side (a constant), measured from across = 0, by arc length.
      std::map<int, std::pair<int, double>> on_cross;  // vertex -> (a, across position)
      for (int s = 0; s < 4; ++s) {
        const Vec3 &A = F.X[static_cast<std::size_t>(s)], &B = F.X[static_cast<std::size_t>((s + 1) % 4)];
        if (A[0] != B[0]) continue;
        const auto frac = arc_length_fractions(L, P.sides[static_cast<std::size_t>(s)]);
        for (std::size_t q = 0; q < frac.size(); ++q)
          on_cross[P.sides[static_cast<std::size_t>(s)][q]] = {int(A[0]), A[static_cast<std::size_t>(F.across)] == 0 ? frac[q] : 1 - frac[q]};
      }
      for (auto chain : inner_chains(input.layout, sub)) {
        const auto a = on_cross.find(chain.front()), b = on_cross.find(chain.back());
        if (a == on_cross.end() || b == on_cross.end() || a->second.first == b->second.first) return {};  // not a strip boundary
        Line line;
        if (a->second.first == 1) std::reverse(chain.begin(), chain.end());
        line.f0 = a->second.first == 0 ? a->second.second : b->second.second;
        line.f1 = a->second.first == 0 ? b->second.second : a->second.second;
        line.chain = std::move(chain);
        F.lines.push_back(std::move(line));
      }
      std::sort(F.lines.begin(), F.lines.end(), [](const Line& x, const Line& y) { return x.f0 < y.f0; });
      any = any || !F.lines.empty();
    }
  }
  if (!any) return {};
  // One height per line and face index, the same in every cube.
  std::array<std::vector<double>, 4> u;
  for (int i = 0; i < 4; ++i) {
    const std::size_t count = faces[0][static_cast<std::size_t>(i)].lines.size();
    u[static_cast<std::size_t>(i)].assign(count, 0.0);
    for (int k = 0; k < n; ++k) {
      const Face& F = faces[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)];
      if (F.lines.size() != count) return {};
      for (std::size_t j = 0; j < count; ++j) u[static_cast<std::size_t>(i)][j] += (F.lines[j].f0 + F.lines[j].f1) / (2.0 * n);
    }
  }
  // Opposite faces with as many lines at nearly the same heights share them: the cuts run through
  // the whole cube, and two nearly equal ones would leave a sliver of elements.
  for (int i = 0; i < 2; ++i) {
    auto &p = u[static_cast<std::size_t>(i)], &q = u[static_cast<std::size_t>(i + 2)];
    if (p.size() != q.size()) continue;
    bool close = true;
    for (std::size_t j = 0; j < p.size(); ++j) close = close && std::abs(p[j] - q[j]) < 0.1;
    if (close)
      for (std::size_t j = 0; j < p.size(); ++j) p[j] = q[j] = (p[j] + q[j]) / 2;
  }
  std::array<std::vector<double>, 3> cuts;
  for (int i = 0; i < 4; ++i) {
    const auto& ui = u[static_cast<std::size_t>(i)];
    if (!ui.empty()) cuts[static_cast<std::size_t>(faces[0][static_cast<std::size_t>(i)].across)].insert(cuts[static_cast<std::size_t>(faces[0][static_cast<std::size_t>(i)].across)].end(), ui.begin(), ui.end());
  }
  for (auto& c : cuts) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end(), [](double x, double y) { return std::abs(x - y) < 1e-9; }), c.end());
    double last = 0;
    for (const double x : c) {
      if (x - last < 0.05) return {};  // lines this close would leave slivers of elements
      last = x;
    }
    if (!c.empty() && 1 - last < 0.05) return {};
  }
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < 4; ++i) {
      const Face& F = faces[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)];
      if (F.lines.empty()) continue;
      const auto& ui = u[static_cast<std::size_t>(i)];
      const std::size_t ax = static_cast<std::size_t>(F.across);
      const split::Patch& P = L.patches[static_cast<std::size_t>(F.patch)];
      // Local coordinates -> the patch square (the face is axis-aligned, so the map is affine).
      const Vec3 &X0 = F.X[0], &X1 = F.X[1], &X3 = F.X[3];
      std::map<int, std::array<double, 2>> fixed;
      auto fix = [&](int v, const Vec3& x) {
        double s = 0, t = 0;
        for (int q = 0; q < 3; ++q) s += (x[q] - X0[q]) * (X1[q] - X0[q]), t += (x[q] - X0[q]) * (X3[q] - X0[q]);
        fixed[v] = {s, t};
      };
      for (int s = 0; s < 4; ++s) {
        const Vec3 &A = F.X[static_cast<std::size_t>(s)], &B = F.X[static_cast<std::size_t>((s + 1) % 4)];
        const auto& side = P.sides[static_cast<std::size_t>(s)];
        if (A[0] != B[0]) {  // along the ring: by arc length, as every patch side
          const auto frac = arc_length_fractions(L, side);
          for (std::size_t q = 0; q < side.size(); ++q) {
            Vec3 x;
            for (int c = 0; c < 3; ++c) x[c] = A[c] + frac[q] * (B[c] - A[c]);
            fix(side[q], x);
          }
          continue;
        }
        // A cross side: the lines' ends at their heights, arc length in between.
        const int a = int(A[0]);
        std::vector<std::size_t> breaks{0};
        std::vector<double> at{A[ax]};
        for (std::size_t j = 0; j < F.lines.size(); ++j) {
          const int end = a == 0 ? F.lines[j].chain.front() : F.lines[j].chain.back();
          const auto it = std::find(side.begin(), side.end(), end);
          if (it == side.end()) return {};
          breaks.push_back(static_cast<std::size_t>(it - side.begin()));
          at.push_back(ui[j]);
        }
        breaks.push_back(side.size() - 1);
        at.push_back(B[ax]);
        // Sort the breaks along the side (heights run from A to B).
        std::vector<std::size_t> order(breaks.size());
        for (std::size_t q = 0; q < order.size(); ++q) order[q] = q;
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return breaks[x] < breaks[y]; });
        for (std::size_t q = 0; q + 1 < order.size(); ++q) {
          const std::size_t lo = breaks[order[q]], hi = breaks[order[q + 1]];
          const double h0 = at[order[q]], h1 = at[order[q + 1]];
          if ((h1 - h0) * (B[ax] - A[ax]) <= 0 && lo != hi) return {};  // lines out of order along the side
          const std::vector<int> piece(side.begin() + static_cast<long>(lo), side.begin() + static_cast<long>(hi) + 1);
          const auto frac = arc_length_fractions(L, piece);
          for (std::size_t r = 0; r < piece.size(); ++r) {
            Vec3 x = A;
            x[ax] = h0 + frac[r] * (h1 - h0);
            fix(piece[r], x);
          }
        }
      }
      for (std::size_t j = 0; j < F.lines.size(); ++j) {
        const auto& chain = F.lines[j].chain;
        const auto frac = arc_length_fractions(L, chain);
        for (std::size_t r = 0; r < chain.size(); ++r) {
          Vec3 x = X0;
          x[0] = frac[r];
          x[ax] = ui[j];
          fix(chain[r], x);
        }
      }
      const auto pos = harmonic_positions(L, P.triangles, fixed, params, "patch " + std::to_string(F.patch));
      PatchMap pm;
      for (const auto& [v, x] : pos) pm.vertices.push_back(v), pm.st.push_back(x);
      const MapQuality q = map_quality(L, P.triangles, pos);
      pm.flipped_triangles = q.flipped_triangles;
      pm.max_angle_distortion_deg = q.max_angle_distortion_deg;
      maps.at(static_cast<std::size_t>(F.patch)) = std::move(pm);
    }
  return cuts;
}

}  // namespace

TorusSurfaceMap map_torus_surface(const split::Decomposition& input, const PatchMapParams& params) {
  TorusSurfaceMap m;
  if (params.profile != "auto" && params.profile != "square")
    throw core::ConfigError("polycube.profile must be 'auto' or 'square', not '" + params.profile + "'");
  // Only faces of several patches can hide a concave corner (a smooth torus skips the attempt).
  const bool several = std::any_of(input.components.begin(), input.components.end(), [](const split::Component& c) {
    return std::any_of(c.faces.begin(), c.faces.end(), [](const split::CubeFace& f) { return f.patches.size() > 1; });
  });
  if (params.profile == "auto" && several) {
    const auto maps = map_patches(input, params);
    std::string why;
    if (auto e = embed_profile_ring(input, maps, why)) {
      m.embedding = std::move(*e);
      for (const auto& p : maps) {
        m.flipped_surface_triangles += p.flipped_triangles;
        m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, p.max_angle_distortion_deg);
      }
      core::log("polycube: rectilinear cross section with " + std::to_string(m.embedding.profile.concave_corners) + " concave corners: " +
                std::to_string(m.embedding.profile.cells.size()) + " cubes per sector");
      return m;
    }
    core::log_verbose("polycube: square cross section (" + why + ")");
  }
  const split::Decomposition d = merge_face_patches(input);
  auto maps = map_patches(d, params);
  m.embedding = embed_torus(d, maps);
  if (params.sharp_lines) m.cuts = straighten_sharp_curves(input, d, m.embedding, params, maps);
  if (!m.cuts[1].empty() || !m.cuts[2].empty()) m.embedding = embed_torus(d, maps);
  for (const auto& p : maps) {
    m.flipped_surface_triangles += p.flipped_triangles;
    m.max_angle_distortion_deg = std::max(m.max_angle_distortion_deg, p.max_angle_distortion_deg);
  }
  return m;
}

core::Json to_json(const TorusSurfaceMap& m) {
  std::vector<double> pts, cells;
  for (const auto& p : m.embedding.points) pts.insert(pts.end(), p.begin(), p.end());
  for (const auto& c : m.embedding.cells)
    for (const auto& p : c) cells.insert(cells.end(), p.begin(), p.end());
  return core::Json{{"kind", "torus"},
                    {"ring", m.embedding.ring},
                    {"mirrored", m.embedding.mirrored},
                    {"boundary_gap", m.embedding.boundary_gap},
                    {"points", pts},
                    {"cells", cells},
                    {"corner_vertex", m.embedding.corner_vertex},
                    {"cuts", m.cuts},
                    {"profile", m.embedding.profile.empty() ? core::Json() : core::Json{{"b", m.embedding.profile.b},
                                                                                            {"c", m.embedding.profile.c},
                                                                                            {"cells", m.embedding.profile.cells},
                                                                                            {"polygon", m.embedding.profile.polygon},
                                                                                            {"concave_corners", m.embedding.profile.concave_corners}}},
                    {"flipped_surface_triangles", m.flipped_surface_triangles},
                    {"max_angle_distortion_deg", m.max_angle_distortion_deg}};
}

viz::PolyData torus_polydata(const split::Decomposition& d, const TorusSurfaceMap& m, bool mapped, const std::array<double, 3>& offset) {
  const split::Layout& L = d.layout;
  std::vector<int> comp(L.triangles.size(), -1);
  for (std::size_t c = 0; c < d.components.size(); ++c)
    for (int p : d.components[c].patches)
      for (int t : L.patches[p].triangles) comp[t] = static_cast<int>(c);
  std::vector<Vec3> at = m.embedding.points;
  for (auto& p : at)
    for (int k = 0; k < 3; ++k) p[k] += offset[k];
  viz::PolyData v;
  v.points = mapped ? at : L.points;
  viz::Field other{mapped ? "xyz" : "uvw", 3, {}}, cf{"component_id", 1, {}}, ff{"filled", 1, {}};
  for (const auto& p : mapped ? L.points : at) other.values.insert(other.values.end(), p.begin(), p.end());
  for (std::size_t t = 0; t < L.triangles.size(); ++t) {
    v.polys.push_back({L.triangles[t][0], L.triangles[t][1], L.triangles[t][2]});
    cf.values.push_back(comp[t]);
    ff.values.push_back(L.filled[t]);
  }
  v.point_fields = {other};
  v.cell_fields = {cf, ff};
  return v;
}

void write_torus_vtp(const std::string& path, const split::Decomposition& d, const TorusSurfaceMap& m, bool mapped) {
  viz::write_vtp(path, torus_polydata(d, m, mapped, {0, 0, 0}));
}

}  // namespace volts::polycube
