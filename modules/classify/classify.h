// volts::classify — stage 1: corners, curves and patches of a closed surface (Liu et al. 2013, §3
// "Curve Extraction": curve classification and sharp feature detection).
//
// Sharp edges are found by dihedral angle and chained into curves split at corners; closed chains
// without corners stay closed curves. Patches are the face regions bounded by sharp curves. A curve
// is a *difference* curve when it bounds a hole in a patch (C13, C14 in Fig. 3 of the paper: the
// rims of a cylinder subtracted from a cube) and a *feature* curve otherwise.
#pragma once

#include <string>
#include <vector>

#include "core/stage_file.h"
#include "surface/surface.h"

namespace volts::classify {

/// Parameters of classify().
struct Params {
  double sharp_angle_deg = 30.0;   ///< an edge is sharp if its face normals differ by more than this [degrees]
  double corner_angle_deg = 30.0;  ///< a curve vertex becomes a corner if the curve turns by more than this [degrees]
};

enum class CurveKind { feature, difference };
const char* to_string(CurveKind kind);

struct Curve {
  std::vector<int> vertices;  ///< vertex chain; for a closed curve the first vertex is not repeated
  bool closed = false;        ///< a loop without corners
  CurveKind kind = CurveKind::feature;
  int patch_left = -1, patch_right = -1;  ///< patches on both sides (left = side of the first edge's face)
};

struct Classification {
  std::vector<int> corners;         ///< vertex indices, increasing
  std::vector<Curve> curves;
  std::vector<int> face_patch;      ///< patch id of each face
  int patches = 0;
  std::vector<int> sharp_edge_vertices;  ///< pairs (a,b), a < b, of every sharp edge
  int genus = 0;
  int feature_curves() const;
  int difference_curves() const;
};

/// Classifies `mesh` (a valid closed surface from surface::read_surface).
Classification classify(const surface::Mesh& mesh, const Params& params);

/// Stage-file payload of a classification (see docs/formats.md) and its inverse; from_json throws
/// core::InvalidInputError naming `file` on malformed data.
core::Json to_json(const Classification& c);
Classification from_json(const core::Json& j, const std::string& file);

/// The report figures of classify (keys: corners, curves, feature_curves, difference_curves,
/// patches, sharp_edges, genus).
core::Json report_figures(const Classification& c);

/// ParaView view: faces with patch_id, curves as lines with curve_id and kind (0 feature, 1
/// difference), corners as vertices with corner_id.
void write_vtp(const std::string& path, const surface::Mesh& mesh, const Classification& c);

}  // namespace volts::classify
