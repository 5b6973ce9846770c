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

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <map>
#include <new>
#include <set>
#include <stdexcept>
#include <utility>

#include "bezier/bernstein.h"

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/limits.h"

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

// ---- Pre-scan of the sizes a .vtu declares (hand-written: VTK has no such check). VTK's XML reader
// allocates what the header and the binary block headers declare before it reads the data, so a
// 1 KB file could ask for gigabytes (found by fuzz_vtu). Every declared size is checked here against
// what the file can hold: at most kMaxExpansion bytes per file byte (zlib's limit is ~1032, LZ4's
// ~255; LZMA can exceed it, but no writer volts knows produces such arrays), at least 64 MiB, and
// never more than half the physical memory.
constexpr double kMaxExpansion = 1100.0;

// Value of attribute `name` inside one tag's text, or "" when absent.
std::string xml_attribute(const std::string& tag, const std::string& name) {
  for (std::size_t at = tag.find(name + "=\""); at != std::string::npos; at = tag.find(name + "=\"", at + 1)) {
    if (at > 0 && !std::isspace(static_cast<unsigned char>(tag[at - 1]))) continue;  // "NumberOfPoints" in "xNumberOfPoints"
    const std::size_t begin = at + name.size() + 2, end = tag.find('"', begin);
    if (end == std::string::npos) return {};
    return tag.substr(begin, end - begin);
  }
  return {};
}

// A non-negative integer attribute; -1 if absent, throws if it is not a number.
double number_attribute(const std::string& path, const std::string& tag, const std::string& name) {
  const std::string v = xml_attribute(tag, name);
  if (v.empty()) return -1;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || !std::isfinite(x) || x < 0)
    throw core::InvalidInputError(path + ": malformed .vtu file: " + name + "=\"" + v.substr(0, 40) + "\" is not a size");
  return x;
}

// First `n` bytes of a base64 text (whitespace skipped), fewer if it ends or holds other characters.
std::string base64_prefix(const char* p, const char* end, std::size_t n) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  unsigned bits = 0;
  int nbits = 0;
  for (; p < end && out.size() < n; ++p) {
    if (std::isspace(static_cast<unsigned char>(*p))) continue;
    const int v = value(*p);
    if (v < 0) break;
    bits = (bits << 6) | unsigned(v);
    nbits += 6;
    if (nbits >= 8) {
      nbits -= 8;
      out.push_back(static_cast<char>((bits >> nbits) & 0xFF));
    }
  }
  return out;
}

// The innermost section (Piece, Points, PointData, CellData, Cells) whose opening tag precedes
// `at`: its position and opening tag. Both the length check of ASCII arrays and the duplicate-name
// check need it.
std::pair<std::size_t, std::string> section_of(const std::string& text, std::size_t at) {
  std::pair<std::size_t, std::string> section{0, std::string()};
  for (const char* open : {"<Piece", "<Points", "<PointData", "<CellData", "<Cells"}) {
    const std::size_t o = text.rfind(open, at);
    if (o != std::string::npos && (section.second.empty() || o > section.first)) section = {o, open};
  }
  return section;
}

// An ASCII DataArray: every value a number (an integer for integer types) and at least as many
// as its section needs. VTK 9.1 leaks the array it was filling when an ASCII read fails
// (fuzz_vtu: a cell type "=9"), so such files are refused before VTK reads them.
void check_ascii_array(const std::string& path, const std::string& text, std::size_t at, const std::string& tag, double components) {
  const std::size_t begin = text.find('>', at), end = text.find("</DataArray>", at);
  if (begin == std::string::npos || end == std::string::npos || begin > end) return;  // VTK's XML parser reports it
  if (text[begin - 1] == '/') return;  // <DataArray .../>: no values
  const std::string type = xml_attribute(tag, "type");
  const bool integer = type.find("Int") != std::string::npos;
  std::size_t values = 0;
  for (std::size_t i = begin + 1; i < end;) {
    if (std::isspace(static_cast<unsigned char>(text[i]))) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < end && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    const std::string token = text.substr(i, j - i);
    char* stop = nullptr;
    if (integer)
      std::strtoll(token.c_str(), &stop, 10);
    else
      std::strtod(token.c_str(), &stop);
    if (stop != token.c_str() + token.size())
      throw core::InvalidInputError(path + ": malformed .vtu file: '" + token.substr(0, 40) + "' in the " + type + " DataArray" +
                                    (xml_attribute(tag, "Name").empty() ? std::string() : " " + xml_attribute(tag, "Name")) +
                                    " is not " + (integer ? "an integer" : "a number"));
    ++values;
    i = j;
  }
  // Values the section needs: points and point data per point, cell data and cell types/offsets per cell.
  const std::size_t piece = text.rfind("<Piece", at);
  if (piece == std::string::npos) return;
  const std::string piece_tag = text.substr(piece, text.find('>', piece) - piece);
  const double np = number_attribute(path, piece_tag, "NumberOfPoints"), nc = number_attribute(path, piece_tag, "NumberOfCells");
  const std::string name = section_of(text, at).second;
  const std::string array = xml_attribute(tag, "Name");
  double needed = 0;
  if (name == "<Points" || name == "<PointData") needed = std::max(np, 0.0) * components;
  else if (name == "<CellData" || (name == "<Cells" && (array == "types" || array == "offsets"))) needed = std::max(nc, 0.0) * components;
  if (static_cast<double>(values) < needed)
    throw core::InvalidInputError(path + ": malformed .vtu file: the ASCII DataArray" + (array.empty() ? std::string() : " " + array) +
                                  " holds " + std::to_string(values) + " values where " + std::to_string(static_cast<long long>(needed)) +
                                  " are needed (truncated?)");
}

void check_declared_sizes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const double file_bytes = static_cast<double>(text.size());
  const double budget = std::min(0.5 * static_cast<double>(core::physical_memory_bytes()),
                                 std::max(64.0 * 1024 * 1024, kMaxExpansion * file_bytes));
  auto refuse = [&](const std::string& what, double bytes) {
    throw core::InvalidInputError(path + ": malformed .vtu file: implausible sizes (" + what + " needs " +
                                  std::to_string(static_cast<long long>(std::min(bytes, 9e18))) + " bytes; the file is " +
                                  std::to_string(text.size()) + " bytes)");
  };
  const std::size_t appended_tag = text.find("<AppendedData");
  const std::size_t xml_end = appended_tag == std::string::npos ? text.size() : appended_tag;
  auto tag_at = [&](std::size_t at) { return text.substr(at, text.find('>', at) - at); };

  const std::size_t file_tag = text.find("<VTKFile");
  const std::string vtkfile = file_tag == std::string::npos ? std::string() : tag_at(file_tag);
  const std::size_t header_bytes = xml_attribute(vtkfile, "header_type") == "UInt64" ? 8 : 4;
  const bool big_endian = xml_attribute(vtkfile, "byte_order") == "BigEndian";
  const bool compressed = !xml_attribute(vtkfile, "compressor").empty();
  auto header_int = [&](const std::string& bytes, std::size_t i) {
    double v = 0;
    for (std::size_t b = 0; b < header_bytes; ++b) {
      const std::size_t at = i * header_bytes + (big_endian ? b : header_bytes - 1 - b);
      v = v * 256 + static_cast<unsigned char>(bytes[at]);
    }
    return v;
  };

  double tuples = 0;  // most tuples an array of the current piece may hold
  for (std::size_t at = text.find("<Piece"); at < xml_end; at = text.find("<Piece", at + 1)) {
    const std::string piece = tag_at(at);
    const double np = number_attribute(path, piece, "NumberOfPoints"), nc = number_attribute(path, piece, "NumberOfCells");
    if (np * 3 * 8 > budget) refuse("NumberOfPoints", np * 3 * 8);
    if (nc * 8 * 3 > budget) refuse("NumberOfCells", nc * 8 * 3);
    tuples = std::max({tuples, np, nc});
  }
  // VTK leaks the array it made when the points have other than 3 components (fuzz_vtu).
  for (std::size_t at = text.find("<Points"); at < xml_end; at = text.find("<Points", at + 1)) {
    const std::size_t array = text.find("<DataArray", at);
    if (array >= xml_end) break;
    const std::string tag = tag_at(array);
    if (number_attribute(path, tag, "NumberOfComponents") != 3)
      throw core::InvalidInputError(path + ": malformed .vtu file: the Points array has NumberOfComponents=\"" +
                                    xml_attribute(tag, "NumberOfComponents").substr(0, 20) + "\", VTK needs 3");
  }
  // As VTK finds it: the first non-blank character after the tag's '>' is taken for the '_'
  // marker, whatever it is (a ';' there shifted every offset: fuzz_vtu).
  std::size_t underscore = appended_tag == std::string::npos ? std::string::npos : text.find('>', appended_tag);
  if (underscore != std::string::npos) {
    ++underscore;
    while (underscore < text.size() && std::strchr(" \t\n\r", text[underscore]) && text[underscore]) ++underscore;  // VTK's blanks
    if (underscore >= text.size()) underscore = std::string::npos;
  }
  const std::string appended = appended_tag == std::string::npos ? std::string() : tag_at(appended_tag);
  const bool appended_base64 = xml_attribute(appended, "encoding") == "base64";
  std::set<std::pair<std::size_t, std::string>> names;
  for (std::size_t at = text.find("<DataArray"); at < xml_end; at = text.find("<DataArray", at + 1)) {
    const std::string tag = tag_at(at);
    const double components = std::max(1.0, number_attribute(path, tag, "NumberOfComponents"));
    const double declared = number_attribute(path, tag, "NumberOfTuples");
    const double n = declared >= 0 ? declared : tuples;
    if (n * components * 8 > budget) refuse("a DataArray (NumberOfComponents x tuples)", n * components * 8);
    // Two arrays of one name in a section make VTK dereference null (fuzz_vtu: a second
    // max_scaled_jacobian in CellData).
    const std::string array_name = xml_attribute(tag, "Name");
    if (!array_name.empty() && !names.insert({section_of(text, at).first, array_name}).second)
      throw core::InvalidInputError(path + ": malformed .vtu file: two arrays named '" + array_name.substr(0, 60) + "' in one section");
    const std::string format = xml_attribute(tag, "format");
    if (format == "ascii") check_ascii_array(path, text, at, tag, components);
    // Binary data: the block header in front of the array (sizes of the uncompressed data).
    const char* data = nullptr;
    const char* data_end = text.data() + text.size();
    bool base64 = false;
    // VTK reads an array with an offset from the appended data unless it says ascii or binary,
    // even when the format attribute is missing or misspelt (fuzz_vtu: "fomart").
    if (format == "appended" || (format != "ascii" && format != "binary" && !xml_attribute(tag, "offset").empty())) {
      const double offset = number_attribute(path, tag, "offset");
      if (underscore == std::string::npos || offset < 0) continue;  // VTK reports these itself
      if (offset >= file_bytes - double(underscore) - 1) refuse("a DataArray offset past the end of the file", offset);
      data = text.data() + underscore + 1 + static_cast<std::size_t>(offset);
      base64 = appended_base64;
    } else if (format == "binary" && text.find('>', at) != std::string::npos) {
      data = text.data() + text.find('>', at) + 1;
      base64 = true;
    } else {
      continue;
    }
    const std::size_t words = compressed ? 3 : 1;
    std::string head = base64 ? base64_prefix(data, data_end, words * header_bytes)
                              : std::string(data, std::min<std::size_t>(words * header_bytes, static_cast<std::size_t>(data_end - data)));
    if (head.size() < words * header_bytes) continue;  // VTK reports a short header itself
    const double available = static_cast<double>(data_end - data);
    if (!compressed) {
      if (header_int(head, 0) > available) refuse("a binary DataArray", header_int(head, 0));
      continue;
    }
    const double blocks = header_int(head, 0), block_size = header_int(head, 1), last_size = header_int(head, 2);
    if (blocks * header_bytes > available) refuse("a compressed DataArray's block table", blocks * header_bytes);
    // VTK divides by the block size and subtracts it for a partial last block (fuzz_vtu: SIGFPE).
    if ((blocks > 0 && block_size == 0) || last_size > block_size || (blocks == 0 && last_size > 0))
      throw core::InvalidInputError(path + ": malformed .vtu file: inconsistent compressed block header (" +
                                    std::to_string(static_cast<long long>(std::min(blocks, 9e18))) + " blocks of " +
                                    std::to_string(static_cast<long long>(std::min(block_size, 9e18))) + " bytes, the last of " +
                                    std::to_string(static_cast<long long>(std::min(last_size, 9e18))) + ")");
    if (std::max(block_size, last_size) > budget || blocks * block_size > budget)
      refuse("a compressed DataArray", std::max(blocks * block_size, std::max(block_size, last_size)));
    // VTK allocates each block's compressed size as the table gives it (fuzz_vtu: 1 TB).
    const std::size_t table = (3 + static_cast<std::size_t>(blocks)) * header_bytes;
    head = base64 ? base64_prefix(data, data_end, table)
                  : std::string(data, std::min<std::size_t>(table, static_cast<std::size_t>(data_end - data)));
    if (head.size() < table) continue;  // VTK reports a short table itself
    double compressed_total = 0;
    for (std::size_t b = 0; b < static_cast<std::size_t>(blocks); ++b) compressed_total += header_int(head, 3 + b);
    if (compressed_total > available) refuse("a compressed DataArray's blocks", compressed_total);
  }
}

vtkSmartPointer<vtkUnstructuredGrid> read_grid(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw core::InvalidInputError(path + ": no such file");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  if (!reader->CanReadFile(path.c_str()))
    throw core::InvalidInputError(path + ": not a VTK XML unstructured grid (.vtu) file");
  check_declared_sizes(path);
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
                      const std::vector<CellArray>& cell_arrays, const std::vector<int>& shared) {
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
  // Sized once: growing the arrays point by point reallocated and copied them (a tenth of extract).
  vtkIdType total = 0;
  for (const BezierHex& hex : hexes) total += hex.num_points();
  vtkIdType distinct = total;
  if (!shared.empty()) {
    if (shared.size() != static_cast<std::size_t>(total))
      throw core::InvalidInputError(path + ": " + std::to_string(shared.size()) + " shared point ids for " + std::to_string(total) + " control points");
    distinct = 0;
    for (const int id : shared) {
      if (id < 0 || id > distinct) throw core::InvalidInputError(path + ": shared point ids must be numbered in order of first use, got " + std::to_string(id));
      if (id == distinct) ++distinct;
    }
  }
  points->SetNumberOfPoints(distinct);
  weights->SetNumberOfValues(distinct);
  std::vector<vtkIdType> ids;
  vtkIdType base = 0, next = 0;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    const BezierHex& hex = hexes[h];
    ids.assign(hex.num_points(), 0);
    for (int n = 0; n < hex.num_points(); ++n) {
      const vtkIdType id = shared.empty() ? base + n : shared[static_cast<std::size_t>(base + n)];
      if (id == next) {
        points->SetPoint(id, hex.points[n].data());
        weights->SetValue(id, hex.weight(n));
        ++next;
      }
      const auto [i, j, k] = hex.ijk(n);
      ids[vtk_hex_point_index(i, j, k, hex.degree)] = id;
    }
    grid->InsertNextCell(VTK_BEZIER_HEXAHEDRON, static_cast<vtkIdType>(ids.size()), ids.data());
    base += hex.num_points();
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
    // LZ4: zlib (VTK's default) took 0.2-0.5 s for the torus' 3,072 cubic elements, LZ4 0.01 s for
    // a file 1.4 times larger (4.8 MB); VTK >= 8 and ParaView read both.
    writer->SetCompressorTypeToLZ4();
    writer->SetHeaderTypeToUInt64();  // arrays over 4 GiB
    if (writer->Write() != 1 || writer->GetErrorCode() != vtkErrorCode::NoError)
      throw core::IoError(path + ": VTK writer failed: " + describe(writer->GetErrorCode()));
  });
}

}  // namespace volts::bezier
