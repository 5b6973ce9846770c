#include "exports.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <vector>

#include "core/log.h"
#include "core/parallel.h"
#include "extract/export.h"

namespace volts::pipeline {

void check_exports(const StageContext& ctx, int degree, const std::string& degree_key) {
  extract::check_exports(ctx.config.extract.exports, degree, degree_key);
}

std::string vtu_path(const StageContext& ctx) { return ctx.output.empty() ? ctx.path("bezier.vtu") : ctx.output; }

namespace {

// Each export is a task of its own (they only read r and each writes its own files, atomically):
// the rod's five, 0.35 GB in all, took 4.0 s one after another.
std::vector<std::function<void()>> solver_export_tasks(const StageContext& ctx, const extract::Result& r, core::Json& files) {
  const auto& exports = ctx.config.extract.exports;
  const auto wanted = [&](const char* name) { return std::find(exports.begin(), exports.end(), name) != exports.end(); };
  const std::filesystem::path stem = std::filesystem::path(vtu_path(ctx)).replace_extension();
  const auto beside = [stem](const char* ext) { return stem.string() + ext; };
  files = core::Json::object();
  std::vector<std::function<void()>> tasks;
  if (wanted("bext")) {
    tasks.emplace_back([&r, beside, stem] {
      extract::write_bext(beside(".bext"), r);
      extract::write_lsdyna_deck(beside(".k"), stem.filename().string() + ".bext");
    });
    files["bext"] = beside(".bext"), files["k"] = beside(".k");
  }
  if (wanted("json")) {
    const auto operators = ctx.config.extract.json_operators == "kronecker" ? extract::JsonOperators::kronecker : extract::JsonOperators::triplets;
    tasks.emplace_back([&r, beside, operators] { extract::write_bezier_json(beside(".json"), r, operators); });
    files["json"] = beside(".json");
  }
  if (wanted("msh")) {
    tasks.emplace_back([&r, beside] {
      const std::size_t nodes = extract::write_gmsh(beside(".msh"), r.hexes);
      core::log("bezier.msh: " + std::to_string(nodes) + " nodes (shared between neighbouring elements)");
    });
    files["msh"] = beside(".msh");
  }
  if (wanted("png")) {
    const std::string png = ctx.path("scaled_jacobian_histogram.png");
    tasks.emplace_back([&r, png] { extract::write_histogram_png(png, r.min_scaled_jacobian); });
    files["png"] = png;
  }
  return tasks;
}

}  // namespace

core::Json write_solver_exports(const StageContext& ctx, const extract::Result& r) {
  core::Json files;
  core::parallel_tasks(solver_export_tasks(ctx, r, files));
  return files;
}

core::Json write_exports(const StageContext& ctx, const extract::Result& r) {
  const auto& exports = ctx.config.extract.exports;
  const bool vtu = std::find(exports.begin(), exports.end(), "vtu") != exports.end();
  const std::string out = vtu_path(ctx);
  core::Json files;
  {
    core::LogSection s("write");
    std::vector<std::function<void()>> tasks = solver_export_tasks(ctx, r, files);
    if (vtu) tasks.emplace_back([&] { extract::write_bezier_vtu(out, r); }), files["vtu"] = out;
    core::parallel_tasks(tasks);
  }
  core::log(std::to_string(r.hexes.size()) + " Bézier elements of degree " + std::to_string(r.degree) + ", " +
            std::to_string(r.certified_valid) + " certified valid, scaled Jacobian [" + std::to_string(r.min_scaled) + ", " +
            std::to_string(r.max_scaled) + "], hausdorff_rel " + std::to_string(r.hausdorff_rel) + ", volume_rel_error " +
            std::to_string(r.volume_rel_error));
  auto log_worst = [](const std::string& what, const extract::Result::Worst& w, const std::string& key) {
    char at[160];
    std::snprintf(at, sizeof at, "(%.4g, %.4g, %.4g), uvw (%.3g, %.3g, %.3g)", w.sample.position[0], w.sample.position[1], w.sample.position[2],
                  w.sample.uvw[0], w.sample.uvw[1], w.sample.uvw[2]);
    core::log(what + " " + std::to_string(w.sample.element) + " (block " + std::to_string(w.block) + ", " + w.block_kind + ", cube " +
              std::to_string(w.component) + "): " + std::to_string(w.sample.scaled_jacobian) + " at a " +
              (w.sample.at_corner ? "corner" : w.sample.on_grid ? "grid point" : "Gauss point") + " " + at + " on " +
              std::to_string(w.sample.boundary_faces) + " boundary faces" +
              (w.sample.surface_bound < 1 ? ", bounded there by the surface's tangents to " + std::to_string(w.sample.surface_bound) : std::string()) +
              " (report: extract." + key + ")");
  };
  if (!r.worst.empty()) log_worst("worst element", r.worst.front(), "worst_elements");
  if (!r.worst_dense.empty()) log_worst("worst element between the samples", r.worst_dense.front(), "worst_elements_dense");
  if (vtu) core::log("open in ParaView: " + out);
  core::Json fig = extract::report_figures(r);
  if (vtu) fig["output"] = out;
  fig["outputs"] = files;
  return fig;
}

}  // namespace volts::pipeline
