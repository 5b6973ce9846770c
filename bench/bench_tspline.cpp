// Benchmark (not a test) of the refinement rules that make the polynomial T-spline basis of an
// adaptive octree T-mesh a partition of unity (tspline/suitable.h): per family of refinements
// (toward a point, a plane, a sphere surface, random predicates with fixed seeds) and max level
// 3–5, the 2:1 balanced tree is refined by each rule and the table gives leaves before/after,
// functions, Bézier elements, Σ N error (TSpline::partition_of_unity_error), the identity error of
// Greville control points (polynomial: exact on the Bézier coefficients and at random points;
// rational Σ R_i g_i at random points) and the rule's time (refinement only).
// Usage: bench_tspline [--levels 3,4,5] [--rules none,vertex,graded2,repair,slab,uniform] [--samples N]
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "common/octree_families.h"
#include "octree/octree.h"
#include "octree/refine.h"
#include "tspline/suitable.h"
#include "tspline/tspline.h"

using namespace volts;
using octree::Cell;
using octree::Octree;

namespace {

using Predicate = std::function<bool(const Cell&)>;

std::vector<std::pair<std::string, Predicate>> families() {
  std::vector<std::pair<std::string, Predicate>> out;
  out.push_back({"point", test::toward_point});
  out.push_back({"plane", test::toward_plane});
  out.push_back({"sphere", test::toward_sphere});
  for (std::uint64_t seed = 1; seed <= 2; ++seed)
    out.push_back({"random" + std::to_string(seed),
                   [seed](const Cell& c) { return c.level == 0 || octree::random_split(c, seed, 0.25); }});
  return out;
}

std::vector<std::string> split_list(const std::string& v) {
  std::vector<std::string> out;
  std::stringstream s(v);
  for (std::string m; std::getline(s, m, ',');) out.push_back(m);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> levels = {3, 4, 5};
  std::vector<std::string> rules = {"none", "vertex", "graded2", "repair", "slab", "uniform"};
  int samples = 300;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h" || i + 1 == argc) {
      std::fprintf(a == "--help" || a == "-h" ? stdout : stderr,
                   "usage: bench_tspline [--levels 3,4,5] [--rules none,vertex,graded2,repair,slab,uniform] [--samples N]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
    const std::string v = argv[i + 1];
    if (a == "--levels") {
      levels.clear();
      for (const std::string& l : split_list(v)) levels.push_back(std::stoi(l));
    } else if (a == "--rules") {
      rules = split_list(v);
    } else if (a == "--samples") {
      samples = std::stoi(v);
    } else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  std::printf("| family | L | rule | leaves before | leaves after | x | functions | elements | Σ N error | "
              "identity err (Bézier) | Σ N g - u (random) | Σ R g - u (random) | balanced | rule s |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|\n");
  for (const auto& [name, predicate] : families())
    for (int L : levels) {
      Octree base(octree::OctreeParams{L});
      base.refine(predicate);
      base.balance();
      for (const std::string& rule : rules) {
        Octree t = base;
        std::string label = rule;
        const auto t0 = std::chrono::steady_clock::now();
        try {
          if (rule == "vertex") {
            tspline::balance_neighbourhood(t, 1);
          } else if (rule == "graded2") {
            tspline::balance_neighbourhood(t, 2);
          } else if (rule == "repair") {
            int its = 0;
            tspline::repair_partition_of_unity(t, 1e-12, 64, &its);
            label += " (" + std::to_string(its) + " rounds)";
          } else if (rule == "slab") {
            tspline::SuitableReport rep;
            tspline::make_partition_of_unity(t, {}, &rep);
            label += " (axis " + std::to_string(rep.axis) + ", " + std::to_string(rep.repair_iterations) + " repairs)";
          } else if (rule == "uniform") {
            t.refine([](const Cell&) { return true; });
          } else if (rule != "none") {
            std::fprintf(stderr, "unknown rule %s\n", rule.c_str());
            return 2;
          }
        } catch (const std::exception& e) {
          std::printf("| %s | %d | %s | failed: %s |\n", name.c_str(), L, rule.c_str(), e.what());
          continue;
        }
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const tspline::TSpline ts(t);
        const auto [poly, rat] = test::random_identity_errors(ts, samples, 17);
        std::printf("| %s | %d | %s | %zu | %zu | %.2f | %d | %zu | %.2g | %.2g | %.2g | %.2g | %s | %.2f |\n", name.c_str(), L,
                    label.c_str(), base.leaves().size(), t.leaves().size(),
                    double(t.leaves().size()) / double(base.leaves().size()), ts.num_functions(), ts.elements().size(),
                    ts.partition_of_unity_error(), tspline::greville_identity_error(ts), poly, rat,
                    octree::check(t).ok() ? "ok" : "NO", secs);
        std::fflush(stdout);
      }
    }
  return 0;
}
