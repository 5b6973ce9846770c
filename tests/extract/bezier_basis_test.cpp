// extract::bezier_basis: the global basis of C0 Bézier hexes (the tet route's). Two hand-built
// hexes sharing a face; then over a family of tet meshes and degrees, the route's hexes must be
// conforming: every hex face's functions belong to one other hex across it, or to none exactly
// on the boundary (three hex faces per boundary triangle), and Cᵀ·P gives back every hex.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "common/test_util.h"
#include "core/errors.h"
#include "extract/extract.h"
#include "tet2hex/tet2hex.h"

using namespace volts;

namespace {

// The Bézier hex of degree p of the axis box [x0, x0 + 1] x [0,1] x [0,1] (points on the lattice).
bezier::BezierHex box_hex(int p, double x0) {
  bezier::BezierHex h;
  h.degree = {p, p, p};
  for (int k = 0; k <= p; ++k)
    for (int j = 0; j <= p; ++j)
      for (int i = 0; i <= p; ++i) h.points.emplace_back(x0 + double(i) / p, double(j) / p, double(k) / p);
  return h;
}

// The functions on face f (2·axis + side) of element e, ascending.
std::vector<int> face_functions(const bezier::BezierHex& h, const extract::ExtractionElement& el, int f) {
  const int p = h.degree[0], axis = f / 2, at = (f % 2) * p;
  std::vector<int> out;
  for (int r = 0; r < el.op.outerSize(); ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(el.op, r); it; ++it)
      if (h.ijk(static_cast<int>(it.col()))[static_cast<std::size_t>(axis)] == at) out.push_back(el.functions[static_cast<std::size_t>(r)]);
  std::sort(out.begin(), out.end());
  return out;
}

// Cᵀ·P against the hex's points and the column sums: the largest deviations.
std::pair<double, double> reproduction(const extract::GlobalBasis& g, const std::vector<bezier::BezierHex>& hexes) {
  double dev = 0, pou = 0;
  for (std::size_t e = 0; e < hexes.size(); ++e) {
    const auto& el = g.elements[e];
    std::vector<Eigen::Vector3d> x(hexes[e].points.size(), Eigen::Vector3d::Zero());
    std::vector<double> sum(hexes[e].points.size(), 0.0);
    for (int r = 0; r < el.op.outerSize(); ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(el.op, r); it; ++it) {
        x[static_cast<std::size_t>(it.col())] += it.value() * g.points[static_cast<std::size_t>(el.functions[static_cast<std::size_t>(r)])];
        sum[static_cast<std::size_t>(it.col())] += it.value();
      }
    for (std::size_t b = 0; b < x.size(); ++b) {
      dev = std::max(dev, (x[b] - hexes[e].points[b]).norm());
      pou = std::max(pou, std::abs(sum[b] - 1));
    }
  }
  return {dev, pou};
}

}  // namespace

TEST(BezierBasis, TwoHexesSharingAFaceShareItsFunctions) {
  for (int p = 1; p <= 4; ++p) {
    const std::vector<bezier::BezierHex> hexes = {box_hex(p, 0), box_hex(p, 1)};
    const extract::GlobalBasis g = extract::bezier_basis(hexes);
    const int n = (p + 1) * (p + 1) * (p + 1), face = (p + 1) * (p + 1);
    EXPECT_EQ(static_cast<int>(g.points.size()), 2 * n - face) << "degree " << p;
    ASSERT_EQ(g.elements.size(), 2u);
    EXPECT_EQ(face_functions(hexes[0], g.elements[0], 1), face_functions(hexes[1], g.elements[1], 0)) << "degree " << p;
    EXPECT_NE(face_functions(hexes[0], g.elements[0], 0), face_functions(hexes[1], g.elements[1], 1)) << "degree " << p;
    const auto [dev, pou] = reproduction(g, hexes);
    EXPECT_EQ(dev, 0.0);
    EXPECT_EQ(pou, 0.0);
    EXPECT_EQ(g.partition_of_unity_error, 0.0);
    for (const double w : g.weights) EXPECT_EQ(w, 1.0);
    // Without the operators: the same functions, no elements.
    const extract::GlobalBasis lean = extract::bezier_basis(hexes, false);
    EXPECT_EQ(lean.points.size(), g.points.size());
    EXPECT_TRUE(lean.elements.empty());
  }
}

TEST(BezierBasis, TetRouteHexesAreConforming) {
  struct Case {
    const char* model;
    int resolution, degree;
  };
  for (const Case c : {Case{"tetrahedron", 4, 2}, Case{"box", 6, 3}, Case{"sphere", 8, 3}, Case{"cube-with-hole", 8, 2}}) {
    const std::string name = std::string(c.model) + " at degree " + std::to_string(c.degree);
    tet2hex::Params params;
    params.degree = c.degree;
    const tet2hex::Result r = tet2hex::run(test::generated_model(c.model, c.resolution), params);
    ASSERT_GT(r.hexes.size(), 0u) << name;
    const extract::GlobalBasis g = extract::bezier_basis(r.hexes);
    ASSERT_EQ(g.elements.size(), r.hexes.size()) << name;
    // Every face's function set: shared by exactly two hexes inside, one on the boundary.
    std::map<std::vector<int>, int> faces;
    for (std::size_t e = 0; e < r.hexes.size(); ++e)
      for (int f = 0; f < 6; ++f) ++faces[face_functions(r.hexes[e], g.elements[e], f)];
    int once = 0, twice = 0, more = 0;
    for (const auto& [fs, n] : faces) (n == 1 ? once : n == 2 ? twice : more) += 1;
    EXPECT_EQ(more, 0) << name;
    EXPECT_EQ(once, 3 * r.boundary_faces) << name << ": the faces no other hex shares are the boundary's, three per triangle";
    EXPECT_EQ(once + 2 * twice, static_cast<int>(6 * r.hexes.size())) << name;
    const auto [dev, pou] = reproduction(g, r.hexes);
    EXPECT_LT(dev, 1e-12) << name;
    EXPECT_EQ(pou, 0.0) << name;
    // Fewer functions than Bernstein functions: neighbours share theirs.
    EXPECT_LT(g.points.size(), r.hexes.size() * r.hexes[0].points.size()) << name;
  }
}

TEST(BezierBasis, DegenerateOrNonConformingElementsAreRefused) {
  std::vector<bezier::BezierHex> hexes = {box_hex(2, 0)};
  hexes[0].points[1] = hexes[0].points[0];  // two control points of one element at one place
  try {
    extract::bezier_basis(hexes);
    ADD_FAILURE() << "a degenerate element was accepted";
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("element 0"), std::string::npos) << e.what();
  }
  hexes = {box_hex(2, 0), box_hex(2, 1)};
  hexes[1].weights.assign(hexes[1].points.size(), 2.0);  // the shared face with another weight
  try {
    extract::bezier_basis(hexes);
    ADD_FAILURE() << "a shared point with two weights was accepted";
  } catch (const core::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("element 1"), std::string::npos) << e.what();
  }
  hexes[0].weights.assign(hexes[0].points.size(), 2.0);  // same weights: one rational basis
  const extract::GlobalBasis g = extract::bezier_basis(hexes);
  EXPECT_EQ(g.points.size(), 2u * 27 - 9);
  for (const double w : g.weights) EXPECT_EQ(w, 2.0);
}
