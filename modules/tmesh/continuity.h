// volts::tmesh — C2 across the faces between blocks (Liu et al. 2013 §5.3; issue 8 item 1, first
// step). Each block is a clamped cubic tensor B-spline and blocks share their face points: C0 at
// every block face, a zero-parametric-length layer (repeated knots) on whole faces. The paper
// repeats knots only around irregular nodes and is C2 elsewhere. raise_continuity() makes a block
// face between two blocks of one level C2 across, away from the face's rim: per line of control
// points crossing the face, the two clamped extras next to it (Greville t - 1/3 and t + 1/3 in
// index space, one element = one knot interval) become rows of their neighbours (a T-junction-like
// TMesh::Constraint marked `smooth`), so the spline is the knot-removed one, t a simple knot.
// Lines within `margin` face points of the face's rim keep the repeated knots: at the block
// edges, where three (the pillow's corners) or five blocks meet, that is the template of C0
// around the irregular nodes. At regular edges (four blocks, 2 x 2; regular_edges, session 51)
// the 3 x 3 points around each edge point become rows too, the tensor product of the two
// directions' rows, so the spline is C2 up to the edge. docs/status.md "Session 39" has the plan. volts-tmesh (`tmesh.continuity: c2`, session 50) adds
// the rows to the net as it goes out (optimized and h-refined: one refined element of C0 at the
// inner rims), up to and on the surface (surface_layer, a surface point moving at most a tenth of
// epsilon_rel), fits each face's knot-interval ratio and bounds the moves (fit_ratio,
// max_move_rel below), then optimizes again (optimize_moved, optimize.h).
#pragma once

#include <array>
#include <limits>
#include <vector>

#include "tmesh/tmesh.h"

namespace volts::tmesh {

struct ContinuityParams {
  /// Lines of control points this close to a face's rim (in face points: 0 = on the rim, 1 = the
  /// clamped extra next to it) keep C0; below 2 the rows of two faces at an edge would name
  /// each other's extras [2, 100].
  int margin = 2;
  /// true: each constrained point moves onto its row (the spline is projected onto the C2 splines
  /// along the line); false: only lines where the points lie on their rows already (to 1e-9 of
  /// the net's extent) get them — the h-refined net of a spline that is C2 there.
  bool project = true;
  /// Optional: per block, per axis, the block's parameter length in the units the spline is C2 in
  /// (knot intervals across a face are its knot intervals times this). Empty: the number of its
  /// element spans, i.e. every element one unit — the net as laid out or h-refined. A net whose
  /// pillow layer was split further (Params::pillow_splits) is C2 in the units of its uniform
  /// refinement: its blocks' spans there before the split (refinement_splits()).
  std::vector<std::array<double, 3>> lengths;
  /// With `project`: per face, the ratio of the knot intervals on its two sides (A's scaled
  /// against B's, within [1/8, 8], golden-section search on its logarithm) that moves the
  /// extras least, so the C2 spline is the one nearest the net's (any positive ratio is a C2
  /// spline: the faces' parameters are glued by an affine map each, as the blocks' index spaces
  /// are). false: the ratio `lengths` gives (index space: 1).
  bool fit_ratio = false;
  /// With `project`: a line whose extra would move farther than this times its distance to the
  /// face point keeps C0 (a thin pillow slab's line projected across it folds its elements).
  /// Infinity: every line.
  double max_move_rel = std::numeric_limits<double>::infinity();
  /// Rims of a face on the surface keep no margin (where only the face's two blocks hold the rim;
  /// a third block around it makes it an irregular edge): the lines up to the surface are made C2 too,
  /// the lines in the surface itself moving surface control points (the boundary moves by at
  /// most their largest move: the basis is non-negative and sums to one). false: every rim keeps
  /// `margin` (C0 on the surface across block faces).
  bool surface_layer = false;
  /// With surface_layer and `project`: a line in the surface whose extra would move farther than
  /// this (a length) keeps C0 — a sharp edge along the rim would be rounded.
  double surface_move_max = std::numeric_limits<double>::infinity();
  /// Regular edges: where four blocks meet around an inner block edge (2 x 2, no surface), the
  /// 3 x 3 points around each edge point — C0 within one element of the edge otherwise — become
  /// rows too (the tensor product of the two faces' knot removals: C2 across both faces up to the
  /// edge), when the lines two points from the edge on all four faces are C2. The two faces on
  /// either side of the edge then share one knot-interval ratio (fit_ratio fits it over both;
  /// faces linked through edges form a sheet, fitted as one). Edges of valence 3 or 5 (irregular
  /// nodes) keep the margin.
  bool regular_edges = false;
};

struct ContinuityResult {
  int faces = 0;        ///< block faces made C2 across (some lines)
  int lines = 0;        ///< lines of control points across them made C2
  int constrained = 0;  ///< control points that became rows (two per line)
  int faces_kept = 0;   ///< inner faces left C0: levels differ, T-junctions on them, or no line away from the rim
  double moved_max = 0;  ///< the largest distance a constrained point moved (projection)
  int lines_kept = 0;    ///< lines left C0 by max_move_rel or surface_move_max
  int surface_lines = 0; ///< lines in the surface among `lines` (surface_layer)
  int edge_points = 0;   ///< points of regular edges made C2 around (regular_edges): 8 rows each
};

/// A block face two blocks share (the same four corner ids): face `fa` (2·axis + side) of block
/// `a` is face `fb` of block `b`.
struct SharedFace {
  int a = 0, fa = 0, b = 0, fb = 0;
};

/// The inner faces (not on the surface) that exactly two blocks share, in the order of their
/// sorted corner ids. Blocks need function_ids (core::InvalidInputError otherwise).
std::vector<SharedFace> shared_faces(const std::vector<TMesh>& blocks);

/// Adds the smooth rows to `blocks` (TMesh::constraints, `smooth` true) and moves each constrained
/// control point onto its row (the spline near the face changes: it is projected onto the C2
/// splines along each line). Blocks need function_ids; degree 3 only.
/// Throws core::ConfigError for another degree, margin out of range or a negative (or NaN)
/// max_move_rel or surface_move_max, core::InvalidInputError
/// for blocks without function_ids or `lengths` not one positive triple per block.
ContinuityResult raise_continuity(std::vector<TMesh>& blocks, const ContinuityParams& params = {});

/// Writes the smooth rows in the B-spline basis of the C2 spline. Per line across a face made C2,
/// the knot removal's rows give the two extras in terms of the points two in on either side (TA,
/// TB) and the face point F — as functions, combinations of the C2 spline's B-splines with
/// negative weights. Here the extras and F become rows of TA, TB and a new node V (a free node,
/// TMesh::free_nodes; its function is the B-spline centred on the face): XA = a TA + (1-a) V,
/// F = b TA + c V + d TB, XB = (1-e) V + e TB, all weights in [0, 1] (unit intervals: 1/3, 2/3;
/// 1/6, 2/3, 1/6), derived from the stored rows alone (no knots needed). Every block control
/// point stays where it is (the same spline); the global functions become non-negative. A line
/// whose rows are not of that form (a weight outside [0, 1] to 1e-9, its face point named by
/// another row) keeps its rows. Around a regular edge point (ContinuityParams::regular_edges) the
/// 3 x 3 points become rows of the tensor product of the four lines' bases: the edge point's new
/// free node W and the lines' nodes (an edge whose four lines do not all convert keeps its rows,
/// and so do those lines). Returns the lines rewritten.
int smooth_rows_as_bsplines(std::vector<TMesh>& blocks);

}  // namespace volts::tmesh
