// volts::tmesh — stage 4: the T-mesh, i.e. the control mesh of the volumetric spline (Liu et al.
// 2013, §5.1–5.2).
//
// Implemented so far: a uniform octree level per cube, pillowing (pillow.h), one clamped B-spline per
// block whose control points make it interpolate the polycube volume map at its Greville points
// (so the boundary rows interpolate the surface map: the spline boundary is on the input surface
// to the interpolation error), shared control points across block faces, and optimization of the
// worst Jacobian (optimize.h; surface nodes slide along the input surface, slide_surface.h).
// Adaptivity per cube (§5.1, coarser than the paper's per element): a cube goes one octree
// level finer (every element of its blocks split in eight) while its boundary deviates from the
// input surface by more than ε, with 2:1 balance between cubes; where levels differ across a
// block face the finer side's control points there are T-junctions, the knot-insertion
// combinations of the coarser side's (TMesh::constraints), so the spline is C0 there and its
// basis a partition of unity. Per element (Params::refine "spans"): the spans along the surface of
// each deviating element face are halved by knot insertion and the halving runs on across block
// faces as whole knot planes — the slab rule under which an octree T-spline is analysis-suitable
// (tspline/suitable.h), so no T-junction. A per-leaf octree T-spline inside a cube
// (modules/octree, modules/tspline) is not wired; sharp curves inside a face become block faces
// only on tori (polycube.sharp_lines, off by default).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/stage_file.h"

namespace volts::tmesh {

/// Parameters of build().
struct Params {
  int level = 3;   ///< uniform octree level: 2^level elements along each cube edge, plus the pillow layers [1, 7]
  int degree = 3;  ///< spline degree in each direction [1, 5]
  int pillow_layers = 1;    ///< element layers of the pillow under the surface (§5.2); 0 = none [0, 4]
  /// Bound on sweeps of per-node worst-Jacobian optimization (§5.2); it stops earlier when no element
  /// is below 0.5, a sweep moves nothing, or two sweeps in a row stall (OptimizeParams); 0 = none [0, 100].
  int optimize_sweeps = 40;
  /// The optimization stops once every element is certified valid with its worst sampled scaled
  /// Jacobian at least this and none dips below it between the samples (OptimizeParams::stop_at); 1 = off [0, 1].
  double stop_at = 1.0;
  /// Joint L-BFGS rounds before the per-node sweeps, their bound on evaluations each, the
  /// sharpness of their soft minimum and the window they narrow to after a refused step
  /// (OptimizeParams::joint_rounds / joint_evaluations / joint_sharpness / joint_window)
  /// [0, 100] / [1, 100000] / (0, 1000] per unit of scaled Jacobian / [0, 1] scaled Jacobian.
  int joint_rounds = 30;
  /// Cycles of joint rounds and per-node sweeps (OptimizeParams::cycles) [1, 100].
  int optimize_cycles = 10;
  /// Bound on passes of the trilinear pass after the Bézier optimization
  /// (OptimizeParams::trilinear_sweeps) [0, 100]; 0 = none.
  int trilinear_sweeps = 3;
  /// The Bézier passes also look after the corner hexes once every element is certified valid
  /// (OptimizeParams::trilinear_guard).
  bool trilinear_guard = true;
  int joint_evaluations = 100;
  /// Points per direction of the uniform grid (faces, edges, corners) the optimizer samples the
  /// scaled Jacobian at besides its Gauss points (OptimizeParams::grid_points); 2 = the corners
  /// alone (the paper's sample) [2, 8].
  int grid_points = 5;
  /// After each cycle, elements whose field dips between the samples (below them by more than
  /// check_tolerance, and below the target) on a uniform grid of check_points per direction are
  /// sampled on it from then on (OptimizeParams::check_points / check_tolerance) [0 or 2..32] /
  /// [0, 1] scaled Jacobian; 0 = no check.
  int check_points = 13;
  double check_tolerance = 0.01;
  double joint_sharpness = 40;
  double joint_window = 0.1;
  /// The joint rounds' NLopt method: "ccsaq" or "lbfgs" (OptimizeParams::joint_method).
  std::string joint_method = "ccsaq";
  /// The joint rounds slide surface nodes along the input surface where no sharp edge is within
  /// their reach (optimize(); Liu et al. §5.2 "surface nodes on the surface"); false = fixed.
  bool slide_surface = true;
  /// When they start sliding: "stall" (once the rounds with fixed surface nodes stop), "start" or
  /// "valid" (once every element is certified valid) (OptimizeParams::slide_from).
  std::string slide_from = "valid";
  /// Elements left not certified valid: optimize again from the start with slide_from "start"
  /// and keep the better end (OptimizeParams::fold_retry).
  bool fold_retry = true;
  /// Continuity across the faces between blocks: "c0" (every block face a zero-parametric-length
  /// layer), "c2" (raise_continuity(), continuity.h, on the optimized and h-refined net: C2
  /// across the faces between blocks of one level and up to the edges where four blocks meet —
  /// C0 stays within two control points of the others, the template around irregular nodes — then optimized
  /// again by volts-tmesh and written in the B-spline basis, smooth_rows_as_bsplines; cubic only)
  /// or "auto": c2 for cubics, c0 otherwise (continuity_mode()).
  std::string continuity = "auto";
  /// Surface nodes on sharp curves slide along them too, away from sharp corners
  /// (OptimizeParams::slide_sharp_curves).
  bool slide_sharp_curves = false;
  /// A connector's lensed end (the rod's shoulder) gets its lens slabs pillowed within the end
  /// face's plane (pillow.h rim_pillow): the face's corners sit where its outline is smooth.
  bool rim_pillow_lenses = true;
  /// The pillow's thickness in a connector's complex of rings and a cube (complex.h
  /// physical_pillow): "physical" (one thickness in the solid along every axis) or "parametric"
  /// (one thickness in every cube's parameters, as before session 25).
  std::string pillow_thickness = "physical";
  /// Adaptive levels (Liu et al. §5.1): a block on the surface goes one level finer while its
  /// boundary faces deviate from the input surface by more than `epsilon_rel` × the surface's
  /// bounding-box diagonal (sampled as `deviation_samples` says, before optimization), up to
  /// `max_level` and while a level lowers its deviation by a fifth at least (Levels::stop);
  /// blocks that share a point differ by at most one level (2:1). 0 = every block at `level`
  /// [0, 1] (dimensionless).
  double epsilon_rel = 0.005;
  /// Points per direction on each boundary element face of the output T-mesh (after h_refine)
  /// where the adaptive levels measure the deviation, corners included: 8 is extract's
  /// hausdorff_rel grid (extract.boundary_samples), so a level within epsilon_rel here is within it
  /// there before optimization (3, corners and midpoints, missed the rod's 0.0057 at 0.0050) [2, 64].
  int deviation_samples = 8;
  /// The finest level adaptivity may reach; at or below `level` there is no refinement [1, 7].
  int max_level = 4;
  /// What adaptivity refines: "boundary" (the blocks with a face on the surface — the pillow
  /// slabs, the boundary elements of §5.1 — each by its own deviation, with the surface blocks of
  /// its cube that share an edge with it, the others only as 2:1 asks), "cube" (every block of
  /// a cube one level, its finest) or "spans" (per element: the two spans along the surface of
  /// each element face that deviates are halved, and every span tied to them across block faces,
  /// each knot a whole knot plane — no T-junctions, analysis-suitable by the slab rule; adjacent
  /// spans at most 2:1; max_level bounds the halvings at max_level − level).
  std::string refine = "boundary";
  /// h-refinement after optimization (h_refine()): every element split in eight this many times
  /// by knot insertion — the same spline (geometry, Jacobian, validity) on 8^h_refine times the
  /// elements and more functions [0, 3]. build() and h_refine() take `level` as the level to
  /// build at; volts-tmesh builds and optimizes at tmesh.level - h_refine (at least 1) and
  /// refines to tmesh.level (optimizing the coarse spline sees its field between the fine
  /// samples: session 32, docs/status.md).
  int h_refine = 1;
  /// Boundary-layer refinement: h_refine() also splits every element of the pillow layer in this
  /// many across the surface by knot insertion — the same spline on thinner elements along it.
  /// The layer is the pillow slabs' elements across their surface face, followed across block
  /// faces wherever it runs on (refinement_splits()). Needs a pillow (pillow_layers >= 1) [1, 8];
  /// 1 = none. build() ignores it: the optimizer sees the unsplit net.
  int pillow_splits = 1;
};

/// The continuity Params::continuity asks for: "c0" or "c2" ("auto" is c2 for cubics, whose C2
/// rows continuity.h writes, and c0 for every other degree).
inline std::string continuity_mode(const Params& p) { return p.continuity != "auto" ? p.continuity : p.degree == 3 ? "c2" : "c0"; }

using Vec3 = std::array<double, 3>;

/// One block of the control mesh: a clamped tensor-product B-spline over a hexahedral region of one
/// cube's parameter domain [0,1]^3. Without pillowing a cube is one block; pillowing (§5.2) makes
/// it a core box plus one slab per boundary face (see pillow.h). Blocks sharing a face have the
/// same control points there (same `function_ids`), so the spline is C0 across block faces and C2
/// inside a block (the repeated knots of the paper's zero-length edges, on whole block faces).
struct TMesh {
  int level = 0;   ///< octree level of the cube (2^level elements per direction of the core)
  int degree = 3;
  std::array<std::vector<double>, 3> knots;            ///< clamped knot vectors on [0,1]
  std::array<int, 3> size{0, 0, 0};                    ///< control points per direction
  std::vector<std::array<double, 3>> control_points;   ///< index i + size0*(j + size1*k)
  std::vector<std::array<double, 3>> parameters;       ///< Greville point of each control point (block parameters)
  /// Per block face 2*axis + side: 1 if it lies on the input surface.
  std::array<int, 6> boundary{1, 1, 1, 1, 1, 1};
  int component = 0;                                   ///< the split component (cube) it belongs to
  /// The block's corners in its cube's parameters (index a + 2b + 4c); block parameters map to
  /// cube parameters trilinearly. Default: the whole cube.
  std::array<Vec3, 8> corners{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
  std::string kind = "cube";                           ///< "cube" (not pillowed), "core" or "pillow"
  /// Global node id of each control point. Blocks (tensor patches) that share a face
  /// have identical control points there and give them the same id, so the spline is C0 across
  /// the face. Empty: ids are numbered block after block (no sharing).
  std::vector<int> function_ids;
  /// A T-junction: control point `point` of a block whose level is finer than its neighbour's
  /// across a block face carries no function of its own; it is sum_k weights[k] × the control
  /// point of node ids[k] (the knot-insertion refinement of the coarser face, so both sides are
  /// one surface there). ids are nodes without a constraint; weights sum to one.
  struct Constraint {
    int point = 0;
    std::vector<int> ids;
    std::vector<double> weights;
    /// A smooth row (continuity.h): a clamped extra next to a face made C2 across, not a
    /// T-junction (its weights need not be positive; stage file key "smooth").
    bool smooth = false;
  };
  std::vector<Constraint> constraints;  ///< ascending `point`; empty without T-junctions
  /// Nodes that this block's constraint rows name and no block holds as a control point: the
  /// B-splines centred on the faces made C2 across (continuity.h, smooth_rows_as_bsplines), each
  /// its id and control point (the same in every block that names it).
  struct FreeNode {
    int id = 0;
    Vec3 point{};
  };
  std::vector<FreeNode> free_nodes;  ///< ascending id; empty but with tmesh.continuity c2
  int elements() const;  ///< product of the knot spans in the three directions
};

/// A block of a cube (pillow.h): corners in cube parameters (index a + 2b + 4c), elements per
/// direction, per block face 2*axis + side whether it lies on the surface, and whether it is a pillow slab.
struct Block {
  std::array<Vec3, 8> corners;
  std::array<int, 3> elements{1, 1, 1};
  std::array<int, 6> boundary{0, 0, 0, 0, 0, 0};
  bool pillow = false;
};

/// A map from the unit cube's parameters to physical space.
using PointMap = std::function<Vec3(const Vec3&)>;

/// The polycube as the T-mesh sees it: its cubes, which of their faces lie on the surface, and
/// two maps of (cube, parameters in [0,1]^3): to physical space (the volume map) and to polycube
/// space (the embedding; equal points there are the same point of the solid, which is how blocks
/// of neighbouring cubes find their shared control points).
struct PolycubeMaps {
  std::vector<std::array<int, 6>> boundary;  ///< per cube, per face 2*axis + side: 1 on the surface
  /// Optional: the blocks of each cube given explicitly (difference_blocks); then `boundary` is not
  /// used and the cubes are these. Empty: each cube's blocks are cube_blocks of its `boundary`.
  std::vector<std::vector<Block>> blocks;
  std::function<Vec3(int, const Vec3&)> physical;
  std::function<Vec3(int, const Vec3&)> polycube;
  /// Optional, for adaptive levels (Params::epsilon_rel): distance of a point to the input
  /// surface, and the surface's bounding-box diagonal. Empty: every cube at Params::level.
  std::function<double(const Vec3&)> surface_distance;
  double diagonal = 0;
};

/// What build() chose: the level of each cube (maps' order; the finest of its blocks, each of
/// which has its own level, TMesh::level) and the sampled boundary deviation of the result
/// relative to the diagonal (0 without a surface_distance).
struct Levels {
  std::vector<int> level;
  int refined_blocks = 0;  ///< blocks finer than Params::level (refine "spans": blocks with a knot inserted)
  std::vector<double> cube_deviation_rel;  ///< per cube, relative to the diagonal (empty without a surface_distance)
  double deviation_rel = 0;
  int refinements = 0;  ///< rounds of refinement run (each raised some cube one level, or halved some spans)
  /// Params::refine "spans": knots inserted, summed over blocks and axes (0 otherwise).
  int knots_inserted = 0;
  /// Params::refine "spans": per block, per axis, its parameter length in elements as laid out
  /// (a halved span counts one half): the units ContinuityParams::lengths takes. Empty otherwise.
  std::vector<std::array<double, 3>> span_units;
  /// "within_epsilon", "max_level", "disabled", "no_gain" (a level did not lower a cube's
  /// deviation by a fifth: the input's faceting, not the spline; a round where no cube gained is
  /// undone) or "not_face_to_face" (a level would break conformity; the last conforming one kept)
  std::string stop;
};

/// Builds the control mesh of every cube: its blocks (pillowed if params.pillow_layers > 0), each
/// a B-spline interpolating the volume map at its Greville points; shared control points get one
/// id and one position. Throws core::ConfigError for parameters out of range and
/// core::NumericalError if the maps fail (a point outside the volume map).
std::vector<TMesh> build(const PolycubeMaps& maps, const Params& params, Levels* levels = nullptr);

/// The same with the level of every cube given (>= params.level; each of its blocks on the
/// surface has its elements split 2^(level - params.level) times along every axis, the others
/// one level less unless params.refine is "cube"; TMesh::level is the block's). Where a block face meets a
/// block of a coarser level, the finer face's control points become constraints (T-junctions).
/// Throws core::TopologyError if levels differ between blocks that do not meet face to face
/// (a finer point where a coarser block has one, left unconstrained), core::ConfigError for a
/// level out of range or a count of levels that is not the number of cubes.
std::vector<TMesh> build(const PolycubeMaps& maps, const Params& params, const std::vector<int>& levels);

/// h-refinement by knot insertion (Boehm; bezier::refinement_matrix): the spline of `coarse` —
/// blocks as build() made them from `maps` and `params`, control points moved since — with every
/// element split in eight `times` times, and the pillow slabs' elements split in
/// params.pillow_splits across the surface on top (refinement_splits()). Knots, node ids and
/// T-junction rows are build()'s at every block's level + times; control points are the
/// refinement of `coarse`'s, so the map, its Jacobian and its validity are unchanged. `parent`
/// (optional): per fine element (blocks in order, i fastest) the index of the coarse element
/// that holds it. Throws core::ConfigError for `times` outside [0, 3], a level above 7 or
/// pillow_splits out of range, core::InvalidInputError if `coarse` is not the block layout of
/// `maps`, core::TopologyError as refinement_splits() or if split blocks meet in part where the
/// other side lacks points (a crack refused), core::NumericalError if
/// its blocks disagree on a shared node or a T-junction is off its row (not C0).
std::vector<TMesh> h_refine(const PolycubeMaps& maps, const Params& params, const std::vector<TMesh>& coarse, int times,
                            std::vector<int>* parent = nullptr);

/// Per axis of a block, per element span along it: into how many elements h_refine() splits it.
using SpanSplits = std::array<std::vector<int>, 3>;

/// The splits h_refine(maps, params, coarse, times) makes, per block of `coarse`: 2^times per
/// span, times params.pillow_splits on the spans of the pillow layer — across the surface in the
/// pillow slabs (kind "pillow", surface faces on one axis), and on every span a block face ties to
/// one of those (across a face both sides split alike, a finer side's two spans as the coarser
/// side's one), so the layer runs on through whatever blocks it crosses (the pillow wrapping a
/// concave edge) and the refined blocks still meet face to face. Throws core::ConfigError for
/// `times` or params out of range, core::TopologyError if two blocks meet corner to corner with
/// span counts that do not nest.
std::vector<SpanSplits> refinement_splits(const PolycubeMaps& maps, const Params& params, const std::vector<TMesh>& coarse, int times);

/// Points per element direction of the T-mesh laid out at `params` (h_refine levels coarser than
/// its `level`) that give Params::deviation_samples per element once it is h-refined: extract's
/// hausdorff_rel grid at its default (i/(n−1) on each refined face).
int deviation_points(const Params& params);

/// Per cube (TMesh::component), the largest distance `distance` gives at the boundary faces of
/// its blocks, sampled on a uniform grid of `points` per direction on every element face, corners
/// included (`distance` is called from several threads); 0 for a cube without boundary faces.
/// Indexed by component (size: the largest component + 1). Throws core::ConfigError for points < 2.
std::vector<double> boundary_deviation(const std::vector<TMesh>& t, const std::function<double(const Vec3&)>& distance, int points = 8);

/// One block by interpolation of `map` (block parameters -> physical) at its Greville points.
TMesh build_block(const PointMap& map, int degree, const std::array<int, 3>& elements);

/// Builds the control mesh of one unpillowed cube by interpolating `map` at the Greville points.
TMesh build(const PointMap& map, const Params& params);

/// The three edge neighbours of each corner of a hexahedron in VTK order, right-handed: the
/// Jacobian at corner c has the columns x[n[c][e]] − x[c], e = 0, 1, 2.
const std::array<std::array<int, 3>, 8>& hex_corner_neighbours();

/// Scaled Jacobian of a trilinear hexahedron at its 8 corners (Liu et al. eq. (1)–(2)); corners in
/// VTK order. Returns the minimum.
double trilinear_min_scaled_jacobian(const std::array<std::array<double, 3>, 8>& x);

core::Json to_json(const TMesh& t);
TMesh from_json(const core::Json& j, const std::string& file);
/// Report keys: nodes (T-mesh nodes: functions and T-junctions), functions, t_junctions,
/// level_interface_nodes (NodeCounts::level_interface),
/// control_points, cubes, blocks, elements, min_level, max_level, irregular_nodes_surface,
/// irregular_nodes_interior, min_scaled_jacobian_before/after.
core::Json report_figures(const std::vector<TMesh>& t, double min_sj_before, double min_sj_after);

/// Node counts of the control mesh (nodes = functions + T-junctions): a surface node is irregular
/// if its number of neighbours on the surface is not 4 — only block corners can be, and their
/// valence is the number of surface block edges that leave them, whatever the levels —, an
/// interior node if its number of neighbours is not 6; T-junctions are neither; a node on a face
/// toward a finer level takes the links of its vertex point in the finer net (a T-junction whose
/// row weighs it by more than a half), else counts one neighbour more per direction across such
/// faces that it does not link.
struct NodeCounts {
  int nodes = 0, surface = 0, irregular_surface = 0, irregular_interior = 0, t_junctions = 0;
  int level_interface = 0;  ///< nodes named by T-junction rows (on faces toward a finer level)
};
NodeCounts count_nodes(const std::vector<TMesh>& t);

/// Minimum scaled Jacobian (eq. (1)–(2)) of the T-mesh elements of `t` as trilinear hexes: each
/// element's corners are the spline at its knot-grid corners (before optimization, the volume map
/// there, up to the interpolation error). The control net itself is not used: the control
/// polygon of a smooth map can be degenerate where the spline is not (u² has c1 = 0 at a clamped end).
/// With h_refine > 0, each element is first split in 2^h_refine per direction: the figure of
/// h_refine(…, t, h_refine) (knot insertion keeps the spline) up to rounding, without building it.
/// Throws core::ConfigError if h_refine is outside [0, 3].
double min_element_scaled_jacobian(const TMesh& t, int h_refine = 0);
/// The same with the element spans split as `splits` says (refinement_splits(): the figure of
/// h_refine() with pillow_splits). Throws core::ConfigError unless there is one count in [1, 64]
/// per span.
double min_element_scaled_jacobian(const TMesh& t, const SpanSplits& splits);

/// ParaView view: the T-mesh elements as trilinear hexes, with `scaled_jacobian`, `component`,
/// `block` and `pillow` per cell, plus the `extra` cell fields (name, one value per element in
/// the T-mesh's element order). Returns the minimum scaled Jacobian of these hexes. Throws
/// std::invalid_argument if an extra field does not have one value per element.
double write_vtu(const std::string& path, const std::vector<TMesh>& t,
                 const std::vector<std::pair<std::string, std::vector<double>>>& extra = {});

}  // namespace volts::tmesh
