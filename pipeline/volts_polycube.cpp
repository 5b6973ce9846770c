// volts-polycube: stage 3 (Liu et al. §4.2–4.3). Reads split.stage.json, builds the polycube
// structure (polycube/structure.h) of split's decomposition and checks it, then maps the surface
// onto the polycube; writes polycube.stage.json (with the structure), polycube_structure.vtu,
// polycube.vtp and polycube_mapped.vtp (tori, two tori and differences also the volume map's tets:
// polycube_tets.vtu, polycube_tets_mapped.vtu).
#include <algorithm>
#include <functional>
#include <optional>
#include <tuple>
#include <utility>

#include "core/errors.h"
#include "core/log.h"
#include "core/parallel.h"
#include "polycube/connector.h"
#include "polycube/difference.h"
#include "polycube/embedding.h"
#include "polycube/polycube.h"
#include "polycube/rings.h"
#include "polycube/structure.h"
#include "tmesh/pillow.h"
#include "volmap/volmap.h"
#include "stage_main.h"
#include "surface/mesh_json.h"

using namespace volts;

namespace {

// ---- The polycube structure of split's decomposition ----------------------------------------

std::string component_name(int c) { return "component " + std::to_string(c); }

// The structure face of face f (split's order) of a torus cube. split's faces 0..3 run around the
// tube through the cross section's corners q_0..q_3, (b, c) = (0,0), (1,0), (1,1), (0,1) in the ring
// embedding's local frame (embedding.cpp), so they are c = 0, b = 1, c = 1, b = 0; faces 4 and 5
// are the cross sections a = 0 and a = 1 (the ring runs along a, as tmesh's cubes).
constexpr int kTorusFace[6] = {4, 3, 5, 2, 0, 1};

// The face (split's order) of component c that is internal face `internal`, or (internal < 0)
// that holds a fill triangle (the disk two tori meet on).
int split_face(const split::Decomposition& d, int c, int internal, const std::string& who) {
  const auto& faces = d.components[c].faces;
  const auto& L = d.layout;
  auto holds_fill = [&](const split::CubeFace& f) {
    for (int p : f.patches)
      if (p >= 0 && p < static_cast<int>(L.patches.size()))
        for (int t : L.patches[p].triangles)
          if (t >= 0 && t < static_cast<int>(L.filled.size()) && L.filled[t]) return true;
    return false;
  };
  for (std::size_t f = 0; f < faces.size() && f < 6; ++f)
    if (internal >= 0 ? faces[f].internal_face == internal : holds_fill(faces[f])) return static_cast<int>(f);
  throw core::TopologyError(who + ": " + component_name(c) + " has no face " +
                            (internal >= 0 ? "on internal face " + std::to_string(internal) : std::string("holding the filled disk")));
}

// The structure of split's decomposition (Liu et al. §4.2–4.3), cubes labelled after their
// components: per torus a torus primitive of its n unit cubes in ring order along a, its ring
// gluings those split's internal-face contacts give (so a ring split did not close, or closed out
// of order, is check()'s error naming the cubes); a unit cube per cube component, each in its own
// frame (split gives no boxes, so two of them are "not connected"); each hole of a difference
// (`holes`: their boxes in the unit cube, as the polycube payload's) as a virtual component of its
// cube — the hole's rims are that component's openings; two tori's filled disk as a non-conforming
// contact of the ring faces holding it (a patch inside those faces, not a rectangle of both: no gluing).
polycube::Structure decomposition_structure(const split::Decomposition& d, const polycube::DifferenceMap* holes) {
  using polycube::Box;
  using split::ComponentType;
  const int nc = static_cast<int>(d.components.size());
  polycube::Structure s;
  std::vector<int> cube_of(static_cast<std::size_t>(nc), -1);
  auto component = [&](int c, const std::string& who) {
    if (c < 0 || c >= nc) throw core::TopologyError(who + " refers to component " + std::to_string(c) + " of " + std::to_string(nc));
    return c;
  };
  for (std::size_t t = 0; t < d.tori.size(); ++t) {
    const auto& ring = d.tori[t].components;
    const std::string label = "torus " + std::to_string(t);
    const std::size_t before = s.gluings.size();
    const int p = polycube::add_torus(s, label, Box{}, 0, static_cast<int>(ring.size()));
    s.gluings.resize(before);  // the ring's gluings are the contacts', below
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const int c = component(ring[k], label);
      if (cube_of[c] >= 0 || d.components[c].type != ComponentType::torus_cube || d.components[c].torus != static_cast<int>(t))
        throw core::TopologyError(label + " lists " + component_name(c) + ", which is not a torus cube of this torus only");
      cube_of[c] = s.primitives[p].cubes[k];
      s.cubes[cube_of[c]].label = component_name(c);
    }
  }
  for (int c = 0; c < nc; ++c) {
    const ComponentType type = d.components[c].type;
    if (type == ComponentType::torus_cube && cube_of[c] < 0) throw core::TopologyError(component_name(c) + " is a torus cube in no torus");
    if (type == ComponentType::cube) {
      cube_of[c] = static_cast<int>(s.cubes.size());
      polycube::add_cube(s, component_name(c), Box{});
    }
  }
  for (int c = 0; c < nc; ++c) {
    if (d.components[c].type != ComponentType::virtual_component) continue;
    const polycube::HoleBox* hole = nullptr;
    if (holes)
      for (const auto& h : holes->holes)
        if (h.virtual_component == c) hole = &h;
    if (!hole || holes->cube < 0 || holes->cube >= nc || cube_of[holes->cube] < 0)
      throw core::TopologyError(component_name(c) + " is a virtual component; only the through holes of a difference (one cube minus "
                                "virtual components) are supported");
    polycube::subtract(s, cube_of[holes->cube], component_name(c), {Box{hole->lo, hole->hi}});
  }
  for (const auto& x : d.contacts) {
    const std::string who = "components " + std::to_string(x.a) + " and " + std::to_string(x.b) + " (" + x.via + " " + std::to_string(x.index) + ")";
    component(x.a, who), component(x.b, who);
    const auto& A = d.components[x.a];
    const auto& B = d.components[x.b];
    if (x.via == "internal_face" && A.torus >= 0 && B.torus >= 0) {
      const int ca = cube_of[x.a], cb = cube_of[x.b];
      const int fa = kTorusFace[split_face(d, x.a, x.index, who)], fb = kTorusFace[split_face(d, x.b, x.index, who)];
      const auto plane = [&](int cube, int f) { return f % 2 ? s.cubes[cube].box.hi[f / 2] : s.cubes[cube].box.lo[f / 2]; };
      polycube::Gluing g{ca, fa, cb, fb, polycube::face_rect(s.cubes[ca].box, fa), {}, -1};
      if (fa / 2 == fb / 2) g.map.offset[fa / 2] = plane(cb, fb) - plane(ca, fa);  // else no translation: glue check names the cubes
      if (g.map.offset != polycube::Point{0, 0, 0} && A.torus == B.torus) g.closes_torus = s.cubes[ca].primitive;
      s.gluings.push_back(g);
    } else if (x.via == "filled_patch" && (A.type == ComponentType::virtual_component) != (B.type == ComponentType::virtual_component)) {
      continue;  // a hole's rim: the opening of the virtual component in its cube
    } else if (x.via == "filled_patch" && A.torus >= 0 && B.torus >= 0 && A.torus != B.torus) {
      polycube::add_contact(s, "disk (patch " + std::to_string(x.index) + ")", cube_of[x.a], kTorusFace[split_face(d, x.a, -1, who)],
                            cube_of[x.b], kTorusFace[split_face(d, x.b, -1, who)]);
    } else if (x.via == "filled_patch" && (A.torus >= 0) != (B.torus >= 0) && holes && holes->foot && (x.a == holes->cube || x.b == holes->cube)) {
      // A torus standing on the cube minus holes: its foot on the rectangle of the holed face.
      const int t = A.torus >= 0 ? x.a : x.b;
      const int face = 2 * holes->axis + (holes->foot->lo[static_cast<std::size_t>(holes->axis)] > 0.5 ? 1 : 0);
      polycube::add_contact(s, "foot (patch " + std::to_string(x.index) + ")", cube_of[t], kTorusFace[split_face(d, t, -1, who)], cube_of[holes->cube], face);
    } else if (x.via == "filled_patch" && (A.torus >= 0) != (B.torus >= 0) && (A.type == ComponentType::cube || B.type == ComponentType::cube)) {
      // A connector cube on a torus's disk: its end a = 0 on torus 0's, a = 1 on torus 1's (connector.h).
      const int t = A.torus >= 0 ? x.a : x.b, c = A.torus >= 0 ? x.b : x.a;
      polycube::add_contact(s, "connector end (patch " + std::to_string(x.index) + ")", cube_of[t], kTorusFace[split_face(d, t, -1, who)],
                            cube_of[c], d.components[t].torus == 0 ? 0 : 1);
    } else {
      throw core::TopologyError(who + ": components meet on a cross section of their torus, on a hole's rim or on the disk between two "
                                "tori; this contact is none of these");
    }
  }
  return s;
}

// The structure, checked before anything is written: a component graph that is no polycube is a
// TopologyError naming the components.
polycube::Structure checked_structure(const split::Decomposition& d, const polycube::DifferenceMap* holes = nullptr) {
  core::LogSection section("structure");
  try {
    polycube::Structure s = decomposition_structure(d, holes);
    polycube::check(s);
    const core::Json f = polycube::report_figures(s);
    core::log_verbose("polycube structure: " + f.dump());
    return s;
  } catch (const core::TopologyError& e) {
    throw core::TopologyError(std::string("polycube: split's decomposition cannot be realized as a polycube: ") + e.what());
  }
}

// The stage file — kind, surface, classification and decomposition as split wrote them, the kind's
// `members` and the structure — and polycube_structure.vtu; the report figures with the
// structure's counts (cubes, tori, virtual_components, gluings, contacts).
void write_stage(pipeline::StageContext& ctx, const core::Json& j, const std::string& kind, core::Json members,
                 const polycube::Structure& s, core::Json& report) {
  members["kind"] = kind;
  for (const char* key : {"surface", "classification", "decomposition"}) members[key] = j[key];
  members["structure"] = polycube::to_json(s);
  core::write_stage_file(ctx.output_file(), "volts-polycube", 2, std::move(members));
  polycube::write_structure_vtu(ctx.path("polycube_structure.vtu"), s);
  report.update(polycube::report_figures(s));
}

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
void map_torus(pipeline::StageContext& ctx, const split::Decomposition& d, const std::string& what, const polycube::Params& params,
               polycube::TorusSurfaceMap& m, volmap::VolumeMap& vm) {
  {
    core::LogSection s(what + "surface map");
    polycube::PatchMapParams pp;
    pp.weights = ctx.config.polycube.weights;
    pp.sharp_lines = ctx.config.polycube.sharp_lines;
    pp.profile = ctx.config.polycube.profile;
    m = polycube::map_torus_surface(d, pp);
    // A profile tmesh cannot pillow conformingly keeps the square ring, which runs, with the sharp
    // curves flattened inside faces. (Since session 12 profile_blocks takes every edge-connected
    // profile tried, all 218 of a 3 x 3 grid: a safety net, not a known case.)
    const polycube::Profile& pr = m.embedding.profile;
    if (!pr.empty()) try {
        tmesh::profile_blocks(pr.cells, 1 << ctx.config.tmesh.level, ctx.config.tmesh.pillow_layers);
      } catch (const core::TopologyError& e) {
        core::log_warning(what + "the rectilinear cross section cannot be pillowed yet (" + e.what() + "): mapped onto the square ring");
        pp.profile = "square";
        m = polycube::map_torus_surface(d, pp);
      }
  }
  {
    core::LogSection s(what + "volume map");
    vm = polycube::torus_volume_map(d, m, params);
  }
  warn_if_flipped(what, m.flipped_surface_triangles, vm);
}

// The stage file of a polycube with one volume map, its surface views (`surface_view(path,
// mapped)`) and the tets in physical and polycube space.
void write_with_volume_map(pipeline::StageContext& ctx, const core::Json& j, const std::string& kind, const core::Json& polycube,
                           const volmap::VolumeMap& vm, const polycube::Structure& structure, core::Json& report,
                           const std::function<void(const std::string&, bool)>& surface_view) {
  core::LogSection s("write");
  // The files share nothing: written side by side (each to a temporary name first; the first
  // failure is rethrown once all are done).
  core::parallel_tasks({[&] { write_stage(ctx, j, kind, {{"polycube", polycube}, {"volume_map", volmap::to_json(vm)}}, structure, report); },
                        [&] { surface_view(ctx.path("polycube.vtp"), false); },
                        [&] { surface_view(ctx.path("polycube_mapped.vtp"), true); },
                        [&] { volmap::write_vtu(ctx.path("polycube_tets.vtu"), vm); },
                        [&] { volmap::write_parameter_vtu(ctx.path("polycube_tets_mapped.vtu"), vm); }});
}

// A torus (Liu et al. §4.2, Fig. 5(b)): patch maps on the ring embedding, then the harmonic volume
// map of the tet mesh onto it, untangled (§4.3).
core::Json torus(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  const polycube::Structure structure = checked_structure(d);
  polycube::TorusSurfaceMap m;
  volmap::VolumeMap vm;
  map_torus(ctx, d, "", ctx.config.polycube, m, vm);
  core::Json r = volmap::report_figures(vm);
  write_with_volume_map(ctx, j, "torus", polycube::to_json(m), vm, structure, r,
                        [&](const std::string& path, bool mapped) { polycube::write_torus_vtp(path, d, m, mapped); });
  r["flipped_surface_triangles"] = m.flipped_surface_triangles;
  r["max_angle_distortion_deg"] = m.max_angle_distortion_deg;
  // A rectilinear cross section: cubes per sector (grid cells) and its concave corners; 1 and 0 for the square.
  r["profile_cells"] = m.embedding.profile.empty() ? 1 : static_cast<int>(m.embedding.profile.cells.size());
  r["concave_corners"] = m.embedding.profile.concave_corners;
  return r;
}

// Two tori united on a filled disk (Liu et al. §4.2, Fig. 6(c)): each torus with the disk is
// mapped like a single torus, on its own ring; the disk gets one (independent) image per ring (in
// the structure: a non-conforming contact, no gluing).
core::Json tori(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  const std::vector<polycube::Ring> rings = polycube::rings(d);
  const polycube::Structure structure = checked_structure(d);
  std::vector<polycube::TorusSurfaceMap> ms(rings.size());
  std::vector<volmap::VolumeMap> vms(rings.size());
  std::optional<polycube::Ring> neck = polycube::connector(d);
  polycube::Params params = ctx.config.polycube;
  if (neck) params.smooth_below_ratio = params.connector_smooth_below_ratio;
  // The rings' maps and the connector's are independent: run concurrently (logs in this order).
  std::vector<std::function<void()>> maps_to_make;
  for (std::size_t i = 0; i < rings.size(); ++i)
    maps_to_make.push_back([&, i] { map_torus(ctx, rings[i].decomposition, "ring " + std::to_string(i) + ": ", params, ms[i], vms[i]); });
  polycube::ConnectorMap nm;
  volmap::VolumeMap neck_vm;
  if (neck)
    maps_to_make.push_back([&] {
      {
        core::LogSection s("connector: surface map");
        polycube::PatchMapParams pp;
        pp.weights = ctx.config.polycube.weights;
        nm = polycube::map_connector(*neck, rings[0], pp);
      }
      {
        core::LogSection s("connector: volume map");
        neck_vm = polycube::connector_volume_map(*neck, nm, params);
      }
    });
  core::parallel_tasks(maps_to_make);
  core::Json list = core::Json::array(), figures = core::Json::array();
  std::vector<const volmap::VolumeMap*> maps;
  std::vector<std::array<double, 3>> offsets;
  core::Json r{{"flipped_surface_triangles", 0}, {"max_angle_distortion_deg", 0.0}, {"tets", 0}, {"flipped_tets", 0},
               {"flipped_tets_before_untangling", 0}};
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
  // A connector cube between the tori (split.genus2: connector): mapped onto the unit cube.
  core::Json connectors = core::Json::array();
  if (neck) {
    warn_if_flipped("connector: ", nm.flipped_surface_triangles, neck_vm);
    connectors.push_back(polycube::to_json(*neck, nm, neck_vm));
    maps.push_back(&neck_vm);
    offsets.push_back({polycube::kRingSpacing * static_cast<double>(rings.size()), 0, 0});
    core::Json f = volmap::report_figures(neck_vm);
    f["flipped_surface_triangles"] = nm.flipped_surface_triangles;
    f["max_angle_distortion_deg"] = nm.max_angle_distortion_deg;
    r["connector"] = f;
    r["flipped_surface_triangles"] = r["flipped_surface_triangles"].get<int>() + nm.flipped_surface_triangles;
    r["max_angle_distortion_deg"] = std::max(r["max_angle_distortion_deg"].get<double>(), nm.max_angle_distortion_deg);
    r["tets"] = r["tets"].get<std::size_t>() + neck_vm.tets.size();
    r["flipped_tets"] = r["flipped_tets"].get<int>() + neck_vm.flipped_tets;
    r["flipped_tets_before_untangling"] = r["flipped_tets_before_untangling"].get<int>() + neck_vm.flipped_tets_before_untangling;
    r["min_volume_ratio"] = std::min(r["min_volume_ratio"].get<double>(), neck_vm.min_volume_ratio);
  }
  {
    core::LogSection s("write");
    core::Json members{{"rings", list}};
    if (neck) members["connectors"] = connectors;
    // As in write_with_volume_map: side by side.
    core::parallel_tasks({[&] { write_stage(ctx, j, "tori", std::move(members), structure, r); },
                          [&] { polycube::write_rings_vtp(ctx.path("polycube.vtp"), rings, ms, false); },
                          [&] { polycube::write_rings_vtp(ctx.path("polycube_mapped.vtp"), rings, ms, true); },
                          [&] { volmap::write_vtu(ctx.path("polycube_tets.vtu"), maps, offsets, "ring"); },
                          [&] { volmap::write_parameter_vtu(ctx.path("polycube_tets_mapped.vtu"), maps, offsets, "ring"); }});
  }
  return r;
}

// A cube minus k >= 1 through holes along one axis (Liu et al. §4.2 difference, §4.3): the solid
// (fills excluded) onto the unit cube minus the holes' boxes, surface then volume.
core::Json difference(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  polycube::DifferenceMap m;
  {
    core::LogSection s("surface map");
    polycube::PatchMapParams pp;
    pp.weights = ctx.config.polycube.weights;
    m = polycube::map_difference_surface(d, pp);
  }
  const polycube::Structure structure = checked_structure(d, &m);
  volmap::VolumeMap vm;
  {
    core::LogSection s("volume map");
    vm = polycube::difference_volume_map(d, m, ctx.config.polycube);
  }
  warn_if_flipped("", m.flipped_surface_triangles, vm);
  core::Json r = volmap::report_figures(vm);
  write_with_volume_map(ctx, j, "difference", polycube::to_json(m), vm, structure, r,
                        [&](const std::string& path, bool mapped) { polycube::write_difference_vtp(path, d, m, mapped); });
  r["hole_axis"] = m.axis;
  const polycube::HoleBox& first = m.holes.at(0);  // hole_width: the first hole's mean width across its axis
  r["hole_width"] = (first.hi[(m.axis + 1) % 3] - first.lo[(m.axis + 1) % 3] + first.hi[(m.axis + 2) % 3] - first.lo[(m.axis + 2) % 3]) / 2;
  r["holes"] = m.holes.size();
  r["flipped_surface_triangles"] = m.flipped_surface_triangles;
  r["max_angle_distortion_deg"] = m.max_angle_distortion_deg;
  return r;
}

// A torus standing on a cube minus through holes (the assembly, Liu et al. 2013 Fig. 1; split's
// union): the ring (the torus closed by its foot) mapped as a torus, the base (the cube minus holes
// closed by the foot) as a difference whose foot is a rectangle of its holed face, concurrently.
// The foot is a contact of the ring cube's face and that rectangle's face (tmesh does not glue it yet).
core::Json torus_on_cube(pipeline::StageContext& ctx, const core::Json& j, const split::Decomposition& d) {
  const polycube::TorusOnCube pieces = polycube::torus_on_cube(d);
  const split::Decomposition& base = pieces.base.decomposition;
  polycube::TorusSurfaceMap rm;
  volmap::VolumeMap rvm, bvm;
  polycube::DifferenceMap bm;
  core::parallel_tasks({[&] { map_torus(ctx, pieces.ring.decomposition, "ring: ", ctx.config.polycube, rm, rvm); },
                        [&] {
                          {
                            core::LogSection s("base: surface map");
                            polycube::PatchMapParams pp;
                            pp.weights = ctx.config.polycube.weights;
                            bm = polycube::map_difference_surface(base, pp, pieces.foot_patch);
                          }
                          core::LogSection s("base: volume map");
                          bvm = polycube::difference_volume_map(base, bm, ctx.config.polycube);
                        }});
  warn_if_flipped("base: ", bm.flipped_surface_triangles, bvm);
  // The structure in the whole decomposition's ids (the base keeps its components' order).
  polycube::DifferenceMap whole = bm;
  whole.cube = pieces.base.component.at(static_cast<std::size_t>(bm.cube));
  for (auto& h : whole.holes) h.virtual_component = pieces.base.component.at(static_cast<std::size_t>(h.virtual_component));
  const polycube::Structure structure = checked_structure(d, &whole);
  core::Json r{{"flipped_surface_triangles", rm.flipped_surface_triangles + bm.flipped_surface_triangles},
               {"max_angle_distortion_deg", std::max(rm.max_angle_distortion_deg, bm.max_angle_distortion_deg)},
               {"tets", rvm.tets.size() + bvm.tets.size()},
               {"flipped_tets", rvm.flipped_tets + bvm.flipped_tets},
               {"flipped_tets_before_untangling", rvm.flipped_tets_before_untangling + bvm.flipped_tets_before_untangling},
               {"min_volume_ratio", std::min(rvm.min_volume_ratio, bvm.min_volume_ratio)},
               {"holes", bm.holes.size()},
               {"foot_lo", bm.foot->lo},
               {"foot_hi", bm.foot->hi}};
  for (const auto& [key, sm_flipped, sm_angle, vm] :
       {std::tuple{"ring", rm.flipped_surface_triangles, rm.max_angle_distortion_deg, &rvm}, {"base", bm.flipped_surface_triangles, bm.max_angle_distortion_deg, &bvm}}) {
    core::Json f = volmap::report_figures(*vm);
    f["flipped_surface_triangles"] = sm_flipped;
    f["max_angle_distortion_deg"] = sm_angle;
    r[key] = f;
  }
  core::Json base_json{{"components", pieces.base.component},
                       {"layout_vertex", pieces.base.layout_vertex},
                       {"layout_triangle", pieces.base.layout_triangle},
                       {"foot_patch", pieces.foot_patch},
                       {"polycube", polycube::to_json(bm)},
                       {"volume_map", volmap::to_json(bvm)}};
  core::Json members{{"ring", polycube::to_json(pieces.ring, rm, rvm)},
                     {"base", std::move(base_json)},
                     {"foot_component", pieces.foot_component}};
  const std::vector<polycube::Ring> ring{pieces.ring};
  const std::vector<polycube::TorusSurfaceMap> ring_map{rm};
  const std::vector<const volmap::VolumeMap*> maps{&rvm, &bvm};
  const std::vector<std::array<double, 3>> offsets{{0, 0, 0}, {polycube::kRingSpacing, 0, 0}};
  core::LogSection s("write");
  core::parallel_tasks({[&] { write_stage(ctx, j, "torus_on_cube", std::move(members), structure, r); },
                        [&] { polycube::write_rings_vtp(ctx.path("polycube.vtp"), ring, ring_map, false); },
                        [&] { polycube::write_rings_vtp(ctx.path("polycube_mapped.vtp"), ring, ring_map, true); },
                        [&] { polycube::write_difference_vtp(ctx.path("polycube_base.vtp"), base, bm, false); },
                        [&] { polycube::write_difference_vtp(ctx.path("polycube_base_mapped.vtp"), base, bm, true); },
                        [&] { volmap::write_vtu(ctx.path("polycube_tets.vtu"), maps, offsets, "piece"); },
                        [&] { volmap::write_parameter_vtu(ctx.path("polycube_tets_mapped.vtu"), maps, offsets, "piece"); }});
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  return pipeline::run_stage(argc, argv, "polycube",
      "Stage 3 (Liu et al. 2013 §4.2-4.3): build the polycube and map the surface onto it\n"
      "(bijective disk map per patch). Input: DIR/split.stage.json. Output: DIR/polycube.stage.json,\n"
      "DIR/polycube_structure.vtu (the polycube's cubes and virtual components as hexahedra),\n"
      "DIR/polycube.vtp (surface with cube coordinates 'uvw'), DIR/polycube_mapped.vtp (the surface on the cube);\n"
      "tori also DIR/polycube_tets.vtu and DIR/polycube_tets_mapped.vtu (the volume map's tets, physical and mapped);\n"
      "two tori meeting on a disk: one ring per torus (cell field 'ring'; ring i drawn 5i along x when mapped);\n"
      "a cube minus through holes: the unit cube minus the holes' boxes (polycube.hole_lo/hole_hi, several holes:\n"
      "polycube.holes), tets too; a torus standing on such a cube (the assembly): the ring as polycube.vtp, the base\n"
      "(its foot a rectangle of a holed face) as DIR/polycube_base.vtp and DIR/polycube_base_mapped.vtp.",
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
        // A torus standing on a cube minus holes (split_torus_on_cube: the assembly).
        if (!d.tori.empty())
          for (const auto& comp : d.components)
            if (comp.type == split::ComponentType::virtual_component) return torus_on_cube(ctx, j, d);
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
        const polycube::Structure structure = checked_structure(d);
        core::Json r = polycube::report_figures(p, d);
        {
          core::LogSection s("write");
          write_stage(ctx, j, "cube", {{"polycube", polycube::to_json(p)}}, structure, r);
          polycube::write_vtp(ctx.path("polycube.vtp"), mesh, c, p);
          polycube::write_mapped_vtp(ctx.path("polycube_mapped.vtp"), mesh, c, p);
        }
        return r;
      });
}
