#include "polycube_input.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/log.h"
#include "polycube/connector.h"
#include "polycube/difference.h"
#include "polycube/embedding.h"
#include "polycube/polycube.h"
#include "polycube/structure.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "tmesh/complex.h"
#include "tmesh/pillow.h"
#include "volmap/volmap.h"

namespace volts::pipeline {

namespace {

// The length of the path at(t), t from a to b, as a polyline of 16 pieces.
template <class At>
double path_length(const At& at, double a, double b) {
  tmesh::Vec3 p = at(a);
  double l = 0;
  for (int i = 1; i <= 16; ++i) {
    const tmesh::Vec3 q = at(a + (b - a) * i / 16.0);
    l += std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
    p = q;
  }
  return l;
}

// The surface map of a ring on its round faces, evaluated where it is defined: the surface
// triangles in the developed coordinates of each face (A = cube index + a around the ring, and b
// or c across), where they tile the face exactly and are affine images of the patch maps. The
// faces lie on the lines b = const or c = const of the cross section (the square's four sides, or
// a profile's grid lines). Point location in the tets instead puts points of the inner round face, which lie inside
// the tets' chords, up to the chords' sagitta inside the surface, at positions that depend on the
// interior vertices (smoothing them moved the spline's boundary).
class RingSurface {
 public:
  RingSurface(const volmap::VolumeMap& vm, const polycube::Embedding& e) : ring_(e.ring) {
    const polycube::Profile& pr = e.profile;
    for (const double b : pr.empty() ? std::vector<double>{0, 1} : pr.b) lines_.push_back({1, b, {}});
    for (const double c : pr.empty() ? std::vector<double>{0, 1} : pr.c) lines_.push_back({2, c, {}});
    std::vector<std::array<double, 3>> dev(static_cast<std::size_t>(vm.surface_vertices));  // (A, b, c)
    for (int v = 0; v < vm.surface_vertices; ++v) {
      const Eigen::Vector3d& x = vm.parameter[static_cast<std::size_t>(v)];
      double theta = std::atan2(x[1], x[0]);
      if (theta < 0) theta += 2 * M_PI;
      dev[static_cast<std::size_t>(v)] = {theta * e.ring / (2 * M_PI), std::hypot(x[0], x[1]) - 1, e.mirrored ? 1 - x[2] : x[2]};
    }
    physical_.assign(vm.physical.begin(), vm.physical.begin() + vm.surface_vertices);
    // Boundary faces of the tets: surface vertices only, each face of one tet.
    std::map<std::array<int, 3>, int> count;
    for (const auto& t : vm.tets)
      for (int f = 0; f < 4; ++f) {
        std::array<int, 3> k{t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4]};
        std::sort(k.begin(), k.end());
        ++count[k];
      }
    for (const auto& [k, n] : count) {
      if (n != 1 || k[2] >= vm.surface_vertices) continue;
      for (Line& line : lines_) {
        const int across = line.across;
        const double level = line.level;
        if (std::all_of(k.begin(), k.end(), [&](int v) { return std::abs(dev[static_cast<std::size_t>(v)][static_cast<std::size_t>(across)] - level) < 1e-9; })) {
          Tri tri{k, {}};
          for (int j = 0; j < 3; ++j)
            tri.uv[j] = {dev[static_cast<std::size_t>(k[j])][0], dev[static_cast<std::size_t>(k[j])][static_cast<std::size_t>(3 - across)]};
          // A triangle across the seam at A = 0 made whole (A may leave [0, ring)).
          for (int j = 1; j < 3; ++j) tri.uv[j][0] = tri.uv[0][0] + std::remainder(tri.uv[j][0] - tri.uv[0][0], e.ring);
          line.tris.push_back(tri);
        }
      }
    }
  }

  /// The surface point of sector coordinates x (after the b <-> c swap) of sector k, if x lies on
  /// the round faces; nullopt otherwise.
  std::optional<std::array<double, 3>> physical(int k, const std::array<double, 3>& x) const {
    for (const Line& line : lines_) {
      const int across = line.across;
      if (std::abs(x[static_cast<std::size_t>(across)] - line.level) > 1e-12) continue;
      const double u = k + x[0], w = x[static_cast<std::size_t>(3 - across)];
      const Tri* best = nullptr;
      std::array<double, 3> best_b{};
      double best_min = -HUGE_VAL;
      for (const Tri& t : line.tris) {
        std::array<std::array<double, 2>, 3> p = t.uv;
        // Moved by whole turns next to u (the seam at A = 0).
        const double shift = u + std::remainder(p[0][0] - u, ring_) - p[0][0];
        for (auto& q : p) q[0] += shift;
        const double d = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if (d == 0) continue;
        const double b1 = ((u - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (w - p[0][1])) / d;
        const double b2 = ((p[1][0] - p[0][0]) * (w - p[0][1]) - (u - p[0][0]) * (p[1][1] - p[0][1])) / d;
        const std::array<double, 3> b{1 - b1 - b2, b1, b2};
        const double m = std::min({b[0], b[1], b[2]});
        if (m > best_min) best_min = m, best = &t, best_b = b;
        if (m >= 0) break;
      }
      if (!best || best_min < -1e-6) continue;  // on the line, not on its faces (a profile cell's inner face)
      Eigen::Vector3d y = Eigen::Vector3d::Zero();
      for (int j = 0; j < 3; ++j) y += std::clamp(best_b[static_cast<std::size_t>(j)], 0.0, 1.0) * physical_[static_cast<std::size_t>(best->v[static_cast<std::size_t>(j)])];
      y /= std::clamp(best_b[0], 0.0, 1.0) + std::clamp(best_b[1], 0.0, 1.0) + std::clamp(best_b[2], 0.0, 1.0);
      return std::array<double, 3>{y[0], y[1], y[2]};
    }
    return std::nullopt;
  }

 private:
  struct Tri {
    std::array<int, 3> v;
    std::array<std::array<double, 2>, 3> uv;  // developed (A, the other in-face coordinate)
  };
  struct Line {
    int across = 1;  // 1: b = level, 2: c = level
    double level = 0;
    std::vector<Tri> tris;
  };
  int ring_ = 0;
  std::vector<Line> lines_;
  std::vector<Eigen::Vector3d> physical_;
};

// One ring of cubes (a torus, §4.2): its embedding and the point location of its volume map.
struct Ring {
  polycube::Embedding embedding;
  std::unique_ptr<volmap::Locator> locate;
  std::unique_ptr<RingSurface> surface;  // points on the round faces
  bool swap = false;  // b <-> c, so that the cubes' parameters are right-handed in physical space
  std::array<std::vector<double>, 3> cuts;  // sharp curves inside faces (local coordinates, before the swap)
};

Ring read_ring(const std::string& in, const core::Json& pc, const core::Json& vmj) {
  Ring r;
  const volmap::VolumeMap vm = volmap::from_json(vmj, in);
  if (vm.flipped_tets > 0)
    throw core::NumericalError(in + ": the volume map has " + std::to_string(vm.flipped_tets) +
                               " flipped tets, so the spline would fold (see polycube_tets_mapped.vtu): rerun polycube with a "
                               "smaller polycube.tet_max_volume_rel, or set `route: tet`");
  // Points of the round ring outside the surface's chords by up to the recorded gap snap onto it.
  const core::Json& gap_json = core::require(pc, "boundary_gap", in);
  const double gap = gap_json.is_number() ? gap_json.get<double>() : -1.0;
  if (!(gap >= 0 && std::isfinite(gap))) throw core::InvalidInputError(in + ": polycube.boundary_gap must be a number >= 0");
  if (vm.parameter.empty() || vm.tets.empty()) throw core::InvalidInputError(in + ": the volume map has no points or no tets");
  Eigen::Vector3d lo = vm.parameter.front(), hi = lo;
  for (const auto& p : vm.parameter) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double snap = std::max(1e-6, 2 * gap / (hi - lo).norm());
  if (!(snap < 0.1))
    throw core::InvalidInputError(in + ": polycube.boundary_gap " + std::to_string(gap) + " is not small against the volume map's extent");
  r.locate = std::make_unique<volmap::Locator>(vm, snap);
  polycube::Embedding& e = r.embedding;
  try {
    const auto cells = core::require(pc, "cells", in).get<std::vector<double>>();
    if (cells.empty() || cells.size() % 24) throw core::InvalidInputError(in + ": polycube.cells needs 24 numbers per cube");
    e.cells.resize(cells.size() / 24);
    e.ring = core::require(pc, "ring", in).get<int>();
    e.mirrored = core::require(pc, "mirrored", in).get<bool>();
    if (e.ring != static_cast<int>(e.cells.size())) throw core::InvalidInputError(in + ": polycube.ring does not match its cells");
    for (std::size_t i = 0; i < cells.size(); ++i) e.cells[i / 24][(i % 24) / 3][i % 3] = cells[i];
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(in + ": malformed polycube.cells: " + x.what());
  }
  if (pc.contains("profile") && !pc["profile"].is_null()) {  // a rectilinear cross section (embedding.h, Profile)
    polycube::Profile& pr = e.profile;
    try {
      const core::Json& pj = pc["profile"];
      pr.b = core::require(pj, "b", in).get<std::vector<double>>();
      pr.c = core::require(pj, "c", in).get<std::vector<double>>();
      // Read as numbers and checked before they become indices (a huge or fractional one is no cell).
      for (const auto& c : core::require(pj, "cells", in).get<std::vector<std::array<double, 2>>>()) {
        for (const double x : c)
          if (!(x >= 0 && x < 1e6 && x == std::floor(x))) throw core::InvalidInputError(in + ": polycube.profile has a cell index that is no grid index");
        pr.cells.push_back({static_cast<int>(c[0]), static_cast<int>(c[1])});
      }
    } catch (const core::Json::exception& x) {
      throw core::InvalidInputError(in + ": malformed polycube.profile: " + x.what());
    }
    for (const auto* lines : {&pr.b, &pr.c}) {
      bool ok = lines->size() >= 2 && lines->front() == 0 && lines->back() == 1;
      for (std::size_t i = 1; ok && i < lines->size(); ++i) ok = (*lines)[i] > (*lines)[i - 1] + 1e-3;
      if (!ok) throw core::InvalidInputError(in + ": polycube.profile grid lines must increase from 0 to 1, at least 1e-3 apart");
    }
    for (const auto& [i, j] : pr.cells)
      if (i >= static_cast<int>(pr.b.size()) - 1 || j >= static_cast<int>(pr.c.size()) - 1)
        throw core::InvalidInputError(in + ": polycube.profile has a cell outside its grid");
    if (pr.cells.empty()) throw core::InvalidInputError(in + ": polycube.profile has no cells");
  }
  r.surface = std::make_unique<RingSurface>(vm, e);
  if (pc.contains("cuts")) {  // files written before session 11 have none
    try {
      r.cuts = pc["cuts"].get<std::array<std::vector<double>, 3>>();
    } catch (const core::Json::exception& x) {
      throw core::InvalidInputError(in + ": malformed polycube.cuts: " + x.what());
    }
    for (const auto& c : r.cuts)
      for (std::size_t i = 0; i < c.size(); ++i)
        if (!(c[i] >= 0.01 && c[i] <= 0.99) || (i > 0 && !(c[i] > c[i - 1] + 0.01)) || !r.cuts[0].empty())
          throw core::InvalidInputError(in + ": polycube.cuts must be increasing heights in [0.01, 0.99] at least 0.01 apart, none along the ring");
  }
  // The ring's local frame is right- or left-handed depending on the directions split chose; the
  // sign of the map's Jacobian at the first cube's centre (central differences) tells which.
  // (The centre of the first profile cell: a profile's sector centre may lie outside it.)
  const double h = 0.05;
  std::array<Eigen::Vector3d, 3> d;
  for (int a = 0; a < 3; ++a) {
    std::array<double, 3> lo3{0.5, 0.5, 0.5}, hi3{0.5, 0.5, 0.5};
    lo3[a] -= h, hi3[a] += h;
    const auto p = r.locate->physical(polycube::cell_point(e, 0, polycube::profile_to_sector(e.profile, 0, hi3)));
    const auto q = r.locate->physical(polycube::cell_point(e, 0, polycube::profile_to_sector(e.profile, 0, lo3)));
    if (!p || !q) throw core::NumericalError(in + ": the first cube's centre is outside the volume map");
    d[a] = Eigen::Vector3d((*p)[0] - (*q)[0], (*p)[1] - (*q)[1], (*p)[2] - (*q)[2]);
  }
  r.swap = d[0].dot(d[1].cross(d[2])) < 0;
  return r;
}

// Tori: every ring's cubes, numbered ring after ring (a ring with a profile: sector after sector,
// the profile's cells in order within each); a = 0 and a = 1 are cross sections (shared with the
// neighbouring cube), the faces without a neighbouring cell lie on the surface. Rings are
// translated apart in polycube space so their points never coincide.
tmesh::PolycubeMaps ring_maps(std::vector<Ring> list, const tmesh::Params& params) {
  const auto rings = std::make_shared<const std::vector<Ring>>(std::move(list));
  tmesh::PolycubeMaps m;
  struct Cube {
    int ring, sector, cell;
  };
  std::vector<Cube> cube;
  bool explicit_blocks = false;
  for (const Ring& r : *rings) explicit_blocks = explicit_blocks || !r.cuts[1].empty() || !r.cuts[2].empty() || !r.embedding.profile.empty();
  const int n = 1 << params.level;
  for (std::size_t r = 0; r < rings->size(); ++r) {
    const Ring& ring = (*rings)[r];
    const polycube::Profile& pr = ring.embedding.profile;
    std::vector<std::vector<tmesh::Block>> cell_blocks;
    if (!pr.empty()) {
      // One cube per cell and sector; the pillow wraps around the concave edges (pillow.h).
      std::vector<std::array<int, 2>> cells = pr.cells;
      if (ring.swap)
        for (auto& c : cells) std::swap(c[0], c[1]);
      cell_blocks = tmesh::profile_blocks(cells, n, params.pillow_layers);
    } else if (explicit_blocks) {
      // Sharp curves inside faces lie on block faces: C0 there (Liu et al. §5.2, repeated knots).
      std::array<std::vector<double>, 3> cuts = ring.cuts;
      if (ring.swap) std::swap(cuts[1], cuts[2]);
      cell_blocks = {tmesh::cube_blocks({0, 0, 1, 1, 1, 1}, {n, n, n}, params.pillow_layers, cuts)};
    }
    const int cells = pr.empty() ? 1 : static_cast<int>(pr.cells.size());
    for (int k = 0; k < ring.embedding.ring; ++k)
      for (int c = 0; c < cells; ++c) {
        cube.push_back({static_cast<int>(r), k, c});
        m.boundary.push_back({0, 0, 1, 1, 1, 1});  // of the square ring's cubes; with explicit blocks (profiles, cuts) not used
        if (explicit_blocks) m.blocks.push_back(cell_blocks[static_cast<std::size_t>(c)]);
      }
  }
  // Sector coordinates of cube c's parameters.
  auto sector = [rings, cube](int c, std::array<double, 3> abc) {
    const Cube& q = cube.at(static_cast<std::size_t>(c));
    const Ring& ring = (*rings)[static_cast<std::size_t>(q.ring)];
    if (ring.swap) std::swap(abc[1], abc[2]);
    return polycube::profile_to_sector(ring.embedding.profile, q.cell, abc);
  };
  auto local = [rings, cube, sector](int c, const std::array<double, 3>& abc) {
    const Cube& q = cube.at(static_cast<std::size_t>(c));
    return std::make_pair(q.ring, polycube::cell_point((*rings)[static_cast<std::size_t>(q.ring)].embedding, q.sector, sector(c, abc)));
  };
  m.polycube = [local](int c, const tmesh::Vec3& abc) {
    auto [r, x] = local(c, abc);
    x[0] += 10.0 * r;  // the round ring's radius is 2
    return x;
  };
  m.physical = [local, rings, cube, sector](int c, const tmesh::Vec3& abc) {
    const auto [r, x] = local(c, abc);
    const Ring& ring = (*rings)[static_cast<std::size_t>(r)];
    if (const auto s = ring.surface->physical(cube.at(static_cast<std::size_t>(c)).sector, sector(c, abc))) return *s;
    const auto p = ring.locate->physical(x);
    if (!p) throw core::NumericalError("tmesh: cube " + std::to_string(c) + " point outside the volume map");
    return *p;
  };
  return m;
}

// The face of one of ring r's cubes whose four corner vertices are `want` (layout ids, any
// order): its sector, its face (2..5) and its corners (layout ids, and cube parameters: b and c
// swapped from the sector's if swap) in the face's order, so that corners 1 and 2 are corner 0's
// neighbours along the face's two axes. Throws core::InvalidInputError naming `in` for a
// malformed ring, nullopt if no face has those corners.
struct RingFace {
  int sector = -1, face = -1;
  std::array<int, 4> vertex{};
  std::array<tmesh::Vec3, 4> corner{};
};

std::optional<RingFace> find_ring_face(const std::string& in, const Ring& ring, int r, const core::Json& ring_json, const std::array<int, 4>& want) {
  std::vector<int> layout_vertex;
  std::vector<std::array<int, 8>> corner_vertex;
  try {
    layout_vertex = core::require(ring_json, "layout_vertex", in).get<std::vector<int>>();
    corner_vertex = core::require(core::require(ring_json, "polycube", in), "corner_vertex", in)
                        .get<std::vector<std::array<int, 8>>>();
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(in + ": malformed rings[" + std::to_string(r) + "] layout_vertex or polycube.corner_vertex: " + x.what());
  }
  if (static_cast<int>(corner_vertex.size()) != ring.embedding.ring) throw core::InvalidInputError(in + ": rings[" + std::to_string(r) + "].polycube.corner_vertex does not match its ring");
  // Layout vertex at cube corner i (cube parameters: b and c swapped from the sector's if swap).
  auto cube_corner = [&](int sector, int i) {
    int a = i & 1, b = (i >> 1) & 1, c = (i >> 2) & 1;
    if (ring.swap) std::swap(b, c);
    const int v = corner_vertex[static_cast<std::size_t>(sector)][static_cast<std::size_t>(a + 2 * b + 4 * c)];
    if (v < 0 || v >= static_cast<int>(layout_vertex.size())) throw core::InvalidInputError(in + ": rings[" + std::to_string(r) + "].polycube.corner_vertex is out of range");
    return layout_vertex[static_cast<std::size_t>(v)];
  };
  std::array<int, 4> sorted_want = want;
  std::sort(sorted_want.begin(), sorted_want.end());
  for (int sector = 0; sector < ring.embedding.ring; ++sector)
    for (int f = 2; f < 6; ++f) {
      const int d = f / 2, side = f % 2;
      RingFace rf{sector, f, {}, {}};
      for (int i = 0, n = 0; i < 8; ++i)
        if (((i >> d) & 1) == side) rf.vertex[n] = cube_corner(sector, i), rf.corner[n++] = {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)};
      std::array<int, 4> have = rf.vertex;
      std::sort(have.begin(), have.end());
      if (have == sorted_want) return rf;
    }
  return std::nullopt;
}

// The signed permutation taking ring face rf's corners onto the points q(vertex) of another
// cube's parameters or of a frame (only the signs of their differences count) and the face's
// outward normal onto `inward`: P = Q U^T (U's columns are unit axis vectors).
tmesh::AxisMap face_axes(const RingFace& rf, const std::function<tmesh::Vec3(int)>& q, const tmesh::Vec3& inward) {
  std::array<tmesh::Vec3, 3> U{}, Q{};
  for (int e = 0; e < 2; ++e) {
    const tmesh::Vec3 &p0 = rf.corner[0], &p1 = rf.corner[static_cast<std::size_t>(e + 1)];
    const tmesh::Vec3 q0 = q(rf.vertex[0]), q1 = q(rf.vertex[static_cast<std::size_t>(e + 1)]);
    for (int x = 0; x < 3; ++x) {
      const double dq = q1[x] - q0[x];
      U[static_cast<std::size_t>(e)][x] = p1[x] - p0[x], Q[static_cast<std::size_t>(e)][x] = std::abs(dq) > 1e-12 ? (dq > 0 ? 1 : -1) : 0;
    }
  }
  U[2] = {0, 0, 0}, Q[2] = inward;
  U[2][rf.face / 2] = rf.face % 2 ? 1 : -1;
  tmesh::AxisMap m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double v = 0;
      for (int e = 0; e < 3; ++e) v += Q[static_cast<std::size_t>(e)][i] * U[static_cast<std::size_t>(e)][j];
      m.P[i][j] = static_cast<int>(std::lround(v));
    }
  return m;
}

// Glues the cube face of ring r (cubes first, first + 1, ... of k) whose corner vertices are
// `want` (layout ids) to face a = r of the connector cube nk, corner want[i] onto the connector's
// parameters q[i] (the corners of that face). Throws core::InvalidInputError naming `in` if no
// face of the ring has those corners or they do not lie on it as the square q.
void glue_connector_end(tmesh::CubeComplex& k, const std::string& in, const Ring& ring, int r, const core::Json& ring_json, int first, int nk,
                        const std::array<int, 4>& want, const std::array<tmesh::Vec3, 4>& q) {
  const std::optional<RingFace> rf = find_ring_face(in, ring, r, ring_json, want);
  if (!rf) throw core::InvalidInputError(in + ": no cube face of ring " + std::to_string(r) + " has the corners of the connector's end");
  const int neck_face = r;  // a = 0 on ring 0's disk, a = 1 on ring 1's
  auto at = [&](int v) { return q[static_cast<std::size_t>(std::find(want.begin(), want.end(), v) - want.begin())]; };
  tmesh::AxisMap m = face_axes(*rf, at, {neck_face ? -1.0 : 1.0, 0, 0});
  const tmesh::Vec3 y = m.linear(rf->corner[0]), q0 = at(rf->vertex[0]);
  m.t = {q0[0] - y[0], q0[1] - y[1], q0[2] - y[2]};
  for (int i = 1; i < 4; ++i) {
    const tmesh::Vec3 z = m(rf->corner[static_cast<std::size_t>(i)]), w = at(rf->vertex[static_cast<std::size_t>(i)]);
    if (z != w) throw core::InvalidInputError(in + ": the connector's end does not lie on ring " + std::to_string(r) + "'s face as a square");
  }
  tmesh::glue_faces(k, first + rf->sector, rf->face, nk, neck_face, m);
}

// The physical and polycube maps of a connector complex: `where` takes a point of cube c's
// parameters to the cube holding it (rings' cubes, then the connector nk) and its parameters there.
void set_connector_point_maps(tmesh::PolycubeMaps& m, const std::function<std::pair<int, tmesh::Vec3>(int, const tmesh::Vec3&)>& where,
                              const tmesh::PolycubeMaps& ring, const std::shared_ptr<volmap::Locator>& neck, int nk) {
  m.physical = [where, ring, neck, nk](int c, const tmesh::Vec3& x) {
    const auto [cube, y] = where(c, x);
    if (cube != nk) return ring.physical(cube, y);
    const auto p = neck->physical(y);
    if (!p) throw core::NumericalError("tmesh: a point of the connector lies outside its volume map");
    return *p;
  };
  m.polycube = [where, ring, nk](int c, const tmesh::Vec3& x) {
    const auto [cube, y] = where(c, x);
    if (cube != nk) return ring.polycube(cube, y);
    return tmesh::Vec3{y[0] + 30.0, y[1], y[2]};  // the rings lie within x < 13
  };
}

// A lensed connector end (polycube's end_strip; split.connector_end: shoulder): face a = end of
// the connector is three strips across cube axis `axis`, the ring's disk on [lo, hi]; `vertex`:
// the ring face's corners (the lenses' tips, layout ids) at (other axis, axis) = (i & 1, lo or hi
// by i >> 1).
struct EndStrip {
  int end = 1, axis = 1;
  double lo = 0, hi = 1;
  std::array<int, 4> vertex{};
};

std::optional<EndStrip> read_end_strip(const core::Json& cj, const std::string& in) {
  if (!cj.contains("end_strip")) return std::nullopt;
  EndStrip e;
  std::vector<int> layout_vertex;
  std::array<int, 4> piece{};
  try {
    const core::Json& j = cj["end_strip"];
    e.end = core::require(j, "end", in).get<int>();
    e.axis = core::require(j, "axis", in).get<int>();
    e.lo = core::require(j, "lo", in).get<double>();
    e.hi = core::require(j, "hi", in).get<double>();
    piece = core::require(j, "corner_vertex", in).get<std::array<int, 4>>();
    layout_vertex = core::require(cj, "layout_vertex", in).get<std::vector<int>>();
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(in + ": malformed connector end_strip: " + x.what());
  }
  if ((e.end != 0 && e.end != 1) || (e.axis != 1 && e.axis != 2) || !(0 < e.lo && e.lo < e.hi && e.hi < 1))
    throw core::InvalidInputError(in + ": connector end_strip needs end 0 or 1, axis 1 or 2 and 0 < lo < hi < 1");
  for (int i = 0; i < 4; ++i) {
    const int v = piece[static_cast<std::size_t>(i)];
    if (v < 0 || v >= static_cast<int>(layout_vertex.size())) throw core::InvalidInputError(in + ": connector end_strip.corner_vertex is out of range");
    e.vertex[static_cast<std::size_t>(i)] = layout_vertex[static_cast<std::size_t>(v)];
  }
  return e;
}

// The complex of a connector with a lensed end (Liu et al. §4.3, Fig. 6(a)/13: the rod's shank
// ending on its thinner eye), glued in part: laid out in one frame (develop), the ring's boxes
// narrowed along the strip axis to the disk's strip, cut where faces end (box_complex) and
// pillowed as one complex with one thickness in the frame. A point of a cube is found in the
// frame; a point on the face the ring shares with the connector is the ring's.
tmesh::PolycubeMaps strip_connector_maps(const std::string& in, const tmesh::CubeComplex& k, const EndStrip& strip, const tmesh::PolycubeMaps& ring,
                                         const std::shared_ptr<volmap::Locator>& neck, int first, int cubes, const tmesh::Params& params) {
  const int nk = static_cast<int>(k.glue.size()) - 1;
  tmesh::BoxLayout layout;
  const std::vector<tmesh::AxisMap> frame = tmesh::develop(k, layout);
  int F = -1;  // the frame axis of the strip axis
  for (int f = 0; f < 3; ++f)
    if (frame[static_cast<std::size_t>(nk)].P[f][strip.axis] != 0) F = f;
  tmesh::Vec3 at_lo{double(strip.end), 0, 0}, at_hi = at_lo;
  at_lo[static_cast<std::size_t>(strip.axis)] = strip.lo, at_hi[static_cast<std::size_t>(strip.axis)] = strip.hi;
  const auto& nb = layout.boxes[static_cast<std::size_t>(nk)];
  const double x0 = tmesh::cube_to_frame(frame[static_cast<std::size_t>(nk)], nb, at_lo)[F],
               x1 = tmesh::cube_to_frame(frame[static_cast<std::size_t>(nk)], nb, at_hi)[F];
  for (int c = first; c < first + cubes; ++c) {
    auto& b = layout.boxes[static_cast<std::size_t>(c)];
    if (std::abs(b[0][F] - nb[0][F]) > 1e-9 || std::abs(b[1][F] - nb[1][F]) > 1e-9)
      throw core::InvalidInputError(in + ": the ring on the connector's lensed end does not run across its strips (cube " + std::to_string(c) + ")");
    b[0][F] = std::min(x0, x1), b[1][F] = std::max(x0, x1);
  }
  const auto bc = std::make_shared<const tmesh::BoxComplex>(tmesh::box_complex(layout));
  const int n = 1 << params.level;
  // 2^level elements per unit of frame length, at least one. (Per unit of each cube's own
  // parameters instead, the narrowed ring keeping 2^level across its strip, measured worse on the
  // rod: 7,136 elements, 6 not certified valid, against 5,696 and 2.)
  std::vector<std::array<int, 3>> wanted(bc->extent.size());
  for (std::size_t i = 0; i < wanted.size(); ++i)
    for (int d = 0; d < 3; ++d)
      wanted[i][static_cast<std::size_t>(d)] = std::max(1, static_cast<int>(std::lround(n * (bc->extent[i][1][d] - bc->extent[i][0][d]))));
  // A unit cube's pillow, thinner where a sub-box is thin (a lens strip): at most 0.45 of it.
  double p = static_cast<double>(params.pillow_layers) / (n + 2 * params.pillow_layers);
  for (const auto& e : bc->extent)
    for (int d = 0; d < 3; ++d) p = std::min(p, 0.45 * (e[1][d] - e[0][d]));
  tmesh::PolycubeMaps m;
  // Where a lens meets the next ring sector's face in one plane of the frame, the ring turns
  // away in the solid (OppositePlanes::in_plane).
  m.blocks = tmesh::blocks_in_cubes(*bc, frame,
                                    tmesh::complex_blocks(bc->complex, tmesh::element_counts(bc->complex, wanted), params.pillow_layers,
                                                          bc->pillow(p), tmesh::OppositePlanes::in_plane));
  // The lenses' outline is the shank's round section, smooth at the end face's corners: pillow
  // their slabs within the end face's plane (tmesh::rim_pillow).
  if (params.rim_pillow_lenses) {
    std::vector<tmesh::Block> kept;
    for (const tmesh::Block& b : m.blocks[static_cast<std::size_t>(nk)]) {
      if (!(b.pillow && b.boundary[static_cast<std::size_t>(strip.end)])) {
        kept.push_back(b);
        continue;
      }
      for (const tmesh::Block& r : tmesh::rim_pillow(b, params.pillow_layers)) kept.push_back(r);
    }
    m.blocks[static_cast<std::size_t>(nk)] = std::move(kept);
  }
  m.boundary.assign(m.blocks.size(), {0, 0, 0, 0, 0, 0});
  // The cube holding a point of cube c's parameters and the point in its parameters: through the
  // frame (across the rings' closures), a ring's cube first.
  auto where = [bc, frame, nk](int c, const tmesh::Vec3& x) {
    const tmesh::Vec3 y = tmesh::cube_to_frame(frame[static_cast<std::size_t>(c)], bc->boxes[static_cast<std::size_t>(c)], x);
    const auto at = bc->locate(y);
    if (!at)
      throw core::NumericalError("tmesh: a point of cube " + std::to_string(c) + " (" + std::to_string(x[0]) + ", " + std::to_string(x[1]) + ", " +
                                 std::to_string(x[2]) + ") lies outside the polycube of the rings and the connector");
    const tmesh::Vec3 z = bc->to_frame(at->first, at->second);
    int owner = bc->box[static_cast<std::size_t>(at->first)];
    const double tol = 1e-9 * bc->size;
    for (int b = 0; b < nk && owner == nk; ++b) {
      const auto& B = bc->boxes[static_cast<std::size_t>(b)];
      bool inside = true;
      for (int d = 0; d < 3; ++d) inside = inside && z[d] > B[0][d] - tol && z[d] < B[1][d] + tol;
      if (inside) owner = b;
    }
    tmesh::Vec3 u = tmesh::frame_to_cube(frame[static_cast<std::size_t>(owner)], bc->boxes[static_cast<std::size_t>(owner)], z);
    for (double& v : u) v = std::clamp(v, 0.0, 1.0);
    return std::make_pair(owner, u);
  };
  set_connector_point_maps(m, where, ring, neck, nk);
  return m;
}

// A connector cube between the two rings (split.genus2: connector; polycube/connector.h): the
// rings' cubes and the connector as one complex of glued cubes (tmesh/complex.h), pillowed as a
// whole so that the pillow wraps around the concave edges where the connector stands on a ring's
// face (a per-cube pillow cannot conform there). Cubes: the rings' sectors as ring_maps numbers
// them, then the connector. A point of a block may lie in a neighbouring cube: it is carried
// there first; points of the faces the connector shares with the rings are the rings' (their
// surface map of the disk), so both sides give one polycube point and one physical point.
tmesh::PolycubeMaps connector_maps(const std::string& in, std::vector<Ring> list, const core::Json& rings_json, const core::Json& cj,
                                   const tmesh::Params& params) {
  if (list.size() != 2) throw core::InvalidInputError(in + ": a connector needs exactly two rings");
  for (const Ring& r : list)
    if (!r.embedding.profile.empty() || !r.cuts[1].empty() || !r.cuts[2].empty())
      throw core::InvalidInputError(in + ": rings with a rectilinear profile or sharp-curve cuts cannot take a connector yet");
  if (params.pillow_layers < 1) throw core::ConfigError("tmesh.pillow_layers must be at least 1 for a connector cube between two rings");
  std::shared_ptr<volmap::Locator> neck;
  {
    const volmap::VolumeMap vm = volmap::from_json(core::require(cj, "volume_map", in), in);
    if (vm.flipped_tets > 0)
      throw core::NumericalError(in + ": the connector's volume map has " + std::to_string(vm.flipped_tets) +
                                 " flipped tets, so the spline would fold (see polycube_tets_mapped.vtu)");
    if (vm.parameter.empty() || vm.tets.empty()) throw core::InvalidInputError(in + ": the connector's volume map has no points or no tets");
    neck = std::make_shared<volmap::Locator>(vm);
  }
  const std::array<int, 8> neck_corner = polycube::connector_corners(cj, in);
  std::array<int, 2> first{0, list[0].embedding.ring};
  const int nk = list[0].embedding.ring + list[1].embedding.ring;  // the connector's cube
  tmesh::CubeComplex k;
  k.glue.resize(static_cast<std::size_t>(nk + 1));
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < list[static_cast<std::size_t>(r)].embedding.ring; ++i) {
      tmesh::AxisMap next;
      next.t = {-1, 0, 0};
      tmesh::glue_faces(k, first[r] + i, 1, first[r] + (i + 1) % list[static_cast<std::size_t>(r)].embedding.ring, 0, next);
    }
  // Each end of the connector onto the ring cube face with the same four corner vertices; a lensed
  // end's ring face has the tips as corners and is glued to the whole end face for now (its
  // strip is set in the frame below).
  const std::optional<EndStrip> strip = read_end_strip(cj, in);
  for (int r = 0; r < 2; ++r) {
    std::array<int, 4> want{};
    std::array<tmesh::Vec3, 4> q{};
    if (strip && strip->end == r) {
      for (int i = 0; i < 4; ++i) {
        tmesh::Vec3 x{double(r), 0, 0};
        x[static_cast<std::size_t>(3 - strip->axis)] = i & 1, x[static_cast<std::size_t>(strip->axis)] = (i >> 1) & 1;
        want[static_cast<std::size_t>(i)] = strip->vertex[static_cast<std::size_t>(i)], q[static_cast<std::size_t>(i)] = x;
      }
    } else {
      for (int i = 0, n = 0; i < 8; ++i)
        if ((i & 1) == r) want[n] = neck_corner[static_cast<std::size_t>(i)], q[n++] = {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)};
    }
    glue_connector_end(k, in, list[static_cast<std::size_t>(r)], r, rings_json[static_cast<std::size_t>(r)], first[r], nk, want, q);
  }
  const std::array<int, 2> ring_cubes{list[0].embedding.ring, list[1].embedding.ring};
  const tmesh::PolycubeMaps ring = ring_maps(std::move(list), params);
  if (strip) return strip_connector_maps(in, k, *strip, ring, neck, first[strip->end], ring_cubes[static_cast<std::size_t>(strip->end)], params);
  const auto complex = std::make_shared<const tmesh::CubeComplex>(std::move(k));
  tmesh::PolycubeMaps m;
  if (params.pillow_thickness == "physical") {
    // Each cube's length along each axis in the solid: the polyline through its centre.
    const int n = 1 << params.level;
    std::vector<std::array<double, 3>> length(complex->glue.size());
    for (int c = 0; c <= nk; ++c)
      for (int d = 0; d < 3; ++d) {
        auto at = [&](double t) {
          tmesh::Vec3 u{0.5, 0.5, 0.5};
          u[static_cast<std::size_t>(d)] = t;
          if (c != nk) return ring.physical(c, u);
          const auto p = neck->physical(u);
          if (!p) throw core::NumericalError(in + ": a point of the connector lies outside its volume map");
          return *p;
        };
        length[static_cast<std::size_t>(c)][static_cast<std::size_t>(d)] = path_length(at, 0.0, 1.0);
      }
    m.blocks = tmesh::complex_blocks(*complex, std::vector<std::array<int, 3>>(complex->glue.size(), {n, n, n}), params.pillow_layers,
                                     tmesh::physical_pillow(*complex, n, params.pillow_layers, length));
  } else {
    m.blocks = tmesh::complex_blocks(*complex, 1 << params.level, params.pillow_layers);
  }
  m.boundary.assign(m.blocks.size(), {0, 0, 0, 0, 0, 0});
  // The cube holding a block point; the connector's end faces belong to the rings.
  auto where = [complex, nk](int c, const tmesh::Vec3& x) {
    auto at = tmesh::locate(*complex, c, x);
    if (!at) throw core::NumericalError("tmesh: a point of cube " + std::to_string(c) + " lies outside the polycube of the rings and the connector");
    if (at->first == nk)
      for (int f = 0; f < 2; ++f)
        if (std::abs(at->second[0] - f) < 1e-12) {
          const auto& g = complex->glue[static_cast<std::size_t>(nk)][static_cast<std::size_t>(f)];
          tmesh::Vec3 y = g->map(at->second);
          for (double& v : y) v = std::clamp(v, 0.0, 1.0);
          return std::make_pair(g->cube, y);
        }
    return *at;
  };
  set_connector_point_maps(m, where, ring, neck, nk);
  return m;
}

// The mean length in the solid of the cube's four edges along each axis (1e-3 inside the cube so
// that every point lies in a tet of the volume map).
std::array<double, 3> cube_side_lengths(const volmap::Locator& locate, const std::string& in) {
  std::array<double, 3> out{};
  const double e = 1e-3;
  for (int d = 0; d < 3; ++d) {
    const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
    double sum = 0;
    for (const double s1 : {e, 1 - e})
      for (const double s2 : {e, 1 - e}) {
        auto at = [&](double t) {
          tmesh::Vec3 u{};
          u[static_cast<std::size_t>(d)] = t, u[static_cast<std::size_t>(d1)] = s1, u[static_cast<std::size_t>(d2)] = s2;
          const auto p = locate.physical(u);
          if (!p) throw core::NumericalError(in + ": a point of the cube's edge lies outside the volume map");
          return *p;
        };
        sum += path_length(at, e, 1 - e);
      }
    out[static_cast<std::size_t>(d)] = sum / 4;
  }
  return out;
}

// The point location of a difference's volume map (`vmj`), checked against its surface map m.
std::shared_ptr<volmap::Locator> difference_locator(const std::string& in, const core::Json& vmj, const polycube::DifferenceMap& m) {
  const volmap::VolumeMap vm = volmap::from_json(vmj, in);
  if (vm.flipped_tets > 0)
    throw core::NumericalError(in + ": the volume map has " + std::to_string(vm.flipped_tets) +
                               " flipped tets, so the spline would fold (see polycube_tets_mapped.vtu): rerun polycube with a "
                               "smaller polycube.tet_max_volume_rel, or set `route: tet`");
  if (vm.parameter.empty() || vm.tets.empty()) throw core::InvalidInputError(in + ": the volume map has no points or no tets");
  if (vm.surface_vertices != m.solid_vertices)
    throw core::InvalidInputError(in + ": the volume map has " + std::to_string(vm.surface_vertices) + " surface vertices, the polycube " +
                                  std::to_string(m.solid_vertices) + " solid vertices");
  return std::make_shared<volmap::Locator>(vm);
}

// The assembly (kind torus_on_cube; Liu et al. 2013 Fig. 1, §4.2: a torus united with a cube on
// part of a face). One frame holds the base — the cube minus its holes as the boxes of the grid of
// the holes' and the foot's lines, outside the holes, scaled to the cube's sides in the solid —,
// the ring's foot cube standing on the foot's rectangle and the ring's other cubes in a row beyond
// the base along the ring, closed onto the foot cube by two closures; box_complex cuts it until
// faces meet whole. Pillowed as one complex: where the ring leaves its foot, the ring's next cube
// and the base's cell beside the foot touch without being glued (a crack; in the solid a wedge of
// air), and the pillow moves away from it within its plane (complex_blocks,
// OppositePlanes::in_plane). Blocks are given per sub-box; a point belongs to the box holding it in
// the frame (across the closures), a point on the foot to the ring (its surface map there).
tmesh::PolycubeMaps foot_maps(const std::string& in, const core::Json& j, const tmesh::Params& params) {
  if (params.pillow_layers < 1) throw core::ConfigError("tmesh.pillow_layers must be at least 1 for a torus standing on a cube (the assembly)");
  const core::Json& rj = core::require(j, "ring", in);
  const core::Json& bj = core::require(j, "base", in);
  std::vector<Ring> list;
  const polycube::DifferenceMap m = polycube::difference_from_json(core::require(bj, "polycube", in), in);
  std::shared_ptr<volmap::Locator> base;
  {
    core::LogSection s("volume map");
    list.push_back(read_ring(in, core::require(rj, "polycube", in), core::require(rj, "volume_map", in)));
    base = difference_locator(in, core::require(bj, "volume_map", in), m);
  }
  if (!list[0].embedding.profile.empty() || !list[0].cuts[1].empty() || !list[0].cuts[2].empty())
    throw core::InvalidInputError(in + ": a ring with a rectilinear profile or sharp-curve cuts cannot stand on a cube yet");
  if (!m.foot) throw core::InvalidInputError(in + ": base.polycube has no foot");
  std::vector<int> base_vertex;
  try {
    base_vertex = core::require(bj, "layout_vertex", in).get<std::vector<int>>();
  } catch (const core::Json::exception& x) {
    throw core::InvalidInputError(in + ": malformed base.layout_vertex: " + x.what());
  }
  const int A = m.axis;
  const polycube::FootRect& foot = *m.foot;
  const bool above = foot.lo[static_cast<std::size_t>(A)] == 1;  // difference_from_json checked: on a holed face
  // The foot's corners: the base's solid vertices at its rectangle's corners.
  std::array<int, 4> want{};
  std::array<tmesh::Vec3, 4> q{};
  int corners = 0;
  for (int i = 0; i < m.solid_vertices && i < static_cast<int>(m.points.size()); ++i) {
    const auto& x = m.points[static_cast<std::size_t>(i)];
    bool corner = true;
    for (std::size_t d = 0; d < 3; ++d) corner = corner && (std::abs(x[d] - foot.lo[d]) < 1e-9 || std::abs(x[d] - foot.hi[d]) < 1e-9);
    if (!corner) continue;
    if (corners == 4 || i >= static_cast<int>(base_vertex.size())) throw core::InvalidInputError(in + ": base.polycube.foot does not have four corner vertices");
    want[static_cast<std::size_t>(corners)] = base_vertex[static_cast<std::size_t>(i)], q[static_cast<std::size_t>(corners++)] = {x[0], x[1], x[2]};
  }
  if (corners != 4) throw core::InvalidInputError(in + ": base.polycube.foot has " + std::to_string(corners) + " corner vertices, not 4");
  const std::optional<RingFace> rf = find_ring_face(in, list[0], 0, rj, want);
  if (!rf) throw core::InvalidInputError(in + ": no cube face of the ring has the foot's corners (base.layout_vertex, base.polycube.foot)");
  // The ring cubes' axes in the frame (the base's): the foot face's outward normal into the base.
  tmesh::Vec3 inward{0, 0, 0};
  inward[static_cast<std::size_t>(A)] = above ? -1 : 1;
  const tmesh::AxisMap axes = face_axes(*rf, [&](int v) { return q[static_cast<std::size_t>(std::find(want.begin(), want.end(), v) - want.begin())]; }, inward);
  int Fa = -1, sigma = 0;  // the frame axis of the ring's a and its sign
  for (int f = 0; f < 3; ++f) {
    int nonzero = 0;
    for (int a = 0; a < 3; ++a) nonzero += axes.P[f][a] != 0;
    if (nonzero != 1) throw core::InvalidInputError(in + ": the foot's corners do not lie on the ring's face as a rectangle");
    if (axes.P[f][0] != 0) Fa = f, sigma = axes.P[f][0];
  }
  const auto& P = axes.P;
  const int det = P[0][0] * (P[1][1] * P[2][2] - P[1][2] * P[2][1]) - P[0][1] * (P[1][0] * P[2][2] - P[1][2] * P[2][0]) +
                  P[0][2] * (P[1][0] * P[2][1] - P[1][1] * P[2][0]);
  if (det != 1)  // both maps keep the surface's orientation, so the foot's corners must too
    throw core::InvalidInputError(in + ": the foot's corners lie on the ring's face mirrored (base.polycube.foot, ring.polycube.corner_vertex)");
  const int N = list[0].embedding.ring, s0 = rf->sector;
  const std::array<double, 3> side = cube_side_lengths(*base, in);
  const auto ring = std::make_shared<const tmesh::PolycubeMaps>(ring_maps(std::move(list), params));
  // The ring cubes' lengths in the solid along a (through their centres) and the foot cube's height.
  auto ring_length = [&](int sector, int axis) {
    return path_length(
        [&](double t) {
          tmesh::Vec3 u{0.5, 0.5, 0.5};
          u[static_cast<std::size_t>(axis)] = t;
          return ring->physical(sector, u);
        },
        0.0, 1.0);
  };
  // One height for all (the closures join equal faces): the ring cubes' mean across the foot (the
  // foot cube alone, where the plate cuts the tube, is a third of the others at the assembly's
  // waist; its height would make the pillow of the others a third of their thickness).
  double height = 0;
  for (int s = 0; s < N; ++s) height += ring_length(s, rf->face / 2) / N;
  tmesh::BoxLayout layout;
  // The base: the grid of its holes' and its foot's sides, in the frame (the cube's sides in the solid).
  std::array<std::vector<double>, 3> lines;
  for (int d = 0; d < 3; ++d) {
    auto& l = lines[static_cast<std::size_t>(d)];
    l = {0, 1};
    if (d == A) continue;
    for (const auto& h : m.holes) l.push_back(h.lo[static_cast<std::size_t>(d)]), l.push_back(h.hi[static_cast<std::size_t>(d)]);
    l.push_back(foot.lo[static_cast<std::size_t>(d)]), l.push_back(foot.hi[static_cast<std::size_t>(d)]);
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  for (std::size_t k = 0; k + 1 < lines[2].size(); ++k)
    for (std::size_t jj = 0; jj + 1 < lines[1].size(); ++jj)
      for (std::size_t i = 0; i + 1 < lines[0].size(); ++i) {
        const std::array<std::size_t, 3> ijk{i, jj, k};
        std::array<tmesh::Vec3, 2> box;
        tmesh::Vec3 centre;
        for (std::size_t d = 0; d < 3; ++d) {
          const double lo = lines[d][ijk[d]], hi = lines[d][ijk[d] + 1];
          box[0][d] = lo * side[d], box[1][d] = hi * side[d], centre[d] = (lo + hi) / 2;
        }
        bool hole = false;
        for (const auto& h : m.holes) {
          bool in_h = true;
          for (std::size_t d = 0; d < 3; ++d) in_h = in_h && (static_cast<int>(d) == A || (centre[d] > h.lo[d] && centre[d] < h.hi[d]));
          hole = hole || in_h;
        }
        if (!hole) layout.boxes.push_back(box);
      }
  const int plate_boxes = static_cast<int>(layout.boxes.size());
  // The foot cube on the foot's rectangle, the others in a row beyond the base along a.
  std::array<tmesh::Vec3, 2> foot_box;
  for (std::size_t d = 0; d < 3; ++d) foot_box[0][d] = foot.lo[d] * side[d], foot_box[1][d] = foot.hi[d] * side[d];
  foot_box[0][static_cast<std::size_t>(A)] = above ? side[static_cast<std::size_t>(A)] : -height;
  foot_box[1][static_cast<std::size_t>(A)] = above ? side[static_cast<std::size_t>(A)] + height : 0;
  layout.boxes.push_back(foot_box);
  std::vector<int> sector{s0};
  double at = sigma > 0 ? side[static_cast<std::size_t>(Fa)] + height : -height;  // the row's start, clear of the base
  for (int i = 1; i < N; ++i) {
    const int s = (s0 + i) % N;
    const double len = ring_length(s, 0);
    std::array<tmesh::Vec3, 2> box = foot_box;
    box[0][static_cast<std::size_t>(Fa)] = sigma > 0 ? at : at - len;
    box[1][static_cast<std::size_t>(Fa)] = sigma > 0 ? at + len : at;
    at += sigma * len;
    layout.boxes.push_back(box);
    sector.push_back(s);
  }
  // a = 1 of the foot cube is its next cube's a = 0; the last cube's a = 1 is the foot cube's a = 0.
  const int hi_face = 2 * Fa + (sigma > 0 ? 1 : 0), lo_face = 2 * Fa + (sigma > 0 ? 0 : 1);
  auto face_at = [&](int b, int f) { return layout.boxes[static_cast<std::size_t>(b)][static_cast<std::size_t>(f % 2)][static_cast<std::size_t>(f / 2)]; };
  for (const auto& [a, b] : {std::pair{plate_boxes, plate_boxes + 1}, std::pair{plate_boxes + N - 1, plate_boxes}}) {
    tmesh::BoxLayout::Closure c;
    c.a = a, c.fa = hi_face, c.b = b, c.fb = lo_face;
    c.shift[static_cast<std::size_t>(Fa)] = face_at(b, lo_face) - face_at(a, hi_face);
    layout.closures.push_back(c);
  }
  // 2^level elements along the base's shortest side, as many per unit of frame length elsewhere;
  // one pillow thickness in the frame, a layer of such elements (at most 0.45 of a thin sub-box).
  const int n = 1 << params.level;
  const double shortest = *std::min_element(side.begin(), side.end());
  double thickness = shortest * params.pillow_layers / (n + 2 * params.pillow_layers);
  // Where the ring leaves its foot (the foot's two ends along a), the ring's next cubes and the
  // base's cells beside the foot are cut two pillow thicknesses from that end: the slabs on the
  // crack between them taper to its root within that length (over a whole cube they were
  // slivers that the map's kink at the root turned inside out). The foot cube is cut as far
  // inside its ends (the cut runs on through the base's cells beside and under it): the concave
  // edges along the foot's sides then have vertices of their own between its ends, whose inner
  // copies go into the base; with only the ends' (in the plate's top plane, by the crack rule)
  // the pillow along the whole side was flat (scaled Jacobian 0.04 there before optimization).
  std::vector<std::array<std::vector<double>, 3>> cuts(layout.boxes.size());
  {
    const double l = 2 * thickness, f0 = foot_box[0][static_cast<std::size_t>(Fa)], f1 = foot_box[1][static_cast<std::size_t>(Fa)];
    auto cut = [&](int b, double x) {
      const auto& B = layout.boxes[static_cast<std::size_t>(b)];
      if (x > B[0][static_cast<std::size_t>(Fa)] + l / 4 && x < B[1][static_cast<std::size_t>(Fa)] - l / 4) cuts[static_cast<std::size_t>(b)][static_cast<std::size_t>(Fa)].push_back(x);
    };
    cut(plate_boxes, f0 + l), cut(plate_boxes, f1 - l);
    cut(plate_boxes + 1, face_at(plate_boxes + 1, lo_face) + sigma * l);
    cut(plate_boxes + N - 1, face_at(plate_boxes + N - 1, hi_face) - sigma * l);
    const int W = 3 - A - Fa;  // across the foot
    for (int b = 0; b < plate_boxes; ++b) {
      const auto& B = layout.boxes[static_cast<std::size_t>(b)];
      if (B[0][static_cast<std::size_t>(W)] < foot_box[0][static_cast<std::size_t>(W)] - 1e-12 || B[1][static_cast<std::size_t>(W)] > foot_box[1][static_cast<std::size_t>(W)] + 1e-12) continue;
      if (std::abs(B[1][static_cast<std::size_t>(Fa)] - f0) < 1e-12) cut(b, f0 - l);
      if (std::abs(B[0][static_cast<std::size_t>(Fa)] - f1) < 1e-12) cut(b, f1 + l);
    }
  }
  const auto bc = std::make_shared<const tmesh::BoxComplex>(tmesh::box_complex(layout, cuts));
  std::vector<std::array<int, 3>> wanted(bc->extent.size());
  for (std::size_t i = 0; i < wanted.size(); ++i)
    for (std::size_t d = 0; d < 3; ++d) {
      const double e = bc->extent[i][1][d] - bc->extent[i][0][d];
      wanted[i][d] = std::max(1, static_cast<int>(std::lround(n * e / shortest)));
      thickness = std::min(thickness, 0.45 * e);
    }
  core::log("the base as " + std::to_string(plate_boxes) + " boxes, the ring's " + std::to_string(N) + " cubes standing on its foot: " +
            std::to_string(bc->extent.size()) + " sub-boxes, pillow " + std::to_string(thickness) + " thick in the frame");
  tmesh::PolycubeMaps out;
  out.blocks = tmesh::complex_blocks(bc->complex, tmesh::element_counts(bc->complex, wanted), params.pillow_layers, bc->pillow(thickness),
                                     tmesh::OppositePlanes::in_plane);
  out.boundary.assign(out.blocks.size(), {0, 0, 0, 0, 0, 0});
  // The box holding a point of sub-box c's parameters and the point in the frame.
  const double tol = 1e-9 * bc->size, plane = above ? side[static_cast<std::size_t>(A)] : 0;
  const auto boxes = std::make_shared<const std::vector<std::array<tmesh::Vec3, 2>>>(layout.boxes);
  auto where = [bc, boxes, plate_boxes, A, plane, tol](int c, const tmesh::Vec3& x) {
    const auto at = bc->locate(bc->to_frame(c, x), c);
    if (!at)
      throw core::NumericalError("tmesh: a point of sub-box " + std::to_string(c) + " (" + std::to_string(x[0]) + ", " + std::to_string(x[1]) + ", " +
                                 std::to_string(x[2]) + ") lies outside the polycube of the base and the ring");
    const tmesh::Vec3 z = bc->to_frame(at->first, at->second);
    int b = bc->box[static_cast<std::size_t>(at->first)];
    if (b < plate_boxes && std::abs(z[static_cast<std::size_t>(A)] - plane) < tol) {  // on the foot: the ring's
      const auto& f = (*boxes)[static_cast<std::size_t>(plate_boxes)];
      bool on = true;
      for (std::size_t d = 0; d < 3; ++d) on = on && (static_cast<int>(d) == A || (z[d] > f[0][d] - tol && z[d] < f[1][d] + tol));
      if (on) b = plate_boxes;
    }
    return std::make_pair(b, z);
  };
  // A ring box's point in its cube's parameters.
  auto ring_point = [boxes, axes, plate_boxes](int b, const tmesh::Vec3& z) {
    tmesh::Vec3 u = tmesh::frame_to_cube(axes, (*boxes)[static_cast<std::size_t>(b)], z);
    for (double& v : u) v = std::clamp(v, 0.0, 1.0);
    return u;
  };
  auto base_point = [side](const tmesh::Vec3& z) {
    tmesh::Vec3 u;
    for (std::size_t d = 0; d < 3; ++d) u[d] = std::clamp(z[d] / side[d], 0.0, 1.0);
    return u;
  };
  out.physical = [where, ring_point, base_point, ring, base, sector, plate_boxes](int c, const tmesh::Vec3& x) {
    const auto [b, z] = where(c, x);
    if (b >= plate_boxes) return ring->physical(sector[static_cast<std::size_t>(b - plate_boxes)], ring_point(b, z));
    const auto p = base->physical(base_point(z));
    if (!p) throw core::NumericalError("tmesh: a point of the base lies outside its volume map");
    return *p;
  };
  out.polycube = [where, ring_point, base_point, ring, sector, plate_boxes](int c, const tmesh::Vec3& x) {
    const auto [b, z] = where(c, x);
    if (b >= plate_boxes) return ring->polycube(sector[static_cast<std::size_t>(b - plate_boxes)], ring_point(b, z));
    tmesh::Vec3 u = base_point(z);
    u[0] += 30.0;  // the ring's annulus lies within |x| < 3
    return u;
  };
  // How far the two maps of the foot (the base's rectangle, the ring's face) are apart: the base's
  // blocks under the foot meet the ring's points on it.
  double gap = 0, size = 0;
  for (int i = 0; i <= 8; ++i)
    for (int k = 0; k <= 8; ++k) {
      tmesh::Vec3 z;
      const auto& f = (*boxes)[static_cast<std::size_t>(plate_boxes)];
      for (std::size_t d = 0; d < 3; ++d) z[d] = f[0][d];
      int e = 0;
      for (std::size_t d = 0; d < 3; ++d)
        if (static_cast<int>(d) != A) z[d] = f[0][d] + (e++ ? k : i) / 8.0 * (f[1][d] - f[0][d]);
      z[static_cast<std::size_t>(A)] = plane;
      const auto p = base->physical(base_point(z));
      const tmesh::Vec3 r = ring->physical(s0, ring_point(plate_boxes, z));
      if (p) gap = std::max(gap, std::hypot((*p)[0] - r[0], (*p)[1] - r[1], (*p)[2] - r[2]));
    }
  for (std::size_t d = 0; d < 3; ++d)
    if (static_cast<int>(d) != A) size = std::max(size, (foot.hi[d] - foot.lo[d]) * side[d]);
  core::log("the base's and the ring's maps of the foot differ by up to " + std::to_string(gap) + " (" + std::to_string(size > 0 ? gap / size : 0.0) +
            " of the foot's length)");
  return out;
}

// The polycube structure the stage wrote (structure.h), if the file has one (files written before
// it had none and are read as before): read, checked to be a polycube and to be the structure of
// `kind` (its counts of tori, virtual components and, for one cube, cubes). The file was checked
// when written, so any failure means it was edited or corrupted: InvalidInputError naming it.
std::optional<polycube::Structure> read_structure(const std::string& in, const core::Json& j, const std::string& kind) {
  if (!j.contains("structure")) return std::nullopt;
  polycube::Structure s = polycube::structure_from_json(j["structure"], in);
  try {
    polycube::check(s);
  } catch (const core::TopologyError& e) {
    throw core::InvalidInputError(in + ": structure is not a polycube: " + e.what());
  }
  const core::Json f = polycube::report_figures(s);
  const std::size_t rings = kind == "tori" && j.contains("rings") && j["rings"].is_array() ? j["rings"].size() : 0;
  // A difference has one virtual component per hole (its polycube's `holes`, or one).
  std::size_t holes = 1;
  const core::Json* pc = kind == "difference" && j.contains("polycube") ? &j["polycube"]
                         : kind == "torus_on_cube" && j.contains("base") && j["base"].is_object() && j["base"].contains("polycube") ? &j["base"]["polycube"]
                                                                                                                                    : nullptr;
  if (pc && pc->is_object() && pc->contains("holes") && (*pc)["holes"].is_array()) holes = (*pc)["holes"].size();
  const bool differs = kind == "difference" || kind == "torus_on_cube";
  const std::size_t tori = kind == "torus" || kind == "torus_on_cube" ? 1 : kind == "tori" ? rings : 0, virt = differs ? holes : 0;
  const bool one_cube = kind == "cube" || kind == "difference";
  if (f["tori"] != tori || f["virtual_components"] != virt || (one_cube && f["cubes"] != 1))
    throw core::InvalidInputError(in + ": structure does not match kind '" + kind + "': it has " + f["cubes"].dump() + " cubes, " +
                                  f["tori"].dump() + " tori and " + f["virtual_components"].dump() + " virtual components");
  return s;
}

}  // namespace

PolycubeInput read_polycube_input(const std::string& in, const tmesh::Params& params) {
  const core::Json j = core::read_stage_file(in, "volts-polycube", 2);
  PolycubeInput r;
  if (j.contains("kind") && !j["kind"].is_string()) throw core::InvalidInputError(in + ": polycube kind must be a string");
  const std::string kind = j.value("kind", std::string("cube"));
  r.kind = kind;
  if (kind != "cube" && kind != "torus" && kind != "tori" && kind != "difference" && kind != "torus_on_cube")
    throw core::InvalidInputError(in + ": unknown polycube kind '" + kind + "'");
  r.surface = core::require(j, "surface", in);
  const std::optional<polycube::Structure> structure = read_structure(in, j, kind);
  if (kind == "torus_on_cube") {
    core::log("a torus standing on a cube minus holes: one pillowed complex of boxes");
    r.maps = foot_maps(in, j, params);
    return r;
  }
  if (kind == "torus" || kind == "tori") {
    std::vector<Ring> rings;
    {
      core::LogSection s("volume map");
      if (kind == "torus") {
        rings.push_back(read_ring(in, core::require(j, "polycube", in), core::require(j, "volume_map", in)));
      } else {
        const core::Json& list = core::require(j, "rings", in);
        if (!list.is_array() || list.empty()) throw core::InvalidInputError(in + ": rings must be a non-empty list");
        for (const auto& ring : list) rings.push_back(read_ring(in, core::require(ring, "polycube", in), core::require(ring, "volume_map", in)));
      }
    }
    if (kind == "tori" && j.contains("connectors") && !j["connectors"].empty()) {
      const core::Json& cs = j["connectors"];
      if (!cs.is_array() || cs.size() != 1) throw core::InvalidInputError(in + ": connectors must be a list of one connector");
      core::log("a connector cube joins the rings: one pillowed complex of cubes");
      r.maps = connector_maps(in, std::move(rings), j["rings"], cs[0], params);
      return r;
    }
    try {
      r.maps = ring_maps(std::move(rings), params);
    } catch (const core::InvalidInputError& e) {  // a profile tmesh cannot lay blocks on (tmesh::profile_blocks)
      throw core::InvalidInputError(in + ": polycube.profile: " + e.what());
    } catch (const core::TopologyError& e) {
      throw core::TopologyError(in + ": polycube.profile: " + e.what());
    }
    return r;
  }
  if (kind == "difference") {
    // A cube minus through holes: the blocks around the holes (pillowed under the outer faces
    // and the walls alike), every point through the volume map.
    const polycube::DifferenceMap m = polycube::difference_from_json(core::require(j, "polycube", in), in);
    if (structure) {
      for (std::size_t h = 0; h < m.holes.size(); ++h) {
        const auto& boxes = structure->virtual_components.at(h).boxes;
        if (boxes.size() != 1 || boxes[0].lo != m.holes[h].lo || boxes[0].hi != m.holes[h].hi)
          throw core::InvalidInputError(in + ": structure's virtual component " + std::to_string(h) + " is not hole " + std::to_string(h) +
                                        "'s box in polycube");
      }
    }
    std::shared_ptr<volmap::Locator> locate;
    {
      core::LogSection s("volume map");
      locate = difference_locator(in, core::require(j, "volume_map", in), m);
    }
    tmesh::PolycubeMaps& maps = r.maps;
    std::vector<std::array<tmesh::Vec3, 2>> boxes;
    for (const auto& h : m.holes) boxes.push_back({h.lo, h.hi});
    if (boxes.size() == 1) {
      maps.blocks = {tmesh::difference_blocks(m.axis, boxes, 1 << params.level, params.pillow_layers)};
    } else {
      // Several holes (a plate with bolt holes): 2^level elements along the cube's shortest side in
      // the solid, the others as many more as they are longer, so elements (and the pillow, layers
      // of them) are about as long one way as another; one count for all would make a flat
      // plate's elements 8:1 and leave no room for the pillow between its holes and its sides.
      const std::array<double, 3> length = cube_side_lengths(*locate, in);
      const double shortest = *std::min_element(length.begin(), length.end());
      std::array<int, 3> counts{};
      for (int a = 0; a < 3; ++a)
        counts[static_cast<std::size_t>(a)] = std::max(1, static_cast<int>(std::lround((1 << params.level) * length[static_cast<std::size_t>(a)] / shortest)));
      core::log("elements per cube axis " + std::to_string(counts[0]) + " x " + std::to_string(counts[1]) + " x " + std::to_string(counts[2]) +
                " (sides " + std::to_string(length[0]) + ", " + std::to_string(length[1]) + ", " + std::to_string(length[2]) + " in the solid)");
      maps.blocks = {tmesh::difference_blocks(m.axis, boxes, counts, params.pillow_layers)};
    }
    maps.physical = [locate](int, const tmesh::Vec3& abc) {
      const auto p = locate->physical(abc);
      if (!p) throw core::NumericalError("tmesh: a point of the cube minus the hole lies outside the volume map");
      return *p;
    };
    maps.polycube = [](int, const tmesh::Vec3& abc) { return abc; };
    return r;
  }
  pipeline::check_integer_members(in, j);
  const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
  const classify::Classification c = classify::from_json(core::require(j, "classification", in), in);
  const polycube::Polycube p = polycube::from_json(core::require(j, "polycube", in), in);
  pipeline::check_classification(in, mesh, c);
  pipeline::check_polycube(in, mesh, c, p);
  std::shared_ptr<polycube::VolumeMap> map;
  {
    core::LogSection s("volume map");
    map = std::make_shared<polycube::VolumeMap>(mesh, c, p);
  }
  tmesh::PolycubeMaps& maps = r.maps;
  maps.boundary = {{1, 1, 1, 1, 1, 1}};
  maps.physical = [map](int, const tmesh::Vec3& abc) { return (*map)(abc); };
  maps.polycube = [](int, const tmesh::Vec3& abc) { return abc; };
  return r;
}

}  // namespace volts::pipeline
