// Helper of bench_tet_route (its own process: libgmsh embeds a TetGen that would shadow libtet's).
// bench_gmsh_hex SURFACE.stl OUT.txt [straight]: Gmsh's all-hex route on the surface — the STL as a discrete
// volume, Delaunay tets split into hexes (Mesh.SubdivisionAlgorithm = 2), order 3 — and the
// 64-node Lagrange hexes as Bézier hexes by interpolation at Gmsh's own reference node coordinates
// (getElementProperties(92)). OUT: "seconds count", then per hex 64 control points (index
// i + 4(j + 4k)) and 6 flags (face axis 0..2 × side 0/1 on the boundary).
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <map>

#include "bezier/bernstein.h"
#include "bezier/bezier_hex.h"
#include "core/log.h"

using namespace volts;

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: bench_gmsh_hex SURFACE.stl OUT.txt [straight]\n");
    return 2;
  }
  const std::string stl = argv[1], out = argv[2], geo = out + ".geo";
  {
    std::ofstream g(geo);
    g << "Merge \"" << stl << "\";\nSurface Loop(1) = {1};\nVolume(1) = {1};\nMesh.SubdivisionAlgorithm = 2;\nMesh.ElementOrder = 3;\n";
    // straight: high-order nodes on the straight edges/faces (Mesh.SecondOrderLinear) instead of
    // snapped onto Gmsh's parametrization of the discrete (STL) surface.
    if (argc == 4 && std::string(argv[3]) == "straight") g << "Mesh.SecondOrderLinear = 1;\n";
  }
  core::Stopwatch watch;
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open(geo);
  gmsh::model::mesh::generate(3);
  const double seconds = watch.seconds();
  std::string name;
  int dim, order, nn, np;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(92, name, dim, order, nn, local, np);
  std::vector<std::size_t> tags, conn, node_tags;
  gmsh::model::mesh::getElementsByType(92, tags, conn);
  std::vector<double> coord, param;
  gmsh::model::mesh::getNodes(node_tags, coord, param);
  gmsh::finalize();
  std::map<std::size_t, Eigen::Vector3d> node;
  for (std::size_t i = 0; i < node_tags.size(); ++i) node[node_tags[i]] = Eigen::Vector3d(coord[3 * i], coord[3 * i + 1], coord[3 * i + 2]);
  const int p = 3, N = 64;
  bezier::BezierHex tmpl;
  tmpl.degree = {p, p, p};
  Eigen::MatrixXd B(N, N);
  for (int a = 0; a < N; ++a) {
    const Eigen::VectorXd bu = bezier::bernstein_basis(p, (local[3 * a] + 1) / 2), bv = bezier::bernstein_basis(p, (local[3 * a + 1] + 1) / 2),
                          bw = bezier::bernstein_basis(p, (local[3 * a + 2] + 1) / 2);
    for (int k = 0; k <= p; ++k)
      for (int j = 0; j <= p; ++j)
        for (int i = 0; i <= p; ++i) B(a, tmpl.index(i, j, k)) = bu[i] * bv[j] * bw[k];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(B);
  // Boundary faces: corner-node sets used by one hex only.
  std::map<std::array<std::size_t, 4>, int> count;
  auto face_key = [&](std::size_t e, int axis, int side) {
    std::array<std::size_t, 4> key;
    int m = 0;
    for (int c = 0; c < np; ++c)
      if ((local[3 * c + axis] > 0) == (side == 1)) key[m++] = conn[e * N + c];
    std::sort(key.begin(), key.end());
    return key;
  };
  for (std::size_t e = 0; e < tags.size(); ++e)
    for (int f = 0; f < 6; ++f) ++count[face_key(e, f / 2, f % 2)];
  std::ofstream o(out);
  o.precision(17);
  o << seconds << " " << tags.size() << "\n";
  for (std::size_t e = 0; e < tags.size(); ++e) {
    Eigen::MatrixXd X(N, 3);
    for (int a = 0; a < N; ++a) X.row(a) = node.at(conn[e * N + a]).transpose();
    const Eigen::MatrixXd C = lu.solve(X);
    for (int a = 0; a < N; ++a) o << C(a, 0) << " " << C(a, 1) << " " << C(a, 2) << "\n";
    for (int f = 0; f < 6; ++f) o << (count[face_key(e, f / 2, f % 2)] == 1) << (f < 5 ? " " : "\n");
  }
  return 0;
}
