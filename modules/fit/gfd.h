// volts::fit — geometric iterative fitting with feasible directions (GFD) of Lin, Huang & Hu 2018,
// "Geometric iterative fitting": the control points of the seven solids move, in the order
// boundary curves, boundary surfaces, solids, toward the volume map's points, each move kept
// inside the feasible region of the validity condition; then the smoothness across the solids'
// common faces is improved the same way (Proposition 4), then the fairness of each solid's net.
//
// A phase works on the curves (block edges), surfaces (block faces) or interiors of the solids.
// Each sweep moves every free control point of the phase toward a target: for curves and surfaces
// the least-squares fit of the map's points on it with the other control points held (so a
// feasible full step solves the phase at once), for the solids' interiors the progressive
// iterative approximation direction Δ_i = Σ_j N_i(t_j) r_j / Σ_j N_i(t_j) (LSPIA, Deng & Lin 2014;
// damped, it keeps interior nets smooth instead of chasing the piecewise-linear map). A move μΔ
// starts with μ = 1 and is halved until it lies in the feasible region of every solid holding
// the point:
// * a solid whose initial net satisfies Proposition 3: the sub-grids around the point still do
//   (the paper's region; Proposition 3 implies det J > 0, so the solid's curves and surfaces are
//   regular too and Propositions 1–2 are not imposed separately — Proposition 2 as printed also
//   rejects valid grids, validity.h);
// * a solid whose initial net fails it somewhere (it is only sufficient: on a distorted map most
//   sub-grids can fail while every element is valid): every Bézier element around the point that
//   is certified valid (bezier::certify, det J > 0 by Bernstein coefficients) stays so, and no
//   other element's certified lower bound of det J falls.
// Block corners (the cube's and Ω_c's vertices) stay where the map puts them.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fit/net.h"
#include "tmesh/tmesh.h"

namespace volts::fit {

struct GfdParams {
  int samples = 3;          ///< data points per knot span and free direction [1, 16]
  int sweeps = 30;          ///< bound on sweeps per fitting phase (curves, surfaces, solids) [0, 1000]
  double stop_rel = 1e-7;   ///< a phase stops when no point moves more than this × the bounding-box diagonal [0, 1)
  int halvings = 6;         ///< halvings of a move before it is refused [0, 30]
  int g1_sweeps = 20;       ///< sweeps of the smoothness improvement across common faces [0, 1000]
  /// Sweeps of the fairness improvement after G1: control points deep inside each solid (two rows
  /// or more from its faces) move toward the minimiser of the net's second differences [0, 1000]
  int fairness_sweeps = 10;
  /// Moves keep this margin [0, 1): Proposition 3's triple products of unit vectors stay above
  /// min(min_margin, half the solid's initial margin); a certified-valid element's lower bound of
  /// det J stays above min(its value before, min_margin × its mean det J).
  double min_margin = 1e-3;
  /// Sweeps of a last repair phase on elements not certified valid (in solids guarded by
  /// certification): their control points off the surface move toward their neighbours' mean inside the feasible
  /// region; stops after a sweep that raised no such element's certified lower bound of det J
  /// [0, 1000]; 0 = none.
  int repair_sweeps = 10;
  /// Rounds of the valid start: control points of elements of the sampled nets that are not
  /// certified valid are pulled halfway toward the affine fit of the net per round (then onto it),
  /// so fitting starts from nets with every element valid [0, 60]; 0 = none (fitting then keeps
  /// the valid elements valid and the repair phase tries the others).
  int start_rounds = 20;
  /// Called with the nets of all solids after every accepted move (tests check the validity
  /// condition at every iteration); empty = none.
  std::function<void(const std::vector<SolidNet>&)> observer;
};

/// What one phase did. Errors are distances |Q_j − X(t_j)| over the phase's data points,
/// relative to the bounding-box diagonal of the solids' control points.
struct PhaseReport {
  /// "curves", "surfaces", "solids", "g1" (before/after: angles in degrees), "fairness" (rms and max
  /// second difference of the nets / diagonal) or "repair" (elements not certified valid)
  std::string name;
  int points = 0;     ///< control points the phase may move
  int sweeps = 0;
  int moves = 0;      ///< accepted moves (full or shortened)
  int shortened = 0;  ///< accepted after at least one halving
  int refused = 0;    ///< refused after params.halvings halvings
  double rms_before = 0, rms_after = 0, max_before = 0, max_after = 0;
};

/// Smoothness across one common face of two solids (Proposition 4): at each inner control point P0
/// of the face (off its edges, which lie on the cube's edges or where three or more solids meet,
/// outside the proposition's two-solid setting) with neighbours a (solid `first`, one row inside)
/// and b (solid `second`), the angle between P0 − a and b − P0 (0 where G1 holds).
struct Interface {
  int first = -1, second = -1;  ///< solids (indices into the list)
  int points = 0;               ///< inner face control points
  double max_angle_deg = 0;
  double mean_angle_deg = 0;
  double alpha = 0;             ///< |P0 − a| / |b − P0| summed over the points (the α of Proposition 4)
};

struct GfdReport {
  std::vector<PhaseReport> phases;
  int start_not_valid = 0;       ///< elements of the sampled nets not certified valid
  int start_rounds = 0;          ///< rounds of the valid start
  int start_blended_points = 0;  ///< control points it moved toward the affine fit
  double start_max_shift = 0;    ///< their largest move, relative to the bounding-box diagonal
  int initial_failing_subgrids = 0;  ///< Proposition 3 failures of the initial nets
  /// and at the end: 0 in the solids whose initial nets had none; the others (guarded by their
  /// certified elements instead) may have more
  int final_failing_subgrids = 0;
  double initial_margin = 0, final_margin = 0;  ///< min T^u·(T^v × T^w) over all sub-grids (validity.h margin)
  /// G1 defects of the initial nets (before any fitting) and at the end; the g1 phase's own
  /// before figures are after the fitting phases
  std::vector<Interface> g1_before, g1_after;
};

/// Fits the solids (initial_solids(), same `map` from [0,1]^3 to physical space) in place.
/// Throws core::ConfigError for parameters out of range, core::InvalidInputError for solids
/// without function ids or of mixed degree, what `map` throws.
GfdReport fit_solids(std::vector<tmesh::TMesh>& solids, const std::function<tmesh::Vec3(const tmesh::Vec3&)>& map,
                     const GfdParams& params);

/// The smoothness of every common face of the solids (Proposition 4's quantities).
std::vector<Interface> g1_defects(const std::vector<tmesh::TMesh>& solids);

}  // namespace volts::fit
