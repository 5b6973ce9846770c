// Benchmark (not a test) of the tet route against Gmsh's all-hex route on the same surfaces, in the
// same run: cinolib_torus.obj, cfwen_eight.off, loopycuts_rod_rem.obj (../shared/models) and the
// generated tetrahedron and cone.
//   volts: TetGen tets → cubic Bézier tets → 4 hexes each (Xu et al. 2018), tet2hex::run defaults.
//   Gmsh:  the same surface as a discrete STL volume, Delaunay tets split into hexes
//          (Mesh.SubdivisionAlgorithm = 2), order 3 (64-node Lagrange hexes), converted to Bézier
//          hexes by interpolation at Gmsh's own reference node coordinates (getElementProperties).
// Both are measured by the same code: bezier::certify, scaled Jacobian sampled at corners and Gauss
// points, hausdorff_rel sampled on the boundary faces (one-sided, hex boundary → input surface).
// Usage: bench_tet_route [MODELS_DIR]   (default ../shared/models next to the source tree)
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "bezier/bernstein.h"
#include "bezier/certify.h"
#include "core/log.h"
#include "models/models.h"
#include "surface/surface.h"
#include "tet2hex/tet2hex.h"

using namespace volts;
namespace fs = std::filesystem;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<surface::Kernel, CGAL::AABB_face_graph_triangle_primitive<surface::Mesh>>>;

namespace {

struct Row {
  std::string route;
  std::size_t elements = 0, valid = 0;
  double min_sj = 0, hausdorff_rel = 0, seconds = 0;
};

// Gmsh runs in its own process (bench_gmsh_hex): libgmsh carries its own TetGen, whose symbols
// would replace libtet's in a process linking both.
Row gmsh_route(const surface::Mesh& s, const fs::path& work, bool straight) {
  Row row{straight ? "gmsh strt" : "gmsh", 0, 0, 1, 0, 0};
  const fs::path stl = work / "surface.stl", out = work / "gmsh_hexes.txt";
  surface::write_surface(stl.string(), s);
  const std::string cmd = std::string(VOLTS_GMSH_HELPER) + " " + stl.string() + " " + out.string() + (straight ? " straight" : "");
  if (std::system(cmd.c_str()) != 0) {
    std::fprintf(stderr, "bench: %s failed\n", cmd.c_str());
    return row;
  }
  std::ifstream in(out);
  std::size_t n = 0;
  in >> row.seconds >> n;
  const int p = 3;
  std::vector<bezier::BezierHex> hexes(n);
  std::vector<std::array<int, 6>> boundary(n);
  for (std::size_t e = 0; e < n; ++e) {
    hexes[e].degree = {p, p, p};
    hexes[e].points.resize(64);
    for (auto& x : hexes[e].points) in >> x[0] >> x[1] >> x[2];
    for (auto& b : boundary[e]) in >> b;
  }
  row.elements = n;
  Tree tree(faces(s).first, faces(s).second, s);
  tree.accelerate_distance_queries();
  double worst = 0;
  for (std::size_t e = 0; e < n; ++e)
    for (int f = 0; f < 6; ++f) {
      if (!boundary[e][f]) continue;
      const int axis = f / 2, side = f % 2;
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) {
          Eigen::Vector3d uvw;
          uvw[axis] = side, uvw[(axis + 1) % 3] = a / 7.0, uvw[(axis + 2) % 3] = b / 7.0;
          const Eigen::Vector3d x = bezier::evaluate(hexes[e], uvw);
          worst = std::max(worst, std::sqrt(tree.squared_distance(surface::Point(x[0], x[1], x[2]))));
        }
    }
  row.hausdorff_rel = worst / surface::bbox_diagonal(s);
  for (const auto& h : hexes) {
    row.min_sj = std::min(row.min_sj, bezier::sample_jacobian(h, p + 1).min_scaled);
    row.valid += bezier::certify(h).status == bezier::Validity::valid;
  }
  return row;
}

Row volts_route(const surface::Mesh& s) {
  core::Stopwatch watch;
  const tet2hex::Result r = tet2hex::run(s, tet2hex::Params{});
  return {"volts tet", r.hexes.size(), static_cast<std::size_t>(r.certified_valid), r.min_scaled, r.hausdorff_rel, watch.seconds()};
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path models = argc > 1 ? fs::path(argv[1]) : fs::path(VOLTS_SOURCE_DIR) / ".." / "shared" / "models";
  core::set_log_level(core::LogLevel::quiet);
  const fs::path work = fs::temp_directory_path() / ("volts_bench_tet_" + std::to_string(::getpid()));
  fs::create_directories(work);
  std::vector<std::pair<std::string, surface::Mesh>> inputs;
  for (const char* f : {"cinolib_torus.obj", "cfwen_eight.off", "loopycuts_rod_rem.obj"}) inputs.emplace_back(f, surface::read_surface((models / f).string()));
  for (const char* g : {"tetrahedron", "cone"}) {
    models::ModelParams mp;
    mp.name = g;
    inputs.emplace_back(std::string(g) + " (generated, 16)", models::make_model(mp));
  }
  std::printf("%-28s %-10s %9s %9s %8s %10s %11s %9s\n", "surface", "route", "triangles", "hexes", "valid%", "min SJ", "hausdorff", "time s");
  for (const auto& [name, s] : inputs) {
    for (const Row& row : {volts_route(s), gmsh_route(s, work, false), gmsh_route(s, work, true)})
      std::printf("%-28s %-10s %9zu %9zu %8.2f %10.4f %11.2e %9.2f\n", name.c_str(), row.route.c_str(), static_cast<std::size_t>(s.number_of_faces()), row.elements,
                  row.elements ? 100.0 * row.valid / row.elements : 0.0, row.min_sj, row.hausdorff_rel, row.seconds);
  }
  fs::remove_all(work);
  std::printf("\nvolts time: TetGen + conversion + certification + measures; gmsh time: meshing (tets, split, order 3) only.\n"
              "valid%%: certified det J > 0 (bezier::certify); min SJ: sampled at corners and Gauss points; hausdorff: sampled, one-sided.\n");
  return 0;
}
