// Benchmark (not a test) of the refinement rules that make the polynomial T-spline basis of an
// adaptive octree T-mesh a partition of unity (tspline/suitable.h): per family of refinements
// (toward a point, a plane, a sphere surface, random predicates with fixed seeds) and max level
// 3–5, the 2:1 balanced tree is refined by each rule and the table gives leaves before/after,
// functions, Bézier elements, Σ N error (TSpline::partition_of_unity_error), the identity error of
// Greville control points (polynomial: exact on the Bézier coefficients and at random points;
// rational Σ R_i g_i at random points) and the rule's time (refinement only).
// Usage: bench_tspline [--levels 3,4,5] [--rules none,vertex,graded2,repair,slab,uniform] [--samples N]
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "octree/octree.h"
#include "tspline/suitable.h"
#include "tspline/tspline.h"

using namespace volts;
using octree::Cell;
using octree::Octree;

namespace {

bool random_split(const Cell& c, std::uint64_t seed, double p) {
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ull + std::uint64_t(c.level) * 0xBF58476D1CE4E5B9ull +
                    (std::uint64_t(c.lo[0]) << 40) + (std::uint64_t(c.lo[1]) << 20) + std::uint64_t(c.lo[2]);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return (x >> 11) * 0x1.0p-53 < p;
}

using Predicate = std::function<bool(const Cell&)>;

std::vector<std::pair<std::string, Predicate>> families() {
  std::vector<std::pair<std::string, Predicate>> out;
  out.push_back({"point", [](const Cell& c) {
                   const octree::Vec3 q{0.3, 0.61, 0.77};
                   for (int a = 0; a < 3; ++a)
                     if (q[a] < c.unit_lo[a] || q[a] > c.unit_hi[a]) return false;
                   return true;
                 }});
  out.push_back({"plane", [](const Cell& c) {  // x + 2y - z = 0.7
                   double mn = 1e9, mx = -1e9;
                   for (int k = 0; k < 8; ++k) {
                     const double s = (k & 1 ? c.unit_hi[0] : c.unit_lo[0]) + 2 * (k & 2 ? c.unit_hi[1] : c.unit_lo[1]) -
                                      (k & 4 ? c.unit_hi[2] : c.unit_lo[2]) - 0.7;
                     mn = std::min(mn, s);
                     mx = std::max(mx, s);
                   }
                   return mn <= 0 && mx >= 0;
                 }});
  out.push_back({"sphere", [](const Cell& c) {  // cells meeting |x - m| = 0.3
                   const octree::Vec3 m{0.45, 0.5, 0.55};
                   double near = 0, far = 0;
                   for (int a = 0; a < 3; ++a) {
                     const double d = std::max({c.unit_lo[a] - m[a], 0.0, m[a] - c.unit_hi[a]});
                     const double e = std::max(std::abs(m[a] - c.unit_lo[a]), std::abs(m[a] - c.unit_hi[a]));
                     near += d * d;
                     far += e * e;
                   }
                   return std::sqrt(near) <= 0.3 && 0.3 <= std::sqrt(far);
                 }});
  for (std::uint64_t seed = 1; seed <= 2; ++seed)
    out.push_back({"random" + std::to_string(seed),
                   [seed](const Cell& c) { return c.level == 0 || random_split(c, seed, 0.25); }});
  return out;
}

// Max |Σ N_i g_i - u| and |Σ R_i g_i - u| at random points.
std::pair<double, double> random_identity_errors(const tspline::TSpline& ts, int samples) {
  const std::vector<Eigen::Vector3d> g = tspline::greville_points(ts);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double poly = 0, rat = 0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector3d u(U(rng), U(rng), U(rng));
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (const auto& [i, v] : ts.basis(u)) x += v * g[i];
    poly = std::max(poly, (x - u).cwiseAbs().maxCoeff());
    rat = std::max(rat, (ts.evaluate(g, u) - u).cwiseAbs().maxCoeff());
  }
  return {poly, rat};
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
        const auto [poly, rat] = random_identity_errors(ts, samples);
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
