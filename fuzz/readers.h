// Every reader volts applies to a user's file, by kind, exactly as the executables run them: the
// libFuzzer targets (fuzz_*.cpp) and the regression tests of their finds
// (tests/hardening/fuzz_regression_test.cpp) call the same function.
#pragma once

#include <string>

#include "bezier/vtk_bezier.h"
#include "classify/classify.h"
#include "config/config.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stage_file.h"
#include "polycube_input.h"
#include "split/split.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "surface/surface.h"
#include "tmesh/tmesh.h"

namespace volts::fuzz {

/// Kinds: "off", "obj", "stl", "ply" (read_surface; the file's extension picks the parser),
/// "config", "stage_classify", "stage_split", "stage_polycube", "stage_tmesh", "vtu".
/// Returns normally or throws core::Error; anything else is a bug.
inline void read_input(const std::string& kind, const std::string& path) {
  if (kind == "off" || kind == "obj" || kind == "stl" || kind == "ply") {
    const surface::Mesh mesh = surface::read_surface(path);
    // What read_surface promises every later stage.
    if (mesh.is_empty() || !CGAL::is_closed(mesh) || !CGAL::is_triangle_mesh(mesh))
      throw std::logic_error("read_surface returned an invalid mesh");
  } else if (kind == "config") {
    const config::Config c = config::parse_config(core::read_text_file(path), path);
    (void)config::to_yaml(c);  // what `volts run` writes back into the work directory
  } else if (kind == "vtu") {
    (void)bezier::read_bezier_vtu(path);
  } else if (kind.rfind("stage_", 0) == 0) {
    // The header check, the payload readers and the cross-checks the next stage runs, in order.
    const std::string stage = kind.substr(6);
    // The newest version each reading executable accepts (pipeline/volts_<next stage>.cpp).
    const int version = stage == "split" || stage == "polycube" || stage == "tmesh" ? 2 : 1;
    const core::Json j = core::read_stage_file(path, "volts-" + stage, version);
    pipeline::check_integer_members(path, j);
    const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", path), path);
    if (stage == "tmesh") {
      const core::Json& list = core::require(j, "tmeshes", path);
      if (!list.is_array()) throw core::InvalidInputError(path + ": tmeshes must be a list");
      for (const auto& t : list) (void)tmesh::from_json(t, path);
      return;
    }
    const classify::Classification c = classify::from_json(core::require(j, "classification", path), path);
    pipeline::check_classification(path, mesh, c);
    if (stage == "classify") return;
    const split::Decomposition d = split::from_json(core::require(j, "decomposition", path), path);
    pipeline::check_decomposition(path, c, d);
    // What volts-tmesh reads: every kind of polycube with its volume map (at the default T-mesh
    // parameters, which only shape a difference's blocks).
    if (stage == "polycube") (void)pipeline::read_polycube_input(path, tmesh::Params{});
  } else {
    throw std::logic_error("unknown reader kind " + kind);
  }
}

}  // namespace volts::fuzz
