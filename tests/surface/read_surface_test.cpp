// read_surface: every format reads known closed meshes; real models validate; broken inputs are
// refused with the file name and the specific problem.
#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "surface/surface.h"
#include "surface_test_util.h"

namespace volts::surface::test {
namespace {

using Faces = std::vector<std::array<std::size_t, 3>>;
using Coords = std::vector<std::array<double, 3>>;

// ---- Known meshes and writers for each format ----------------------------------------------

const Coords kTetraPoints = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const Faces kTetraFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

const Coords kOctaPoints = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
Faces octahedron_faces() {
  Faces faces;  // one face per octant, ordered so that its normal points into the octant
  for (std::size_t x : {0, 1})
    for (std::size_t y : {2, 3})
      for (std::size_t z : {4, 5}) {
        const bool positive = (x == 0) == (y == 2) ? z == 4 : z == 5;
        faces.push_back(positive ? std::array<std::size_t, 3>{x, y, z} : std::array<std::size_t, 3>{x, z, y});
      }
  return faces;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::string off_text(const Coords& points, const Faces& faces) {
  std::string s = "OFF\n" + std::to_string(points.size()) + " " + std::to_string(faces.size()) + " 0\n";
  for (const auto& p : points) s += number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
  for (const auto& f : faces) s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

std::string ascii_stl(const Coords& points, const Faces& faces) {
  std::string s = "solid test\n";
  for (const auto& f : faces) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (std::size_t v : f) s += "      vertex " + number(points[v][0]) + " " + number(points[v][1]) + " " + number(points[v][2]) + "\n";
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid test\n";
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}
void put_float(std::string& s, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put_u32(s, bits);
}
void put_double(std::string& s, double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, 8);
  for (int i = 0; i < 8; ++i) s += static_cast<char>((bits >> (8 * i)) & 0xff);
}

std::string binary_stl(const Coords& points, const Faces& faces, const std::string& header = "binary test") {
  std::string s = header;
  s.resize(80, ' ');
  put_u32(s, static_cast<std::uint32_t>(faces.size()));
  for (const auto& f : faces) {
    for (int i = 0; i < 3; ++i) put_float(s, 0.0f);  // normal, ignored
    for (std::size_t v : f)
      for (double c : points[v]) put_float(s, static_cast<float>(c));
    s += std::string(2, '\0');  // attribute byte count
  }
  return s;
}

std::string ply_header(const std::string& encoding, const std::string& coord_type, std::size_t nv, std::size_t nf) {
  return "ply\nformat " + encoding + " 1.0\ncomment written by read_surface_test\nelement vertex " + std::to_string(nv) +
         "\nproperty " + coord_type + " x\nproperty " + coord_type + " y\nproperty " + coord_type +
         " z\nelement face " + std::to_string(nf) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string ascii_ply(const Coords& points, const Faces& faces) {
  std::string s = ply_header("ascii", "double", points.size(), faces.size());
  for (const auto& p : points) s += number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
  for (const auto& f : faces) s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

/// Little-endian binary PLY; `wide_counts` stores face sizes as uint instead of uchar.
std::string binary_ply(const Coords& points, const Faces& faces, bool wide_counts = false) {
  std::string s = ply_header("binary_little_endian", "double", points.size(), faces.size());
  if (wide_counts) s.replace(s.find("list uchar int"), 14, "list uint int");
  for (const auto& p : points)
    for (double c : p) put_double(s, c);
  for (const auto& f : faces) {
    if (wide_counts)
      put_u32(s, 3);
    else
      s += static_cast<char>(3);
    for (std::size_t v : f) put_u32(s, static_cast<std::uint32_t>(v));
  }
  return s;
}

Faces reversed(Faces faces) {
  for (auto& f : faces) std::swap(f[1], f[2]);
  return faces;
}

/// Two tetrahedra sharing their first `shared` vertices: 2 shares the edge 0-1 (the second is the
/// first turned by 180 degrees about the x axis), 1 shares vertex 0 (point reflection through the
/// origin, which reverses orientation), 0 shares nothing (translation).
std::pair<Coords, Faces> two_tetrahedra(std::size_t shared) {
  Coords points = kTetraPoints;
  Faces faces = kTetraFaces;
  std::vector<std::size_t> map(4);
  for (std::size_t v = 0; v < 4; ++v) {
    if (v < shared) {
      map[v] = v;
      continue;
    }
    const auto& p = kTetraPoints[v];
    map[v] = points.size();
    if (shared == 2)
      points.push_back({p[0], -p[1], -p[2]});
    else if (shared == 1)
      points.push_back({-p[0], -p[1], -p[2]});
    else
      points.push_back({p[0] + 3, p[1], p[2]});
  }
  for (const auto& f : kTetraFaces)
    faces.push_back(shared == 1 ? std::array<std::size_t, 3>{map[f[0]], map[f[2]], map[f[1]]}
                                : std::array<std::size_t, 3>{map[f[0]], map[f[1]], map[f[2]]});
  return {points, faces};
}

void expect_mesh(const Mesh& mesh, std::size_t vertices, std::size_t faces, double volume) {
  EXPECT_EQ(mesh.number_of_vertices(), vertices);
  EXPECT_EQ(mesh.number_of_faces(), faces);
  EXPECT_TRUE(CGAL::is_triangle_mesh(mesh));
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_EQ(genus(mesh), 0);
  EXPECT_NEAR(signed_volume(mesh), volume, 1e-12);
}

// ---- Every format -------------------------------------------------------------------------

TEST(ReadSurface, OffTetrahedron) {
  TempDir dir;
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("tetra.off", kTetrahedronOff), &info);
  expect_mesh(mesh, 4, 4, 1.0 / 6.0);
  EXPECT_EQ(info.format, "off");
  EXPECT_EQ(info.file_vertices, 4u);
  EXPECT_EQ(info.welded_vertices, 0u);
  EXPECT_EQ(info.triangulated_faces, 0u);
  EXPECT_FALSE(info.flipped);
  // Vertices keep the file's order and values.
  std::size_t i = 0;
  for (const auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    EXPECT_EQ(p, Point(kTetraPoints[i][0], kTetraPoints[i][1], kTetraPoints[i][2]));
    ++i;
  }
}

TEST(ReadSurface, OffCubeOfQuadsIsTriangulated) {
  TempDir dir;
  const std::string cube =
      "OFF\n# unit cube, one quad per side\n8 6 12\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("cube.off", cube), &info);
  expect_mesh(mesh, 8, 12, 1.0);
  EXPECT_EQ(info.triangulated_faces, 6u);
}

TEST(ReadSurface, NonConvexPolygonsAreTriangulated) {
  // An L-shaped prism: two non-convex hexagonal caps (area 3) and six quads, height 1.
  const Coords l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  std::string text = "OFF\n12 8 0\n";
  for (double z : {0.0, 1.0})
    for (const auto& p : l) text += number(p[0]) + " " + number(p[1]) + " " + number(z) + "\n";
  text += "6 5 4 3 2 1 0\n6 6 7 8 9 10 11\n";
  for (std::size_t i = 0; i < 6; ++i) {
    const std::size_t j = (i + 1) % 6;
    text += "4 " + std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(6 + j) + " " + std::to_string(6 + i) + "\n";
  }
  TempDir dir;
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("l.off", text), &info);
  EXPECT_EQ(info.triangulated_faces, 8u);
  expect_mesh(mesh, 12, 20, 3.0);
}

TEST(ReadSurface, ObjPyramidWithQuadBase) {
  TempDir dir;
  const std::string pyramid =
      "# square pyramid\nmtllib none.mtl\no pyramid\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
      "vn 0 0 -1\nvt 0 0\ng base\nf 1//1 4//1 3//1 2//1\ng sides\ns off\nf 1/1 2/1 5/1\nf 2\t3\t5\nf 3 4 5\nf -2 -5 -1\n";
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("pyramid.obj", pyramid), &info);
  expect_mesh(mesh, 5, 6, 1.0 / 3.0);
  EXPECT_EQ(info.format, "obj");
  EXPECT_EQ(info.file_vertices, 5u);
  EXPECT_EQ(info.triangulated_faces, 1u);
}

TEST(ReadSurface, AsciiStlOctahedronIsWelded) {
  TempDir dir;
  const Faces faces = octahedron_faces();
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("octa.stl", ascii_stl(kOctaPoints, faces)), &info);
  expect_mesh(mesh, 6, 8, 4.0 / 3.0);
  EXPECT_EQ(info.format, "stl");
  EXPECT_EQ(info.file_vertices, 3 * faces.size());
  EXPECT_EQ(info.welded_vertices, 3 * faces.size() - 6);
}

TEST(ReadSurface, BinaryStlTetrahedronIsWelded) {
  TempDir dir;
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("tetra.stl", binary_stl(kTetraPoints, kTetraFaces)), &info);
  expect_mesh(mesh, 4, 4, 1.0 / 6.0);
  EXPECT_EQ(info.file_vertices, 12u);
  EXPECT_EQ(info.welded_vertices, 8u);
}

TEST(ReadSurface, BinaryStlWhoseHeaderSaysSolid) {
  // Many exporters start the binary header with "solid"; the file size must decide.
  TempDir dir;
  const Faces faces = octahedron_faces();
  const Mesh mesh = read_surface(dir.write("octa.stl", binary_stl(kOctaPoints, faces, "solid exported by a CAD tool")));
  expect_mesh(mesh, 6, 8, 4.0 / 3.0);
}

TEST(ReadSurface, AsciiPlyOctahedron) {
  TempDir dir;
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("octa.ply", ascii_ply(kOctaPoints, octahedron_faces())), &info);
  expect_mesh(mesh, 6, 8, 4.0 / 3.0);
  EXPECT_EQ(info.format, "ply");
}

TEST(ReadSurface, BinaryPlyTetrahedron) {
  TempDir dir;
  const Mesh mesh = read_surface(dir.write("tetra.ply", binary_ply(kTetraPoints, kTetraFaces)));
  expect_mesh(mesh, 4, 4, 1.0 / 6.0);
}

TEST(ReadSurface, BinaryPlyWithFloatCoordinatesAndExtraProperties) {
  TempDir dir;
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 4\n"
      "property list uchar uint vertex_index\nend_header\n";
  for (const auto& p : kTetraPoints) {
    for (double c : p) put_float(s, static_cast<float>(c));
    s += std::string("\x10\x20\x30", 3);
  }
  for (const auto& f : kTetraFaces) {
    s += static_cast<char>(3);
    for (std::size_t v : f) put_u32(s, static_cast<std::uint32_t>(v));
  }
  expect_mesh(read_surface(dir.write("tetra.ply", s)), 4, 4, 1.0 / 6.0);
}

TEST(ReadSurface, PlyWith32BitListCounts) {
  TempDir dir;
  std::string ascii = ascii_ply(kTetraPoints, kTetraFaces);
  ascii.replace(ascii.find("list uchar int"), 14, "list int int");
  expect_mesh(read_surface(dir.write("ascii.ply", ascii)), 4, 4, 1.0 / 6.0);
  std::string binary = ply_header("binary_big_endian", "double", 4, 4);
  binary.replace(binary.find("list uchar int"), 14, "list uint int");
  const auto put_be32 = [&](std::uint32_t v) {
    for (int i = 3; i >= 0; --i) binary += static_cast<char>((v >> (8 * i)) & 0xff);
  };
  for (const auto& p : kTetraPoints)
    for (double c : p) {
      std::uint64_t bits;
      std::memcpy(&bits, &c, 8);
      for (int i = 7; i >= 0; --i) binary += static_cast<char>((bits >> (8 * i)) & 0xff);
    }
  for (const auto& f : kTetraFaces) {
    put_be32(3);
    for (std::size_t v : f) put_be32(static_cast<std::uint32_t>(v));
  }
  expect_mesh(read_surface(dir.write("binary.ply", binary)), 4, 4, 1.0 / 6.0);
}

TEST(ReadSurface, ExtensionIsCaseInsensitive) {
  TempDir dir;
  ReadInfo info;
  expect_mesh(read_surface(dir.write("TETRA.Off", kTetrahedronOff), &info), 4, 4, 1.0 / 6.0);
  EXPECT_EQ(info.format, "off");
}

TEST(ReadSurface, InvertedTetrahedronIsFlipped) {
  TempDir dir;
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("inverted.off", off_text(kTetraPoints, reversed(kTetraFaces))), &info);
  EXPECT_TRUE(info.flipped);
  expect_mesh(mesh, 4, 4, 1.0 / 6.0);
}

TEST(ReadSurface, UnusedVerticesAreDropped) {
  TempDir dir;
  Coords points = kTetraPoints;
  points.push_back({5, 5, 5});
  ReadInfo info;
  const Mesh mesh = read_surface(dir.write("extra.off", off_text(points, kTetraFaces)), &info);
  EXPECT_EQ(info.file_vertices, 5u);
  EXPECT_EQ(info.isolated_vertices, 1u);
  expect_mesh(mesh, 4, 4, 1.0 / 6.0);
}

// ---- Real models --------------------------------------------------------------------------

struct Model {
  const char* file;
  std::size_t vertices;
  int genus;
};

void PrintTo(const Model& m, std::ostream* os) { *os << m.file; }

class RealModel : public ::testing::TestWithParam<Model> {};

TEST_P(RealModel, ReadsAndValidates) {
  const Model& m = GetParam();
  const std::string path = std::string(VOLTS_SHARED_MODELS) + "/" + m.file;
  ReadInfo info;
  const Mesh mesh = read_surface(path, &info);
  EXPECT_EQ(mesh.number_of_vertices(), m.vertices);
  EXPECT_EQ(info.file_vertices, m.vertices);  // no duplicates, nothing unused
  EXPECT_EQ(genus(mesh), m.genus);
  // Closed triangle mesh: E = 3F/2, so V - F/2 = 2 - 2g.
  EXPECT_EQ(mesh.number_of_faces(), 2 * (m.vertices - 2 + 2 * static_cast<std::size_t>(m.genus)));
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_FALSE(info.flipped);  // SOURCES.md: outward normals
  EXPECT_GT(signed_volume(mesh), 0.0);
  EXPECT_GT(bbox_diagonal(mesh), 0.0);
}

INSTANTIATE_TEST_SUITE_P(SharedModels, RealModel,
                         ::testing::Values(Model{"cinolib_torus.obj", 768, 1}, Model{"cfwen_eight.off", 766, 2},
                                           Model{"loopycuts_rod_rem.obj", 2212, 2}, Model{"vhacd_tube1.off", 48, 1},
                                           Model{"c3d_fandisk.obj", 6475, 0},
                                           Model{"loopycuts_mechanical08_rem.obj", 1464, 1}),
                         [](const auto& info) {
                           std::string name = info.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// ---- Broken inputs ------------------------------------------------------------------------

TEST(ReadSurfaceRefuses, MissingFile) {
  TempDir dir;
  const std::string path = dir.file("nothing.off");
  expect_invalid_input([&] { read_surface(path); }, path, "cannot open");
}

TEST(ReadSurfaceRefuses, EmptyFile) {
  TempDir dir;
  for (const std::string name : {"empty.off", "empty.obj", "empty.stl", "empty.ply"}) {
    const std::string path = dir.write(name, "");
    expect_invalid_input([&] { read_surface(path); }, path, "empty file");
  }
  const std::string blank = dir.write("blank.off", " \n\t\r\n");
  expect_invalid_input([&] { read_surface(blank); }, blank, "empty file");
}

TEST(ReadSurfaceRefuses, UnknownExtension) {
  TempDir dir;
  const std::string path = dir.write("tetra.xyz", kTetrahedronOff);
  expect_invalid_input([&] { read_surface(path); }, path, "unknown extension '.xyz'");
  const std::string bare = dir.write("tetra", kTetrahedronOff);
  expect_invalid_input([&] { read_surface(bare); }, bare, "unknown extension ''");
}

TEST(ReadSurfaceRefuses, OpenMesh) {
  TempDir dir;
  Faces faces = kTetraFaces;
  faces.pop_back();  // remove face (1, 2, 3): its three edges become boundary edges
  const std::string path = dir.write("open.off", off_text(kTetraPoints, faces));
  expect_invalid_input([&] { read_surface(path); }, path, "open surface: 3 boundary edges, first at vertex ");
  // Same through STL, where vertices are triangle corners.
  const std::string stl = dir.write("open.stl", binary_stl(kTetraPoints, faces));
  expect_invalid_input([&] { read_surface(stl); }, stl, "open surface: 3 boundary edges, first at vertex ");
}

TEST(ReadSurfaceRefuses, NonManifoldEdge) {
  TempDir dir;
  const auto [points, faces] = two_tetrahedra(2);  // share the edge 0-1, used by 4 faces
  const std::string path = dir.write("edge.off", off_text(points, faces));
  expect_invalid_input([&] { read_surface(path); }, path,
                       "1 non-manifold edge (used by more than 2 faces), first is the edge between vertex 0 (0, 0, 0) "
                       "and vertex 1 (1, 0, 0) (4 faces)");
}

TEST(ReadSurfaceRefuses, NonManifoldVertex) {
  TempDir dir;
  const auto [points, faces] = two_tetrahedra(1);  // share vertex 0 only
  const std::string path = dir.write("vertex.obj", [&] {
    std::string s;
    for (const auto& p : points) s += "v " + number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
    for (const auto& f : faces) s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
    return s;
  }());
  expect_invalid_input([&] { read_surface(path); }, path,
                       "1 non-manifold vertex (the faces around it form more than one fan), first is vertex 0 (0, 0, 0)");
}

TEST(ReadSurfaceRefuses, InconsistentOrientation) {
  TempDir dir;
  Faces faces = kTetraFaces;
  std::swap(faces[3][1], faces[3][2]);
  const std::string path = dir.write("orientation.ply", ascii_ply(kTetraPoints, faces));
  expect_invalid_input([&] { read_surface(path); }, path,
                       "inconsistent orientation: 3 edges traversed twice in the same direction, first between vertex 1");
}

TEST(ReadSurfaceRefuses, NanCoordinate) {
  TempDir dir;
  const std::string off = dir.write("nan.off", "OFF\n4 4 0\n0 0 0\n1 0 0\nnan 1 0\n0 0 -nan\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_invalid_input([&] { read_surface(off); }, off,
                       "2 vertices with non-finite coordinates (NaN/Inf), first at vertex 2 (line 5: 'nan 1 0')");

  Coords points = kTetraPoints;
  points[3][1] = std::numeric_limits<double>::quiet_NaN();
  const std::string stl = dir.write("nan.stl", binary_stl(points, kTetraFaces));
  // Vertex 3 is a corner of triangles 1, 2 and 3; the first is corner 2 of triangle 1 (0, 1, 3).
  expect_invalid_input([&] { read_surface(stl); }, stl,
                       "3 vertices with non-finite coordinates (NaN/Inf), first at vertex 5 (corner 2 of triangle 1)");
  const std::string ply = dir.write("nan.ply", binary_ply(points, kTetraFaces));
  expect_invalid_input([&] { read_surface(ply); }, ply, "1 vertex with non-finite coordinates (NaN/Inf), first at vertex 3");
}

TEST(ReadSurfaceRefuses, InfCoordinate) {
  TempDir dir;
  const std::string obj = dir.write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  expect_invalid_input([&] { read_surface(obj); }, obj,
                       "1 vertex with non-finite coordinates (NaN/Inf), first at vertex 3 (line 4: 'v 0 0 inf')");
  // An overflowing literal is infinite too.
  const std::string off = dir.write("inf.off", "OFF\n4 4 0\n0 0 0\n1e999 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_invalid_input([&] { read_surface(off); }, off, "1 vertex with non-finite coordinates (NaN/Inf), first at vertex 1");
  const std::string stl = dir.write("inf.stl", "solid s\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex -Infinity 0 0\n"
                                                "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n");
  expect_invalid_input([&] { read_surface(stl); }, stl, "1 vertex with non-finite coordinates (NaN/Inf), first at vertex 1");
}

TEST(ReadSurfaceRefuses, ZeroAreaFace) {
  TempDir dir;
  Coords points = kTetraPoints;
  points[3] = {2, 0, 0};  // collinear with vertices 0 and 1: face 1 (0, 1, 3) has zero area
  const std::string path = dir.write("flat.off", off_text(points, kTetraFaces));
  expect_invalid_input([&] { read_surface(path); }, path, "1 zero-area face, first is face 1");
}

TEST(ReadSurfaceRefuses, NonFiniteIsReportedBeforeZeroArea) {
  TempDir dir;
  Coords points = kTetraPoints;
  points[3] = {2, 0, 0};
  points[2][2] = std::numeric_limits<double>::infinity();
  const std::string path = dir.write("both.ply", binary_ply(points, kTetraFaces));
  expect_invalid_input([&] { read_surface(path); }, path, "non-finite coordinates (NaN/Inf), first at vertex 2");
}

TEST(ReadSurfaceRefuses, TwoComponents) {
  TempDir dir;
  const auto [points, faces] = two_tetrahedra(0);
  const std::string path = dir.write("two.stl", ascii_stl(points, faces));
  expect_invalid_input([&] { read_surface(path); }, path,
                       "2 connected components; volts needs one closed solid (4 faces from face 0, 4 faces from face 4)");
}

TEST(ReadSurfaceRefuses, EnclosedVolumeZero) {
  TempDir dir;
  const std::string path = dir.write("pillow.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n");
  expect_invalid_input([&] { read_surface(path); }, path, "encloses no volume");
}

TEST(ReadSurfaceRefuses, VertexUsedTwiceByAFace) {
  TempDir dir;
  // Vertices 1 and 4 are at the same position: after welding face 0 uses one vertex twice.
  const std::string path = dir.write("pinch.off", "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0\n"
                                                   "3 4 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_invalid_input([&] { read_surface(path); }, path, "1 face uses a vertex twice, first is face 0 (vertex 1 (1, 0, 0) twice)");
}

TEST(ReadSurfaceRefuses, TruncatedOff) {
  TempDir dir;
  const std::string& full = kTetrahedronOff;
  // Cut after the second face line.
  const std::size_t cut = full.find("3 0 3 2");
  const std::string at_line = dir.write("cut_line.off", full.substr(0, cut));
  expect_invalid_input([&] { read_surface(at_line); }, at_line,
                       "truncated OFF file: the header announces 4 vertices and 4 faces, the file ends after 4 vertices "
                       "and 2 faces (line 8: '3 0 1 3')");
  // Cut in the middle of the third face line.
  const std::string mid_line = dir.write("cut_mid.off", full.substr(0, cut + 5));
  expect_invalid_input([&] { read_surface(mid_line); }, mid_line, "truncated OFF file");
  // Cut early: the header's counts cannot fit in what is left.
  const std::string early = dir.write("cut_early.off", full.substr(0, 16));
  expect_invalid_input([&] { read_surface(early); }, early, "truncated OFF file: the header announces 4 vertices and 4 faces");
}

TEST(ReadSurfaceRefuses, OffWithMoreFacesThanAnnounced) {
  TempDir dir;
  std::string text = kTetrahedronOff;
  text.replace(text.find("4 4 0"), 5, "4 3 0");
  const std::string path = dir.write("counts.off", text);
  expect_invalid_input([&] { read_surface(path); }, path, "data after the 3 faces the header announces (line 10: '3 1 2 3')");
}

TEST(ReadSurfaceRefuses, TruncatedBinaryStl) {
  TempDir dir;
  const std::string full = binary_stl(kTetraPoints, kTetraFaces);
  const std::string cut = dir.write("cut.stl", full.substr(0, full.size() - 30));
  expect_invalid_input([&] { read_surface(cut); }, cut,
                       "truncated binary STL file: its header announces 4 triangles, i.e. 284 bytes, but the file has 254 bytes");
  const std::string longer = dir.write("long.stl", full + std::string(7, '\0'));
  expect_invalid_input([&] { read_surface(longer); }, longer, "malformed binary STL file: its header announces 4 triangles");
}

TEST(ReadSurfaceRefuses, TruncatedAsciiStlAndPly) {
  TempDir dir;
  const std::string stl_text = ascii_stl(kOctaPoints, octahedron_faces());
  const std::string stl = dir.write("cut.stl", stl_text.substr(0, stl_text.size() / 2));
  expect_invalid_input([&] { read_surface(stl); }, stl, "truncated ASCII STL file: it does not end with 'endsolid'");

  const std::string ascii = ascii_ply(kOctaPoints, octahedron_faces());
  const std::string ply = dir.write("cut.ply", ascii.substr(0, ascii.size() - 4));  // in the last face
  expect_invalid_input([&] { read_surface(ply); }, ply, "truncated ASCII PLY file: the header announces 14 element items");
  const std::string ply_lines = dir.write("cut_lines.ply", ascii.substr(0, ascii.find("\n3 ") + 1));  // no faces
  expect_invalid_input([&] { read_surface(ply_lines); }, ply_lines, "truncated ASCII PLY file");

  const std::string binary = binary_ply(kTetraPoints, kTetraFaces);
  const std::string bply = dir.write("cut_binary.ply", binary.substr(0, binary.size() - 3));
  expect_invalid_input([&] { read_surface(bply); }, bply, "truncated binary PLY file");
}

TEST(ReadSurfaceRefuses, FaceIndexOutOfRange) {
  TempDir dir;
  std::string text = kTetrahedronOff;
  text.replace(text.find("3 1 2 3"), 7, "3 1 2 9");
  const std::string off = dir.write("range.off", text);
  expect_invalid_input([&] { read_surface(off); }, off,
                       "1 face with a vertex index out of range, first is face 3 (vertex index 9, but there are 4 vertices; "
                       "line 10: '3 1 2 9')");
  // CGAL's OBJ reader lets index == number of vertices through (off by one); the soup checks stop it.
  const std::string obj = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 5\n");
  expect_invalid_input([&] { read_surface(obj); }, obj,
                       "1 face with a vertex index out of range, first is face 3 (vertex index 4, but there are 4 vertices)");
  const std::string obj_far = dir.write("far.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 40\n");
  expect_invalid_input([&] { read_surface(obj_far); }, obj_far, "first is face 3 (vertex index 39, but there are 4 vertices)");
  Faces faces = kTetraFaces;
  faces[2][1] = 4;
  const std::string ply = dir.write("range.ply", binary_ply(kTetraPoints, faces));
  expect_invalid_input([&] { read_surface(ply); }, ply, "first is face 2 (vertex index 4, but there are 4 vertices)");
}

TEST(ReadSurfaceRefuses, UnsupportedPlyCoordinates) {
  // CGAL's PLY reader would dereference a null pointer on integer coordinates.
  TempDir dir;
  const std::string path = dir.write("int.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty int x\nproperty int y\n"
                                                 "property int z\nelement face 4\nproperty list uchar int vertex_indices\n"
                                                 "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_invalid_input([&] { read_surface(path); }, path, "unsupported PLY: vertex coordinate 'x' is of type int");
}

TEST(ReadSurfaceRefuses, HugeCountsAreNotAllocated) {
  // CGAL would size these arrays from the counts before reading: the counts must be caught first.
  TempDir dir;
  const std::string header = dir.write("header.off", "OFF\n2000000000 2000000000 0\n0 0 0\n");
  // Refused from the header alone, before CGAL's scanner (whose int arithmetic on them would overflow).
  expect_invalid_input([&] { read_surface(header); }, header,
                       "declares 2000000000 vertices, more than this machine can hold (limit ");
  std::string text = kTetrahedronOff;
  text.replace(text.find("3 1 2 3"), 7, "3000000000 1 2 3");
  const std::string face = dir.write("face.off", text);
  expect_invalid_input([&] { read_surface(face); }, face, "malformed face 3: 3000000000 vertex indices announced, 3 given");
  std::string ply = binary_ply(kTetraPoints, kTetraFaces, /*wide_counts=*/true);
  const std::size_t first_face = ply.find("end_header\n") + 11 + 4 * 3 * 8;
  ply.replace(first_face, 4, std::string("\xff\xff\xff\x7f", 4));  // face 0: 2^31 - 1 entries
  const std::string huge = dir.write("huge.ply", ply);
  expect_invalid_input([&] { read_surface(huge); }, huge,
                       "malformed PLY file: face 0 announces a list of 2147483647 entries, more than the rest of the file holds");
}

TEST(ReadSurfaceRefuses, MalformedLines) {
  TempDir dir;
  const std::string off = dir.write("word.off", "OFF\n4 4 0\n0 0 0\n1 zero 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_invalid_input([&] { read_surface(off); }, off, "malformed vertex 1: 'zero' is not a number (line 4: '1 zero 0')");
  const std::string obj = dir.write("word.obj", "v 0 0 0\nv 1 0 0\nbogus statement\nv 0 1 0\n");
  expect_invalid_input([&] { read_surface(obj); }, obj, "malformed or unsupported OBJ statement (line 3: 'bogus statement')");
  const std::string header = dir.write("header.off", "OFF\nfour four zero\n");
  expect_invalid_input([&] { read_surface(header); }, header, "not an OFF file: missing or malformed header");
  const std::string ply = dir.write("header.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
  expect_invalid_input([&] { read_surface(ply); }, ply, "malformed PLY header: no 'end_header' line");
}

TEST(ReadSurfaceRefuses, GarbageBytes) {
  TempDir dir;
  std::mt19937 random(12345);
  for (const std::string prefix : {"", "OFF\n", "OFF\n3 1 0\n", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n",
                                   "solid x\n", "v 0 0 0\n"}) {
    for (const std::string ext : {"off", "obj", "stl", "ply"}) {
      for (const std::size_t size : {7u, 100u, 4096u}) {
        std::string bytes = prefix;
        for (std::size_t i = 0; i < size; ++i) bytes += static_cast<char>(random() & 0xff);
        const std::string path = dir.write("garbage." + ext, bytes);
        expect_invalid_input([&] { read_surface(path); }, path, "");
      }
    }
  }
}

}  // namespace
}  // namespace volts::surface::test
