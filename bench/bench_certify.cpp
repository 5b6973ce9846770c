// bench_certify: certified Jacobian validity (bezier/certify.h) of N valid cubic Bézier hexes,
// compared with Gmsh's Jacobian-bound check (Plugin(AnalyseMeshQuality), JacobianDeterminant = 1)
// on the same elements written as cubic Lagrange hexes (MSH 4.1, element type 92).
//
// The elements: a (3nx+1) x (3ny+1) x (3nz+1) grid of Lagrange nodes moved by a random smooth
// displacement (sums of sines, gradient < 0.3, so every element is valid); each cell's 64 nodes
// convert exactly to Bézier control points (inverse Bernstein collocation). Gmsh's node order of
// type 92 is taken from Gmsh itself: it meshes one order-3 hex and the node coordinates are read
// back. Single thread on both sides (Gmsh: General.NumThreads = 1), so the rates are per core.
//
// Usage: bench_certify [--elements N] [--seed S] [--workdir DIR] [--no-gmsh]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bezier/bernstein.h"
#include "bezier/certify.h"
#include "bezier/jacobian_bernstein.h"

using namespace volts;
using Eigen::Vector3d;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
// Process CPU time: the rates are per core even when other jobs share the machine.
double cpu_since(std::clock_t t) { return double(std::clock() - t) / CLOCKS_PER_SEC; }

struct Field {
  // x + Σ_m a_m sin(k_m · x + φ_m) d_m, random directions d_m, wave vectors k_m, phases φ_m.
  std::vector<Vector3d> k, d;
  std::vector<double> phase, amp;
  Vector3d operator()(const Vector3d& x) const {
    Vector3d y = x;
    for (std::size_t m = 0; m < k.size(); ++m) y += amp[m] * std::sin(k[m].dot(x) + phase[m]) * d[m];
    return y;
  }
};

Field random_field(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1), ph(0, 6.283185307179586);
  Field f;
  for (int m = 0; m < 6; ++m) {
    Vector3d k(u(rng), u(rng), u(rng));
    k = k.normalized() * (0.3 + 0.4 * std::abs(u(rng)));  // wavelengths of 9..21 cells
    f.k.push_back(k);
    f.d.push_back(Vector3d(u(rng), u(rng), u(rng)).normalized());
    f.phase.push_back(ph(rng));
    f.amp.push_back(0.3 / 6 / k.norm());  // |∇| <= Σ a |k| = 0.3
  }
  return f;
}

// Gmsh's local node order of element type 92 as (i,j,k) in {0..3}^3, read from a one-element
// mesh that Gmsh makes itself. Empty (with a message) if Gmsh fails.
std::vector<std::array<int, 3>> gmsh_hex64_order(const std::string& dir) {
  const std::string geo = dir + "/ref.geo", msh = dir + "/ref.msh";
  std::ofstream(geo) << "Point(1)={0,0,0}; Point(2)={1,0,0}; Point(3)={1,1,0}; Point(4)={0,1,0};\n"
                        "Line(1)={1,2}; Line(2)={2,3}; Line(3)={3,4}; Line(4)={4,1};\n"
                        "Curve Loop(1)={1,2,3,4}; Plane Surface(1)={1};\n"
                        "Transfinite Curve{1,2,3,4}=2; Transfinite Surface{1}; Recombine Surface{1};\n"
                        "Extrude{0,0,1}{ Surface{1}; Layers{1}; Recombine; }\n"
                        "Mesh.ElementOrder=3; Mesh.SecondOrderIncomplete=0; Mesh.MshFileVersion=4.1; Mesh.Binary=0;\n"
                        "Mesh 3; Save \"" + msh + "\";\n";
  if (std::system(("gmsh " + geo + " - > " + dir + "/ref.log 2>&1").c_str()) != 0) return {};
  std::ifstream in(msh);
  std::string line;
  std::map<long, Vector3d> nodes;
  std::vector<std::array<int, 3>> order;
  while (std::getline(in, line)) {
    if (line == "$Nodes") {
      long blocks, n, a, b;
      in >> blocks >> n >> a >> b;
      for (long bl = 0; bl < blocks; ++bl) {
        int dim, tag, param;
        long cnt;
        in >> dim >> tag >> param >> cnt;
        std::vector<long> tags(cnt);
        for (auto& t : tags) in >> t;
        for (long t : tags) in >> nodes[t][0] >> nodes[t][1] >> nodes[t][2];
      }
    } else if (line == "$Elements") {
      long blocks, n, a, b;
      in >> blocks >> n >> a >> b;
      for (long bl = 0; bl < blocks; ++bl) {
        int dim, tag, type;
        long cnt;
        in >> dim >> tag >> type >> cnt;
        std::getline(in, line);
        for (long e = 0; e < cnt; ++e) {
          std::getline(in, line);
          if (type != 92) continue;
          std::istringstream ls(line);
          long id, t;
          ls >> id;
          while (ls >> t) {
            const Vector3d x = nodes[t] * 3;
            order.push_back({int(std::lround(x[0])), int(std::lround(x[1])), int(std::lround(x[2]))});
          }
        }
      }
    }
  }
  return order;
}

}  // namespace

int main(int argc, char** argv) {
  long n_elements = 100000;
  unsigned seed = 1;
  std::string dir = "/tmp/volts-bench";
  bool with_gmsh = true;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "--elements" && a + 1 < argc) n_elements = std::atol(argv[++a]);
    else if (s == "--seed" && a + 1 < argc) seed = unsigned(std::atol(argv[++a]));
    else if (s == "--workdir" && a + 1 < argc) dir = argv[++a];
    else if (s == "--no-gmsh") with_gmsh = false;
    else {
      std::cout << "usage: bench_certify [--elements N] [--seed S] [--workdir DIR] [--no-gmsh]\n";
      return s == "--help" ? 0 : 2;
    }
  }
  std::system(("mkdir -p " + dir).c_str());
  std::mt19937 rng(seed);
  const Field phi = random_field(rng);
  const int nx = 50, ny = 50, nz = int((n_elements + nx * ny - 1) / (nx * ny));
  const int gx = 3 * nx + 1, gy = 3 * ny + 1, gz = 3 * nz + 1;
  const auto node_id = [&](int i, int j, int k) { return long(i) + long(gx) * (j + long(gy) * k); };

  // Lagrange nodes -> Bézier points: per direction solve B c = x, B(a,b) = B_b^3(a/3).
  Eigen::Matrix4d B;
  for (int a = 0; a < 4; ++a) B.row(a) = bezier::bernstein_basis(3, a / 3.0).transpose();
  const Eigen::Matrix4d Binv = B.inverse();
  std::vector<bezier::BezierHex> hexes(n_elements);
  for (long e = 0; e < n_elements; ++e) {
    const int ci = int(e % nx), cj = int((e / nx) % ny), ck = int(e / (long(nx) * ny));
    bezier::BezierHex& h = hexes[e];
    h.points.resize(64);
    for (int n = 0; n < 64; ++n) {
      const auto [i, j, k] = h.ijk(n);
      h.points[n] = phi(Vector3d(3 * ci + i, 3 * cj + j, 3 * ck + k) / 3.0);
    }
    h = bezier::map_coefficients(h, {Binv, Binv, Binv});
  }

  // Certification, one thread.
  bezier::TensorBernstein det;
  std::clock_t c0 = std::clock();
  for (const auto& h : hexes) bezier::jacobian_determinant(h, det);
  const double t_coef = cpu_since(c0);
  long valid = 0, invalid = 0, subdivided = 0;
  double min_rel = INFINITY;
  c0 = std::clock();
  for (const auto& h : hexes) {
    const bezier::CertifyResult r = bezier::certify(h);
    valid += r.status == bezier::Validity::valid;
    invalid += r.status == bezier::Validity::invalid;
    subdivided += r.subdivisions > 0;
    min_rel = std::min(min_rel, r.min_detj_lower);  // det J of an undeformed cell is 1
  }
  const double t_cert = cpu_since(c0);
  std::printf("volts certify: %ld cubic hexes: %ld valid, %ld invalid, %ld undecided; %ld needed subdivision\n",
              n_elements, valid, invalid, n_elements - valid - invalid, subdivided);
  std::printf("volts certify (CPU time): det J coefficients only %.3f s (%.0f hexes/s), full certification %.3f s = %.0f hexes/s/core"
              " (min det J lower bound / undeformed %.3f)\n",
              t_coef, n_elements / t_coef, t_cert, n_elements / t_cert, min_rel);
  if (!with_gmsh) return 0;

  const auto order = gmsh_hex64_order(dir);
  if (order.size() != 64) {
    std::printf("gmsh: not available or no type-92 element in its reference mesh (see %s/ref.log); skipped\n", dir.c_str());
    return 0;
  }
  const std::string msh = dir + "/bench_hex64.msh";
  auto t0 = Clock::now();
  {
    std::ofstream out(msh);
    out.precision(17);
    const long nn = long(gx) * gy * gz;
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n1 0 0 0 " << 3 * nx << " " << 3 * ny << " "
        << 3 * nz << " 0 0\n$EndEntities\n";
    out << "$Nodes\n1 " << nn << " 1 " << nn << "\n3 1 0 " << nn << "\n";
    for (long t = 1; t <= nn; ++t) out << t << "\n";
    for (int k = 0; k < gz; ++k)
      for (int j = 0; j < gy; ++j)
        for (int i = 0; i < gx; ++i) {
          const Vector3d x = phi(Vector3d(i, j, k) / 3.0);
          out << x[0] << " " << x[1] << " " << x[2] << "\n";
        }
    out << "$EndNodes\n$Elements\n1 " << n_elements << " 1 " << n_elements << "\n3 1 92 " << n_elements << "\n";
    for (long e = 0; e < n_elements; ++e) {
      const int ci = int(e % nx), cj = int((e / nx) % ny), ck = int(e / (long(nx) * ny));
      out << e + 1;
      for (const auto& o : order) out << " " << node_id(3 * ci + o[0], 3 * cj + o[1], 3 * ck + o[2]) + 1;
      out << "\n";
    }
    out << "$EndElements\n";
  }
  std::printf("gmsh: wrote %s in %.1f s\n", msh.c_str(), seconds_since(t0));
  const std::string geo = dir + "/bench.geo", log = dir + "/bench_gmsh.log";
  std::ofstream(geo) << "General.NumThreads = 1;\nMerge \"" << msh << "\";\nt0 = Cpu;\n"
                     << "Plugin(AnalyseMeshQuality).JacobianDeterminant = 1;\n"
                        "Plugin(AnalyseMeshQuality).IGEMeasure = 0;\nPlugin(AnalyseMeshQuality).ICNMeasure = 0;\n"
                        "Plugin(AnalyseMeshQuality).HidingThreshold = 99;\nPlugin(AnalyseMeshQuality).DimensionOfElements = -1;\n"
                        "Plugin(AnalyseMeshQuality).CreateView = 0;\nPlugin(AnalyseMeshQuality).Recompute = 1;\n"
                        "Plugin(AnalyseMeshQuality).Run;\nPrintf(\"volts-bench: plugin cpu %g s\", Cpu - t0);\n";
  if (std::system(("gmsh " + geo + " - > " + log + " 2>&1").c_str()) != 0) {
    std::printf("gmsh: failed, see %s\n", log.c_str());
    return 1;
  }
  std::ifstream in(log);
  std::string line, done, minj;
  double plugin_cpu = -1;
  while (std::getline(in, line)) {
    if (line.find("Done computing Jacobian for 3D") != std::string::npos) done = line;
    if (line.find("minJ      =") != std::string::npos) minj = line;
    std::smatch m;
    if (std::regex_search(line, m, std::regex("volts-bench: plugin cpu ([0-9.eE+-]+) s"))) plugin_cpu = std::stod(m[1]);
  }
  std::smatch m;
  double gmsh_cpu = plugin_cpu;
  if (std::regex_search(done, m, std::regex("CPU ([0-9.eE+-]+)s"))) gmsh_cpu = std::stod(m[1]);
  std::printf("gmsh AnalyseMeshQuality (JacobianDeterminant): %.3f s CPU in the Jacobian check (%.3f s whole plugin) ="
              " %.0f hexes/s/core\n  %s\n", gmsh_cpu, plugin_cpu, n_elements / gmsh_cpu,
              minj.empty() ? "(no minJ line)" : minj.substr(minj.find("minJ")).c_str());
  std::printf("ratio: volts certify is %.1fx the speed of gmsh\n", gmsh_cpu / t_cert);
  return 0;
}
