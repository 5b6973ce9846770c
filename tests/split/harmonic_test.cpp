// Harmonic fields and their critical points (Liu et al. §4.1) over generated and real surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "classify/classify.h"
#include "core/errors.h"
#include "models/models.h"
#include "split/harmonic.h"
#include "split/isoline.h"
#include "split/split.h"

using namespace volts;

namespace {

surface::Mesh shared(const std::string& f) { return surface::read_surface(std::string(VOLTS_SHARED_MODELS) + "/" + f); }
surface::Mesh model(const std::string& name, int res) {
  models::ModelParams p;
  p.name = name;
  p.resolution = res;
  return models::make_model(p);
}

// Vertices with the smallest and largest z.
std::pair<int, int> z_extremes(const surface::Mesh& m) {
  int lo = 0, hi = 0;
  for (auto v : m.vertices()) {
    if (m.point(v).z() < m.point(surface::Mesh::Vertex_index(lo)).z()) lo = static_cast<int>(v);
    if (m.point(v).z() > m.point(surface::Mesh::Vertex_index(hi)).z()) hi = static_cast<int>(v);
  }
  return {lo, hi};
}

}  // namespace

TEST(Harmonic, ConstraintsHoldAndTheFieldIsInsideTheirRange) {
  for (const auto& mesh : {model("torus", 24), model("sphere", 16), shared("cinolib_torus.obj")}) {
    const auto [lo, hi] = z_extremes(mesh);
    const auto f = split::harmonic_field(mesh, {{lo, -1.0}, {hi, 2.0}});
    EXPECT_EQ(f[lo], -1.0);
    EXPECT_EQ(f[hi], 2.0);
    for (double x : f) {
      EXPECT_GE(x, -1.0 - 1e-9);
      EXPECT_LE(x, 2.0 + 1e-9);
    }
  }
}

TEST(Harmonic, OneFactorizationSolvesLinearly) {
  const auto mesh = shared("cfwen_eight.off");
  const split::HarmonicSolver solver(mesh, {3, 100, 500});
  const auto a = solver.solve({0, 1, 0}), b = solver.solve({1, 0, 2}), ab = solver.solve({2, 3, 4});
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(ab[i], 3 * a[i] + 2 * b[i], 1e-9);
  const auto constant = solver.solve({5, 5, 5});
  for (double x : constant) EXPECT_NEAR(x, 5.0, 1e-9);
}

TEST(Harmonic, MorseCountsGiveTheEulerCharacteristicForAnyField) {
  // Holds for every piecewise-linear field with symbolic perturbation: a check of the classifier.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  struct Case { surface::Mesh mesh; int genus; };
  for (const auto& c : {Case{model("sphere", 12), 0}, Case{shared("cinolib_torus.obj"), 1}, Case{shared("cfwen_eight.off"), 2},
                        Case{shared("loopycuts_rod_rem.obj"), 2}}) {
    std::vector<double> f(c.mesh.number_of_vertices());
    for (auto& x : f) x = u(rng);
    EXPECT_EQ(split::critical_points(c.mesh, f).euler_characteristic(), 2 - 2 * c.genus);
    std::vector<double> flat(c.mesh.number_of_vertices(), 1.0);  // all ties: index breaks them
    EXPECT_EQ(split::critical_points(c.mesh, flat).euler_characteristic(), 2 - 2 * c.genus);
  }
}

TEST(Harmonic, HeightLikeFieldOnToriHasOneMinOneMaxAndTwoSaddlesPerHandle) {
  // Liu et al. Fig. 4(a): min and max at the lowest and highest points of a torus standing upright.
  struct Case { surface::Mesh mesh; int genus; };
  for (const auto& c : {Case{shared("cinolib_torus.obj"), 1}, Case{shared("cfwen_eight.off"), 2}}) {
    const auto [lo, hi] = z_extremes(c.mesh);
    const auto cp = split::critical_points(c.mesh, split::harmonic_field(c.mesh, {{lo, 0.0}, {hi, 1.0}}));
    EXPECT_EQ(cp.minima, std::vector<int>{lo});
    EXPECT_EQ(cp.maxima, std::vector<int>{hi});
    EXPECT_EQ(cp.saddle_count(), 2 * c.genus);
  }
}

TEST(Harmonic, BadConstraintsAreErrors) {
  const auto mesh = model("sphere", 8);
  EXPECT_THROW(split::harmonic_field(mesh, {}), core::InvalidInputError);
  EXPECT_THROW(split::harmonic_field(mesh, {{0, 0.0}, {0, 1.0}}), core::InvalidInputError);
  EXPECT_THROW(split::harmonic_field(mesh, {{-1, 0.0}}), core::InvalidInputError);
  EXPECT_THROW(split::harmonic_field(mesh, {{static_cast<int>(mesh.number_of_vertices()), 0.0}}), core::InvalidInputError);
}

TEST(Harmonic, PeriodicFieldWithItsOwnValuesAsConstraintsIsUnchanged) {
  // A cross section of a split torus as the cut; the unconstrained field's values, lifted on the
  // surface cut open along it, as Dirichlet values at a third of the vertices: the field is
  // harmonic at the others, so the constrained solve must give the same field.
  const surface::Mesh torus = model("torus", 16);
  const split::Decomposition d = split::split(torus, classify::classify(torus, {}), {});
  const surface::Mesh m = split::layout_mesh(d.layout, false);
  const std::vector<int> cut = d.layout.internal_faces.at(0).loop;
  const std::vector<double> u0 = split::periodic_harmonic_field(m, cut);
  std::vector<char> on_cut(m.number_of_vertices(), 0);
  for (int v : cut) on_cut[static_cast<std::size_t>(v)] = 1;
  const double c = u0[static_cast<std::size_t>(cut[0])];
  std::vector<split::Constraint> cons;
  for (int v = 0; v < static_cast<int>(m.number_of_vertices()); v += 3)
    if (!on_cut[static_cast<std::size_t>(v)]) cons.push_back({v, c + std::fmod(u0[static_cast<std::size_t>(v)] - c + 1.0, 1.0)});
  ASSERT_GT(cons.size(), 10u);
  const std::vector<double> u1 = split::periodic_harmonic_field(m, cut, cons);
  double worst = 0;
  for (std::size_t v = 0; v < u0.size(); ++v) worst = std::max(worst, std::abs(split::circle_difference(u0[v], u1[v], 1.0)));
  EXPECT_LT(worst, 1e-9);
  // A constraint on the cut, or the same vertex twice, is refused.
  EXPECT_THROW(split::periodic_harmonic_field(m, cut, {{cut[1], 0.5}}), core::InvalidInputError);
  EXPECT_THROW(split::periodic_harmonic_field(m, cut, {cons[0], cons[0]}), core::InvalidInputError);
}
