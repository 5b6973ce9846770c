// The solver exports of the two-block spline, read back with independent readers: .bext (counts,
// weights, operator rows), .json (round trip), .msh (conforming node count, nodes = the Bézier
// element at Gmsh's Lagrange points; Gmsh's order checked against gmsh itself when installed),
// the keyword deck and the histogram PNG.
#include <gtest/gtest.h>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <filesystem>
#include <random>
#include <sstream>

#include "common/test_util.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stage_file.h"
#include "extract/export.h"
#include "extract/readers.h"
#include "extract/two_blocks.h"
#include "tmesh/ring_cubes.h"

namespace fs = std::filesystem;
using namespace volts;

namespace {

class Exports : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = test::fresh_dir("extract", "exports");
    r = test::two_block_result();
  }
  static fs::path dir;
  static extract::Result r;
};
fs::path Exports::dir;
extract::Result Exports::r;

}  // namespace

TEST_F(Exports, BextHoldsTheGlobalBasisAndEveryOperatorRow) {
  const std::string path = (dir / "bezier.bext").string();
  extract::write_bext(path, r);
  const test::Bext b = test::read_bext(path);
  EXPECT_EQ(b.patch, 1);
  EXPECT_EQ(b.nodes, 225);
  EXPECT_EQ(b.elements, 16);
  EXPECT_EQ(b.weight_flag, 1);
  EXPECT_EQ(static_cast<long>(b.coefficient_vectors.size()), b.vectors);
  EXPECT_LT(b.vectors, 16 * 64);  // shared: uniform knots repeat the same rows
  for (long i = 0; i < b.nodes; ++i) {
    EXPECT_EQ(b.xyzw[i].head<3>(), r.basis.points[i]) << "node " << i << " (17 digits round-trip)";
    EXPECT_EQ(b.xyzw[i][3], 1.0);
  }
  for (std::size_t e = 0; e < 16; ++e) {
    EXPECT_EQ(b.degrees[e], (std::array<long, 3>{3, 3, 3}));
    const auto& el = r.basis.elements[e];
    ASSERT_EQ(b.element_nodes[e].size(), el.functions.size());
    const Eigen::MatrixXd C(el.op);
    Eigen::MatrixXd bez = Eigen::MatrixXd::Zero(64, 3);
    for (std::size_t row = 0; row < el.functions.size(); ++row) {
      EXPECT_EQ(b.element_nodes[e][row], el.functions[row]);
      const auto& v = b.coefficient_vectors[b.element_vectors[e][row]];
      ASSERT_EQ(v.size(), 64u);
      for (int c = 0; c < 64; ++c) {
        EXPECT_EQ(v[c], C(static_cast<int>(row), c));
        bez.row(c) += v[c] * b.xyzw[b.element_nodes[e][row]].head<3>().transpose();
      }
    }
    for (int c = 0; c < 64; ++c) EXPECT_LT((bez.row(c).transpose() - r.hexes[e].points[c]).norm(), 1e-13);
  }
}

TEST_F(Exports, KeywordDeckIncludesTheBext) {
  const std::string path = (dir / "bezier.k").string();
  extract::write_lsdyna_deck(path, "bezier.bext");
  const std::string k = core::read_text_file(path);
  EXPECT_EQ(k.rfind("*KEYWORD\n", 0), 0u);
  const auto inc = k.find("*IGA_INCLUDE_BEZIER\n");
  ASSERT_NE(inc, std::string::npos);
  EXPECT_NE(k.find("\nbezier.bext\n", inc), std::string::npos);
  EXPECT_NE(k.find("*SECTION_SOLID"), std::string::npos);
  EXPECT_NE(k.find("       201"), std::string::npos);
  EXPECT_EQ(k.substr(k.size() - 5), "*END\n");
  // Data cards are fixed format, 10 columns a field: every non-comment line after a card name
  // (except the file name and the part title) is a multiple of 10 wide.
  std::istringstream lines(k);
  std::string line, previous;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '*' || line[0] == '$' || line == "bezier.bext" || line == "volts spline") continue;
    EXPECT_EQ(line.size() % 10, 0u) << "'" << line << "'";
  }
  EXPECT_THROW(extract::write_lsdyna_deck(path, std::string(81, 'a')), core::InvalidInputError);
}

TEST_F(Exports, JsonRoundTrips) {
  const std::string path = (dir / "bezier.json").string();
  extract::write_bezier_json(path, r);
  const core::Json j = core::read_stage_file(path, "volts-bezier", 1);
  const auto& gf = j["global_functions"];
  ASSERT_EQ(gf["count"], 225);
  const auto pts = gf["points"].get<std::vector<double>>();
  for (std::size_t i = 0; i < 225; ++i)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(pts[3 * i + d], r.basis.points[i][d]);
  EXPECT_EQ(gf["weights"].get<std::vector<double>>(), std::vector<double>(225, 1.0));
  ASSERT_EQ(j["elements"].size(), 16u);
  for (std::size_t e = 0; e < 16; ++e) {
    const auto& je = j["elements"][e];
    EXPECT_EQ(je["degree"].get<std::vector<int>>(), (std::vector<int>{3, 3, 3}));
    EXPECT_EQ(je["functions"].get<std::vector<int>>(), r.basis.elements[e].functions);
    EXPECT_EQ(je["status"], 1);
    EXPECT_EQ(je["min_scaled_jacobian"].get<double>(), r.min_scaled_jacobian[e]);
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(je["operator"]["rows"].get<int>(), je["operator"]["columns"].get<int>());
    for (const auto& t : je["operator"]["triplets"]) C(t[0].get<int>(), t[1].get<int>()) = t[2].get<double>();
    EXPECT_EQ(C, Eigen::MatrixXd(r.basis.elements[e].op)) << "element " << e;
  }
}

TEST_F(Exports, MshIsConformingAndItsNodesAreTheElementsAtGmshsPoints) {
  const std::string path = (dir / "bezier.msh").string();
  const std::size_t written = extract::write_gmsh(path, r.hexes);
  const test::Msh m = test::read_msh(path);
  EXPECT_EQ(m.nodes.size(), 13u * 7u * 7u);  // 4 x 2 x 2 cubic elements sharing their nodes
  EXPECT_EQ(written, m.nodes.size());
  ASSERT_EQ(m.elements.size(), 16u);
  const auto lattice = extract::gmsh_hex_nodes(3);
  for (std::size_t e = 0; e < 16; ++e) {
    EXPECT_EQ(m.types[e], 92);
    ASSERT_EQ(m.elements[e].size(), 64u);
    for (int n = 0; n < 64; ++n) {
      const Eigen::Vector3d uvw = Eigen::Vector3d(lattice[n][0], lattice[n][1], lattice[n][2]) / 3.0;
      EXPECT_LT((m.nodes.at(m.elements[e][n]) - bezier::evaluate(r.hexes[e], uvw)).norm(), 1e-14) << e << " node " << n;
    }
  }
  // Corners 0..7 are Gmsh's (and VTK's) hexahedron corners; node 8 lies on edge 0-1 at 1/3.
  EXPECT_EQ(lattice[6], (std::array<int, 3>{3, 3, 3}));
  EXPECT_EQ(lattice[8], (std::array<int, 3>{1, 0, 0}));
  EXPECT_THROW(extract::gmsh_hex_nodes(4), core::InvalidInputError);
  EXPECT_THROW(extract::check_exports({"vtu", "msh"}, 4), core::ConfigError);
  EXPECT_THROW(extract::check_exports({"stl"}, 3), core::ConfigError);
  EXPECT_NO_THROW(extract::check_exports({"bext", "png"}, 4));
}

// Gmsh's own cubic hexahedron: an extruded unit cube meshed at -order 3; the node positions in the
// element's corner frame must be our table (this is where the table came from).
TEST(Gmsh, NodeOrderOfTheCubicHexahedronIsGmshsOwn) {
  if (test::run("gmsh --version").code != 0) GTEST_SKIP() << "gmsh is not installed";
  const fs::path d = test::fresh_dir("extract", "gmsh_order");
  for (int order = 1; order <= 3; ++order) {
    test::write_text(d / "cube.geo",
                     "Point(1)={0,0,0,1}; Point(2)={1,0,0,1}; Point(3)={1,1,0,1}; Point(4)={0,1,0,1};\n"
                     "Line(1)={1,2}; Line(2)={2,3}; Line(3)={3,4}; Line(4)={4,1};\n"
                     "Curve Loop(1)={1,2,3,4}; Plane Surface(1)={1};\n"
                     "Transfinite Curve{1,2,3,4}=2; Transfinite Surface{1}; Recombine Surface{1};\n"
                     "Extrude{0,0,1}{Surface{1}; Layers{1}; Recombine;}\n");
    const auto out = test::run("gmsh " + (d / "cube.geo").string() + " -3 -order " + std::to_string(order) + " -format msh41 -o " +
                               (d / "cube.msh").string());
    ASSERT_EQ(out.code, 0) << out.output;
    const test::Msh m = test::read_msh((d / "cube.msh").string());
    const auto lattice = extract::gmsh_hex_nodes(order);
    bool found = false;
    for (std::size_t e = 0; e < m.elements.size(); ++e) {
      if (m.types[e] != extract::gmsh_hex_type(order)) continue;
      found = true;
      const auto& c = m.elements[e];
      const Eigen::Vector3d x0 = m.nodes.at(c[0]);
      const Eigen::Vector3d a[3] = {m.nodes.at(c[1]) - x0, m.nodes.at(c[3]) - x0, m.nodes.at(c[4]) - x0};
      ASSERT_EQ(c.size(), lattice.size());
      for (std::size_t n = 0; n < c.size(); ++n)
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR((m.nodes.at(c[n]) - x0).dot(a[k]) / a[k].squaredNorm() * order, lattice[n][k], 1e-9)
              << "order " << order << " node " << n;
    }
    EXPECT_TRUE(found);
  }
}

TEST_F(Exports, HistogramPngReadsBackWithItsSizeAndBars) {
  const std::string path = (dir / "scaled_jacobian_histogram.png").string();
  extract::write_histogram_png(path, r.min_scaled_jacobian);
  vtkNew<vtkPNGReader> reader;
  ASSERT_TRUE(reader->CanReadFile(path.c_str()));
  reader->SetFileName(path.c_str());
  reader->Update();
  int dims[3];
  reader->GetOutput()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 420);
  EXPECT_EQ(dims[1], 260);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfScalarComponents(), 3);
  // Values 0, 0.05, ..., 0.75 fill bins 10..25 of 20 over [-1, 1] (two per bin from bin 10): the
  // bars stand right of the middle, nothing left of it.
  const auto blue = [&](int x, int y) {
    const auto* c = static_cast<unsigned char*>(reader->GetOutput()->GetScalarPointer(x, y, 0));
    return c[0] == 40 && c[1] == 90 && c[2] == 200;
  };
  EXPECT_TRUE(blue(20 + 380 * 21 / 40, 22));  // bin 10 (values 0 and 0.05), just above the axis
  EXPECT_FALSE(blue(20 + 380 * 9 / 40, 22));  // bin 4: empty
  EXPECT_THROW(extract::write_histogram_png(path, {}, {0, -1, 1, 420, 260}), core::InvalidInputError);
}

TEST_F(Exports, MshStillMergesItsNodesFarFromTheOrigin) {
  std::vector<bezier::BezierHex> far = r.hexes;
  for (auto& h : far)
    for (auto& p : h.points) p += Eigen::Vector3d(1e5, -2e5, 5e4);
  const std::string path = (dir / "far.msh").string();
  EXPECT_EQ(extract::write_gmsh(path, far), 13u * 7u * 7u);
}

// bezier.json version 2 (extract.json_operators kronecker): a ring of three cubes of levels 1, 2,
// 1 has elements whose operators are Kronecker products (inside a block) and elements with
// T-junction rows among their functions (at the level faces). Each is written as factors or as
// triplets accordingly, and both decode to the operator global_basis made, to 1e-14.
TEST(JsonOperators, KroneckerWhereTheOperatorIsAProductTripletsElsewhere) {
  const fs::path d = test::fresh_dir("extract", "json_kronecker");
  tmesh::Params p;
  p.level = 1;
  const auto ts = tmesh::build(test::ring(3), p, {1, 2, 1});
  extract::Result r;
  r.hexes = test::hexes(ts);
  r.basis = extract::global_basis(ts, r.hexes);
  r.degree = 3;
  extract::write_bezier_json((d / "k.json").string(), r, extract::JsonOperators::kronecker);
  extract::write_bezier_json((d / "t.json").string(), r, extract::JsonOperators::triplets);
  const core::Json j = core::read_stage_file((d / "k.json").string(), "volts-bezier", 2);
  EXPECT_EQ(j["version"], 2);
  EXPECT_EQ(core::read_stage_file((d / "t.json").string(), "volts-bezier", 2)["version"], 1);
  ASSERT_EQ(j["elements"].size(), r.basis.elements.size());
  int products = 0, rows = 0;
  for (std::size_t e = 0; e < r.basis.elements.size(); ++e) {
    const auto& op = j["elements"][e]["operator"];
    const Eigen::MatrixXd want(r.basis.elements[e].op);
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(op["rows"].get<int>(), op["columns"].get<int>());
    // The functions: the same set; for a product, in the order of its factors' rows.
    std::vector<int> functions = j["elements"][e]["functions"].get<std::vector<int>>(), sorted = functions;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, r.basis.elements[e].functions);
    Eigen::MatrixXd want_rows = want;  // rows in the file's order of functions
    for (std::size_t row = 0; row < functions.size(); ++row) {
      const auto it = std::find(r.basis.elements[e].functions.begin(), r.basis.elements[e].functions.end(), functions[row]);
      want_rows.row(static_cast<Eigen::Index>(row)) = want.row(it - r.basis.elements[e].functions.begin());
    }
    if (op.contains("kronecker")) {
      ++products;
      EXPECT_FALSE(op.contains("triplets"));
      std::array<std::vector<double>, 3> k;
      for (int f = 0; f < 3; ++f) k[static_cast<std::size_t>(f)] = op["kronecker"][static_cast<std::size_t>(f)].get<std::vector<double>>();
      for (int row = 0; row < 64; ++row)
        for (int col = 0; col < 64; ++col)
          C(row, col) = k[0][static_cast<std::size_t>(4 * (row % 4) + col % 4)] * k[1][static_cast<std::size_t>(4 * (row / 4 % 4) + col / 4 % 4)] *
                        k[2][static_cast<std::size_t>(4 * (row / 16) + col / 16)];
    } else {
      ++rows;
      for (const auto& t : op["triplets"]) C(t[0].get<int>(), t[1].get<int>()) = t[2].get<double>();
    }
    ASSERT_EQ(C.rows(), want.rows());
    EXPECT_LE((C - want_rows).cwiseAbs().maxCoeff(), 1e-14) << "element " << e;
  }
  EXPECT_GT(products, 0);
  EXPECT_GT(rows, 0) << "no element with a T-junction row: the ring would not test the fallback";
  EXPECT_LT(fs::file_size(d / "k.json"), fs::file_size(d / "t.json"));
}

TEST(JsonOperators, KroneckerFactorsAreFoundOnlyWhereTheyReproduceTheOperator) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.1, 1);
  std::array<Eigen::MatrixXd, 3> f;
  for (auto& m : f) {
    m = Eigen::MatrixXd::NullaryExpr(4, 4, [&] { return u(rng); });
    for (int a = 0; a < 4; ++a) m.col(a) /= m.col(a).sum();
  }
  Eigen::MatrixXd C(64, 64);
  for (int row = 0; row < 64; ++row)
    for (int col = 0; col < 64; ++col) C(row, col) = f[0](row % 4, col % 4) * f[1](row / 4 % 4, col / 4 % 4) * f[2](row / 16, col / 16);
  // Rows in any order (the functions ascending by global id): shuffled, the factors and the row of
  // each tensor index still give back every entry, and each factor is one of f's up to the order
  // of its rows, with columns summing to one.
  std::vector<int> perm(64);
  for (int i = 0; i < 64; ++i) perm[static_cast<std::size_t>(i)] = i;
  for (const bool shuffle : {false, true}) {
    if (shuffle) std::shuffle(perm.begin(), perm.end(), rng);
    Eigen::MatrixXd rows(64, 64);
    for (int i = 0; i < 64; ++i) rows.row(i) = C.row(perm[static_cast<std::size_t>(i)]);
    std::array<Eigen::MatrixXd, 3> k;
    std::vector<int> order;
    ASSERT_TRUE(extract::kronecker_factors(rows.sparseView(), 3, &k, &order)) << shuffle;
    ASSERT_EQ(order.size(), 64u);
    std::vector<int> seen = order;
    std::sort(seen.begin(), seen.end());
    for (int i = 0; i < 64; ++i) EXPECT_EQ(seen[static_cast<std::size_t>(i)], i);
    double gap = 0;
    for (int t = 0; t < 64; ++t)
      for (int col = 0; col < 64; ++col)
        gap = std::max(gap, std::abs(k[0](t % 4, col % 4) * k[1](t / 4 % 4, col / 4 % 4) * k[2](t / 16, col / 16) - rows(order[static_cast<std::size_t>(t)], col)));
    EXPECT_LE(gap, 1e-14);
    for (int d = 0; d < 3; ++d) {
      EXPECT_LE((k[static_cast<std::size_t>(d)].colwise().sum().array() - 1).abs().maxCoeff(), 1e-14);
      for (int i = 0; i < 4; ++i) {
        double best = 1;
        for (int j = 0; j < 4; ++j) best = std::min(best, (k[static_cast<std::size_t>(d)].row(i) - f[static_cast<std::size_t>(d)].row(j)).cwiseAbs().maxCoeff());
        EXPECT_LE(best, 1e-14) << "factor " << d << " row " << i;
      }
    }
  }
  std::array<Eigen::MatrixXd, 3> got;
  Eigen::MatrixXd bent = C;
  bent(5, 7) += 1e-10;
  EXPECT_FALSE(extract::kronecker_factors(bent.sparseView(), 3, &got));
  EXPECT_FALSE(extract::kronecker_factors(C.topRows(63).sparseView(), 3, &got));
  EXPECT_FALSE(extract::kronecker_factors(C.sparseView(), 2, &got));
}
