#include "bezier/vtk_bezier.h"

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkHigherOrderTetra.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkSmartPointer.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <new>
#include <stdexcept>

#include "bezier/bernstein.h"

#include "core/atomic_file.h"
#include "core/errors.h"

namespace volts::bezier {

int vtk_hex_point_index(int i, int j, int k, const std::array<int, 3>& degree) {
  const int p = degree[0], q = degree[1], r = degree[2];
  if (p < 1 || q < 1 || r < 1)
    throw core::InvalidInputError("vtk_hex_point_index: degrees must be >= 1");
  if (i < 0 || i > p || j < 0 || j > q || k < 0 || k > r)
    throw core::InvalidInputError("vtk_hex_point_index: (" + std::to_string(i) + "," + std::to_string(j) + "," +
                                  std::to_string(k) + ") outside the control grid");
  const bool ib = i == 0 || i == p, jb = j == 0 || j == q, kb = k == 0 || k == r;
  const int on = int(ib) + int(jb) + int(kb);
  // Corners counter-clockwise in the bottom face (k = 0), then the top face.
  const int corner_in_face = i ? (j ? 2 : 1) : (j ? 3 : 0);
  if (on == 3) return corner_in_face + (k ? 4 : 0);
  int offset = 8;
  if (on == 2) {
    // Bottom edges: (j=0), (i=p), (j=q), (i=0), all running in increasing i or j; top edges the
    // same; then the vertical edges at corners 0..3, increasing k.
    const int ring = 2 * (p - 1) + 2 * (q - 1);
    if (!ib) return offset + (k ? ring : 0) + (j ? (p - 1) + (q - 1) : 0) + (i - 1);
    if (!jb) return offset + (k ? ring : 0) + (i ? (p - 1) : 2 * (p - 1) + (q - 1)) + (j - 1);
    return offset + 2 * ring + corner_in_face * (r - 1) + (k - 1);
  }
  offset += 4 * ((p - 1) + (q - 1) + (r - 1));
  if (on == 1) {
    // Faces i=0, i=p (j fastest), j=0, j=q (i fastest), k=0, k=r (i fastest).
    if (ib) return offset + (i ? (q - 1) * (r - 1) : 0) + (j - 1) + (q - 1) * (k - 1);
    offset += 2 * (q - 1) * (r - 1);
    if (jb) return offset + (j ? (p - 1) * (r - 1) : 0) + (i - 1) + (p - 1) * (k - 1);
    offset += 2 * (p - 1) * (r - 1);
    return offset + (k ? (p - 1) * (q - 1) : 0) + (i - 1) + (p - 1) * (j - 1);
  }
  offset += 2 * ((q - 1) * (r - 1) + (p - 1) * (r - 1) + (p - 1) * (q - 1));
  return offset + (i - 1) + (p - 1) * ((j - 1) + (q - 1) * (k - 1));
}

namespace {

// vtkErrorCode::GetStringFromErrorCode lives in VTK::CommonMisc; the few codes a writer sets are
// named here instead of linking one more VTK library.
std::string describe(unsigned long code) {
  switch (code) {
    case vtkErrorCode::CannotOpenFileError: return "cannot open file";
    case vtkErrorCode::OutOfDiskSpaceError: return "out of disk space";
    case vtkErrorCode::NoFileNameError: return "no file name";
    default: return "vtkErrorCode " + std::to_string(code);
  }
}

// Collects VTK error messages of a reader (VTK would otherwise print them and carry on).
struct ErrorCatcher {
  std::string message;
  vtkNew<vtkCallbackCommand> callback;
  ErrorCatcher() {
    callback->SetClientData(this);
    callback->SetCallback([](vtkObject*, unsigned long, void* self, void* data) {
      auto* me = static_cast<ErrorCatcher*>(self);
      if (me->message.empty() && data) me->message = static_cast<const char*>(data);
    });
  }
};

vtkSmartPointer<vtkUnstructuredGrid> read_grid(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw core::InvalidInputError(path + ": no such file");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  if (!reader->CanReadFile(path.c_str()))
    throw core::InvalidInputError(path + ": not a VTK XML unstructured grid (.vtu) file");
  ErrorCatcher errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors.callback);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors.callback);
  reader->SetReaderErrorObserver(errors.callback);
  reader->SetParserErrorObserver(errors.callback);
  reader->SetFileName(path.c_str());
  // The XML parser reports through its own objects: silence VTK's console output, the error is ours to raise.
  const int display = vtkObject::GetGlobalWarningDisplay();
  vtkObject::GlobalWarningDisplayOff();
  int ok = 0;
  try {
    ok = reader->GetExecutive()->Update();
  } catch (const std::bad_alloc&) {  // VTK sizes arrays and compressed blocks from the file (found by fuzz_vtu)
    vtkObject::SetGlobalWarningDisplay(display);
    throw core::InvalidInputError(path + ": malformed .vtu file: implausible sizes (out of memory while reading)");
  } catch (const std::length_error&) {
    vtkObject::SetGlobalWarningDisplay(display);
    throw core::InvalidInputError(path + ": malformed .vtu file: implausible sizes");
  }
  vtkObject::SetGlobalWarningDisplay(display);
  if (!ok || !errors.message.empty() || reader->GetErrorCode() != vtkErrorCode::NoError || !reader->GetOutput()) {
    std::string m = errors.message;
    while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
    throw core::InvalidInputError(path + ": malformed .vtu file" + (m.empty() ? std::string() : ": " + m.substr(m.rfind('\n') + 1)));
  }
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  // A truncated appended section can read "successfully" with short or garbage arrays (VTK fills
  // what it has): check the cell structure before anything walks it (VTK's own writer crashed on
  // a cut bezier.vtu).
  vtkCellArray* cells = grid->GetCells();
  const vtkIdType nc = grid->GetNumberOfCells(), np = grid->GetNumberOfPoints();
  if (nc != reader->GetNumberOfCells() || np != reader->GetNumberOfPoints() || (nc > 0 && !grid->GetPoints()))
    throw core::InvalidInputError(path + ": malformed .vtu file: it declares " + std::to_string(reader->GetNumberOfCells()) + " cells and " +
                                  std::to_string(reader->GetNumberOfPoints()) + " points but holds " + std::to_string(nc) + " and " +
                                  std::to_string(np) + " (truncated file?)");
  if (nc == 0 || !cells) throw core::InvalidInputError(path + ": malformed .vtu file: no cells");
  {
    vtkDataArray* offsets = cells ? cells->GetOffsetsArray() : nullptr;
    vtkDataArray* conn = cells ? cells->GetConnectivityArray() : nullptr;
    vtkUnsignedCharArray* types = grid->GetCellTypesArray();
    if (!offsets || !conn || !types || offsets->GetNumberOfTuples() != nc + 1 || types->GetNumberOfTuples() < nc)
      throw core::InvalidInputError(path + ": malformed .vtu file: the cell arrays are incomplete (truncated file?)");
    vtkIdType prev = 0;
    for (vtkIdType c = 0; c <= nc; ++c) {
      const auto o = static_cast<vtkIdType>(offsets->GetComponent(c, 0));
      if (o < prev || o > conn->GetNumberOfTuples())
        throw core::InvalidInputError(path + ": malformed .vtu file: cell offsets out of order or past the connectivity (truncated file?)");
      prev = o;
    }
    for (vtkIdType i = 0; i < conn->GetNumberOfTuples(); ++i) {
      const double id = conn->GetComponent(i, 0);
      if (!(id >= 0 && id < static_cast<double>(np)))
        throw core::InvalidInputError(path + ": malformed .vtu file: a cell refers to point " + std::to_string(static_cast<long long>(id)) +
                                      " of " + std::to_string(np));
    }
  }
  return grid;
}

// Inverse of the collocation at equispaced nodes a/p: Bézier coefficients from node values.
Eigen::MatrixXd lagrange_to_bezier_1d(int p) {
  Eigen::MatrixXd B(p + 1, p + 1);
  for (int a = 0; a <= p; ++a) B.row(a) = bernstein_basis(p, double(a) / p).transpose();
  return B.inverse();
}

// The same on the tetrahedron (nodes β/n in simplex_index order), cached per degree.
const Eigen::MatrixXd& lagrange_to_bezier_tet(int n) {
  static thread_local std::map<int, Eigen::MatrixXd> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  const auto idx = simplex_multi_indices(3, n);
  const int N = static_cast<int>(idx.size());
  Eigen::MatrixXd M(N, N);
  for (int r = 0; r < N; ++r) {
    const double l[4] = {double(idx[r][0]) / n, double(idx[r][1]) / n, double(idx[r][2]) / n, double(idx[r][3]) / n};
    for (int c = 0; c < N; ++c) {
      double b = 1;  // n!/α! λ^α, by a product of binomials
      int rest = n;
      for (int k = 0; k < 4; ++k) {
        double bin = 1;
        for (int t = 1; t <= idx[c][k]; ++t) bin = bin * (rest - idx[c][k] + t) / t;
        rest -= idx[c][k];
        b *= bin * std::pow(l[k], idx[c][k]);
      }
      M(r, c) = b;
    }
  }
  return cache[n] = M.inverse();
}

// Highest degree read from a .vtu (VTK itself handles far less; keeps point counts small).
constexpr int kMaxVtuDegree = 30;

int cube_root(int n) {
  const int r = static_cast<int>(std::lround(std::cbrt(double(n))));
  return r * r * r == n ? r : -1;
}

int tet_degree(int npts) {
  for (int n = 1; n < 40; ++n)
    if (simplex_size(3, n) == npts) return n;
  return -1;
}

}  // namespace

int vtk_tet_point_index(int a1, int a2, int a3, int degree) {
  const vtkIdType b[4] = {a1, a2, a3, degree - a1 - a2 - a3};
  return static_cast<int>(vtkHigherOrderTetra::Index(b, degree));
}

VtuElements read_bezier_vtu(const std::string& path) {
  vtkSmartPointer<vtkUnstructuredGrid> grid = read_grid(path);
  vtkDataArray* weights = grid->GetPointData()->GetRationalWeights();
  if (!weights) weights = grid->GetPointData()->GetArray("RationalWeights");
  vtkDataArray* degrees = grid->GetCellData()->GetHigherOrderDegrees();
  if (!degrees) degrees = grid->GetCellData()->GetArray("HigherOrderDegrees");
  VtuElements out;
  const vtkIdType nc = grid->GetNumberOfCells(), npoints = grid->GetNumberOfPoints();
  // VTK reads the arrays as they are: their sizes are checked here, before any lookup.
  if (weights && (weights->GetNumberOfTuples() < npoints || weights->GetNumberOfComponents() < 1))
    throw core::InvalidInputError(path + ": RationalWeights has " + std::to_string(weights->GetNumberOfTuples()) +
                                  " values for " + std::to_string(npoints) + " points");
  if (degrees && degrees->GetNumberOfTuples() < nc)
    throw core::InvalidInputError(path + ": HigherOrderDegrees has " + std::to_string(degrees->GetNumberOfTuples()) +
                                  " values for " + std::to_string(nc) + " cells");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < nc; ++c) {
    const int type = grid->GetCellType(c);
    grid->GetCellPoints(c, ids);
    const int np = static_cast<int>(ids->GetNumberOfIds());
    const std::string where = path + ": cell " + std::to_string(c) + " (VTK type " + std::to_string(type) + ", " +
                              std::to_string(np) + " points)";
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      if (ids->GetId(k) < 0 || ids->GetId(k) >= npoints)
        throw core::InvalidInputError(where + ": point id " + std::to_string(ids->GetId(k)) + " out of range (" +
                                      std::to_string(npoints) + " points)");
    const auto point = [&](int local) {
      double x[3];
      grid->GetPoint(ids->GetId(local), x);
      if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
        throw core::InvalidInputError(where + ": point " + std::to_string(ids->GetId(local)) + " is not finite");
      return Eigen::Vector3d(x[0], x[1], x[2]);
    };
    const auto weight = [&](int local) { return weights ? weights->GetComponent(ids->GetId(local), 0) : 1.0; };
    out.vtk_type.push_back(type);
    if (type == VTK_BEZIER_HEXAHEDRON || type == VTK_LAGRANGE_HEXAHEDRON || type == VTK_HEXAHEDRON) {
      BezierHex h;
      if (type == VTK_HEXAHEDRON) {
        h.degree = {1, 1, 1};
      } else if (degrees && degrees->GetNumberOfComponents() >= 3) {
        for (int d = 0; d < 3; ++d) {
          // Checked as a double: a cast of NaN or 1e30 to int is undefined.
          const double g = degrees->GetComponent(c, d);
          if (!(g >= 1 && g <= kMaxVtuDegree) || g != std::floor(g))
            throw core::InvalidInputError(where + ": HigherOrderDegrees " + std::to_string(g) + " is not a degree in [1, " +
                                          std::to_string(kMaxVtuDegree) + "]");
          h.degree[d] = static_cast<int>(g);
        }
      } else {
        const int r = cube_root(np) - 1;
        h.degree = {r, r, r};
      }
      if (h.degree[0] < 1 || h.degree[1] < 1 || h.degree[2] < 1 || h.num_points() != np)
        throw core::InvalidInputError(where + ": the point count does not match degrees " + std::to_string(h.degree[0]) +
                                      "," + std::to_string(h.degree[1]) + "," + std::to_string(h.degree[2]));
      h.points.resize(np);
      bool rational = false;
      std::vector<double> w(np);
      for (int n = 0; n < np; ++n) {
        const auto [i, j, k] = h.ijk(n);
        const int local = vtk_hex_point_index(i, j, k, h.degree);
        h.points[n] = point(local);
        w[n] = weight(local);
        rational = rational || w[n] != 1.0;
      }
      if (type == VTK_BEZIER_HEXAHEDRON && rational) h.weights = w;
      if (type == VTK_LAGRANGE_HEXAHEDRON)
        h = map_coefficients(h, {lagrange_to_bezier_1d(h.degree[0]), lagrange_to_bezier_1d(h.degree[1]),
                                 lagrange_to_bezier_1d(h.degree[2])});
      try {
        check(h);
      } catch (const core::InvalidInputError& e) {
        throw core::InvalidInputError(where + ": " + e.what());
      }
      out.element.push_back(static_cast<int>(out.hexes.size()));
      out.hexes.push_back(std::move(h));
    } else if (type == VTK_BEZIER_TETRAHEDRON || type == VTK_LAGRANGE_TETRAHEDRON || type == VTK_TETRA) {
      BezierTet t;
      t.degree = type == VTK_TETRA ? 1 : tet_degree(np);
      if (t.degree < 1 || simplex_size(3, t.degree) != np)
        throw core::InvalidInputError(where + ": the point count is not that of a tetrahedron of any degree");
      t.points.resize(np);
      std::vector<double> w(np);
      bool rational = false;
      int n = 0;
      for (const auto& a : simplex_multi_indices(3, t.degree)) {
        const int local = vtk_tet_point_index(a[1], a[2], a[3], t.degree);
        t.points[n] = point(local);
        w[n] = weight(local);
        rational = rational || w[n] != 1.0;
        ++n;
      }
      if (type == VTK_BEZIER_TETRAHEDRON && rational) t.weights = w;
      if (type == VTK_LAGRANGE_TETRAHEDRON) {
        const Eigen::MatrixXd& M = lagrange_to_bezier_tet(t.degree);
        std::vector<Eigen::Vector3d> b(np, Eigen::Vector3d::Zero());
        for (int r = 0; r < np; ++r)
          for (int s = 0; s < np; ++s) b[r] += M(r, s) * t.points[s];
        t.points = std::move(b);
      }
      try {
        check(t);
      } catch (const core::InvalidInputError& e) {
        throw core::InvalidInputError(where + ": " + e.what());
      }
      out.element.push_back(static_cast<int>(out.tets.size()));
      out.tets.push_back(std::move(t));
    } else {
      throw core::InvalidInputError(where + ": unsupported cell type; readable are hexahedra (79 Bézier, 72 Lagrange, "
                                    "12 linear) and tetrahedra (78 Bézier, 71 Lagrange, 10 linear)");
    }
  }
  return out;
}

void write_vtu_with_cell_arrays(const std::string& in, const std::string& out, const std::vector<CellArray>& arrays) {
  vtkSmartPointer<vtkUnstructuredGrid> grid = read_grid(in);
  const vtkIdType nc = grid->GetNumberOfCells();
  for (const CellArray& a : arrays) {
    if (a.name.empty() || a.components < 1 || a.values.size() != static_cast<std::size_t>(nc) * a.components)
      throw core::InvalidInputError(out + ": cell array '" + a.name + "' has " + std::to_string(a.values.size()) +
                                    " values for " + std::to_string(nc) + " cells");
    vtkNew<vtkDoubleArray> arr;
    arr->SetName(a.name.c_str());
    arr->SetNumberOfComponents(a.components);
    arr->SetNumberOfTuples(nc);
    for (std::size_t v = 0; v < a.values.size(); ++v) arr->SetValue(static_cast<vtkIdType>(v), a.values[v]);
    grid->GetCellData()->RemoveArray(a.name.c_str());
    grid->GetCellData()->AddArray(arr);
  }
  core::write_atomically(out, [&](const std::string& tmp) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetHeaderTypeToUInt64();
    if (writer->Write() != 1 || writer->GetErrorCode() != vtkErrorCode::NoError)
      throw core::IoError(out + ": VTK writer failed: " + describe(writer->GetErrorCode()));
  });
}

void write_bezier_vtu(const std::string& path, const std::vector<BezierHex>& hexes,
                      const std::vector<CellArray>& cell_arrays) {
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    try {
      check(hexes[h]);
    } catch (const core::InvalidInputError& e) {
      throw core::InvalidInputError(path + ": hex " + std::to_string(h) + ": " + e.what());
    }
  }
  for (const CellArray& a : cell_arrays) {
    if (a.name.empty() || a.name == "HigherOrderDegrees" || a.name == "RationalWeights")
      throw core::InvalidInputError(path + ": cell array name '" + a.name + "' is empty or reserved");
    if (a.components < 1 || a.values.size() != hexes.size() * static_cast<std::size_t>(a.components))
      throw core::InvalidInputError(path + ": cell array '" + a.name + "' has " + std::to_string(a.values.size()) +
                                    " values, expected " + std::to_string(a.components) + " per hex for " +
                                    std::to_string(hexes.size()) + " hexes");
  }

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();  // control points at full precision
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("RationalWeights");
  vtkNew<vtkIntArray> degrees;
  degrees->SetName("HigherOrderDegrees");
  degrees->SetNumberOfComponents(3);
  degrees->SetNumberOfTuples(static_cast<vtkIdType>(hexes.size()));
  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(static_cast<vtkIdType>(hexes.size()));
  std::vector<vtkIdType> ids;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    const BezierHex& hex = hexes[h];
    const vtkIdType base = points->GetNumberOfPoints();
    ids.assign(hex.num_points(), 0);
    for (int n = 0; n < hex.num_points(); ++n) {
      points->InsertNextPoint(hex.points[n].data());
      weights->InsertNextValue(hex.weight(n));
      const auto [i, j, k] = hex.ijk(n);
      ids[vtk_hex_point_index(i, j, k, hex.degree)] = base + n;
    }
    grid->InsertNextCell(VTK_BEZIER_HEXAHEDRON, static_cast<vtkIdType>(ids.size()), ids.data());
    degrees->SetTuple3(static_cast<vtkIdType>(h), hex.degree[0], hex.degree[1], hex.degree[2]);
  }
  grid->SetPoints(points);
  // Declared active so that readers (ParaView) use them; written as attributes of <PointData>/<CellData>.
  grid->GetPointData()->SetRationalWeights(weights);
  grid->GetCellData()->SetHigherOrderDegrees(degrees);
  for (const CellArray& a : cell_arrays) {
    vtkNew<vtkDoubleArray> arr;
    arr->SetName(a.name.c_str());
    arr->SetNumberOfComponents(a.components);
    arr->SetNumberOfTuples(static_cast<vtkIdType>(hexes.size()));
    for (std::size_t v = 0; v < a.values.size(); ++v) arr->SetValue(static_cast<vtkIdType>(v), a.values[v]);
    grid->GetCellData()->AddArray(arr);
  }

  core::write_atomically(path, [&](const std::string& tmp) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();  // raw binary
    writer->SetHeaderTypeToUInt64();  // arrays over 4 GiB
    if (writer->Write() != 1 || writer->GetErrorCode() != vtkErrorCode::NoError)
      throw core::IoError(path + ": VTK writer failed: " + describe(writer->GetErrorCode()));
  });
}

}  // namespace volts::bezier
