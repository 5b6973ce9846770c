// volts-polycube: stage 3 (Liu et al. §4.2–4.3). Reads split.stage.json, builds the polycube and
// maps the surface onto it; writes polycube.stage.json, polycube.vtp and polycube_mapped.vtp
// (tori, two tori and differences also the volume map's tets: polycube_tets.vtu, polycube_tets_mapped.vtu).
#include <algorithm>
#include <functional>

#include "core/log.h"
#include "polycube/difference.h"
#include "polycube/embedding.h"
#include "polycube/polycube.h"
#include "polycube/rings.h"
#include "volmap/volmap.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

namespace {

// Warnings for a map with flipped surface triangles or tets left flipped by untangling (tmesh
// refuses such a volume map), under `what`.
void warn_if_flipped(const std::string& what, int flipped_surface_triangles, const volmap::VolumeMap& vm) {
  if (flipped_surface_triangles > 0)
    core::log_warning(what + std::to_string(flipped_surface_triangles) + " surface triangles are flipped by the map");
  if (vm.flipped_tets > 0)
    core::log_warning(what + std::to_string(vm.flipped_tets) + " tets stay flipped after untangling (it stopped: " + vm.untangle_stop +
                      " after " + std::to_string(vm.untangle_sweeps) + " sweeps; see polycube_tets_mapped.vtu); a smaller "
                      "polycube.tet_max_volume_rel can help when the surface map is good (max_angle_distortion_deg), else "
                      "the decomposition cannot be mapped without folds: set `route: tet`");
}

// The surface and volume map of one torus (its layout triangles, fills included, are its closed
// surface), logged under `what`.
void map_torus(pipeline::StageContext& ctx, const split::Decomposition& d, const std::string& what, polycube::TorusSurfaceMap& m,
               volmap::VolumeMap& vm) {
  {
    core::LogSection s(what + "surface map");
    polycube::PatchMapParams pp;
    pp.weights = ctx.config.polycube.weights;
    m = polycube::map_torus_surface(d, pp);
  }
  {
    core::LogSection s(what + "volume map");
    vm = polycube::torus_volume_map(d, m, ctx.config.polycube);
  }
  warn_if_flipped(what, m.flipped_surface_triangles, vm);
}

// The stage file of a polycube with one volume map, its surface views (`surface_view(path,
// mapped)`) and the tets in physical and polycube space.
void write_with_volume_map(pipeline::StageContext& ctx, const core::Json& j, const std::string& kind, const core::Json& polycube,
                           const volmap::VolumeMap& vm, const std::function<void(const std::string&, bool)>& surface_view) {
  core::LogSection s("write");
  core::write_stage_file(ctx.output_file(), "volts-polycube", 2,
                         {{"kind", kind}, {"surface", j["surface"]}, {"classification", j["classification"]},
                          {"decomposition", j["decomposition"]}, {"polycube", polycube}, {"volume_map", volmap::to_json(vm)}});
  surface_view(ctx.path("polycube.vtp"), false);
  surface_view(ctx.path("polycube_mapped.vtp"), true);
  volmap::write_vtu(ctx.path("polycube_tets.vtu"), vm);
  volmap::write_parameter_vtu(ctx.path("polycube_tets_mapped.vtu"), vm);
}

// A torus (Liu et al. §4.2, Fig. 5(b)): patch maps on the ring embedding, then the harmonic volume
// map of the tet mesh onto it, untangled (§4.3).
core::Json torus(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  polycube::TorusSurfaceMap m;
  volmap::VolumeMap vm;
  map_torus(ctx, d, "", m, vm);
  write_with_volume_map(ctx, j, "torus", polycube::to_json(m), vm,
                        [&](const std::string& path, bool mapped) { polycube::write_torus_vtp(path, d, m, mapped); });
  core::Json r = volmap::report_figures(vm);
  r["cubes"] = d.components.size();
  r["tori"] = 1;
  r["virtual_components"] = 0;
  r["flipped_surface_triangles"] = m.flipped_surface_triangles;
  r["max_angle_distortion_deg"] = m.max_angle_distortion_deg;
  return r;
}

// Two tori united on a filled disk (Liu et al. §4.2, Fig. 6(c)): each torus with the disk is
// mapped like a single torus, on its own ring; the disk gets one (independent) image per ring.
core::Json tori(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  const std::vector<polycube::Ring> rings = polycube::rings(d);
  std::vector<polycube::TorusSurfaceMap> ms(rings.size());
  std::vector<volmap::VolumeMap> vms(rings.size());
  for (std::size_t i = 0; i < rings.size(); ++i) map_torus(ctx, rings[i].decomposition, "ring " + std::to_string(i) + ": ", ms[i], vms[i]);
  core::Json list = core::Json::array(), figures = core::Json::array();
  std::vector<const volmap::VolumeMap*> maps;
  std::vector<std::array<double, 3>> offsets;
  core::Json r{{"cubes", d.components.size()}, {"tori", rings.size()}, {"virtual_components", 0}, {"flipped_surface_triangles", 0},
               {"max_angle_distortion_deg", 0.0}, {"tets", 0}, {"flipped_tets", 0}, {"flipped_tets_before_untangling", 0}};
  for (std::size_t i = 0; i < rings.size(); ++i) {
    list.push_back(polycube::to_json(rings[i], ms[i], vms[i]));
    maps.push_back(&vms[i]);
    offsets.push_back({polycube::kRingSpacing * static_cast<double>(i), 0, 0});
    core::Json f = volmap::report_figures(vms[i]);
    f["flipped_surface_triangles"] = ms[i].flipped_surface_triangles;
    f["max_angle_distortion_deg"] = ms[i].max_angle_distortion_deg;
    figures.push_back(f);
    r["flipped_surface_triangles"] = r["flipped_surface_triangles"].get<int>() + ms[i].flipped_surface_triangles;
    r["max_angle_distortion_deg"] = std::max(r["max_angle_distortion_deg"].get<double>(), ms[i].max_angle_distortion_deg);
    r["tets"] = r["tets"].get<std::size_t>() + vms[i].tets.size();
    r["flipped_tets"] = r["flipped_tets"].get<int>() + vms[i].flipped_tets;
    r["flipped_tets_before_untangling"] = r["flipped_tets_before_untangling"].get<int>() + vms[i].flipped_tets_before_untangling;
    r["min_volume_ratio"] = i == 0 ? vms[i].min_volume_ratio : std::min(r["min_volume_ratio"].get<double>(), vms[i].min_volume_ratio);
  }
  r["rings"] = figures;
  {
    core::LogSection s("write");
    core::write_stage_file(ctx.output_file(), "volts-polycube", 2,
                           {{"kind", "tori"}, {"surface", j["surface"]}, {"classification", j["classification"]},
                            {"decomposition", j["decomposition"]}, {"rings", list}});
    polycube::write_rings_vtp(ctx.path("polycube.vtp"), rings, ms, false);
    polycube::write_rings_vtp(ctx.path("polycube_mapped.vtp"), rings, ms, true);
    volmap::write_vtu(ctx.path("polycube_tets.vtu"), maps, offsets, "ring");
    volmap::write_parameter_vtu(ctx.path("polycube_tets_mapped.vtu"), maps, offsets, "ring");
  }
  return r;
}

// A cube minus a through hole (Liu et al. §4.2 difference, §4.3): the solid (fills excluded) onto
// the unit cube minus the hole's box, surface then volume.
core::Json difference(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  polycube::DifferenceMap m;
  {
    core::LogSection s("surface map");
    polycube::PatchMapParams pp;
    pp.weights = ctx.config.polycube.weights;
    m = polycube::map_difference_surface(d, pp);
  }
  volmap::VolumeMap vm;
  {
    core::LogSection s("volume map");
    vm = polycube::difference_volume_map(d, m, ctx.config.polycube);
  }
  warn_if_flipped("", m.flipped_surface_triangles, vm);
  write_with_volume_map(ctx, j, "difference", polycube::to_json(m), vm,
                        [&](const std::string& path, bool mapped) { polycube::write_difference_vtp(path, d, m, mapped); });
  core::Json r = volmap::report_figures(vm);
  r["cubes"] = 1;
  r["tori"] = 0;
  r["virtual_components"] = 1;
  r["hole_axis"] = m.axis;
  r["hole_width"] = m.hole_hi[(m.axis + 1) % 3] - m.hole_lo[(m.axis + 1) % 3];
  r["flipped_surface_triangles"] = m.flipped_surface_triangles;
  r["max_angle_distortion_deg"] = m.max_angle_distortion_deg;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "polycube",
      "Stage 3 (Liu et al. 2013 §4.2-4.3): build the polycube and map the surface onto it\n"
      "(bijective disk map per patch). Input: DIR/split.stage.json. Output: DIR/polycube.stage.json,\n"
      "DIR/polycube.vtp (surface with cube coordinates 'uvw'), DIR/polycube_mapped.vtp (the surface on the cube);\n"
      "tori also DIR/polycube_tets.vtu and DIR/polycube_tets_mapped.vtu (the volume map's tets, physical and mapped);\n"
      "two tori meeting on a disk: one ring per torus (cell field 'ring'; ring i drawn 5i along x when mapped);\n"
      "a cube minus a through hole: the unit cube minus the hole's box (polycube.hole_lo/hole_hi), tets too.",
      [](pipeline::StageContext& ctx) {
        const std::string in = ctx.input_file("split");
        const core::Json j = core::read_stage_file(in, "volts-split", 2);
        pipeline::check_integer_members(in, j);
        const surface::Mesh mesh = surface::mesh_from_json(core::require(j, "surface", in), in);
        const classify::Classification c = classify::from_json(core::require(j, "classification", in), in);
        const split::Decomposition d = split::from_json(core::require(j, "decomposition", in), in);
        pipeline::check_classification(in, mesh, c);
        pipeline::check_decomposition(in, c, d);
        if (d.tori.size() == 1 && d.components.size() == d.tori[0].components.size()) return torus(ctx, j, d);
        if (!d.tori.empty()) return tori(ctx, j, d);  // two tori on a disk, else a TopologyError naming the components
        for (const auto& comp : d.components)
          if (comp.type == split::ComponentType::virtual_component) return difference(ctx, j, d);
        polycube::Polycube p;
        {
          core::LogSection s("surface map");
          p = polycube::map_surface(mesh, c, d, ctx.config.polycube);
        }
        if (p.flipped_surface_triangles > 0)
          core::log_warning(std::to_string(p.flipped_surface_triangles) + " surface triangles are flipped by the map");
        {
          core::LogSection s("write");
          core::write_stage_file(ctx.output_file(), "volts-polycube", 2,
                                 {{"kind", "cube"}, {"surface", j["surface"]}, {"classification", j["classification"]},
                                  {"decomposition", j["decomposition"]}, {"polycube", polycube::to_json(p)}});
          polycube::write_vtp(ctx.path("polycube.vtp"), mesh, c, p);
          polycube::write_mapped_vtp(ctx.path("polycube_mapped.vtp"), mesh, c, p);
        }
        return polycube::report_figures(p, d);
      });
}
