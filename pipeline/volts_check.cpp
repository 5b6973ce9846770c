// volts-check — certified Jacobian validity of every element of a .vtu (Bézier/Lagrange hexahedra
// and tetrahedra), Randrianarivony 2008 §4 via bezier::certify.
//
//   volts-check FILE.vtu [-o OUT.vtu] [--max-depth N] [--no-output] [--list N]
//
// Exit codes: 0 every element certified valid, 8 (core::ExitCode::not_certified) some element
// invalid or undecided, otherwise the error codes of docs/errors.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>

#include "bezier/certify.h"
#include "bezier/vtk_bezier.h"
#include "core/errors.h"

namespace {

using namespace volts;
using core::UsageError;

const char* const kTool = "volts-check";

void print_help(std::ostream& out) {
  const bezier::CertifyParams d;
  out << "usage: " << kTool << " FILE.vtu [-o OUT.vtu] [--max-depth N] [--no-output] [--list N]\n\n"
      << "Certifies the sign of the Jacobian determinant of every element (Bernstein coefficients of det J,\n"
      << "adaptive subdivision; Randrianarivony 2008 §4). Reads VTK Bézier hexahedra (79) and tetrahedra (78)\n"
      << "with RationalWeights/HigherOrderDegrees, Lagrange hexahedra/tetrahedra (72/71) and linear ones\n"
      << "(12/10). Prints a summary and writes OUT.vtu (default FILE.check.vtu) with the cell arrays\n"
      << "status (1 valid, -1 invalid, 0 undecided), certified_min_detj (lower bound of min det J),\n"
      << "certified_min_detj_rel (that bound over the element's mean det J) and min_scaled_jacobian (sampled).\n\n"
      << "options:\n"
      << "  -o, --output OUT.vtu  where to write the annotated copy\n"
      << "  --no-output           write nothing\n"
      << "  --max-depth N         subdivision levels before 'undecided', 0..20 (default " << d.max_depth << ")\n"
      << "  --list N              name at most N invalid/undecided elements (default 20)\n\n"
      << "exit code: 0 if every element is certified valid, 8 if some element is invalid or undecided,\n"
      << "2 usage, 4 unreadable/malformed file or unsupported cell, 6 output not written (docs/errors.md).\n";
}

template <typename T>
T parse_number(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  T value{};
  if (!(in >> value) || !(in >> std::ws).eof()) throw UsageError(option + " expects a number, got '" + text + "'");
  return value;
}

std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

// Scaled Jacobian of a tet sampled at the corners and the degree-(n+1) lattice's interior points.
double min_scaled_tet(const bezier::BezierTet& t) {
  const int m = t.degree + 1;
  double s = 1.0;
  for (const auto& a : bezier::simplex_multi_indices(3, m)) {
    Eigen::Matrix3d J;
    bezier::evaluate(t, Eigen::Vector3d(a[1], a[2], a[3]) / m, &J);
    s = std::min(s, bezier::scaled_jacobian(J));
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string input, output;
    bool write = true;
    int list = 20;
    bezier::CertifyParams params;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      const auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw UsageError(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--help" || arg == "-h") {
        print_help(std::cout);
        return 0;
      } else if (arg == "-o" || arg == "--output") {
        output = value();
      } else if (arg == "--no-output") {
        write = false;
      } else if (arg == "--max-depth") {
        params.max_depth = parse_number<int>(arg, value());
        if (params.max_depth < 0 || params.max_depth > 20) throw UsageError("--max-depth must be in [0, 20]");
      } else if (arg == "--list") {
        list = parse_number<int>(arg, value());
      } else if (arg.size() > 1 && arg[0] == '-') {
        throw UsageError("unknown option '" + arg + "' (see --help)");
      } else if (!input.empty()) {
        throw UsageError("more than one input file: '" + input + "' and '" + arg + "'");
      } else {
        input = arg;
      }
    }
    if (input.empty()) throw UsageError("no input file given (see --help)");
    if (output.empty()) {
      const auto dot = input.rfind(".vtu");
      output = (dot != std::string::npos && dot + 4 == input.size() ? input.substr(0, dot) : input) + ".check.vtu";
    }

    const bezier::VtuElements el = bezier::read_bezier_vtu(input);
    const int nc = static_cast<int>(el.vtk_type.size());
    std::vector<double> status(nc), lower(nc), rel(nc), scaled(nc);
    int valid = 0, invalid = 0, undecided = 0, worst_rel_cell = -1, worst_sj_cell = -1, listed = 0;
    double worst_rel = std::numeric_limits<double>::infinity(), worst_sj = worst_rel;
    std::ostringstream problems;
    for (int c = 0; c < nc; ++c) {
      const bool tet = el.is_tet(c);
      const bezier::CertifyResult r =
          tet ? bezier::certify(el.tets[el.element[c]], params) : bezier::certify(el.hexes[el.element[c]], params);
      if (tet) {
        scaled[c] = min_scaled_tet(el.tets[el.element[c]]);
      } else {
        const auto& h = el.hexes[el.element[c]];
        scaled[c] = bezier::sample_jacobian(h, std::max({h.degree[0], h.degree[1], h.degree[2]}) + 1).min_scaled;
      }
      status[c] = static_cast<int>(r.status);
      lower[c] = r.min_detj_lower;
      // Relative to the element's size; a non-positive mean (inverted element) gives -1 per unit.
      rel[c] = r.min_detj_lower / std::abs(r.mean_detj > 0 || r.mean_detj < 0 ? r.mean_detj : 1.0);
      valid += r.status == bezier::Validity::valid;
      invalid += r.status == bezier::Validity::invalid;
      undecided += r.status == bezier::Validity::undecided;
      if (rel[c] < worst_rel) worst_rel = rel[c], worst_rel_cell = c;
      if (scaled[c] < worst_sj) worst_sj = scaled[c], worst_sj_cell = c;
      if (r.status != bezier::Validity::valid && listed++ < list) {
        const Eigen::Vector3d& w = r.witness;
        problems << "  cell " << c << " (" << (tet ? "tet" : "hex") << "): " << bezier::to_string(r.status);
        if (r.status == bezier::Validity::invalid)
          problems << ", det J = " << fmt(r.min_detj_upper) << " at (u,v,w) = (" << fmt(w[0]) << ", " << fmt(w[1]) << ", "
                   << fmt(w[2]) << ")\n";
        else
          problems << ", min det J in [" << fmt(r.min_detj_lower) << ", " << fmt(r.min_detj_upper) << "] after "
                   << params.max_depth << " subdivision levels\n";
      }
    }
    const int hexes = static_cast<int>(el.hexes.size()), tets = static_cast<int>(el.tets.size());
    std::cout << kTool << ": " << input << ": " << nc << " elements (" << hexes << " hexahedra, " << tets
              << " tetrahedra): " << valid << " certified valid, " << invalid << " invalid, " << undecided << " undecided\n";
    if (nc > 0) {
      std::cout << "  certified min det J / element mean det J: " << fmt(worst_rel) << " (cell " << worst_rel_cell << ")\n"
                << "  min sampled scaled Jacobian: " << fmt(worst_sj) << " (cell " << worst_sj_cell << ")\n";
    }
    std::cout << problems.str();
    if (listed > list) std::cout << "  ... and " << listed - list << " more\n";
    if (write) {
      std::vector<bezier::CellArray> arrays = {{"status", 1, status},
                                               {"certified_min_detj", 1, lower},
                                               {"certified_min_detj_rel", 1, rel},
                                               {"min_scaled_jacobian", 1, scaled}};
      bezier::write_vtu_with_cell_arrays(input, output, arrays);
      std::cout << "  wrote " << output << " (cell arrays status, certified_min_detj, certified_min_detj_rel, "
                << "min_scaled_jacobian)\n";
    }
    if (valid == nc) return 0;
    std::cerr << kTool << ": " << input << ": " << nc - valid << " of " << nc << " elements not certified valid\n";
    return static_cast<int>(core::ExitCode::not_certified);
  } catch (const core::Error& e) {
    std::cerr << kTool << ": error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << kTool << ": error: internal error (please report): " << e.what() << "\n";
    return static_cast<int>(core::ExitCode::internal);
  }
}
