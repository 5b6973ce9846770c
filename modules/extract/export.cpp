#include "extract/export.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <fstream>
#include <sstream>
#include <string_view>

#include "bezier/bernstein.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stage_file.h"
#include "extract/point_index.h"

namespace volts::extract {

namespace {

// The file's text streamed to a temporary file renamed once complete (no copy in memory: the
// rod's .bext with pillow_splits 3 is 64 MB).
void write_stream(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  core::write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw core::IoError(path + ": cannot open for writing");
    fill(out);
    out.close();
    if (!out) throw core::IoError(path + ": write failed (disk full?)");
  });
}

// Fixed-width fields as in LS-DYNA's own .bext files: integers 8 wide (10 a line), reals 24 wide
// with 17 significant digits (round trip), 5 a line for coefficient vectors.
void put_int(std::ostream& out, long v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%8ld", v);
  out << buf;
}
void put_real(std::ostream& out, double v) {
  if (std::abs(v) < 1e-99) v = 0.0;  // a 3-digit exponent would fill the field without a separating space
  char buf[40];
  std::snprintf(buf, sizeof buf, "%24.16e", v);
  out << buf;
}
template <class T, class Put>
void put_lines(std::ostream& out, const std::vector<T>& values, int per_line, Put put) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    put(out, values[i]);
    if ((i + 1) % per_line == 0 || i + 1 == values.size()) out << '\n';
  }
}

int degree_of(const std::vector<bezier::BezierHex>& hexes) {
  if (hexes.empty()) throw core::InvalidInputError("export: no Bézier elements");
  const int p = hexes[0].degree[0];
  for (const auto& h : hexes)
    if (h.degree[0] != p || h.degree[1] != p || h.degree[2] != p)
      throw core::InvalidInputError("export: elements of mixed or anisotropic degrees cannot be written");
  return p;
}

}  // namespace

void check_exports(const std::vector<std::string>& exports, int degree, const std::string& degree_key) {
  const auto& known = export_names();
  for (const auto& e : exports)
    if (std::find(known.begin(), known.end(), e) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw core::ConfigError("extract.exports: '" + e + "' is not one of: " + list);
    }
  if (std::find(exports.begin(), exports.end(), "msh") != exports.end() && (degree < 1 || degree > 3))
    throw core::ConfigError("extract.exports: msh is written for degrees 1 to 3 (Gmsh Lagrange hexahedra 5, 12, 92), the spline has degree " +
                            std::to_string(degree) + ": remove msh from extract.exports or set " + degree_key + " to 3 or less");
}

// ---------------------------------------------------------------------------------------------
// BEXT 2.0

void write_bext(const std::string& path, const Result& r) {
  const GlobalBasis& g = r.basis;
  if (g.elements.empty()) throw core::InvalidInputError(path + ": no elements to write");
  const int p = r.degree, nb = (p + 1) * (p + 1) * (p + 1);
  // Distinct coefficient vectors: extraction made equal 1-D rows bit-identical, so exact keys share.
  std::map<std::vector<double>, int> index;
  std::vector<const std::vector<double>*> vectors;
  std::vector<std::vector<int>> element_vectors(g.elements.size());
  for (std::size_t e = 0; e < g.elements.size(); ++e) {
    const auto& op = g.elements[e].op;
    for (int row = 0; row < op.outerSize(); ++row) {
      std::vector<double> v(nb, 0.0);
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(op, row); it; ++it) v[it.col()] = it.value();
      auto [it, added] = index.emplace(std::move(v), static_cast<int>(vectors.size()));
      if (added) vectors.push_back(&it->first);
      element_vectors[e].push_back(it->second);
    }
  }
  // Element blocks: one per function count (a single block unless an element repeats a function).
  std::map<std::size_t, std::vector<std::size_t>> blocks;
  for (std::size_t e = 0; e < g.elements.size(); ++e) blocks[g.elements[e].functions.size()].push_back(e);

  write_stream(path, [&](std::ostream& out) {
    out << "B E X T 2.0\n";
    out << "$# " << core::producer() << ": " << g.points.size() << " nodes (x y z w), " << g.elements.size()
        << " Bezier elements of degree " << p << ", " << vectors.size() << " coefficient vectors\n";
    put_int(out, 1), put_int(out, static_cast<long>(g.points.size())), put_int(out, static_cast<long>(g.elements.size()));
    put_int(out, static_cast<long>(vectors.size())), put_int(out, 1);  // patch 1, weights given
    out << '\n';
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      for (int d = 0; d < 3; ++d) put_real(out, g.points[i][d]);
      put_real(out, g.weights[i]);
      out << '\n';
    }
    put_int(out, static_cast<long>(blocks.size()));
    out << '\n';
    for (const auto& [count, elems] : blocks) {
      // Element type 1 (Bézier), elements, nodes and coefficient vectors per element, degrees.
      put_int(out, 1), put_int(out, static_cast<long>(elems.size())), put_int(out, static_cast<long>(count));
      put_int(out, static_cast<long>(count)), put_int(out, p), put_int(out, p), put_int(out, p);
      out << '\n';
    }
    for (const auto& [count, elems] : blocks)
      for (const std::size_t e : elems) {
        std::vector<long> nodes, cvs;
        for (const int f : g.elements[e].functions) nodes.push_back(f + 1);
        for (const int v : element_vectors[e]) cvs.push_back(v + 1);
        put_lines(out, nodes, 10, put_int);
        put_lines(out, cvs, 10, put_int);
      }
    put_int(out, 1), put_int(out, 0);  // one dense block, no sparse block
    out << '\n';
    put_int(out, static_cast<long>(vectors.size())), put_int(out, nb);
    out << '\n';
    for (const auto* v : vectors) put_lines(out, *v, 5, put_real);
  });
}

void write_lsdyna_deck(const std::string& path, const std::string& bext_name) {
  if (bext_name.empty() || bext_name.size() > 80 || bext_name.find('\n') != std::string::npos)
    throw core::InvalidInputError(path + ": the included file name must be 1 to 80 characters: '" + bext_name + "'");
  // Cards in LS-DYNA's fixed format: fields of 10 columns.
  std::ostringstream k;
  k << "*KEYWORD\n"
    << "$ " << core::producer() << ": the Bezier extraction file " << bext_name << " as an IGA solid part.\n"
    << "$ EDIT the *PART, *SECTION_SOLID and *MAT_ELASTIC lines below (placeholders, units mm-t-s-N-MPa),\n"
    << "$ then add loads, boundary conditions and *CONTROL cards.\n"
    << "*IGA_INCLUDE_BEZIER\n"
    << "$#                                                                      filename\n"
    << bext_name << "\n"
    << "$#    type       pid       dim\n"
    << "         1         1         3\n"
    << "$#  idpoff    fctlen    tranid\n"
    << "         0       1.0         0\n"
    << "*PART\n"
    << "$# title (EDIT)\n"
    << "volts spline\n"
    << "$#     pid     secid       mid\n"
    << "         1         1         1\n"
    << "*SECTION_SOLID\n"
    << "$#   secid    elform (201: isogeometric solid)\n"
    << "         1       201\n"
    << "*MAT_ELASTIC\n"
    << "$#     mid        ro         e        pr   (EDIT: steel placeholder)\n"
    << "         1   7.85e-9  210000.0       0.3\n"
    << "*END\n";
  core::write_text_atomically(path, k.str());
}

// ---------------------------------------------------------------------------------------------
// JSON

namespace {

// JSON numbers as nlohmann's compact dump writes them (shortest round trip, ".0" on integral
// values, null for non-finite ones), appended to a string: the file is written as it is built,
// without a tree of a million small JSON values (the torus's 56 MB took 1.2 s that way).
void put_json(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  const std::string_view t(buf, static_cast<std::size_t>(res.ptr - buf));
  out += t;
  if (t.find_first_of(".eE") == std::string_view::npos) out += ".0";
}
void put_json(std::string& out, long v) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, static_cast<std::size_t>(res.ptr - buf));
}

}  // namespace

bool kronecker_factors(const Eigen::SparseMatrix<double, Eigen::RowMajor>& op, int degree, std::array<Eigen::MatrixXd, 3>* factors,
                       std::vector<int>* order) {
  const int n = degree + 1, m = n * n * n;
  if (degree < 1 || op.rows() != m || op.cols() != m) return false;
  const Eigen::MatrixXd C(op);
  const double top = C.cwiseAbs().maxCoeff();
  if (!(top > 0)) return false;
  // Rows are the element's functions in global order. A function of a product is the product of
  // one function per direction, and its coefficients summed over the other two directions are
  // that function's 1-D row up to scale: rows with the same such marginal share that direction's
  // index. The distinct marginals, ordered by their centroid, number that direction's functions.
  std::array<int, 3> col_stride{1, n, n * n};
  std::vector<std::array<int, 3>> at(static_cast<std::size_t>(m));
  for (int d = 0; d < 3; ++d) {
    std::vector<Eigen::VectorXd> marginal(static_cast<std::size_t>(m), Eigen::VectorXd::Zero(n));
    for (int r = 0; r < m; ++r) {
      Eigen::VectorXd& v = marginal[static_cast<std::size_t>(r)];
      for (int c = 0; c < m; ++c) v[c / col_stride[static_cast<std::size_t>(d)] % n] += C(r, c);
      const double sum = v.sum();
      if (!(std::abs(sum) > 1e-300)) return false;
      v /= sum;
    }
    std::vector<Eigen::VectorXd> distinct;
    for (int r = 0; r < m; ++r) {
      std::size_t k = 0;
      while (k < distinct.size() && (distinct[k] - marginal[static_cast<std::size_t>(r)]).cwiseAbs().maxCoeff() > 1e-12) ++k;
      if (k == distinct.size()) {
        if (static_cast<int>(distinct.size()) == n) return false;
        distinct.push_back(marginal[static_cast<std::size_t>(r)]);
      }
      at[static_cast<std::size_t>(r)][static_cast<std::size_t>(d)] = static_cast<int>(k);
    }
    if (static_cast<int>(distinct.size()) != n) return false;
    std::vector<int> rank(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) rank[static_cast<std::size_t>(k)] = k;
    const Eigen::VectorXd position = Eigen::VectorXd::LinSpaced(n, 0, n - 1);
    std::stable_sort(rank.begin(), rank.end(), [&](int a, int b) { return distinct[static_cast<std::size_t>(a)].dot(position) < distinct[static_cast<std::size_t>(b)].dot(position); });
    std::vector<int> index_of(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) index_of[static_cast<std::size_t>(rank[static_cast<std::size_t>(k)])] = k;
    for (auto& a : at) a[static_cast<std::size_t>(d)] = index_of[static_cast<std::size_t>(a[static_cast<std::size_t>(d)])];
  }
  std::vector<int> row_of(static_cast<std::size_t>(m), -1);
  for (int r = 0; r < m; ++r) {
    const auto& a = at[static_cast<std::size_t>(r)];
    int& slot = row_of[static_cast<std::size_t>(a[0] + n * (a[1] + n * a[2]))];
    if (slot >= 0) return false;
    slot = r;
  }
  // The factors through the largest entry (i0 j0 k0, a0 b0 c0): the slices along each direction,
  // each scaled to columns summing to one (the 1-D extraction operators).
  Eigen::MatrixXd P(m, m);
  for (int t = 0; t < m; ++t) P.row(t) = C.row(row_of[static_cast<std::size_t>(t)]);
  Eigen::Index r0 = 0, c0 = 0;
  P.cwiseAbs().maxCoeff(&r0, &c0);
  const std::array<int, 3> ri{static_cast<int>(r0) % n, static_cast<int>(r0) / n % n, static_cast<int>(r0) / (n * n)};
  const std::array<int, 3> ci{static_cast<int>(c0) % n, static_cast<int>(c0) / n % n, static_cast<int>(c0) / (n * n)};
  for (int d = 0; d < 3; ++d) {
    Eigen::MatrixXd& f = (*factors)[static_cast<std::size_t>(d)];
    f.resize(n, n);
    for (int i = 0; i < n; ++i)
      for (int a = 0; a < n; ++a) {
        int row = 0, col = 0;
        for (int e = 0; e < 3; ++e) {
          row += (e == d ? i : ri[static_cast<std::size_t>(e)]) * col_stride[static_cast<std::size_t>(e)];
          col += (e == d ? a : ci[static_cast<std::size_t>(e)]) * col_stride[static_cast<std::size_t>(e)];
        }
        f(i, a) = P(row, col);
      }
    for (int a = 0; a < n; ++a) {
      const double sum = f.col(a).sum();
      if (!(std::abs(sum) > 1e-300)) return false;
      f.col(a) /= sum;
    }
  }
  const Eigen::MatrixXd& k0 = (*factors)[0];
  const Eigen::MatrixXd& k1 = (*factors)[1];
  const Eigen::MatrixXd& k2 = (*factors)[2];
  for (int t = 0; t < m; ++t)
    for (int col = 0; col < m; ++col) {
      const double v = k0(t % n, col % n) * k1(t / n % n, col / n % n) * k2(t / (n * n), col / (n * n));
      if (!(std::abs(v - P(t, col)) <= 1e-14 * top)) return false;
    }
  if (order) *order = std::move(row_of);
  return true;
}

namespace {

void write_bezier_json_to(std::ostream& file, const Result& r, JsonOperators operators) {
  const GlobalBasis& g = r.basis;
  const bool kronecker = operators == JsonOperators::kronecker;
  // Keys in nlohmann's order (sorted), as core::write_stage_file writes them. The text goes to the
  // file in pieces of a few MB (the rod with pillow_splits 3: 892 MB in one string before).
  constexpr std::size_t kPiece = std::size_t{8} << 20;
  std::string out;
  out.reserve(kPiece + (std::size_t{1} << 20));
  const auto flush = [&](bool always) {
    if (!always && out.size() < kPiece) return;
    file.write(out.data(), static_cast<std::streamsize>(out.size()));
    out.clear();
  };
  out += "{\"bernstein_order\":\"i + (p+1)*(j + (p+1)*k), as BezierHex and the .bext\",\"elements\":[";
  for (std::size_t e = 0; e < g.elements.size(); ++e) {
    const auto& el = g.elements[e];
    if (e) out += ',';
    out += "{\"degree\":[";
    for (int d = 0; d < 3; ++d) put_json(out, static_cast<long>(r.degree)), out += d < 2 ? "," : "]";
    // Version 2: a product's functions in the order of its factors' rows (i + n(j + n k)).
    std::array<Eigen::MatrixXd, 3> k;
    std::vector<int> order;
    const bool product = kronecker && kronecker_factors(el.op, r.degree, &k, &order);
    out += ",\"functions\":[";
    for (std::size_t i = 0; i < el.functions.size(); ++i) {
      if (i) out += ',';
      put_json(out, static_cast<long>(el.functions[product ? static_cast<std::size_t>(order[i]) : i]));
    }
    out += ']';
    if (e < r.min_scaled_jacobian.size()) out += ",\"min_scaled_jacobian\":", put_json(out, r.min_scaled_jacobian[e]);
    out += ",\"operator\":{\"columns\":";
    put_json(out, static_cast<long>(el.op.cols()));
    if (product) {
      out += ",\"kronecker\":[";
      for (int d = 0; d < 3; ++d) {
        out += d ? ",[" : "[";
        for (Eigen::Index i = 0; i < k[static_cast<std::size_t>(d)].rows(); ++i)
          for (Eigen::Index a = 0; a < k[static_cast<std::size_t>(d)].cols(); ++a) {
            if (i || a) out += ',';
            put_json(out, k[static_cast<std::size_t>(d)](i, a));
          }
        out += ']';
      }
      out += "],\"rows\":";
      put_json(out, static_cast<long>(el.op.rows()));
      out += '}';
    } else {
      out += ",\"rows\":";
      put_json(out, static_cast<long>(el.op.rows()));
      out += ",\"triplets\":[";
      bool first = true;
      for (int row = 0; row < el.op.outerSize(); ++row)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(el.op, row); it; ++it) {
          out += first ? "[" : ",[";
          first = false;
          put_json(out, static_cast<long>(row)), out += ',';
          put_json(out, static_cast<long>(it.col())), out += ',';
          put_json(out, it.value()), out += ']';
        }
      out += "]}";
    }
    if (e < r.status.size()) out += ",\"status\":", put_json(out, static_cast<long>(r.status[e]));
    out += '}';
    flush(false);
  }
  out += "],\"format\":\"volts-bezier\",\"global_functions\":{\"count\":";
  put_json(out, static_cast<long>(g.points.size()));
  out += ",\"points\":[";
  for (std::size_t i = 0; i < g.points.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      if (i || d) out += ',';
      put_json(out, g.points[i][d]);
      flush(false);
    }
  out += "],\"weights\":[";
  for (std::size_t i = 0; i < g.weights.size(); ++i) {
    if (i) out += ',';
    put_json(out, g.weights[i]);
  }
  out += "]},\"producer\":" + core::Json(core::producer()).dump() + ",\"version\":" + (kronecker ? "2" : "1") + "}\n";
  flush(true);
}

}  // namespace

void write_bezier_json(const std::string& path, const Result& r, JsonOperators operators) {
  write_stream(path, [&](std::ostream& file) { write_bezier_json_to(file, r, operators); });
}

// ---------------------------------------------------------------------------------------------
// Gmsh

std::vector<std::array<int, 3>> gmsh_hex_nodes(int order) {
  // Read off gmsh 4.8.4: a unit cube extruded with Layers{1}, meshed with -order N, the nodes of
  // its one hexahedron in the element's own corner frame (see docs/formats.md).
  switch (order) {
    case 1:
      return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    case 2:
      return {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}, {1, 0, 0},
              {0, 1, 0}, {0, 0, 1}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {2, 2, 1}, {0, 2, 1}, {1, 0, 2}, {0, 1, 2},
              {2, 1, 2}, {1, 2, 2}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}, {1, 1, 1}};
    case 3:
      return {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {0, 3, 0}, {0, 0, 3}, {3, 0, 3}, {3, 3, 3}, {0, 3, 3},  // corners
              {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 0, 1}, {0, 0, 2}, {3, 1, 0}, {3, 2, 0},  // edges
              {3, 0, 1}, {3, 0, 2}, {2, 3, 0}, {1, 3, 0}, {3, 3, 1}, {3, 3, 2}, {0, 3, 1}, {0, 3, 2},
              {1, 0, 3}, {2, 0, 3}, {0, 1, 3}, {0, 2, 3}, {3, 1, 3}, {3, 2, 3}, {2, 3, 3}, {1, 3, 3},
              {1, 1, 0}, {1, 2, 0}, {2, 2, 0}, {2, 1, 0}, {1, 0, 1}, {2, 0, 1}, {2, 0, 2}, {1, 0, 2},  // faces
              {0, 1, 1}, {0, 1, 2}, {0, 2, 2}, {0, 2, 1}, {3, 1, 1}, {3, 2, 1}, {3, 2, 2}, {3, 1, 2},
              {2, 3, 1}, {1, 3, 1}, {1, 3, 2}, {2, 3, 2}, {1, 1, 3}, {2, 1, 3}, {2, 2, 3}, {1, 2, 3},
              {1, 1, 1}, {2, 1, 1}, {2, 2, 1}, {1, 2, 1}, {1, 1, 2}, {2, 1, 2}, {2, 2, 2}, {1, 2, 2}};  // interior
    default:
      throw core::InvalidInputError("gmsh: no Lagrange hexahedron of order " + std::to_string(order) + " here (1 to 3)");
  }
}

int gmsh_hex_type(int order) {
  switch (order) {
    case 1: return 5;
    case 2: return 12;
    case 3: return 92;
    default: throw core::InvalidInputError("gmsh: no Lagrange hexahedron of order " + std::to_string(order) + " here (1 to 3)");
  }
}

std::size_t write_gmsh(const std::string& path, const std::vector<bezier::BezierHex>& hexes) {
  const int p = degree_of(hexes);
  const int type = gmsh_hex_type(p);
  const auto lattice = gmsh_hex_nodes(p);
  for (const auto& h : hexes)
    for (const double w : h.weights)
      if (w != 1.0) throw core::InvalidInputError(path + ": rational elements cannot be written as Gmsh Lagrange hexahedra");
  Eigen::AlignedBox3d box;
  for (const auto& h : hexes)
    for (const auto& x : h.points) box.extend(x);
  // Nodes closer than the tolerance are one: neighbouring elements share theirs.
  PointIndex index(box, std::max(point_tolerance(box, 1e-12), std::numeric_limits<double>::min()));
  std::vector<std::vector<int>> connectivity(hexes.size());
  // Bernstein values at the lattice's abscissae i / p, tabulated once (polynomial elements: the
  // weights are all 1, checked above).
  const int n1 = p + 1;
  std::vector<Eigen::VectorXd> B(static_cast<std::size_t>(n1));
  for (int i = 0; i <= p; ++i) B[static_cast<std::size_t>(i)] = bezier::bernstein_basis(p, static_cast<double>(i) / p);
  for (std::size_t e = 0; e < hexes.size(); ++e)
    for (const auto& ijk : lattice) {
      const Eigen::VectorXd &bu = B[static_cast<std::size_t>(ijk[0])], &bv = B[static_cast<std::size_t>(ijk[1])], &bw = B[static_cast<std::size_t>(ijk[2])];
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int c = 0; c < n1; ++c)
        for (int b = 0; b < n1; ++b) {
          const double vw = bv[b] * bw[c];
          if (vw == 0) continue;
          for (int a = 0; a < n1; ++a) x += (bu[a] * vw) * hexes[e].points[static_cast<std::size_t>(a + n1 * (b + n1 * c))];
        }
      connectivity[e].push_back(index.find_or_add(x) + 1);  // Gmsh tags are 1-based
    }
  const std::vector<Eigen::Vector3d>& nodes = index.points();
  write_stream(path, [&](std::ostream& out) {
    char buf[256];  // six %.17g fields: up to 6 * 25 characters
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    out << "$PhysicalNames\n1\n3 1 \"volts\"\n$EndPhysicalNames\n";
    out << "$Entities\n0 0 0 1\n";
    std::snprintf(buf, sizeof buf, "1 %.17g %.17g %.17g %.17g %.17g %.17g", box.min()[0], box.min()[1], box.min()[2], box.max()[0],
                  box.max()[1], box.max()[2]);
    out << buf << " 1 1 0\n$EndEntities\n";
    out << "$Nodes\n1 " << nodes.size() << " 1 " << nodes.size() << "\n3 1 0 " << nodes.size() << "\n";
    for (std::size_t n = 0; n < nodes.size(); ++n) out << n + 1 << "\n";
    for (const auto& x : nodes) {
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", x[0], x[1], x[2]);
      out << buf;
    }
    out << "$EndNodes\n";
    out << "$Elements\n1 " << hexes.size() << " 1 " << hexes.size() << "\n3 1 " << type << " " << hexes.size() << "\n";
    for (std::size_t e = 0; e < hexes.size(); ++e) {
      out << e + 1;
      for (const int n : connectivity[e]) out << ' ' << n;
      out << '\n';
    }
    out << "$EndElements\n";
  });
  return nodes.size();
}

// ---------------------------------------------------------------------------------------------
// Histogram

void write_histogram_png(const std::string& path, const std::vector<double>& values, const HistogramParams& params) {
  if (params.bins < 1 || params.bins > 200) throw core::InvalidInputError("histogram: bins must be in [1, 200]");
  if (params.width < 64 || params.width > 4096 || params.height < 64 || params.height > 4096)
    throw core::InvalidInputError("histogram: width and height must be in [64, 4096] pixels");
  if (!(params.lo < params.hi)) throw core::InvalidInputError("histogram: lo must be less than hi");
  std::vector<int> count(params.bins, 0);
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    const int b = static_cast<int>(std::floor((v - params.lo) / (params.hi - params.lo) * params.bins));
    ++count[std::clamp(b, 0, params.bins - 1)];
  }
  const int fullest = std::max(1, *std::max_element(count.begin(), count.end()));
  const int W = params.width, H = params.height, margin = 20;
  const int x0 = margin, x1 = W - margin, y0 = margin, y1 = H - margin;  // plot area; y up from y0
  vtkNew<vtkImageData> image;
  image->SetDimensions(W, H, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* px = static_cast<unsigned char*>(image->GetScalarPointer());
  // vtkImageData row 0 is the bottom row of the PNG, so y counts upwards.
  const auto set = [&](int x, int y, unsigned char r, unsigned char g, unsigned char b) {
    if (x < 0 || x >= W || y < 0 || y >= H) return;
    unsigned char* c = px + 3 * (static_cast<std::size_t>(y) * W + x);
    c[0] = r, c[1] = g, c[2] = b;
  };
  std::fill(px, px + 3 * static_cast<std::size_t>(W) * H, static_cast<unsigned char>(255));
  const auto xof = [&](double v) { return x0 + static_cast<int>(std::lround((v - params.lo) / (params.hi - params.lo) * (x1 - x0))); };
  for (int b = 0; b < params.bins; ++b) {
    const int left = x0 + (x1 - x0) * b / params.bins + 1, right = x0 + (x1 - x0) * (b + 1) / params.bins - 1;
    const int top = y0 + static_cast<int>(std::lround(static_cast<double>(count[b]) / fullest * (y1 - y0)));
    for (int x = left; x <= right; ++x)
      for (int y = y0; y < top; ++y) set(x, y, 40, 90, 200);
  }
  for (int x = x0; x <= x1; ++x) set(x, y0 - 1, 0, 0, 0);  // axis
  for (const double t : {params.lo, 0.5 * (params.lo + params.hi), params.hi})
    for (int y = y0 - 6; y < y0 - 1; ++y) set(xof(t), y, 0, 0, 0);
  if (params.lo < 0.5 && 0.5 < params.hi)
    for (int y = y0; y <= y1; y += 2) set(xof(0.5), y, 220, 30, 30);  // the 0.5 quality threshold
  core::write_atomically(path, [&](const std::string& tmp) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(image);
    writer->Write();
    if (writer->GetErrorCode() != 0) throw core::IoError(path + ": cannot write the PNG");
  });
}

}  // namespace volts::extract
