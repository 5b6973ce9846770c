// validate_soup: each check on its own, the counts and first offenders it reports, and the order
// of the checks (the root problem is named when several are present).
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "surface/surface.h"
#include "surface_test_util.h"

namespace volts::surface::test {
namespace {

using Faces = std::vector<std::vector<std::size_t>>;

const std::string kSource = "soup.gen";
const std::vector<Point> kTetra = {Point(0, 0, 0), Point(1, 0, 0), Point(0, 1, 0), Point(0, 0, 1)};
const Faces kTetraFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

void expect_refused(const std::vector<Point>& points, const Faces& faces, const std::string& text) {
  expect_invalid_input([&] { validate_soup(points, faces, kSource); }, kSource, text);
}

TEST(ValidateSoup, AcceptsClosedSolidsEitherWayRoundAndUnusedVertices) {
  EXPECT_NO_THROW(validate_soup(kTetra, kTetraFaces, kSource));
  Faces inverted = kTetraFaces;
  for (auto& f : inverted) std::swap(f[1], f[2]);
  EXPECT_NO_THROW(validate_soup(kTetra, inverted, kSource));  // a global inversion is read_surface's business
  std::vector<Point> more = kTetra;
  more.emplace_back(9, 9, 9);
  EXPECT_NO_THROW(validate_soup(more, kTetraFaces, kSource));
  // Polygons: a cube of quads.
  std::vector<Point> cube;
  for (int i = 0; i < 8; ++i) cube.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  EXPECT_NO_THROW(validate_soup(cube, {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {1, 3, 7, 5}, {3, 2, 6, 7}, {2, 0, 4, 6}}, kSource));
}

TEST(ValidateSoup, NoFaces) { expect_refused(kTetra, {}, "no faces"); }

TEST(ValidateSoup, NonFiniteCoordinates) {
  std::vector<Point> points = kTetra;
  points[1] = Point(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  points[3] = Point(0, 0, -std::numeric_limits<double>::infinity());
  expect_refused(points, kTetraFaces, "2 vertices with non-finite coordinates (NaN/Inf), first at vertex 1 (nan, 0, 0)");
}

TEST(ValidateSoup, FaceWithFewerThanThreeVertices) {
  Faces faces = kTetraFaces;
  faces.push_back({0, 1});
  expect_refused(kTetra, faces, "1 face with fewer than 3 vertices, first is face 4 (2 vertices)");
}

TEST(ValidateSoup, IndexOutOfRange) {
  Faces faces = kTetraFaces;
  faces[1][2] = 4;
  faces[3][0] = 17;
  expect_refused(kTetra, faces, "2 faces with a vertex index out of range, first is face 1 (vertex index 4, but there are 4 vertices)");
}

TEST(ValidateSoup, RepeatedVertex) {
  Faces faces = kTetraFaces;
  faces[2] = {0, 3, 0};
  expect_refused(kTetra, faces, "1 face uses a vertex twice, first is face 2 (vertex 0 (0, 0, 0) twice)");
}

TEST(ValidateSoup, ZeroAreaTriangleAndPolygon) {
  std::vector<Point> points = kTetra;
  points[3] = Point(0.5, 0.5, 0);  // on the segment from vertex 1 to vertex 2: faces 3 is flat
  expect_refused(points, kTetraFaces, "1 zero-area face, first is face 3");
  // A quad whose four corners lie on one line.
  const std::vector<Point> line = {Point(0, 0, 0), Point(1, 1, 1), Point(2, 2, 2), Point(3, 3, 3)};
  expect_refused(line, {{0, 1, 2, 3}}, "1 zero-area face, first is face 0");
  // Three collinear corners of a quad are fine: it still has area. (Two such quads back to back
  // enclose nothing, but volume is read_surface's check, not validate_soup's.)
  const std::vector<Point> quad = {Point(0, 0, 0), Point(1, 0, 0), Point(2, 0, 0), Point(1, 1, 0)};
  EXPECT_NO_THROW(validate_soup(quad, {{0, 1, 2, 3}, {0, 3, 2, 1}}, kSource));
}

TEST(ValidateSoup, NonManifoldEdge) {
  std::vector<Point> points = kTetra;
  points.emplace_back(0, -1, 0);
  points.emplace_back(0, 0, -1);
  Faces faces = kTetraFaces;
  for (const auto& f : kTetraFaces) {  // the tetra turned about the x axis: shares edge 0-1
    std::vector<std::size_t> g;
    for (std::size_t v : f) g.push_back(v < 2 ? v : v + 2);
    faces.push_back(g);
  }
  expect_refused(points, faces, "1 non-manifold edge (used by more than 2 faces), first is the edge between vertex 0");
}

TEST(ValidateSoup, OpenSurface) {
  Faces faces = kTetraFaces;
  faces.erase(faces.begin() + 1);
  faces.erase(faces.begin() + 1);
  // Two faces left, (0,2,1) and (1,2,3): edge 1-2 is shared, the other four are boundary edges.
  expect_refused(kTetra, faces, "open surface: 4 boundary edges, first at vertex 1 (1, 0, 0), edge to vertex 0 (0, 0, 0) of face 0");
}

TEST(ValidateSoup, InconsistentOrientation) {
  Faces faces = kTetraFaces;
  std::swap(faces[0][1], faces[0][2]);
  expect_refused(kTetra, faces,
                 "inconsistent orientation: 3 edges traversed twice in the same direction, first between vertex 0 (0, 0, 0) "
                 "and vertex 1 (1, 0, 0) (faces 0 and 1)");
}

TEST(ValidateSoup, NonManifoldVertex) {
  std::vector<Point> points = kTetra;
  for (std::size_t v = 1; v < 4; ++v) points.emplace_back(-points[v].x(), -points[v].y(), -points[v].z());
  Faces faces = kTetraFaces;
  for (const auto& f : kTetraFaces) {  // mirrored through the origin (orientation reversed): shares vertex 0 only
    std::vector<std::size_t> g;
    for (std::size_t v : f) g.push_back(v == 0 ? 0 : v + 3);
    faces.push_back({g[0], g[2], g[1]});
  }
  expect_refused(points, faces, "1 non-manifold vertex (the faces around it form more than one fan), first is vertex 0 (0, 0, 0)");
}

TEST(ValidateSoup, SeveralComponents) {
  std::vector<Point> points = kTetra;
  Faces faces = kTetraFaces;
  for (int copy = 1; copy <= 2; ++copy) {
    for (const Point& p : kTetra) points.emplace_back(p.x() + 3 * copy, p.y(), p.z());
    for (const auto& f : kTetraFaces) faces.push_back({f[0] + 4u * copy, f[1] + 4u * copy, f[2] + 4u * copy});
  }
  expect_refused(points, faces,
                 "3 connected components; volts needs one closed solid (4 faces from face 0, 4 faces from face 4, 4 faces "
                 "from face 8)");
}

TEST(ValidateSoup, RootProblemComesFirst) {
  // NaN and a zero-area face: the NaN is named.
  std::vector<Point> points = kTetra;
  points[3] = Point(2, 0, 0);  // face 1 flat
  expect_refused(points, kTetraFaces, "zero-area");
  points[2] = Point(0, std::numeric_limits<double>::quiet_NaN(), 0);
  expect_refused(points, kTetraFaces, "non-finite");
  // A flat face in an open surface: the flat face is named (it breaks every later check).
  Faces open = kTetraFaces;
  open.pop_back();
  points = kTetra;
  points[3] = Point(2, 0, 0);
  expect_refused(points, open, "1 zero-area face, first is face 1");
  // Out of range before repeated vertices.
  Faces faces = kTetraFaces;
  faces[0] = {0, 0, 9};
  expect_refused(kTetra, faces, "out of range");
}

}  // namespace
}  // namespace volts::surface::test
