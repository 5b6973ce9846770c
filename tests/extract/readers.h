// Small independent readers of the solver exports for the tests: Gmsh MSH 4.1 ASCII (one node and
// one element block as volts writes, but parsed by the format's own counts) and BEXT 2.0 (as
// libMesh's DynaIO reads it). Failures are gtest failures, not exceptions.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace volts::test {

struct Msh {
  std::map<long, Eigen::Vector3d> nodes;  ///< by tag
  std::vector<int> types;                 ///< per element
  std::vector<std::vector<long>> elements;
};

/// Reads MSH 4.1 ASCII: $MeshFormat must be 4.1 0 8; all node and element blocks.
inline Msh read_msh(const std::string& path) {
  Msh m;
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::string line;
  while (std::getline(in, line)) {
    if (line == "$MeshFormat") {
      std::getline(in, line);
      EXPECT_EQ(line, "4.1 0 8");
    } else if (line == "$Nodes") {
      long blocks = 0, total = 0, lo = 0, hi = 0;
      in >> blocks >> total >> lo >> hi;
      for (long b = 0; b < blocks; ++b) {
        long dim = 0, tag = 0, param = 0, n = 0;
        in >> dim >> tag >> param >> n;
        std::vector<long> tags(n);
        for (auto& t : tags) in >> t;
        for (const long t : tags) {
          Eigen::Vector3d x;
          in >> x[0] >> x[1] >> x[2];
          m.nodes[t] = x;
        }
      }
      EXPECT_EQ(static_cast<long>(m.nodes.size()), total);
    } else if (line == "$Elements") {
      long blocks = 0, total = 0, lo = 0, hi = 0;
      in >> blocks >> total >> lo >> hi;
      for (long b = 0; b < blocks; ++b) {
        long dim = 0, tag = 0, type = 0, n = 0;
        in >> dim >> tag >> type >> n;
        std::getline(in, line);
        for (long e = 0; e < n; ++e) {
          std::getline(in, line);
          std::istringstream s(line);
          long id = 0, v = 0;
          s >> id;
          std::vector<long> conn;
          while (s >> v) conn.push_back(v);
          m.types.push_back(static_cast<int>(type));
          m.elements.push_back(conn);
        }
      }
      EXPECT_EQ(static_cast<long>(m.elements.size()), total);
    }
  }
  return m;
}

struct Bext {
  long patch = 0, nodes = 0, elements = 0, vectors = 0, weight_flag = 0;
  std::vector<Eigen::Vector4d> xyzw;
  std::vector<std::vector<long>> element_nodes;    ///< 0-based
  std::vector<std::vector<long>> element_vectors;  ///< 0-based
  std::vector<std::array<long, 3>> degrees;        ///< per element
  std::vector<std::vector<double>> coefficient_vectors;
};

/// Reads BEXT 2.0 token by token after the header line, skipping "$#" comment lines.
inline Bext read_bext(const std::string& path) {
  Bext b;
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::string line, text;
  std::getline(in, line);
  EXPECT_EQ(line, "B E X T 2.0");
  while (std::getline(in, line))
    if (line.rfind("$#", 0) != 0) text += line + "\n";
  std::istringstream s(text);
  s >> b.patch >> b.nodes >> b.elements >> b.vectors >> b.weight_flag;
  b.xyzw.resize(b.nodes);
  for (auto& x : b.xyzw) s >> x[0] >> x[1] >> x[2] >> x[3];
  long blocks = 0;
  s >> blocks;
  struct Block { long type, n, nodes, vectors; std::array<long, 3> p; };
  std::vector<Block> bl(blocks);
  for (auto& k : bl) s >> k.type >> k.n >> k.nodes >> k.vectors >> k.p[0] >> k.p[1] >> k.p[2];
  for (const auto& k : bl)
    for (long e = 0; e < k.n; ++e) {
      std::vector<long> n(k.nodes), v(k.vectors);
      for (auto& x : n) s >> x, --x;
      for (auto& x : v) s >> x, --x;
      b.element_nodes.push_back(n);
      b.element_vectors.push_back(v);
      b.degrees.push_back(k.p);
    }
  long dense = 0, sparse = 0;
  s >> dense >> sparse;
  EXPECT_EQ(sparse, 0);
  std::vector<std::array<long, 2>> sizes(dense);
  for (auto& z : sizes) s >> z[0] >> z[1];
  for (const auto& z : sizes)
    for (long v = 0; v < z[0]; ++v) {
      std::vector<double> c(z[1]);
      for (auto& x : c) s >> x;
      b.coefficient_vectors.push_back(c);
    }
  EXPECT_FALSE(s.fail()) << path << ": truncated";
  return b;
}

}  // namespace volts::test
