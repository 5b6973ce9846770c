// volts::tmesh — stage 4: the T-mesh, i.e. the control mesh of the volumetric spline (Liu et al.
// 2013, §5.1–5.2).
//
// Implemented so far: a uniform octree of a given level on the one cube of the polycube, whose
// control mesh is the tensor grid of a clamped cubic B-spline. Control points are chosen so that the
// spline interpolates the polycube volume map at the Greville points; the boundary rows of control
// points then interpolate the surface map, which keeps the spline boundary on the input surface to
// the interpolation error. Adaptive refinement, T-junctions, sharp-feature knots, pillowing,
// smoothing and optimization are issue 7.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/stage_file.h"
#include "polycube/polycube.h"

namespace volts::tmesh {

/// Parameters of build().
struct Params {
  int level = 3;   ///< uniform octree level: 2^level elements along each cube edge [1, 7]
  int degree = 3;  ///< spline degree in each direction [1, 5]
  int pillow_layers = 1;    ///< element layers of the pillow under the surface (§5.2); 0 = none [0, 4]
  int optimize_sweeps = 4;  ///< sweeps of per-node worst-Jacobian optimization (§5.2); 0 = none [0, 100]
};

/// A tensor-product control mesh (the T-mesh of one cube without T-junctions yet).
struct TMesh {
  int level = 0;
  int degree = 3;
  std::array<std::vector<double>, 3> knots;            ///< clamped knot vectors on [0,1]
  std::array<int, 3> size{0, 0, 0};                    ///< control points per direction
  std::vector<std::array<double, 3>> control_points;   ///< index i + size0*(j + size1*k)
  std::vector<std::array<double, 3>> parameters;       ///< Greville point of each control point
  /// Per cube face 2*axis + side: 1 if it lies on the input surface (0: shared with another cube).
  std::array<int, 6> boundary{1, 1, 1, 1, 1, 1};
  int component = 0;                                   ///< the split component (cube) it belongs to
  /// Global basis-function id of each control point. Blocks (tensor patches) that share a face
  /// have identical control points there and give them the same id, so the spline is C0 across
  /// the face. Empty: ids are numbered block after block (no sharing).
  std::vector<int> function_ids;
  int elements() const;  ///< product of the knot spans in the three directions
};

/// A map from the unit cube's parameters to physical space.
using PointMap = std::function<std::array<double, 3>(const std::array<double, 3>&)>;

/// Builds the control mesh by interpolating `map` at the Greville points. Throws core::ConfigError
/// for parameters out of range.
TMesh build(const polycube::VolumeMap& map, const Params& params);
TMesh build(const PointMap& map, const Params& params);

/// Scaled Jacobian of a trilinear hexahedron at its 8 corners (Liu et al. eq. (1)–(2)); corners in
/// VTK order. Returns the minimum.
double trilinear_min_scaled_jacobian(const std::array<std::array<double, 3>, 8>& x);

core::Json to_json(const TMesh& t);
TMesh from_json(const core::Json& j, const std::string& file);
core::Json report_figures(const std::vector<TMesh>& t, double min_scaled_jacobian);

/// ParaView view: the octree elements as trilinear hexes at their mapped corners, with `level` and
/// `scaled_jacobian` per cell. Returns the minimum scaled Jacobian of these elements.
double write_vtu(const std::string& path, const TMesh& t, const polycube::VolumeMap& map);
/// The same for several cubes, each with its own map; cell field `component` added.
double write_vtu(const std::string& path, const std::vector<TMesh>& t, const std::vector<PointMap>& maps);

}  // namespace volts::tmesh
