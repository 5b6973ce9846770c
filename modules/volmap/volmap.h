// volts::volmap — the volume map of the polycube stage (Liu et al. 2013, §4.3 volume map; §4.2 for
// the cube and torus primitives it maps onto): the solid bounded by a closed surface (virtual
// components filled in) is tetrahedralized with TetGen, mapped onto the polycube embedding by a
// volumetric harmonic map with the surface map as boundary condition, untangled where the harmonic
// map inverts tets, and inverted by point location: parameter point -> containing mapped tet ->
// physical point by barycentric interpolation (what the T-mesh stage does for every node, §5.1).
//
// The parameter domain is the region bounded by the surface triangles drawn at their parameter
// positions (a polycube if the surface map puts every triangle on one polycube face).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/stage_file.h"
#include "surface/surface.h"
#include "tetmesh/tetmesh.h"

namespace volts::volmap {

/// Parameters of harmonic_volume_map().
struct Params {
  /// Density and quality of the tet mesh; keep_boundary must stay true (the boundary condition is
  /// given per surface vertex).
  tetmesh::TetgenParams tetgen;
  /// Weights of the Laplacian: "cotangent" (P1 finite-element stiffness; reproduces affine maps
  /// exactly) or "uniform" (graph Laplacian).
  std::string laplacian = "cotangent";
  /// Bound on untangling sweeps (each sweep optimizes every free vertex near a bad tet once) [0, 100000];
  /// 0 = no untangling.
  int untangle_max_sweeps = 500;
  /// Untangling target: tets whose parameter volume is below this fraction of the mean parameter
  /// tet volume are improved [0, 1); 0 = only inverted and flat tets. 0 by default: the smoothing
  /// below lifts thin tets faster (1e-4 took the untangler to its sweep bound on the eight: 2.6 s
  /// against 1.0 s, the same worst tet after smoothing).
  double untangle_min_volume_rel = 0;
  /// Smoothing of a nearly degenerate map: if after untangling the min volume ratio (see
  /// VolumeMap::min_volume_ratio) is below smooth_below_ratio, every interior vertex in turn
  /// descends the foldover-free energy of Garanzha et al. 2021 of its tets (as a barrier: no tet
  /// reaches det J <= 0; Newton steps, the Hessian by differences of the gradient),
  /// smooth_sweeps times [0, 1].
  double smooth_below_ratio = 1e-3;
  int smooth_sweeps = 300;  ///< bound; it stops earlier when a sweep lowers the energy by < 1e-5 of it [0, 10000]; 0 = none
};

/// A tet mesh of the solid with a position in physical space and one in parameter space per point.
struct VolumeMap {
  int surface_vertices = 0;                ///< points [0, surface_vertices) are the surface vertices, same ids
  std::vector<Eigen::Vector3d> physical;   ///< tet mesh points in physical space
  std::vector<Eigen::Vector3d> parameter;  ///< their images in the polycube embedding
  std::vector<std::array<int, 4>> tets;    ///< positively oriented in physical space
  int split_edges = 0;    ///< interior edges joining two surface vertices, split at their midpoint
  int split_faces = 0;    ///< interior faces with three surface vertices, split at their centroid
  /// edges of tets still flat or inverted after untangling, collapsed (collapse_flat_tet_edges);
  /// optional in stage files written before it existed
  int collapsed_edges = 0;
  /// 2-3 and 3-2 flips around such tets (flip_flat_tets); optional in stage files written before it existed
  int flips = 0;
  int flipped_tets_before_untangling = 0;  ///< harmonic map: tets with parameter volume <= 0
  int flipped_tets = 0;   ///< after untangling; 0 means the map is one-to-one onto the parameter domain
  int untangle_sweeps = 0;                 ///< sweeps the untangling took
  int untangle_moves = 0;                  ///< vertex moves it made
  bool untangle_joint = false;             ///< the joint fallback (Garanzha et al. 2021) ran
  /// Why untangling stopped: "not_needed", "done" (no tet below the target), "sweep_bound"
  /// (untangle_max_sweeps reached) or "stalled" (12 sweeps without progress at the largest ring).
  /// Optional in stage files written before it existed.
  std::string untangle_stop = "not_needed";
  /// min over tets of (parameter volume / physical volume) / (total parameter / total physical
  /// volume): the smallest relative Jacobian of the map; 1 for an affine map, <= 0 iff a tet is flipped.
  double min_volume_ratio = 0;
  /// min_volume_ratio before smoothing (equal to it if the map was not smoothed); optional in stage
  /// files written before it existed
  double min_volume_ratio_before_smoothing = 0;
  /// Sweeps the smoothing took (0: not smoothed; Params::smooth_sweeps: it stopped at its bound);
  /// optional in stage files written before it existed.
  int smooth_sweeps = 0;
  double parameter_volume = 0;             ///< volume of the parameter domain
};

/// Tetrahedralizes the closed surface and maps it: surface vertex i (vertex index) ->
/// surface_parameter[i]; interior points by the harmonic (discrete Laplace) map with that Dirichlet
/// condition; then inverted and near-flat tets (parameter space) are untangled by local optimization
/// with the surface vertices fixed: each free vertex near a bad tet moves to maximize the minimum
/// signed volume of its one-ring (a linear program in its position, solved with NLopt SLSQP), in
/// sweeps until no tet is bad or untangle_max_sweeps. If tets stay inverted (a tangle that needs
/// several vertices to move together), the free vertices within 3 rings of them minimize the
/// foldover-free energy of Garanzha et al. 2021 jointly (NLopt L-BFGS, each vertex's variables
/// scaled by its stiffness; the best round is kept if the last is not positive), then sweeps resume.
/// Before mapping, interior edges and faces whose vertices are all on the surface are split: such a
/// chord would have to lie on or outside the boundary of a polycube, so no map could keep its tets
/// positive. While tets stay flat or inverted after untangling (at most 4 rounds),
/// collapse_flat_tet_edges() and flip_flat_tets() (repair.h) remove those they can and untangling
/// runs again.
/// Does not throw when untangling fails: flipped_tets > 0 says so (the caller decides).
/// Throws core::InvalidInputError if surface_parameter does not have one entry per surface vertex,
/// has a non-finite entry, or maps the surface onto a region of volume <= 0 (mirrored), and if the
/// mesh has removed vertices (garbage); core::ConfigError for parameters out of range;
/// what tetmesh::tetrahedralize throws.
VolumeMap harmonic_volume_map(const surface::Mesh& surface, const std::vector<std::array<double, 3>>& surface_parameter,
                              const Params& params);


/// Point location in parameter space: a CGAL AABB tree over the bounding boxes of the mapped tets,
/// then barycentric coordinates. Keeps its own copy of the map.
class Locator {
 public:
  /// snap_tolerance_rel: parameter points outside every tet by at most this × the diagonal of the
  /// parameter domain's bounding box snap to the nearest tet.
  explicit Locator(const VolumeMap& map, double snap_tolerance_rel = 1e-6);
  ~Locator();
  Locator(Locator&&) noexcept;
  Locator& operator=(Locator&&) noexcept;

  /// Physical point of the parameter point uvw (barycentric interpolation in containing_tet), or
  /// std::nullopt if uvw is farther than the snap tolerance from every tet.
  std::optional<std::array<double, 3>> physical(const std::array<double, 3>& uvw) const;

  /// The tet containing uvw: the lowest-index tet whose barycentric coordinates of uvw are all >=
  /// -1e-10 (so a point on a shared face always gets the same tet). If none, the nearest tet within
  /// the snap tolerance, with the coordinates of uvw clamped to it. -1 if none; `bary` (if given)
  /// receives the 4 coordinates (summing to 1).
  int containing_tet(const std::array<double, 3>& uvw, std::array<double, 4>* bary = nullptr) const;

  /// Every tet whose barycentric coordinates of uvw are all >= -bary_tolerance, in increasing order
  /// (for checks: exactly one for a point inside a one-to-one map, away from shared faces).
  std::vector<int> tets_containing(const std::array<double, 3>& uvw, double bary_tolerance) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Signed volume of tet t in parameter space (> 0 unless flipped).
double parameter_volume(const VolumeMap& map, int t);

/// ParaView views of the tet mesh: in physical space with the parameter position as point field
/// `uvw`, and in parameter space (the mapped tets) with `xyz`; both with the cell fields
/// `volume_ratio` (the relative Jacobian of min_volume_ratio) and `flipped` (0/1), and `component`
/// if given (one int per tet). Throws core::IoError if the file cannot be written,
/// core::InvalidInputError if `component` is neither empty nor one value per tet.
void write_vtu(const std::string& path, const VolumeMap& map, const std::vector<int>& component = {});
void write_parameter_vtu(const std::string& path, const VolumeMap& map, const std::vector<int>& component = {});
/// Several maps in one view each (the rings of a polycube): map i's points follow map i-1's, its
/// parameter positions are moved by offsets[i] (so mapped views do not overlap), its tets carry
/// the cell field `index_field` = i; volume_ratio is relative to each map's own totals. Throws
/// core::IoError, core::InvalidInputError if offsets has not one entry per map.
void write_vtu(const std::string& path, const std::vector<const VolumeMap*>& maps, const std::vector<std::array<double, 3>>& offsets,
               const std::string& index_field);
void write_parameter_vtu(const std::string& path, const std::vector<const VolumeMap*>& maps,
                         const std::vector<std::array<double, 3>>& offsets, const std::string& index_field);

/// The map in a stage file: points, tets and figures. from_json throws core::InvalidInputError naming
/// `file` and the key for missing or malformed members, wrong sizes, non-finite values and
/// out-of-range vertex ids.
core::Json to_json(const VolumeMap& map);
VolumeMap from_json(const core::Json& j, const std::string& file);
/// The figures for report.json (no arrays).
core::Json report_figures(const VolumeMap& map);

}  // namespace volts::volmap
