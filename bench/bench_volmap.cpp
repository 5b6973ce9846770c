// Benchmark of the volume map (volts::volmap): builds the map of a torus onto the square ring
// (outer [-2,2]^2, inner [-1,1]^2, height [0,1]) for the generated torus and cinolib_torus.obj, at
// TetGen's default density and a finer one (and the generated torus at resolution 48), then times 1,000,000 random point-location queries
// (parameter -> physical) on one thread. Run by hand: build/bench/bench_volmap [queries].
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/log.h"
#include "models/models.h"
#include "volmap/volmap.h"

using namespace volts;
using UVW = std::array<double, 3>;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::array<double, 2> on_loop(double s, const std::array<std::array<double, 2>, 4>& c) {
  const int k = std::min(3, static_cast<int>(std::floor(4 * s)));
  const double f = 4 * s - k;
  const auto &a = c[k], &b = c[(k + 1) % 4];
  return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])};
}

double turns_from_45(double angle) {
  double s = angle / (2 * kPi) - 0.125;
  s -= std::floor(s);
  s = std::round(s * 5760) / 5760;
  return s >= 1 ? s - 1 : s;
}

// The grid torus (major radius R) onto the ring's boundary, corners on grid lines (as in tests/volmap).
std::vector<UVW> ring_boundary_map(const surface::Mesh& s, double R) {
  std::vector<UVW> r(s.number_of_vertices());
  for (auto v : s.vertices()) {
    const auto& p = s.point(v);
    const auto hz = on_loop(turns_from_45(std::atan2(p.z(), std::hypot(p.x(), p.y()) - R)), {{{2, 1}, {1, 1}, {1, 0}, {2, 0}}});
    const double h = hz[0];
    const auto xy = on_loop(turns_from_45(std::atan2(p.y(), p.x())), {{{h, h}, {-h, h}, {-h, -h}, {h, -h}}});
    r[static_cast<int>(v)] = {xy[0], xy[1], hz[1]};
  }
  return r;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void run(const std::string& name, const surface::Mesh& mesh, double R, double max_volume_rel, int queries) {
  volmap::Params p;
  p.tetgen.max_volume_rel = max_volume_rel;
  auto t0 = std::chrono::steady_clock::now();
  const volmap::VolumeMap m = volmap::harmonic_volume_map(mesh, ring_boundary_map(mesh, R), p);
  const double t_map = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const volmap::Locator loc(m);
  const double t_tree = seconds_since(t0);

  // Random points of the ring's bounding box: 3/4 of them inside the ring, the rest in the hole
  // (located as outside: nullopt), as the T-mesh stage may ask near the boundary.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> xy(-2, 2), z(0, 1);
  std::vector<UVW> pts(queries);
  for (auto& q : pts) q = {xy(rng), xy(rng), z(rng)};
  int found = 0;
  double checksum = 0;
  t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  for (const auto& q : pts) {
    const auto x = loc.physical(q);
    if (x) ++found, checksum += (*x)[0];
  }
  const double t_q = seconds_since(t0), cpu_q = double(std::clock() - c0) / CLOCKS_PER_SEC;
  std::printf("%-14s max_volume_rel %-6g tets %7zu  flipped %3d -> %d%s  min_volume_ratio %.2g  map %.2f s  tree %.3f s\n",
              name.c_str(), max_volume_rel, m.tets.size(), m.flipped_tets_before_untangling, m.flipped_tets,
              m.untangle_joint ? " (joint)" : "", m.min_volume_ratio, t_map, t_tree);
  std::printf("%-14s %d queries in %.3f s wall, %.3f s CPU = %.0f queries/s (CPU) (%d inside, checksum %.6g)\n", "", queries, t_q,
              cpu_q, queries / cpu_q, found, checksum);
}

}  // namespace

int main(int argc, char** argv) {
  const int queries = argc > 1 ? std::stoi(argv[1]) : 1000000;
  core::set_log_level(core::LogLevel::quiet);
  models::ModelParams mp;
  mp.name = "torus";
  mp.resolution = 24;  // 64 x 24 grid: the ring's corners on grid lines
  const surface::Mesh torus = models::make_model(mp);
  const surface::Mesh cinolib = surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/cinolib_torus.obj");
  for (double rel : {0.0, 1e-4}) {
    run("torus", torus, 2.0, rel, queries);
    run("cinolib_torus", cinolib, 3.0, rel, queries);
  }
  mp.resolution = 48;  // 128 x 48 grid: the harmonic map folds more, the joint untangling runs
  run("torus-48", models::make_model(mp), 2.0, 0.0, queries);
  return 0;
}
