// Benchmark (not a test) of route `fit` (Lin, Huang & Hu 2018; issue 9) in one process: per model,
// classify → map onto the cube → seven pillowed solids → GFD fitting → extract's Bézier extraction
// and quality figures, printed against the targets (all seven solids certified valid,
// scaled Jacobian > 0.5 on >= 80 % of the volume, hausdorff_rel <= 0.005) with the G1 defect.
// Usage: bench_fit [--models sphere,bulged-box,fandisk] [--elements N] [--sweeps N] [--g1-sweeps N]
//                  [--resolution N] [--optimize SWEEPS] [--tet-max-volume-rel X]
//                  [--smoothness X] [--weights mean-value|uniform] [--start-rounds N]
//                  [--fairness-sweeps N]; VOLTS_BENCH_FIT_VERBOSE=1 adds
//                  the worst boundary element and the whole fit report per model.
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
#include "fit/route.h"
#include "models/models.h"
#include "surface/surface.h"

using namespace volts;

int main(int argc, char** argv) {
  std::vector<std::string> models = {"sphere", "bulged-box", "fandisk"};
  fit::Params params;
  int resolution = 64;  // the sphere at 16 is faceted enough to cost hausdorff_rel 7e-3 by itself
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h" || i + 1 == argc) {
      std::fprintf(a == "--help" || a == "-h" ? stdout : stderr,
                   "usage: bench_fit [--models sphere,bulged-box,fandisk] [--elements N] [--sweeps N] [--g1-sweeps N]\n"
                   "                 [--resolution N] [--optimize SWEEPS] [--tet-max-volume-rel X] [--smoothness X]\n"
                   "                 [--weights mean-value|uniform] [--start-rounds N]\n"
                   "                 [--fairness-sweeps N]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
    const std::string v = argv[i + 1];
    if (a == "--models") {
      models.clear();
      std::stringstream s(v);
      for (std::string m; std::getline(s, m, ',');) models.push_back(m);
    } else if (a == "--elements") params.pillow.elements = std::stoi(v);
    else if (a == "--sweeps") params.gfd.sweeps = std::stoi(v);
    else if (a == "--g1-sweeps") params.gfd.g1_sweeps = std::stoi(v);
    else if (a == "--fairness-sweeps") params.gfd.fairness_sweeps = std::stoi(v);
    else if (a == "--resolution") resolution = std::stoi(v);
    else if (a == "--optimize") params.optimize_sweeps = std::stoi(v);
    else if (a == "--smoothness") params.cube.segmentation.smoothness = std::stod(v);
    else if (a == "--weights") params.cube.weights = v;
    else if (a == "--tet-max-volume-rel") params.cube.tet_max_volume_rel = std::stod(v);
    else if (a == "--start-rounds") params.gfd.start_rounds = std::stoi(v);
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
      const fit::Result r = fit::run(mesh, c, params);
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
      }
    } catch (const std::exception& x) {
      std::printf("%-11s FAILED: %s\n", name.c_str(), x.what());
    }
  }
  return 0;
}
