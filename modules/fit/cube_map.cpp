#include "fit/cube_map.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/iterator.h>

#include "core/errors.h"
#include "core/log.h"
#include "split/split.h"

namespace volts::fit {

using Mesh = surface::Mesh;

bool box_like(const classify::Classification& c) {
  if (c.genus != 0 || c.patches != 6 || c.curves.size() != 12 || c.corners.size() != 8) return false;
  std::vector<int> curves(6, 0);
  for (const auto& k : c.curves) {
    if (k.closed || k.patch_left == k.patch_right || k.patch_left < 0 || k.patch_right < 0 || k.patch_left >= 6 || k.patch_right >= 6)
      return false;
    ++curves[k.patch_left], ++curves[k.patch_right];
  }
  const auto corners = split::patch_corner_counts(c);
  for (int p = 0; p < 6; ++p)
    if (curves[p] != 4 || corners[p] != 4) return false;
  return true;
}

classify::Classification classification_of(const Mesh& mesh, const SixPatches& s) {
  if (!s.layout.ok()) throw core::TopologyError("fit: the six patches are not cube-like: " + s.layout.problem);
  classify::Classification c;
  c.genus = 0;
  c.patches = 6;
  c.face_patch = s.label;
  c.corners.assign(s.corners.begin(), s.corners.end());
  std::sort(c.corners.begin(), c.corners.end());
  const auto label = [&](Mesh::Halfedge_index h) {
    const auto f = mesh.face(h);
    return f == Mesh::null_face() ? -1 : s.label[f.idx()];
  };
  const auto on_boundary = [&](Mesh::Halfedge_index h) { return label(h) != label(mesh.opposite(h)); };
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    if (!on_boundary(h)) continue;
    int a = static_cast<int>(mesh.source(h).idx()), b = static_cast<int>(mesh.target(h).idx());
    c.sharp_edge_vertices.push_back(std::min(a, b));
    c.sharp_edge_vertices.push_back(std::max(a, b));
  }
  // Curves: from every corner along each boundary edge to the next corner; each curve is found from
  // both ends, kept from the lower corner.
  const std::set<int> corner_set(c.corners.begin(), c.corners.end());
  for (const int v0 : c.corners) {
    const Mesh::Vertex_index vi(static_cast<Mesh::size_type>(v0));
    for (auto h0 : CGAL::halfedges_around_source(vi, mesh)) {
      if (!on_boundary(h0)) continue;
      classify::Curve k;
      k.vertices.push_back(v0);
      k.patch_left = label(h0), k.patch_right = label(mesh.opposite(h0));
      auto h = h0;
      for (std::size_t steps = 0; steps <= mesh.number_of_edges(); ++steps) {
        const int v = static_cast<int>(mesh.target(h).idx());
        k.vertices.push_back(v);
        if (corner_set.count(v)) break;
        // The next boundary edge out of v between the same two labels (exactly one on a cube-like layout).
        Mesh::Halfedge_index next = Mesh::null_halfedge();
        for (auto g : CGAL::halfedges_around_source(mesh.target(h), mesh))
          if (g != mesh.opposite(h) && on_boundary(g)) next = g;
        if (next == Mesh::null_halfedge()) throw core::TopologyError("fit: a patch boundary ends at vertex " + std::to_string(v));
        h = next;
      }
      if (!corner_set.count(k.vertices.back())) throw core::TopologyError("fit: a patch boundary does not reach a corner");
      if (k.vertices.back() > v0) c.curves.push_back(std::move(k));
    }
  }
  if (!box_like(c)) {
    std::ostringstream m;
    m << "fit: the six patches give " << c.curves.size() << " curves between " << c.corners.size() << " corners, not a cube's 12";
    throw core::TopologyError(m.str());
  }
  return c;
}

namespace {

// Signed volume enclosed by the surface at the positions `x` (one per vertex).
double enclosed_volume(const Mesh& mesh, const std::vector<std::array<double, 3>>& x) {
  double v = 0;
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (auto u : mesh.vertices_around_face(mesh.halfedge(f))) p[i++] = Eigen::Vector3d(x[u.idx()][0], x[u.idx()][1], x[u.idx()][2]);
    v += p[0].dot(p[1].cross(p[2])) / 6;
  }
  return v;
}

// A disk map with a convex boundary (arc length on the square's sides) puts flat every triangle
// between a side and an edge joining two of that side's vertices. So, on each patch: every interior
// edge with both ends on the patch's boundary (a chord) is split at its midpoint, then every
// triangle with its three vertices on the boundary at its centroid. The new vertices are interior
// to the patch; new faces keep their patch; the geometry is unchanged. Returns the number of splits.
int split_chords(Mesh& mesh, std::vector<int>& face_patch) {
  const auto patch = [&](Mesh::Halfedge_index h) { return face_patch[mesh.face(h).idx()]; };
  std::vector<char> on_boundary(mesh.number_of_vertices(), 0);
  for (auto h : mesh.halfedges())
    if (patch(h) != patch(mesh.opposite(h))) on_boundary[mesh.source(h).idx()] = on_boundary[mesh.target(h).idx()] = 1;
  const auto midpoint = [&](Mesh::Vertex_index a, Mesh::Vertex_index b) {
    return surface::Point((mesh.point(a).x() + mesh.point(b).x()) / 2, (mesh.point(a).y() + mesh.point(b).y()) / 2,
                          (mesh.point(a).z() + mesh.point(b).z()) / 2);
  };
  int splits = 0;
  std::vector<Mesh::Halfedge_index> chords;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    if (patch(h) == patch(mesh.opposite(h)) && on_boundary[mesh.source(h).idx()] && on_boundary[mesh.target(h).idx()]) chords.push_back(h);
  }
  for (auto h : chords) {
    const int p = patch(h);
    const surface::Point mid = midpoint(mesh.source(h), mesh.target(h));
    const auto hn = CGAL::Euler::split_edge(h, mesh);  // source(h) -> new vertex; h: new vertex -> target
    mesh.point(mesh.target(hn)) = mid;
    CGAL::Euler::split_face(hn, mesh.next(h), mesh);
    CGAL::Euler::split_face(mesh.opposite(h), mesh.next(mesh.opposite(hn)), mesh);
    face_patch.resize(mesh.number_of_faces(), p);
    on_boundary.resize(mesh.number_of_vertices(), 0);
    ++splits;
  }
  std::vector<Mesh::Face_index> flat;
  for (auto f : mesh.faces()) {
    bool all = true;
    for (auto v : mesh.vertices_around_face(mesh.halfedge(f))) all = all && on_boundary[v.idx()];
    if (all) flat.push_back(f);
  }
  for (auto f : flat) {
    const int p = face_patch[f.idx()];
    const auto h0 = mesh.halfedge(f);
    const auto a = mesh.source(h0), b = mesh.target(h0), c = mesh.target(mesh.next(h0));
    const surface::Point centre((mesh.point(a).x() + mesh.point(b).x() + mesh.point(c).x()) / 3,
                                (mesh.point(a).y() + mesh.point(b).y() + mesh.point(c).y()) / 3,
                                (mesh.point(a).z() + mesh.point(b).z() + mesh.point(c).z()) / 3);
    const auto h = CGAL::Euler::add_center_vertex(h0, mesh);
    mesh.point(mesh.target(h)) = centre;
    face_patch.resize(mesh.number_of_faces(), p);
    ++splits;
  }
  return splits;
}

}  // namespace

CubeMap map_to_cube(const Mesh& input, const classify::Classification& c, const CubeMapParams& params) {
  CubeMap m;
  m.mesh = input;
  const Mesh& mesh = m.mesh;
  if (box_like(c)) {
    m.patch_source = "classify";
    m.patches = c;
  } else {
    if (c.genus != 0)
      throw core::TopologyError("fit: the surface has genus " + std::to_string(c.genus) + "; the fit route needs a genus-0 surface (one cube)");
    m.patch_source = "segmentation";
    try {
      m.segmentation = six_patches(mesh, params.segmentation);
    } catch (const core::TopologyError& e) {
      throw core::TopologyError(std::string(e.what()) + " (classify found " + std::to_string(c.patches) + " patches, " +
                                std::to_string(c.curves.size()) + " curves and " + std::to_string(c.corners.size()) +
                                " corners: not six quad patches either)");
    }
    m.patches = classification_of(mesh, m.segmentation);
  }
  m.splits = split_chords(m.mesh, m.patches.face_patch);
  const split::Decomposition d = split::split(mesh, m.patches, split::Params{});
  polycube::Params pp;
  pp.weights = params.weights;
  m.surface = polycube::map_surface(mesh, m.patches, d, pp);
  if (m.surface.flipped_surface_triangles > 0 && pp.weights != "uniform") {
    // Mean-value weights can be negative on a non-convex patch; Tutte's are not (a convex boundary
    // then gives a one-to-one map, Floater 2003).
    core::log_warning("fit: " + std::to_string(m.surface.flipped_surface_triangles) + " surface triangles flipped with " + pp.weights +
                      " weights; mapping again with uniform (Tutte) weights");
    pp.weights = "uniform";
    m.surface = polycube::map_surface(mesh, m.patches, d, pp);
  }
  m.weights = pp.weights;
  core::log("patch maps (" + pp.weights + " weights): " + std::to_string(m.surface.flipped_surface_triangles) +
            " flipped triangles, largest angle distortion " + std::to_string(m.surface.max_angle_distortion_deg) + " degrees");
  if (m.surface.flipped_surface_triangles > 0)
    throw core::NumericalError("fit: " + std::to_string(m.surface.flipped_surface_triangles) + " surface triangles are flipped by the patch maps");
  std::vector<std::array<double, 3>> uvw = m.surface.vertex_uvw;
  if (enclosed_volume(mesh, uvw) < 0) {
    m.mirrored = true;
    for (auto& x : uvw) std::swap(x[0], x[1]);
    for (auto& x : m.surface.vertex_uvw) std::swap(x[0], x[1]);
  }
  volmap::Params vp;
  vp.tetgen.max_volume_rel = params.tet_max_volume_rel;
  vp.smooth_sweeps = params.smooth_sweeps;
  m.volume = volmap::harmonic_volume_map(mesh, uvw, vp);
  if (m.volume.flipped_tets > 0) {
    std::ostringstream s;
    s << "fit: the volume map onto the cube keeps " << m.volume.flipped_tets << " flipped tets (untangling stopped: " << m.volume.untangle_stop
      << "); the patch maps' largest angle distortion is " << m.surface.max_angle_distortion_deg
      << " degrees — a smaller fit.tet_max_volume_rel may help";
    throw core::NumericalError(s.str());
  }
  return m;
}

}  // namespace volts::fit
