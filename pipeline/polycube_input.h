// What volts-tmesh reads from polycube.stage.json (Liu et al. 2013 §5.1: every T-mesh node gets
// its physical position from the polycube's volume map): for each kind of polycube — one cube
// (Coons map of the face maps), a torus or two tori (rings: round annulus embedding + tet map), a
// cube minus a through hole (tet map, explicit blocks) — the maps the T-mesh is built through,
// with the point location they need. Shared by volts-tmesh and the stage_polycube fuzz target, so
// the fuzzer runs exactly what the stage runs.
#pragma once

#include <memory>
#include <string>

#include "core/stage_file.h"
#include "tmesh/tmesh.h"

namespace volts::pipeline {

struct PolycubeInput {
  std::string kind;               ///< "cube", "torus", "tori", "difference" or "torus_on_cube"
  core::Json surface;             ///< the input surface, passed on to the tmesh stage file
  tmesh::PolycubeMaps maps;       ///< owns (through shared pointers) the volume maps it calls
};

/// Reads and checks the file (header, kind, the polycube `structure` if present — parsed, checked
/// with polycube::check and matched to the kind —, payload, the volume map's flipped tets).
/// Difference blocks depend on params.level and params.pillow_layers. Throws
/// core::InvalidInputError naming the file for malformed content (a structure that is no polycube
/// included: the stage checked it before writing, so the file was edited), core::NumericalError if the volume map has flipped tets (the
/// spline would fold), core::TopologyError if the T-mesh cannot be laid out on the polycube.
PolycubeInput read_polycube_input(const std::string& path, const tmesh::Params& params);

}  // namespace volts::pipeline
