// volts::tmesh — optimization of the worst scaled Jacobian (Liu et al. 2013 §5.2, "each node is
// moved toward an optimal position that maximizes the worst Jacobian ... defined based on Bézier
// basis functions ... at the Gaussian integration points and the corner points").
//
// Two phases. First, joint rounds (the paper's BFGS step, on all nodes at once): the interior
// control points of the elements below the target move together by NLopt's CCSAQ (or L-BFGS,
// OptimizeParams::joint_method) on a smooth soft
// minimum of the sampled scaled Jacobians of every element they support, with its analytic
// gradient (sum factorization on the sample grids, then the transpose of the extraction). The
// worst figure is a minimum over many elements that share nodes: a per-node search stalls on a
// plateau of equally bad elements (the eight: 0.25), the joint step does not (0.50 at the target,
// 0.64 when run on). Elements not certified valid are sampled on a dense grid there, and where
// the certifier finds a fold that every sample misses (its witness point), or a step folds an
// element between its samples, the rounds sample around that point from then on
// (OptimizeResult::folds_between_samples).
//
// Then per-node sweeps: the elements below the target are visited worst first and their control
// points not yet moved in this sweep are optimized one at a time (a T-junction's point stands
// for the nodes of its row, which carry it along). Nodes are the spline's global
// functions (control points shared by blocks move together). Node types as in the paper's
// smoothing: nodes on the surface (on a block face marked boundary, which includes sharp corners
// and sharp-curve nodes) stay fixed, except that given the input surface (slide_surface.h) the
// joint rounds slide those with no sharp edge within their reach along it (two tangent
// coordinates each, projected back onto the surface at their offset from it before the step is
// checked): sharp corners and sharp-curve nodes stay where they are; interior nodes move freely within half the distance to their nearest net
// neighbour. Per node the objective is the minimum sampled scaled Jacobian of the Bézier elements
// it supports; it is a minimum (not smooth), so NLopt's derivative-free BOBYQA maximizes it. A
// move (or a joint round) is kept only if the worst scaled Jacobian of its elements rises and
// none of them loses its certified det J > 0 (bezier::certify), so optimization never makes the
// certified validity worse; with elements not certified valid among them, a joint round that
// raises the worst figure of the certified ones is kept too, no fold falling below its own figure
// (a fold no round fixes would otherwise hold the rest where it is); a round refused with folds
// among its elements runs once more without them in its objective (a fold no move raises holds
// the soft minimum, so that the other samples weigh nothing), kept by that rule. After each
// cycle the elements are checked on a denser grid
// (OptimizeParams::check_points): where the field dips between the samples, the element is sampled
// on that grid from then on. A trilinear pass follows (the paper's eq. (1)–(2) figure of the
// T-mesh elements, the hexes of their corner points): see OptimizeParams::trilinear_sweeps.
#pragma once

#include <string>
#include <vector>

#include "tmesh/slide_surface.h"
#include "tmesh/tmesh.h"

namespace volts::tmesh {

struct OptimizeParams {
  int sweeps = 4;             ///< bound on passes over the elements below `target` [0, 100]; 0 = no optimization at all
  double target = 0.5;        ///< elements whose sampled scaled Jacobian is below this are improved
  /// Stop early: once every element is certified valid, its worst sampled figure at least this
  /// and no element found to dip below it between the samples (check_points), the rounds, sweeps and cycles
  /// end there ("reached_stop_at"). The elements chosen and their objective stay the target's, so
  /// up to that point the run is the same as without it: a quicker end, lower than the target.
  /// 1 = off (run to the target) [0, 1].
  double stop_at = 1.0;
  double margin = 0.25;       ///< a node's search looks at its elements below target + margin (the move is checked on all)
  int gauss_points = 4;       ///< Gauss points per direction of the sample (plus the 8 corners); extract's figure uses degree + 1
  /// The sample's other points: a uniform grid of this many per direction, faces, edges and
  /// corners included (bezier::sample_jacobian); 2 = the corners alone, the paper's sample, which
  /// leaves the field free to sag between them (the generated torus: 0.507 sampled, 0.184 on a
  /// 16^3 grid; 5: 0.487) [2, 8].
  int grid_points = 5;
  int max_evaluations = 25;   ///< objective evaluations per node move
  /// Node optimizations per sweep, worst elements first: bounds the time on a poor map (a count,
  /// not seconds, so runs stay reproducible). The demo torus needs about 450 in its first sweep.
  int max_nodes_per_sweep = 1000;
  /// A sweep stalls if it makes too little progress: while elements are not certified valid, if
  /// it fixes fewer than max(1, `min_fixed_rel` × their count) of them (their sampled scaled
  /// Jacobian is meaningless then); once all are valid, if it raises the worst scaled Jacobian by
  /// less than `min_gain`. Optimization stops after `patience` stalled sweeps in a row. Late
  /// sweeps on a torus gain 3e-3–1e-2 each; on a poor map (the eight: 2,800 elements not valid,
  /// the washer: 1,750) every sweep moves ~750 nodes and fixes 0.5–2 % of them, which the bound
  /// on sweeps alone let run for 15 minutes.
  double min_gain = 1e-3;       ///< scaled Jacobian (dimensionless) [0, 1]
  double min_fixed_rel = 2e-2;  ///< fraction of the elements not certified valid [0, 1]
  int patience = 2;             ///< stalled sweeps in a row before stopping [1, 100]
  /// First, joint rounds: the interior nodes of the elements below `target` move
  /// together (joint_method) on a soft minimum of the sampled scaled Jacobian of all their elements,
  /// S = m − (1/β) log Σ exp(−β (SJ − m)), β = `joint_sharpness`. A round is kept only if it
  /// raises the worst figure of those elements or fixes elements not certified valid; where an
  /// element loses its certificate or falls below the worst figure, its nodes go back to where the
  /// round started (repeated until none does). Rounds stop when one neither fixes enough
  /// elements (`min_fixed_rel`) nor raises the worst figure enough (`min_gain`), or when every
  /// sample reaches `target`.
  int joint_rounds = 30;         ///< [0, 100]; 0 = per-node sweeps only
  /// Bound on objective and gradient evaluations per round [1, 100000]. A round gains most in its
  /// first 50-100 (the rod's: CCSAQ's trial points then wander at the same figure); the next round
  /// re-centres every node's box and restarts the method. The rod, 300 -> 100: tmesh 27.6 -> 13.2 s,
  /// worst 0.501 -> 0.500 (docs/status.md "Session 42").
  int joint_evaluations = 100;
  double joint_sharpness = 40;   ///< β, per unit of scaled Jacobian (0, 1000]
  /// The NLopt method of the joint rounds. `ccsaq`: Svanberg's conservative convex separable
  /// approximations with a quadratic penalty (LD_CCSAQ): each step solves a separable model that
  /// stays within the variables' bounds and is only taken once it is conservative, so a round
  /// does not stall on the soft minimum's kinks. `lbfgs`: limited-memory BFGS (LD_LBFGS, the
  /// paper's BFGS). Measured (session 40, every model all certified valid with either): the
  /// eight's one round 68 -> 38 evaluations (wall 1.8 -> 1.5 s, 0.506 -> 0.512), the rod 60.5 ->
  /// 33.9 s (0.483 -> 0.500, 7³ 0.461 -> 0.487), cinolib_torus 0.512 -> 0.556, the washer 0.511 ->
  /// 0.569; the rod family 250-350 0.478-0.496 in 26-45 s (lbfgs: 0.466-0.498, 56-75 s).
  enum class JointMethod { ccsaq, lbfgs };
  JointMethod joint_method = JointMethod::ccsaq;
  /// Elements not certified valid are sampled on a uniform grid of this many points per direction
  /// instead (a fold can lie between the Gauss points) [2, 32]
  int joint_dense_points = 9;
  /// When a round's step is refused while every element is certified valid, the rounds go on
  /// with the elements within `joint_window` of the worst figure only (a smaller problem, whose
  /// soft minimum is not swamped by the many elements just below the target), halving the
  /// window at each further refusal down to joint_window / 8; a narrowed round's β is at least
  /// 4 / window, so the window spans e^4 in the weights (at β = 40 a window of 0.0125 weighed its
  /// elements nearly alike and its rounds raised their mean, not the worst: the rod 0.398 ->
  /// 0.400). All elements below the target at once first, then narrowed: the connector eight
  /// 0.33 -> 0.39 (narrowed from the start: 0.31).
  /// 0 = the rounds stop at the first refusal [0, 1] (scaled Jacobian).
  double joint_window = 0.1;
  /// With a surface to slide on, when the joint rounds start sliding surface nodes:
  /// `stall`: the rounds first run with every surface node fixed and slide once they stop. Every
  ///   kept round raises the worst figure, so this never ends below the fixed rounds' result;
  ///   measured, it ends higher on the eight (0.445 against 0.378 sliding from the start), lower
  ///   on the rod (0.283 against 0.304: its first sliding round is swamped by the many elements
  ///   below the target).
  /// `start`: every round slides.
  /// `valid`: fixed rounds while elements are not certified valid, sliding from the round that
  ///   makes them all valid (from the start if all are): the fixed rounds' later gains (the rod:
  ///   0.0626 -> 0.0641 in two rounds of ~7 s) are what the first sliding round does at once.
  enum class SlideFrom { stall, start, valid };
  SlideFrom slide_from = SlideFrom::valid;
  /// With a surface to slide on and slide_from not `start`: if elements are left not certified
  /// valid, the whole optimization runs once more from the start with `start` (a different path:
  /// the sliding rounds untangle with the surface nodes free), and the better end is kept (fewer
  /// elements not certified valid, then the higher worst figure). Costs a second run only where
  /// the first left folds. Measured: the rod at joint_evaluations 200 left one fold with `valid`,
  /// none with `start` (docs/status.md "Session 43").
  bool fold_retry = true;
  /// With a surface to slide on: surface nodes on a sharp curve slide along it (one coordinate,
  /// projected back onto the curve at their offset from it) where no sharp corner is within their
  /// reach; false: every node on or next to a sharp curve stays. Off by default: measured on the
  /// rod (session 24), 0.304 -> 0.203 sliding from the start, 0.283 -> 0.284 from the stall.
  bool slide_sharp_curves = false;
  /// With a surface to slide on: a joint round's step puts back the sliding nodes of an element
  /// whose boundary faces end farther from the surface than this or than before the round,
  /// whichever is larger (sampled on `deviation_points`² points per face, i/(n−1); the distance is the
  /// one-sided boundary → surface one of extract's hausdorff_rel). Sliding nodes stay on the
  /// surface, but the spline's boundary between them moves: on the rod it crossed issue 8's 0.005
  /// of the diagonal (docs/status.md "Session 41"). A length, in the model's units; 0 = no bound.
  double max_boundary_deviation = 0;
  int deviation_points = 8;  ///< per direction of a boundary face [2, 64]
  /// With a surface to slide on: the per-node sweeps also move surface nodes that may slide
  /// (as in the joint rounds, but not along sharp curves), each in its tangent plane within its
  /// reach, the move projected back onto the surface at its offset before it is checked. Off in
  /// the tmesh stage (its figures were measured without); the tet route turns it on (its worst
  /// hexes lie at the surface, where interior moves cannot help).
  bool sweep_slide = false;
  /// Then the T-mesh elements as trilinear hexes (Liu et al. eq. (1)–(2): each Bézier element's
  /// 8 corner points, the spline at its corners) whose scaled Jacobian is below
  /// `trilinear_target`: at most `trilinear_sweeps` passes, worst first, each interior node of
  /// such an element moved where that raises the worst trilinear figure of its elements, keeps
  /// them all certified valid and no element's sampled Bézier figure below the worst one overall
  /// (the Bézier result stands; nodes of elements not certified valid are left to the Bézier
  /// pass; at most `max_nodes_per_sweep` nodes per pass). A curved element can be valid while the
  /// hex of its corners folds (the eight: Bézier worst 0.154, trilinear -0.12).
  /// Stops earlier when a pass moves nothing or no element is below the target. Measured on the
  /// rod (session 26): −0.063, −0.033, −0.018 after 3 passes, −0.013 after 20 (10–20 nodes moved
  /// in each): the rest is held by nodes the pass may not move.
  int trilinear_sweeps = 3;        ///< [0, 100]
  /// Corner hexes in the Bézier passes, once every element is certified valid: the joint rounds
  /// raise those below `trilinear_target` too (in the soft minimum a corner figure t counts as
  /// target + 10 (t − trilinear_target), so a fold weighs like a Bézier figure ten times as far
  /// below the target: with targets 0.5 / 0.05 the corner hexes balance near +0.04 where the
  /// Bézier worst does at 0.4), and no move of the joint rounds or sweeps folds the corner hex of
  /// a certified-valid element that is not folded. A trade, positive corner hexes first. The rod
  /// (session 28, stage defaults): Bézier 0.4004 with corner hexes +0.051 on, 0.4002 with −0.128
  /// off (the trilinear pass after it may not lower a Bézier figure below the worst, so it cannot
  /// unfold them); the other models of the benchmark are unchanged. On the twisted test cubes
  /// (target 0.95, tests/tmesh/optimize_test.cpp) it ends lower on the three most folded starts
  /// (strongest twist: Bézier 0.24 against 0.95, corner hexes −0.64 against 0.93): folds weighed
  /// ten times swamp the objective there. Off in the library (the fit route's repair); the tmesh
  /// stage turns it on (tmesh.trilinear_guard).
  bool trilinear_guard = false;
  double trilinear_target = 0.05;  ///< scaled Jacobian (dimensionless) [-1, 1]
  /// The joint rounds and the per-node sweeps alternate: once the sweeps stop, the joint rounds
  /// (sliding, given a surface) run again from where the sweeps left the nodes, then the sweeps,
  /// up to `cycles` times (the trilinear pass once at the end). The joint rounds stall where the
  /// worst element's nodes must go back; the single-node moves change that balance, so the next
  /// rounds can move on. Stops early after a cycle that fixes no element and raises the worst
  /// figure by less than `min_gain`, or when no element is below the target. Measured on the rod
  /// (docs/status.md, session 26): 0.351 with one cycle, 0.387 with two, 0.399 with five. [1, 100]
  int cycles = 1;
  /// After each cycle every certified-valid element is sampled on a uniform grid of
  /// `check_points` per direction: one whose figure there is below the target and below its
  /// usual sample's by more than `check_tolerance` (the field dips between the samples) is sampled
  /// on that grid (and its Gauss points) from then on, and the cycles go on. 13 points is what
  /// extract's 7^3 figure sees of an element optimized one level coarser (tmesh.h_refine 1). The
  /// rod (session 34): its field dipped to 0.08-0.12 between the samples of 0.48. 0 = no check
  /// [0 or 2..32]. A tolerance of 0.05 (until session 43) left the rod, the plate and the eight at
  /// 0.474-0.486 on extract's 7³ grid under sampled figures of 0.50; 0.01: 0.499-0.504, about the
  /// same time (docs/status.md "Session 43").
  int check_points = 13;
  double check_tolerance = 0.01;  ///< scaled Jacobian (dimensionless) [0, 1]
  /// A cycle that fixes no element stops the cycles if it raised the worst figure by less than
  /// this (scaled Jacobian, [0, 1]). Smaller than `min_gain`: a late cycle costs a few seconds
  /// and its narrowed rounds gain 1e-4–1e-3 (the rod, session 28: 0.3984 -> 0.3992 in cycle 4).
  double cycle_min_gain = 1e-4;
};

struct OptimizeResult {
  double min_before = 0, min_after = 0;     ///< worst sampled scaled Jacobian of the Bézier elements (Gauss points and the grid_points grid)
  /// The worst on each element's own sample: the check grid's too where the field dipped
  /// (OptimizeParams::check_points); at most min_after.
  double min_after_checked = 0;
  int invalid_before = 0, invalid_after = 0;  ///< elements not certified valid
  int nodes_moved = 0;
  int sweeps = 0;                           ///< sweeps run, over all cycles (a cycle stops early when a sweep moves nothing)
  int sweeps_cut_at_node_bound = 0;         ///< sweeps that stopped at `max_nodes_per_sweep`
  /// Why it stopped: "no_element_below_target", "reached_stop_at", "no_move" (a sweep moved nothing), "stalled" (`patience`
  /// sweeps in a row made too little progress, see min_gain), "disabled" (0 sweeps), "sweep_bound" (`sweeps` ran
  /// out while moves still helped; logged as a warning) or "cycle_bound" (the last cycle's check found
  /// elements that dip between the samples, check_points; a warning too).
  std::string stop_reason;
  double trilinear_before = 0, trilinear_after = 0;  ///< worst scaled Jacobian of the trilinear T-mesh elements around that phase
  int trilinear_nodes_moved = 0;
  int joint_rounds = 0;  ///< joint rounds kept
  int cycles = 0;        ///< cycles of joint rounds and sweeps run (OptimizeParams::cycles)
  /// 0, or the earlier cycle whose end's nodes were kept: the best end once its dips were put on
  /// the check grid (fewest not certified valid, then the highest worst figure)
  int cycle_kept = 0;
  int elements_on_check_grid = 0;  ///< elements sampled on the check grid once their field dipped (OptimizeParams::check_points)
  /// Folds between the samples: points where the certifier found an element folded while its samples
  /// were positive (at a joint round's start, or made by a joint step and undone); the joint rounds
  /// sample around each from then on (at most 8 per element).
  int folds_between_samples = 0;
  /// Elements of the kept joint steps whose sliding nodes went back because their boundary faces
  /// would have ended past OptimizeParams::max_boundary_deviation (and farther than before).
  int deviation_put_back = 0;
  int surface_nodes_slid = 0;  ///< surface nodes the kept joint rounds (once per round) and sliding sweeps (per move) moved along the surface
  /// Per element (the T-mesh's order: block after block, i fastest; write_vtu's): its sampled
  /// scaled Jacobian before and after optimization, so a user sees where the start was poor.
  std::vector<double> element_before, element_after;
  /// OptimizeParams::fold_retry: whether the second run (slide_from `start`) ran, its figures, and
  /// whether its end was kept (else the first run's is).
  struct Retry {
    bool ran = false, kept = false;
    int invalid_after = 0;
    double min_after = 0;
    double seconds = 0;
  } retry;
};

/// Moves interior control points of `blocks` (in place, shared ids together) to raise the worst
/// scaled Jacobian of the Bézier elements; with `surface`, the joint rounds also slide surface
/// control points along it where no sharp edge is within their reach (nullptr: surface control
/// points stay fixed). Throws core::ConfigError for parameters out of range.
OptimizeResult optimize(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface = nullptr);

/// optimize() on a net that moved locally since it was optimized (volts-tmesh: the C2 rows
/// projected onto the h-refined net, continuity.h). `settled` is the same net before the move
/// (same blocks and knots): its elements whose Bézier points the move left as they were count as
/// checked between their samples, so the check grid (check_points) looks only at the elements
/// the move or the rounds touched. Throws core::InvalidInputError when `settled`'s blocks do not
/// have the net's control point counts, core::ConfigError as optimize.
OptimizeResult optimize_moved(std::vector<TMesh>& blocks, const std::vector<TMesh>& settled, const OptimizeParams& params, const SlideSurface* surface = nullptr);

/// Repairs the folds `optimize` left: joint rounds on the nodes of the elements not certified
/// valid and of two rings of their neighbours, until every element is certified valid or a
/// round fixes none. No element certified valid loses its certificate or falls below the worst
/// figure of the valid ones at the start; the rest of the net is not optimized further. Meant
/// for the h-refined net, where each optimized element has 8 (or 64) of its own with their own
/// control points (volts-tmesh runs it there when folds are left).
/// stop_reason: "all_valid" or "stalled". Throws core::ConfigError as optimize.
OptimizeResult repair_folds(std::vector<TMesh>& blocks, const OptimizeParams& params, const SlideSurface* surface = nullptr);

}  // namespace volts::tmesh
