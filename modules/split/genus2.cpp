// Two tori (Liu et al. 2013, §4.1 and the union of Fig. 6(c)): a genus-2 surface is cut along a
// level set of the first harmonic field that separates it into two one-holed tori (the waist of
// an "eight"); the loop is filled with a disk (flagged triangles) where the two tori meet, and each
// closed torus is split into a ring of cubes whose cuts avoid the disk, so the disk lies inside one
// patch of each torus (the faces the two primitives are united on).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "core/errors.h"
#include "split/isoline.h"
#include "split/split_internal.h"

namespace volts::split::detail {

using surface::Mesh;

namespace {

// Genus of a face region with one boundary loop: chi = V - E + F = 1 - 2g.
int region_genus(const Mesh& m, const std::vector<int>& label, int which) {
  std::set<int> vs;
  std::set<Edge> es;
  int faces = 0;
  for (auto f : m.faces()) {
    if (label[f] != which) continue;
    ++faces;
    for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      vs.insert(static_cast<int>(m.target(h)));
      es.insert(edge(static_cast<int>(m.source(h)), static_cast<int>(m.target(h))));
    }
  }
  const int chi = static_cast<int>(vs.size()) - static_cast<int>(es.size()) + faces;
  return (1 - chi) / 2;
}

// A loop of the level set {f = c} that cuts the surface into two parts of genus 1.
bool find_waist(const Mesh& m, const std::vector<double>& f, double c, std::vector<int>* waist) {
  Mesh copy = m;
  std::vector<double> g = f;
  try {
    for (const auto& loop : insert_isoline(copy, g, c)) {
      const auto label = regions_cut_by(copy, {loop});
      if (*std::max_element(label.begin(), label.end()) != 1) continue;
      if (region_genus(copy, label, 0) == 1 && region_genus(copy, label, 1) == 1) {
        if (waist) *waist = loop;
        return true;
      }
    }
  } catch (const core::TopologyError&) {
  }
  return false;
}

}  // namespace

Decomposition split_two_tori(const Mesh& input, const Params& prm) {
  Mesh mesh = input;
  CriticalPoints cp;
  std::vector<double> f = height_field(mesh, prm, &cp);
  const auto gaps = saddle_gaps(f, cp);
  double level = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [w, c] : gaps)
    if (find_waist(mesh, f, level_between_vertices(c, f), nullptr)) {
      level = level_between_vertices(c, f);
      break;
    }
  if (std::isnan(level))
    throw core::TopologyError("split: no level set of the harmonic field separates the genus-2 surface into two tori (" +
                              std::to_string(cp.minima.size()) + " min, " + std::to_string(cp.maxima.size()) + " max, " +
                              std::to_string(cp.saddle_count()) + " saddles); set split.extreme_points to the two ends of the part");
  std::vector<int> waist;
  for (const auto& loop : insert_isoline(mesh, f, level)) {
    const auto label = regions_cut_by(mesh, {loop});
    if (*std::max_element(label.begin(), label.end()) == 1 && region_genus(mesh, label, 0) == 1 && region_genus(mesh, label, 1) == 1)
      waist = loop;
  }
  if (waist.empty()) throw std::logic_error("split: the waist loop vanished on insertion");
  const auto side = regions_cut_by(mesh, {waist});

  // Sides, and the disk that fills the waist (once: the second torus uses it reversed).
  Layout L;
  copy_mesh(mesh, L);
  std::array<std::vector<int>, 2> tris;
  for (std::size_t t = 0; t < side.size(); ++t) tris[side[t]].push_back(static_cast<int>(t));
  std::array<Submesh, 2> torus;
  torus[0] = submesh(L, tris[0], std::vector<char>(tris[0].size(), 0));
  const std::vector<int> fill = fill_openings(torus[0], L, true);  // no chords: flat triangles once the disk is pressed onto a face
  {
    std::vector<int> t1 = tris[1];
    std::vector<char> rev(t1.size(), 0);
    t1.insert(t1.end(), fill.begin(), fill.end());
    rev.resize(t1.size(), 1);
    torus[1] = submesh(L, t1, rev);
  }
  std::set<int> disk_vertices(waist.begin(), waist.end());
  for (int t : fill)
    for (int v : L.triangles[t]) disk_vertices.insert(v);
  const std::set<int> fill_set(fill.begin(), fill.end());
  const int n_input = static_cast<int>(mesh.number_of_vertices());

  Decomposition d;
  d.genus = 2;
  d.critical_min = static_cast<int>(cp.minima.size());
  d.critical_max = static_cast<int>(cp.maxima.size());
  d.critical_saddle = cp.saddle_count();
  d.layout.points = L.points;
  std::array<int, 2> disk_patch{-1, -1}, disk_component{-1, -1};
  std::array<int, 4> disk_corners{-1, -1, -1, -1};  // layout ids, chosen on the first torus
  for (int i = 0; i < 2; ++i) {
    Submesh& T = torus[i];
    // The first field on this torus (the disk at the waist's level), and a meridian: a level set
    // between two saddles on this side that does not separate the closed torus.
    std::vector<double> g(T.mesh.number_of_vertices());
    for (std::size_t v = 0; v < g.size(); ++v) g[v] = T.layout_vertex[v] < n_input ? f[T.layout_vertex[v]] : level;
    const bool below = *std::min_element(g.begin(), g.end()) < level;
    std::vector<int> meridian;
    for (const auto& [w, c] : gaps) {
      if ((c < level) != below) continue;
      Mesh copy = T.mesh;
      std::vector<double> h = g;
      try {
        for (const auto& loop : insert_isoline(copy, h, level_between_vertices(c, g)))
          if (!loop_separates(copy, loop)) {
            meridian = loop;
            break;
          }
      } catch (const core::TopologyError&) {
      }
      if (meridian.empty()) continue;
      meridian.clear();
      for (const auto& loop : insert_isoline(T.mesh, g, level_between_vertices(c, g)))
        if (meridian.empty() && !loop_separates(T.mesh, loop)) meridian = loop;
      break;
    }
    if (meridian.empty())
      throw core::TopologyError("split: torus " + std::to_string(i) + " of the genus-2 surface has no level set around its tube; set split.extreme_points");
    // The disk as one whole patch of this torus, with the same corners in both.
    std::map<int, int> local;
    for (std::size_t v = 0; v < T.layout_vertex.size(); ++v) local[T.layout_vertex[v]] = static_cast<int>(v);
    DiskPatch disk;
    for (int v : waist) disk.rim.push_back(local.at(v));
    for (int v : disk_vertices)
      if (std::find(waist.begin(), waist.end(), v) == waist.end()) disk.inside.push_back(local.at(v));
    if (i == 1)
      for (int k = 0; k < 4; ++k) disk.corners[k] = local.at(disk_corners[k]);
    Decomposition t = split_torus(T.mesh, {}, prm, {}, meridian, &disk);
    if (i == 0)
      for (int k = 0; k < 4; ++k) disk_corners[k] = T.layout_vertex[static_cast<std::size_t>(disk.corners[k])];

    // Merge: vertices new on this torus and its non-disk triangles are appended to the layout.
    std::vector<int> vmap(t.layout.points.size());
    for (std::size_t v = 0; v < vmap.size(); ++v) {
      if (v < T.layout_vertex.size()) {
        vmap[v] = T.layout_vertex[v];
      } else {
        vmap[v] = static_cast<int>(d.layout.points.size());
        d.layout.points.push_back(t.layout.points[v]);
      }
    }
    std::vector<int> tmap(t.layout.triangles.size());
    for (std::size_t k = 0; k < tmap.size(); ++k) {
      if (k < T.layout_triangle.size() && fill_set.count(T.layout_triangle[k])) {
        tmap[k] = -1 - T.layout_triangle[k];  // a disk triangle: resolved below, they come last
        continue;
      }
      const auto& tr = t.layout.triangles[k];
      tmap[k] = static_cast<int>(d.layout.triangles.size());
      d.layout.triangles.push_back({vmap[tr[0]], vmap[tr[1]], vmap[tr[2]]});
      d.layout.filled.push_back(0);
    }
    const int patch_offset = static_cast<int>(d.layout.patches.size());
    const int comp_offset = static_cast<int>(d.components.size());
    const int face_offset = static_cast<int>(d.layout.internal_faces.size());
    for (std::size_t p = 0; p < t.layout.patches.size(); ++p) {
      Patch P = t.layout.patches[p];
      bool has_disk = false;
      for (int& x : P.triangles) {
        has_disk |= tmap[x] < 0;
        x = tmap[x];
      }
      for (int& v : P.corners) v = vmap[v];
      for (auto& s : P.sides)
        for (int& v : s) v = vmap[v];
      if (has_disk) {
        for (int x : P.triangles)
          if (x >= 0) throw core::TopologyError("split: torus " + std::to_string(i) + "'s patch " + std::to_string(p) +
                                                " holds part of the disk where the tori meet and part of the surface; the disk must be a whole patch");
        if (disk_patch[i] >= 0) throw core::TopologyError("split: the disk where the tori meet spans several patches of torus " + std::to_string(i));
        disk_patch[i] = patch_offset + static_cast<int>(p);
      }
      d.layout.patches.push_back(std::move(P));
    }
    for (auto F : t.layout.internal_faces) {
      for (int& v : F.corners) v = vmap[v];
      for (auto& s : F.sides)
        for (int& v : s) v = vmap[v];
      for (int& v : F.loop) v = vmap[v];
      d.layout.internal_faces.push_back(std::move(F));
    }
    for (std::size_t c = 0; c < t.components.size(); ++c) {
      Component C = t.components[c];
      C.torus = static_cast<int>(d.tori.size());
      for (int& p : C.patches) {
        if (patch_offset + p == disk_patch[i]) disk_component[i] = comp_offset + static_cast<int>(c);
        p += patch_offset;
      }
      for (auto& F : C.faces) {
        for (int& p : F.patches) p += patch_offset;
        if (F.internal_face >= 0) F.internal_face += face_offset;
        for (int& v : F.corners) v = vmap[v];
      }
      d.components.push_back(std::move(C));
    }
    Torus R = t.tori.at(0);
    for (int& c : R.components) c += comp_offset;
    for (int& x : R.cross_sections) x += face_offset;
    d.tori.push_back(R);
    for (auto C : t.contacts) d.contacts.push_back({C.a + comp_offset, C.b + comp_offset, C.via, C.index + face_offset});
    for (auto l : t.cross_section_lines) {
      for (int& v : l) v = vmap[v];
      d.cross_section_lines.push_back(l);
    }
    for (auto l : t.longitude_lines) {
      for (int& v : l) v = vmap[v];
      d.longitude_lines.push_back(l);
    }
  }
  // The disk's triangles, once, at the end; patch references resolved.
  std::map<int, int> disk_index;
  for (int t : fill) {
    disk_index[t] = static_cast<int>(d.layout.triangles.size());
    d.layout.triangles.push_back(L.triangles[t]);
    d.layout.filled.push_back(1);
  }
  for (auto& P : d.layout.patches) {
    for (int& x : P.triangles)
      if (x < 0) x = disk_index.at(-1 - x);
    std::sort(P.triangles.begin(), P.triangles.end());
  }
  if (disk_patch[0] < 0 || disk_patch[1] < 0) throw std::logic_error("split: the waist disk is in no patch");
  d.contacts.push_back({disk_component[0], disk_component[1], "filled_patch", disk_patch[0]});
  d.quad_patches = static_cast<int>(d.layout.patches.size());
  return d;
}

}  // namespace volts::split::detail
