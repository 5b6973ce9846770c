// volts::split — quad layouts on a triangle surface: cut curves given as sets of mesh edges, the
// patches they bound, their corners and sides (Liu et al. 2013, §4.1: the patches that become
// polycube faces). Internal to the split module.
#pragma once

#include <array>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "split/split.h"
#include "surface/surface.h"

namespace volts::split::detail {

/// An undirected mesh edge as (smaller vertex, larger vertex).
using Edge = std::pair<int, int>;
inline Edge edge(int a, int b) { return a < b ? Edge{a, b} : Edge{b, a}; }

/// Cut edges labelled by the curve they belong to (a curve id >= 0).
using LabelledEdges = std::map<Edge, int>;

/// Keeps labelled edges valid while isoline insertion splits edges: (a, b, v) replaces a–b by a–v, v–b.
void apply_splits(LabelledEdges& edges, const std::vector<std::array<int, 3>>& splits);
void apply_splits(std::set<Edge>& edges, const std::vector<std::array<int, 3>>& splits);

/// The edges a vertex loop runs along.
void add_loop(LabelledEdges& edges, const std::vector<int>& loop, int label, bool closed = true);

/// Chains a set of edges in which every vertex has degree 2 into closed loops (deterministic
/// order: by smallest vertex). Throws core::TopologyError naming a vertex of another degree.
std::vector<std::vector<int>> chain_loops(const std::set<Edge>& edges);

/// Sum of the circle differences of a periodic field (period 1) along a closed loop: its period
/// around that loop, rounded to an integer.
int loop_period(const std::vector<int>& loop, const std::vector<double>& field);

/// A face region bounded by cut edges, with its boundary loops (counter-clockwise seen from outside).
struct Region {
  std::vector<int> faces;
  std::vector<std::vector<int>> loops;
  int euler = 0;  ///< V - E + F of the region (1 for a disk)
};

/// Face regions of `mesh` bounded by `cuts`; face_region receives each face's region id.
std::vector<Region> regions(const surface::Mesh& mesh, const std::set<Edge>& cuts, std::vector<int>* face_region);

/// The quad patch of a region whose only boundary loop carries exactly four vertices with
/// is_corner set. Throws core::TopologyError "split: <what> <id> is not a quad patch (...)" otherwise.
Patch quad_patch(const Region& r, const std::vector<char>& is_corner, const std::string& what, int id);

/// Splits a closed loop at its corners into four sides starting at the corner with the smallest id
/// (InternalFace). Throws core::TopologyError unless exactly four loop vertices are corners.
InternalFace internal_face(const std::vector<int>& loop, const std::vector<char>& is_corner, int id);

/// Layout points and triangles of a mesh without removed elements (face index = triangle id).
void copy_mesh(const surface::Mesh& mesh, Layout& layout);

/// A closed surface made of some layout triangles (optionally reversed), with compact ids.
struct Submesh {
  surface::Mesh mesh;
  std::vector<int> layout_vertex;    ///< submesh vertex -> layout vertex
  std::vector<int> layout_triangle;  ///< submesh face -> layout triangle
};
/// Throws core::TopologyError if the triangles are not a manifold surface.
Submesh submesh(const Layout& layout, const std::vector<int>& triangles, const std::vector<char>& reversed);

/// The ids in `into` of the vertices of `part`, a decomposition of a submesh whose vertices map to
/// `layout_vertex`: those first ones keep their layout ids, the others (cuts inserted on the
/// submesh) are appended to into.points.
std::vector<int> merge_vertices(const Layout& part, const std::vector<int>& layout_vertex, Layout& into);

/// Maps the patch and component ids of a decomposition of a submesh to layout ids.
void map_ids(Decomposition& sub, const Submesh& s);

/// Fills the opening whose border halfedge is `border` in its plane: the rim projected onto its
/// least-squares plane must be a simple polygon at most `max_off_plane` of its diameter off that
/// plane. Its constrained Delaunay triangulation with interior points on a triangular lattice at
/// the rim's mean edge length, each at least half of that from the rim; no point is added on the
/// rim, so the fill conforms to the rim's edges. Interior points are lifted off the plane by a
/// harmonic interpolation of the rim's offsets. New vertices and faces are appended to the mesh.
/// Returns false, leaving the mesh as it was, if the rim is not such a loop.
bool fill_opening_in_plane(surface::Mesh& mesh, surface::Mesh::Halfedge_index border, double max_off_plane);

/// Fills every opening (border loop) of the submesh with triangles (CGAL's hole filling with
/// refinement; where that fill crosses the surface, every opening by fill_opening_in_plane
/// instead, and core::TopologyError if that is not possible or crosses it too), appends the new vertices and triangles to the layout (flagged filled) and to the
/// submesh's maps. Returns the new layout triangles. With `no_chords`, every fill edge joining two
/// vertices of an opening's rim that is not a rim edge is split at its midpoint (the fill is then
/// a disk that maps one-to-one onto a square with its rim on the sides, Floater 2003: a chord
/// between two points of one side would be flat).
/// How fill_openings fills: CGAL's hole filling (falling back to the planar fill where it
/// crosses the surface), or every opening in its plane.
enum class FillMethod { hole_filling, planar };
/// `planar`, if given, receives the number of openings filled in their planes.
std::vector<int> fill_openings(Submesh& s, Layout& layout, bool no_chords = false, FillMethod method = FillMethod::hole_filling,
                               int* planar = nullptr);

}  // namespace volts::split::detail
