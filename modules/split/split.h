// volts::split — stage 2: decomposition of the surface into components that are topologically
// cubes or tori (Liu et al. 2013, §4.1).
//
// Implemented so far: the direct case of §4.1 ("for simple CAD models, we can directly use the
// feature curves to generate the polycube edges"): a genus-0 surface whose patches meet like the six
// faces of a cube is one cube component. The harmonic-field split of tori and holes is issue 5;
// anything else is a TopologyError that says so.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "classify/classify.h"
#include "core/stage_file.h"

namespace volts::split {

/// Parameters of split(). (The harmonic-field controls of §4.1 will live here.)
struct Params {};

enum class ComponentType { cube, torus_cube, virtual_component };
const char* to_string(ComponentType type);

/// One component of the decomposition: a region bounded like a cube by six quad patches.
struct Component {
  ComponentType type = ComponentType::cube;
  std::vector<int> patches;  ///< the surface patches bounding it
};

struct Decomposition {
  std::vector<Component> components;
  int quad_patches = 0;  ///< patches that are disks bounded by four curves
};

/// Decomposes a classified surface. Throws core::TopologyError naming what was found (genus,
/// patches, corners) when the surface is not one the implemented cases cover.
Decomposition split(const surface::Mesh& mesh, const classify::Classification& c, const Params& params);

/// Number of corners on the boundary of each patch (a quad patch has 4) and number of boundary
/// loops of each patch (a disk has 1).
std::vector<int> patch_corner_counts(const classify::Classification& c);

core::Json to_json(const Decomposition& d);
Decomposition from_json(const core::Json& j, const std::string& file);
core::Json report_figures(const Decomposition& d, const classify::Classification& c);

/// ParaView view: faces with patch_id and component_id, curves as lines.
void write_vtp(const std::string& path, const surface::Mesh& mesh, const classify::Classification& c, const Decomposition& d);

}  // namespace volts::split
