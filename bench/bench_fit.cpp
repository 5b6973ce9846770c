// Benchmark (not a test) of route `fit` (Lin, Huang & Hu 2018; issue 9) in one process: per model,
// classify → map onto the cube → seven pillowed solids → GFD fitting → extract's Bézier extraction
// and quality figures, printed against the targets (all seven solids certified valid,
// scaled Jacobian > 0.5 on >= 80 % of the volume, hausdorff_rel <= 0.005) with the G1 defect.
// Usage: bench_fit [--models sphere,bulged-box,fandisk] [--elements N] [--sweeps N] [--resolution N]
// Models: generated names (volts-make-model --list) or `fandisk` (../shared/models/c3d_fandisk.obj).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "classify/classify.h"
#include "core/errors.h"
#include "core/log.h"
#include "extract/extract.h"
#include "bezier/bspline_volume.h"
#include "fit/route.h"
#include "tmesh/optimize.h"
#include "tmesh/pillow.h"
#include "models/models.h"
#include "surface/surface.h"

using namespace volts;

int main(int argc, char** argv) {
  std::vector<std::string> models = {"sphere", "bulged-box", "fandisk"};
  fit::Params params;
  int resolution = 16;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--models") {
      models.clear();
      std::stringstream s(v);
      for (std::string m; std::getline(s, m, ',');) models.push_back(m);
    } else if (a == "--elements") params.pillow.elements = std::stoi(v);
    else if (a == "--sweeps") params.gfd.sweeps = std::stoi(v);
    else if (a == "--g1-sweeps") params.gfd.g1_sweeps = std::stoi(v);
    else if (a == "--resolution") resolution = std::stoi(v);
    else if (a == "--tet-max-volume-rel") params.cube.tet_max_volume_rel = std::stod(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  std::printf("%-11s %8s %6s %9s %9s %9s %9s %9s %8s %8s %8s\n", "model", "elements", "valid", "min SJ", "vol>0.5", "hausdorff", "vol err",
              "G1 max°", "map s", "fit s", "total s");
  for (const auto& name : models) {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      surface::Mesh mesh;
      if (name == "fandisk") mesh = surface::read_surface(VOLTS_SHARED_MODELS "/c3d_fandisk.obj");
      else {
        models::ModelParams mp;
        mp.name = name;
        mp.resolution = resolution;
        mesh = models::make_model(mp);
      }
      const classify::Classification c = classify::classify(mesh, classify::Params{});
      fit::Result r = fit::run(mesh, c, params);
      if (std::getenv("VOLTS_BENCH_FIT_OPTIMIZE")) {
        tmesh::OptimizeParams op;
        op.sweeps = std::atoi(std::getenv("VOLTS_BENCH_FIT_OPTIMIZE"));
        const auto o = tmesh::optimize(r.solids, op);
        std::printf("  optimize: min %.3f -> %.3f, invalid %d -> %d, %d nodes, %s\n", o.min_before, o.min_after, o.invalid_before, o.invalid_after,
                    o.nodes_moved, o.stop_reason.c_str());
      }
      const extract::Result e = extract::extract(r.solids, mesh, extract::Params{});
      const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%-11s %8zu %6d %9.3f %9.3f %9.2e %9.2e %9.2f %8.1f %8.1f %8.1f\n", name.c_str(), e.hexes.size(), e.certified_valid,
                  e.min_scaled, e.volume_frac_scaled_jacobian_above_0_5, e.hausdorff_rel, e.volume_rel_error,
                  fit::report_figures(r)["g1_max_angle_deg_after"].get<double>(), r.time_map_s, r.time_fit_s, total);
      if (std::getenv("VOLTS_BENCH_FIT_VERBOSE")) {
        std::size_t worst = 0;
        for (std::size_t i = 0; i < e.boundary_distance.size(); ++i)
          if (e.boundary_distance[i] > e.boundary_distance[worst]) worst = i;
        const auto x = bezier::evaluate(e.hexes[worst], Eigen::Vector3d(0.5, 0.5, 0.5));
        std::printf("  worst boundary element %zu (of %zu), distance %.3e, centre (%.3f %.3f %.3f)\n", worst, e.hexes.size(),
                    e.boundary_distance[worst], x[0], x[1], x[2]);
        std::printf("  %s\n", fit::report_figures(r).dump().c_str());
        // Debug: the outer faces of the slabs: spline vs map at the same parameters.
        volmap::Locator loc(r.cube.volume);
        for (std::size_t b = 1; b < r.solids.size(); ++b) {
          const auto& t = r.solids[b];
          bezier::TensorBSplineVolume v;
          v.knots = t.knots;
          v.degree = {t.degree, t.degree, t.degree};
          for (const auto& x : t.control_points) v.points.emplace_back(x[0], x[1], x[2]);
          int axis = -1, side = 0;
          for (int f = 0; f < 6; ++f) if (t.boundary[f]) axis = f / 2, side = f % 2;
          double worst = 0, wu = 0, wv = 0;
          for (int i = 0; i <= 40; ++i)
            for (int j = 0; j <= 40; ++j) {
              Eigen::Vector3d uvw;
              uvw[axis] = side;
              uvw[(axis + 1) % 3] = i / 40.0;
              uvw[(axis + 2) % 3] = j / 40.0;
              const auto x = bezier::evaluate(v, uvw);
              const auto q = *loc.physical(tmesh::block_point(t.corners, {uvw[0], uvw[1], uvw[2]}));
              const double d = (x - Eigen::Vector3d(q[0], q[1], q[2])).norm();
              if (d > worst) worst = d, wu = i / 40.0, wv = j / 40.0;
            }
          std::printf("  solid %zu face axis %d side %d: max |spline - map| %.3e at (%.3f, %.3f)\n", b, axis, side, worst, wu, wv);
          for (double c : {0.4, 0.45, 0.49, 0.5, 0.51, 0.55}) {
            Eigen::Vector3d uvw;
            uvw[axis] = side, uvw[(axis + 1) % 3] = c, uvw[(axis + 2) % 3] = 0.5;
            const auto x = bezier::evaluate(v, uvw);
            const auto q = *loc.physical(tmesh::block_point(t.corners, {uvw[0], uvw[1], uvw[2]}));
            std::printf("    c %.2f spline |x| %.4f map |q| %.4f  q (%.3f %.3f %.3f)\n", c, x.norm(), Eigen::Vector3d(q[0], q[1], q[2]).norm(), q[0], q[1], q[2]);
          }
        }
      }
    } catch (const std::exception& x) {
      std::printf("%-11s FAILED: %s\n", name.c_str(), x.what());
    }
  }
  return 0;
}
