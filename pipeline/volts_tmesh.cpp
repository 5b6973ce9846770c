// volts-tmesh: stage 4 (Liu et al. §5.1–5.2). Reads polycube.stage.json, builds the octree T-mesh
// (control mesh) through the volume map; writes tmesh.stage.json and tmesh.vtu.
#include "core/errors.h"
#include "core/log.h"
#include "stage_main.h"
#include "surface/mesh_json.h"
#include "polycube/embedding.h"
#include "tmesh/tmesh.h"
#include "volmap/volmap.h"

using namespace volts;

namespace {

// A torus: one tensor B-spline per cube of the ring, interpolating the volume map at its Greville
// points through the ring embedding; neighbours sample their shared cross section at the same
// points, so they share its control points (C0 between cubes). The octree is uniform (issue 7).
core::Json torus(pipeline::StageContext& ctx, const std::string& in, const core::Json& j) {
  std::unique_ptr<volmap::Locator> locate;
  polycube::Embedding e;
  {
    core::LogSection s("volume map");
    const volmap::VolumeMap vm = volmap::from_json(core::require(j, "volume_map", in), in);
    if (vm.flipped_tets > 0)
      throw core::NumericalError(in + ": the volume map has " + std::to_string(vm.flipped_tets) +
                                 " flipped tets; rerun polycube with a smaller polycube.tet_max_volume_rel");
    // Points of the round ring outside the surface's chords by up to the recorded gap snap onto it.
    const double gap = core::require(core::require(j, "polycube", in), "boundary_gap", in).get<double>();
    Eigen::Vector3d lo = vm.parameter.at(0), hi = lo;
    for (const auto& p : vm.parameter) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    locate = std::make_unique<volmap::Locator>(vm, std::max(1e-6, 2 * gap / (hi - lo).norm()));
    try {
      const auto cells = core::require(core::require(j, "polycube", in), "cells", in).get<std::vector<double>>();
      if (cells.empty() || cells.size() % 24) throw core::InvalidInputError(in + ": polycube.cells needs 24 numbers per cube");
      e.cells.resize(cells.size() / 24);
      e.ring = core::require(core::require(j, "polycube", in), "ring", in).get<int>();
      e.mirrored = core::require(core::require(j, "polycube", in), "mirrored", in).get<bool>();
      if (e.ring != static_cast<int>(e.cells.size())) throw core::InvalidInputError(in + ": polycube.ring does not match its cells");
      for (std::size_t i = 0; i < cells.size(); ++i) e.cells[i / 24][(i % 24) / 3][i % 3] = cells[i];
    } catch (const core::Json::exception& x) {
      throw core::InvalidInputError(in + ": malformed polycube.cells: " + x.what());
    }
  }
  std::vector<tmesh::TMesh> ts;
  std::vector<tmesh::PointMap> maps;
  // The spline's parameters must be right-handed in physical space; the ring's local frame is
  // right- or left-handed depending on the directions split chose, so swap b and c if needed
  // (all cubes alike, so neighbours still sample their shared cross section at the same points).
  bool swap = false;
  auto point = [&](std::size_t k, std::array<double, 3> abc) {
    if (swap) std::swap(abc[1], abc[2]);
    const auto x = locate->physical(polycube::cell_point(e, static_cast<int>(k), abc));
    if (!x) throw core::NumericalError("tmesh: cube " + std::to_string(k) + " point outside the volume map");
    return *x;
  };
  {
    const double h = 0.05;
    std::array<std::array<double, 3>, 3> d{};
    for (int a = 0; a < 3; ++a) {
      std::array<double, 3> lo{0.5, 0.5, 0.5}, hi{0.5, 0.5, 0.5};
      lo[a] -= h, hi[a] += h;
      const auto p = point(0, hi), q = point(0, lo);
      for (int i = 0; i < 3; ++i) d[a][i] = p[i] - q[i];
    }
    const double det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                       d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
    swap = det < 0;
  }
  for (std::size_t k = 0; k < e.cells.size(); ++k) maps.push_back([&point, k](const std::array<double, 3>& abc) { return point(k, abc); });
  {
    core::LogSection s("octree and control points");
    for (std::size_t k = 0; k < e.cells.size(); ++k) {
      tmesh::TMesh t = tmesh::build(maps[k], ctx.config.tmesh);
      t.boundary = {0, 0, 1, 1, 1, 1};  // the a = 0 and a = 1 faces are cross sections
      t.component = static_cast<int>(k);
      ts.push_back(std::move(t));
    }
  }
  double min_sj = 0;
  {
    core::LogSection s("write");
    core::Json list = core::Json::array();
    for (const auto& t : ts) list.push_back(tmesh::to_json(t));
    core::write_stage_file(ctx.output_file(), "volts-tmesh", 2, {{"surface", j["surface"]}, {"tmeshes", list}});
    min_sj = tmesh::write_vtu(ctx.path("tmesh.vtu"), ts, maps);
  }
  core::log(std::to_string(ts.size()) + " cubes, min trilinear scaled Jacobian " + std::to_string(min_sj));
  return tmesh::report_figures(ts, min_sj);
}

}  // namespace

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "tmesh",
      "Stage 4 (Liu et al. 2013 §5.1-5.2): octree T-mesh of the polycube, control points through the\n"
      "volume map. Input: DIR/polycube.stage.json. Output: DIR/tmesh.stage.json, DIR/tmesh.vtu\n"
      "(octree elements with level and scaled_jacobian).",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("polycube");
        const core::Json j = core::read_stage_file(in, "volts-polycube", 2);
        const std::string kind = j.value("kind", std::string("cube"));
        if (kind == "torus") return torus(ctx, in, j);
        if (kind != "cube") throw core::InvalidInputError(in + ": unknown polycube kind '" + kind + "'");
        pipeline::check_integer_members(in, j);
        const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
        const classify::Classification c = classify::from_json(core::require(j, "classification", in), in);
        const polycube::Polycube p = polycube::from_json(core::require(j, "polycube", in), in);
        pipeline::check_classification(in, mesh, c);
        pipeline::check_polycube(in, mesh, c, p);
        std::unique_ptr<polycube::VolumeMap> map;
        {
          core::LogSection s("volume map");
          map = std::make_unique<polycube::VolumeMap>(mesh, c, p);
        }
        tmesh::TMesh t;
        {
          core::LogSection s("octree and control points");
          t = tmesh::build(*map, ctx.config.tmesh);
        }
        double min_sj = 0;
        {
          core::LogSection s("write");
          core::write_stage_file(ctx.output_file(), "volts-tmesh", 2,
                                 {{"surface", j["surface"]}, {"tmeshes", core::Json::array({tmesh::to_json(t)})}});
          min_sj = tmesh::write_vtu(ctx.path("tmesh.vtu"), t, *map);
        }
        core::log(std::to_string(t.elements()) + " elements, " + std::to_string(t.control_points.size()) +
                  " control points, min trilinear scaled Jacobian " + std::to_string(min_sj));
        return tmesh::report_figures({t}, min_sj);
      });
}
