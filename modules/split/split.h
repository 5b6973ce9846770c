// volts::split — stage 2: decomposition of the surface into components that are topologically
// cubes or tori (Liu et al. 2013, §4.1; the torus/difference choice of §4.3, last paragraph).
//
// Cases handled (see docs/status.md for what is left):
// * box: a genus-0 surface whose sharp curves bound six quad patches like a cube is one cube (§4.1:
//   "for simple CAD models, we can directly use the feature curves");
// * torus: a genus-1 surface without sharp corners becomes a ring of `torus_cubes` cubes. Steps 1–3
//   of §4.1 give a first cross section (a level set of a height-like harmonic field between its two
//   saddles); two circle-valued harmonic fields then give the cross sections (level sets of the one
//   with period 1 around the ring) and the longitudinal lines (level sets of the one with period 1
//   around the tube — these close up, unlike traced gradient lines on a twisted torus). Closed sharp
//   curves that run around the ring are used as longitudinal lines;
// * difference: a genus-1 surface with sharp corners and difference curves (the rims of a through
//   hole) becomes a cube minus a virtual component: both rims are filled with new triangles
//   (flagged), the filled outer surface is the cube, the hole's walls plus the fills the virtual
//   component (a box, or a cylinder cut into a cube by four lines on its wall).
// Every cut is inserted into the mesh (edges split at crossings), so patches are exact unions of
// triangles. Anything else is a core::TopologyError that names what was found and the config key
// that steers it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "classify/classify.h"
#include "core/stage_file.h"

namespace volts::split {

/// split.genus2: auto's second try for the connector's ends when split.connector_cut cannot cut
/// the neck: near the holes (the rod's shank runs almost to its eyes).
constexpr double auto_connector_cut = 0.85;

/// Parameters of split().
struct Params {
  /// Points that get the min and max of the first harmonic field (§4.1 step 1), snapped to the
  /// nearest vertex. Empty: the extreme vertices along the principal axis of the surface [model units].
  std::vector<std::array<double, 3>> extreme_points;
  /// A plane (point, normal) whose section of the ring is the first cross section, instead of the
  /// harmonic field of steps 1–3. Empty: automatic [model units].
  std::vector<double> cross_section_plane;
  /// A point the first cross section of a torus passes through (the nearest vertex's level of the
  /// ring field; the others follow equally spaced). Empty: automatic [model units].
  std::vector<std::array<double, 3>> cross_section_point;
  int torus_cubes = 4;          ///< cube components per torus, along the ring [4, 16]
  std::string hole = "auto";    ///< a through hole becomes: "auto" (§4.3: difference if there are sharp corners), "torus" or "difference"
  /// A genus-2 surface becomes: "disk" (two tori meeting on the disk that fills their waist: not
  /// a conforming interface, the eight's hausdorff_rel is 0.09), "connector" (two tori and a cube
  /// between them, the neck or shank, whose ends are whole faces of the tori; Liu et al. §6, the
  /// rod and the eight: conforming) or "auto" (connector at connector_cut; if split cannot cut
  /// the neck there, at auto_connector_cut (the rod: at 0.5 its rings' cross sections cross the
  /// shank's sharp curves twice); else disk, with a warning)
  std::string genus2 = "auto";
  /// connector: its ends lie this fraction of the way from the waist to the saddle at each hole
  /// (level sets of the first harmonic field) [0.05, 0.95]
  double connector_cut = 0.5;
  /// connector: where its ends lie — "level" (the level sets above) or "shoulder" (each end on
  /// the concave sharp curves of a shoulder between the cut and the waist, joined across the
  /// smooth sides; the rod's small end; where the shoulder's faces are lenses between a concave
  /// and a convex curve, the connector's end face is its disk and both lenses, which polycube maps
  /// as three strips and tmesh glues to the ring in part)
  std::string connector_end = "shoulder";
};

enum class ComponentType { cube, torus_cube, virtual_component };
const char* to_string(ComponentType type);

/// A quad patch: a disk of triangles bounded by four sides.
struct Patch {
  std::vector<int> triangles;               ///< ids into Layout::triangles
  std::array<int, 4> corners{};             ///< vertex ids, counter-clockwise seen from outside the solid
  std::array<std::vector<int>, 4> sides;    ///< side k: vertex chain from corners[k] to corners[(k+1)%4]
};

/// A face inside the solid (a cross section of a torus): a disk spanned by a loop on the surface.
struct InternalFace {
  std::array<int, 4> corners{};
  std::array<std::vector<int>, 4> sides;    ///< side k: chain from corners[k] to corners[(k+1)%4]
  std::vector<int> loop;                    ///< the whole loop (vertex ids)
};

/// One face of a component's cube: either surface patches that tile it or one internal face.
struct CubeFace {
  std::vector<int> patches;
  int internal_face = -1;
  std::array<int, 4> corners{};  ///< the cube face's corners (vertex ids)
};

/// One component: a region bounded like a cube by six faces.
struct Component {
  ComponentType type = ComponentType::cube;
  std::vector<int> patches;       ///< all surface patches bounding it (the union of its faces' patches)
  std::vector<CubeFace> faces;    ///< its six cube faces
  int torus = -1;                 ///< torus_cube: index of its torus; its place in the ring is its order there
};

/// A torus: its cube components in ring order and the internal faces between them
/// (cross_sections[k] lies between components[k] and components[k+1 mod n]).
struct Torus {
  std::vector<int> components;
  std::vector<int> cross_sections;
};

/// Two components that meet, and where.
struct Contact {
  int a = -1, b = -1;
  std::string via;     ///< "internal_face" (a cross section) or "filled_patch" (a hole's fill)
  int index = -1;      ///< the internal face or the shared patch
};

/// The segmented surface: the input surface with the cuts inserted (input vertices first, then
/// the new ones) plus the triangles that fill holes.
struct Layout {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<char> filled;                  ///< per triangle: 1 if it fills a hole (not on the input surface)
  std::vector<Patch> patches;
  std::vector<InternalFace> internal_faces;
};

struct Decomposition {
  std::vector<Component> components;
  std::vector<Torus> tori;
  std::vector<Contact> contacts;
  Layout layout;
  int quad_patches = 0;  ///< patches that are disks bounded by four sides (all of them when split succeeds)
  int genus = 0;
  std::string genus2;  ///< genus 2: what split built, "connector" or "disk" (report only, not in the stage file)
  int planar_fills = 0;  ///< cut openings filled in their planes: CGAL's hole filling crossed the surface there (report only)
  int critical_min = 0, critical_max = 0, critical_saddle = 0;  ///< of the first harmonic field (0 if none)
  // For ParaView: per layout vertex, the harmonic fields (empty if not computed), and the cuts.
  std::vector<double> field, ring_field, tube_field;
  std::vector<std::vector<int>> cross_section_lines, longitude_lines;
};

/// Decomposes a classified surface. Throws core::TopologyError naming what was found (genus,
/// patches, corners) and the key to set when the surface is not one the implemented cases cover,
/// core::ConfigError for parameters out of range.
Decomposition split(const surface::Mesh& mesh, const classify::Classification& c, const Params& params);

/// Number of corners on the boundary of each classify patch (a quad patch has 4).
std::vector<int> patch_corner_counts(const classify::Classification& c);

/// The layout's triangles as a surface mesh (fill triangles excluded unless `with_filled`).
surface::Mesh layout_mesh(const Layout& layout, bool with_filled);

core::Json to_json(const Decomposition& d);
Decomposition from_json(const core::Json& j, const std::string& file);
/// Report keys: genus, critical_points {min, max, saddle}, components [{type, faces, patches}],
/// tori, quad_patches.
core::Json report_figures(const Decomposition& d);

/// ParaView view: the layout's triangles with patch_id, component_id and filled per cell, the
/// harmonic fields per point, and the cuts (cross sections, longitudes) and patch sides as lines.
void write_vtp(const std::string& path, const Decomposition& d);

}  // namespace volts::split
