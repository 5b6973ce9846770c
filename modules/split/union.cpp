// A torus standing on a cube minus through holes (Liu et al. 2013, Fig. 1: the CAD assembly, a
// plate with four holes and a ring on top, the union of a difference and a torus). The ring meets
// the base along its foot: a closed difference curve that, alone of all the rims, cuts the surface
// in two (a hole's rim does not: its wall joins it to the other rim). The foot is filled in its
// plane (flagged triangles); the base plus the fill is a cube minus holes (split_difference, the
// fill inside its face), the ring plus the fill reversed a torus whose fill is one whole patch of
// one of its cubes (split_torus with a DiskPatch, as a connector's end): that cube stands on the
// base's face, the contact (filled_patch) naming its disk patch.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/Dense>

#include "classify/classify.h"
#include "core/errors.h"
#include "split/isoline.h"
#include "split/split_internal.h"

namespace volts::split::detail {

using surface::Mesh;
using VI = Mesh::Vertex_index;

namespace {

Eigen::Vector3d point(const Layout& L, int v) {
  const auto& p = L.points[static_cast<std::size_t>(v)];
  return {p[0], p[1], p[2]};
}

// The ring's first cross section, inserted into its mesh: the section by the plane through the
// ring's axis and the top of its centre line (furthest from the foot), only on the faces on the
// top's side of the ring's centre, so that neither the section across the foot nor any edge of
// the disk is cut (split_torus refuses a first section through the disk; a plane section left
// whole would also split the rim's edges under the DiskPatch's ids).
std::vector<int> section_opposite_the_foot(Submesh& ring, const Layout& L, const std::vector<int>& foot) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), foot_centre = Eigen::Vector3d::Zero();
  for (int v : ring.layout_vertex) centre += point(L, v) / static_cast<double>(ring.layout_vertex.size());
  for (int v : foot) foot_centre += point(L, v) / static_cast<double>(foot.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int v : ring.layout_vertex) cov += (point(L, v) - centre) * (point(L, v) - centre).transpose();
  const Eigen::Vector3d axis = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);  // the ring's normal
  Eigen::Vector3d up = centre - foot_centre;
  up -= up.dot(axis) * axis;  // in the ring's plane
  if (!(up.norm() > 0)) throw core::TopologyError("split: the ring standing on the base is centred on its foot");
  up.normalize();
  const Eigen::Vector3d across = axis.cross(up);
  Mesh& m = ring.mesh;
  std::vector<double> f;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    f.push_back((Eigen::Vector3d(p.x(), p.y(), p.z()) - centre).dot(across));
  }
  std::vector<char> top(m.number_of_faces(), 0);
  for (auto fc : m.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : CGAL::vertices_around_face(m.halfedge(fc), m)) c += Eigen::Vector3d(m.point(v).x(), m.point(v).y(), m.point(v).z()) / 3;
    top[fc] = (c - centre).dot(up) > 0;
  }
  IsolineOptions o;
  o.face_mask = &top;
  for (auto& loop : insert_isoline(m, f, level_between_vertices(0.0, f), o))
    if (!loop_separates(m, loop)) return loop;
  throw core::TopologyError("split: no cross section of the ring standing on the base runs around its tube at its top");
}

}  // namespace

Decomposition split_torus_on_cube(const Mesh& mesh, const classify::Classification& c, const Params& prm) {
  const auto rims = difference_rims(c);
  // The foot: the one rim that alone cuts the surface in two.
  std::vector<int> foot;
  int feet = 0;
  for (const auto& r : rims)
    if (loop_separates(mesh, r)) foot = r, ++feet;
  if (feet != 1)
    throw core::TopologyError("split: " + std::to_string(feet) + " of the " + std::to_string(rims.size()) +
                              " difference loops cut the surface in two; a torus standing on a cube minus holes has one (its foot)");
  const std::vector<int> side = regions_cut_by(mesh, {foot});
  // The base holds the sharp corners; the ring, on the other side, has none off the foot (where a
  // coarse foot turns sharply, classify may find corners on it) and genus 1.
  const std::set<int> on_foot(foot.begin(), foot.end());
  const auto corner = [&](auto v) { return !on_foot.count(static_cast<int>(v)) && std::binary_search(c.corners.begin(), c.corners.end(), static_cast<int>(v)); };
  int base_side = -1;
  for (auto f : mesh.faces())
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (base_side < 0 && corner(v)) base_side = side[f];
  if (base_side < 0) throw core::TopologyError("split: no sharp corner on either side of the foot; the base must be a cube minus holes");
  const int ring_side = 1 - base_side;
  for (auto f : mesh.faces())
    if (side[f] == ring_side)
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        if (corner(v))
          throw core::TopologyError("split: both sides of the foot (the closed difference curve that separates the surface) have sharp corners");
  const int ring_genus = region_genus(mesh, side, ring_side);
  if (ring_genus != 1)
    throw core::TopologyError("split: the part standing on the foot has genus " + std::to_string(ring_genus) + "; only a torus (genus 1) is supported");

  Layout L;
  copy_mesh(mesh, L);
  std::vector<int> ring_tris, base_tris;
  for (auto f : mesh.faces()) (side[f] == ring_side ? ring_tris : base_tris).push_back(static_cast<int>(f));
  // The base closed by the foot's disk, filled in its plane (the base's face), no chords: the disk
  // is also a whole patch of the ring and maps one-to-one onto a square.
  Submesh base = submesh(L, base_tris, std::vector<char>(base_tris.size(), 0));
  int planar = 0;
  const std::vector<int> fill = fill_openings(base, L, true, FillMethod::planar, &planar);
  const std::set<int> fill_set(fill.begin(), fill.end());
  std::vector<int> ring_all = ring_tris;
  ring_all.insert(ring_all.end(), fill.begin(), fill.end());
  std::vector<char> reversed(ring_tris.size(), 0);
  reversed.resize(ring_all.size(), 1);
  Submesh ring = submesh(L, ring_all, reversed);

  const classify::Classification cb = classify::classify(base.mesh, {});
  Decomposition base_d = split_difference(base.mesh, cb, prm);

  DiskPatch disk;
  {
    std::map<int, int> local;
    for (std::size_t v = 0; v < ring.layout_vertex.size(); ++v) local[ring.layout_vertex[v]] = static_cast<int>(v);
    for (int v : foot) disk.rim.push_back(local.at(v));
    std::set<int> inside;
    for (int t : fill)
      for (int v : L.triangles[static_cast<std::size_t>(t)])
        if (!on_foot.count(v)) inside.insert(local.at(v));
    disk.inside.assign(inside.begin(), inside.end());
  }
  const std::vector<int> first = section_opposite_the_foot(ring, L, foot);
  Decomposition ring_d = split_torus(ring.mesh, {}, prm, {}, first, &disk);

  // Merge: the base's layout first (its foot fill once, flagged), then the ring's new vertices and
  // its triangles off the disk; the ring's disk patch names the base's copies of the fill.
  Decomposition d;
  d.genus = c.genus;
  d.layout.points = L.points;
  std::map<int, int> fill_at;  // L's fill triangle -> d's
  const std::vector<int> bmap = merge_vertices(base_d.layout, base.layout_vertex, d.layout);
  std::vector<int> btri(base_d.layout.triangles.size());
  for (std::size_t k = 0; k < btri.size(); ++k) {
    const auto& t = base_d.layout.triangles[k];
    const std::array<int, 3> mapped{bmap[static_cast<std::size_t>(t[0])], bmap[static_cast<std::size_t>(t[1])], bmap[static_cast<std::size_t>(t[2])]};
    const bool foot_fill = k < base.layout_triangle.size() && fill_set.count(base.layout_triangle[k]);
    if (foot_fill) {
      if (mapped != L.triangles[static_cast<std::size_t>(base.layout_triangle[k])]) throw std::logic_error("split: the base's hole cuts changed the foot's fill");
      fill_at[base.layout_triangle[k]] = static_cast<int>(k);
    }
    btri[k] = static_cast<int>(d.layout.triangles.size());
    d.layout.triangles.push_back(mapped);
    d.layout.filled.push_back(foot_fill || base_d.layout.filled[k] ? 1 : 0);
  }
  if (fill_at.size() != fill.size()) throw std::logic_error("split: the foot's fill is not in the base's layout");
  auto map_patch = [](Patch P, const std::vector<int>& tmap, const std::vector<int>& vmap) {
    for (int& x : P.triangles) x = tmap[static_cast<std::size_t>(x)];
    std::sort(P.triangles.begin(), P.triangles.end());
    for (int& v : P.corners) v = vmap[static_cast<std::size_t>(v)];
    for (auto& s : P.sides)
      for (int& v : s) v = vmap[static_cast<std::size_t>(v)];
    return P;
  };
  for (const auto& P : base_d.layout.patches) d.layout.patches.push_back(map_patch(P, btri, bmap));
  for (auto C : base_d.components) {
    for (auto& F : C.faces)
      for (int& v : F.corners) v = bmap[static_cast<std::size_t>(v)];
    d.components.push_back(std::move(C));
  }
  d.contacts = base_d.contacts;

  const std::vector<int> rmap = merge_vertices(ring_d.layout, ring.layout_vertex, d.layout);
  std::vector<int> rtri(ring_d.layout.triangles.size());
  for (std::size_t k = 0; k < rtri.size(); ++k) {
    if (k < ring.layout_triangle.size() && fill_set.count(ring.layout_triangle[k])) {
      rtri[k] = btri[static_cast<std::size_t>(fill_at.at(ring.layout_triangle[k]))];
      continue;
    }
    const auto& t = ring_d.layout.triangles[k];
    rtri[k] = static_cast<int>(d.layout.triangles.size());
    d.layout.triangles.push_back({rmap[static_cast<std::size_t>(t[0])], rmap[static_cast<std::size_t>(t[1])], rmap[static_cast<std::size_t>(t[2])]});
    d.layout.filled.push_back(0);
  }
  const int patch_offset = static_cast<int>(d.layout.patches.size()), comp_offset = static_cast<int>(d.components.size());
  const int face_offset = static_cast<int>(d.layout.internal_faces.size());
  int disk_patch = -1, disk_component = -1;
  for (std::size_t p = 0; p < ring_d.layout.patches.size(); ++p) {
    const Patch& P = ring_d.layout.patches[p];
    const auto in_fill = [&](int x) { return static_cast<std::size_t>(x) < ring.layout_triangle.size() && fill_set.count(ring.layout_triangle[static_cast<std::size_t>(x)]) > 0; };
    const auto n_fill = std::count_if(P.triangles.begin(), P.triangles.end(), in_fill);
    if (n_fill > 0) {
      if (n_fill != static_cast<long>(P.triangles.size()) || disk_patch >= 0)
        throw core::TopologyError("split: the foot's disk is not one whole patch of the ring standing on it");
      disk_patch = patch_offset + static_cast<int>(p);
    }
    d.layout.patches.push_back(map_patch(P, rtri, rmap));
  }
  if (disk_patch < 0 || static_cast<int>(fill.size()) != static_cast<int>(d.layout.patches[static_cast<std::size_t>(disk_patch)].triangles.size()))
    throw core::TopologyError("split: the foot's disk is not one whole patch of the ring standing on it");
  for (auto F : ring_d.layout.internal_faces) {
    for (int& v : F.corners) v = rmap[static_cast<std::size_t>(v)];
    for (auto& s : F.sides)
      for (int& v : s) v = rmap[static_cast<std::size_t>(v)];
    for (int& v : F.loop) v = rmap[static_cast<std::size_t>(v)];
    d.layout.internal_faces.push_back(std::move(F));
  }
  for (std::size_t k = 0; k < ring_d.components.size(); ++k) {
    Component C = ring_d.components[k];
    C.torus = 0;
    for (int& p : C.patches) {
      p += patch_offset;
      if (p == disk_patch) disk_component = comp_offset + static_cast<int>(k);
    }
    for (auto& F : C.faces) {
      for (int& p : F.patches) p += patch_offset;
      if (F.internal_face >= 0) F.internal_face += face_offset;
      for (int& v : F.corners) v = rmap[static_cast<std::size_t>(v)];
    }
    d.components.push_back(std::move(C));
  }
  Torus R = ring_d.tori.at(0);
  for (int& k : R.components) k += comp_offset;
  for (int& x : R.cross_sections) x += face_offset;
  d.tori.push_back(R);
  for (const auto& x : ring_d.contacts) d.contacts.push_back({x.a + comp_offset, x.b + comp_offset, x.via, x.index + (x.via == "internal_face" ? face_offset : 0)});
  d.contacts.push_back({0, disk_component, "filled_patch", disk_patch});
  // For ParaView: the ring's fields on its vertices (NaN on the base's), its cuts.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto [from, to] : {std::pair{&ring_d.field, &d.field}, {&ring_d.ring_field, &d.ring_field}, {&ring_d.tube_field, &d.tube_field}}) {
    if (from->size() != rmap.size()) continue;
    to->assign(d.layout.points.size(), nan);
    for (std::size_t v = 0; v < rmap.size(); ++v) (*to)[static_cast<std::size_t>(rmap[v])] = (*from)[v];
  }
  for (auto [from, to] : {std::pair{&ring_d.cross_section_lines, &d.cross_section_lines}, {&ring_d.longitude_lines, &d.longitude_lines}})
    for (auto l : *from) {
      for (int& v : l) v = rmap[static_cast<std::size_t>(v)];
      to->push_back(l);
    }
  d.critical_min = ring_d.critical_min, d.critical_max = ring_d.critical_max, d.critical_saddle = ring_d.critical_saddle;
  d.planar_fills = planar + base_d.planar_fills;
  d.quad_patches = static_cast<int>(d.layout.patches.size());
  return d;
}

}  // namespace volts::split::detail
