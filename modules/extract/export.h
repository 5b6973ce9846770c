// volts::extract — solver exports of the extracted spline (issue 8): the LS-DYNA Bézier extraction
// file (BEXT 2.0, read with *IGA_INCLUDE_BEZIER) and a keyword deck including it, a JSON file of
// the global basis and the extraction operators, a Gmsh MSH 4.1 mesh of conforming Lagrange
// hexahedra, and a PNG histogram of the per-element min scaled Jacobian. Formats: docs/formats.md.
//
// Every file is written atomically (core::write_atomically); core::IoError if it cannot be.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "extract/extract.h"

namespace volts::extract {

/// Throws core::ConfigError naming extract.exports for an unknown name, or for msh with a degree
/// Gmsh has no table here for (1..3 are written; the message names `degree_key`, the config key
/// that set the degree). Call before writing anything.
void check_exports(const std::vector<std::string>& exports, int degree, const std::string& degree_key = "tmesh.degree");

/// bezier.bext: BEXT 2.0 (as libMesh's DynaIO reads it): one patch, the global functions as
/// nodes x y z w, the elements in blocks of equal function count, each with its ascending 1-based
/// node ids and one coefficient vector id per node; coefficient vectors (rows of C, Bernstein
/// functions u fastest) stored once per distinct vector, dense, full precision.
void write_bext(const std::string& path, const Result& r);

/// The LS-DYNA keyword deck next to the .bext: *KEYWORD, *IGA_INCLUDE_BEZIER of `bext_name` (a
/// file name relative to the deck, at most 80 characters; else core::InvalidInputError), a
/// placeholder *PART, *SECTION_SOLID (ELFORM 201) and *MAT_ELASTIC the user edits, *END.
void write_lsdyna_deck(const std::string& path, const std::string& bext_name);

/// How write_bezier_json stores each element's extraction operator (Params::json_operators).
enum class JsonOperators { triplets, kronecker };

/// bezier.json ("volts-bezier"): global functions (points, weights), per element its degrees,
/// global function ids, extraction operator, status and min scaled Jacobian. Version 1 (triplets):
/// the functions ascending, the operator's nonzeros as [row, column, value]. Version 2
/// (kronecker): where the operator is a Kronecker product (kronecker_factors()) its three factors
/// instead, as "kronecker": [K0, K1, K2], each (p+1)x(p+1) row-major, with the functions in the
/// factors' order: C(i + n(j + n k), a + n(b + n c)) = K0(i,a) K1(j,b) K2(k,c), n = p + 1 —
/// about 50 times smaller for cubics; elsewhere as version 1 (docs/formats.md).
void write_bezier_json(const std::string& path, const Result& r, JsonOperators operators = JsonOperators::triplets);

/// The three 1-D factors of an element's extraction operator `op` (rows: its functions in any
/// order; columns: Bernstein functions, a + n(b + n c), n = degree + 1) if it is a Kronecker
/// product: each factor with columns summing to one (the 1-D extraction operators), and in
/// `order` (optional) the row of `op` of each tensor index i + n(j + n k). False unless the
/// product reproduces every entry to 1e-14 of the largest (an element with a T-junction or
/// smooth row among its functions is no product).
bool kronecker_factors(const Eigen::SparseMatrix<double, Eigen::RowMajor>& op, int degree, std::array<Eigen::MatrixXd, 3>* factors,
                       std::vector<int>* order = nullptr);

/// Gmsh's node order of its Lagrange hexahedron of `order` 1..3 (element types 5, 12, 92), as
/// lattice indices (i, j, k) in 0..order: node n sits at (i, j, k)/order of the [0,1]^3
/// element (Gmsh's reference [-1,1]^3 mapped affinely). Taken from gmsh 4.8 itself (one
/// extruded cube meshed at -order 1..3). Throws core::InvalidInputError for other orders.
std::vector<std::array<int, 3>> gmsh_hex_nodes(int order);

/// Gmsh element type of the Lagrange hexahedron of `order` 1..3 (5, 12, 92).
int gmsh_hex_type(int order);

/// bezier.msh: MSH 4.1 ASCII, one volume entity (physical group 1 "volts"), Lagrange hexahedra of
/// the hexes' degree whose nodes are the Bézier elements evaluated at Gmsh's nodes (exact for
/// polynomial elements). Nodes closer than point_tolerance(bbox, 1e-12) are merged, so
/// neighbouring elements share their nodes. Throws core::InvalidInputError for rational
/// elements (weights cannot be stored), mixed or anisotropic degrees, or a degree outside 1..3.
/// Returns the number of nodes written.
std::size_t write_gmsh(const std::string& path, const std::vector<bezier::BezierHex>& hexes);

/// Parameters of write_histogram_png().
struct HistogramParams {
  int bins = 20;                     ///< bars over [lo, hi] [1, 200]
  double lo = -1.0, hi = 1.0;        ///< value range; values outside go to the end bars
  int width = 420, height = 260;     ///< image size in pixels [64, 4096]
};

/// A histogram of `values` as an RGB PNG (vtkImageData, vtkPNGWriter): blue bars, heights relative
/// to the fullest bin, black axis, ticks at lo, the middle and hi, a red mark at 0.5. Throws
/// core::InvalidInputError for parameters out of range.
void write_histogram_png(const std::string& path, const std::vector<double>& values, const HistogramParams& params = {});

}  // namespace volts::extract
