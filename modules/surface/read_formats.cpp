// Format parsers. CGAL's readers do the parsing; what is hand-written here is what they lack:
// they answer only true/false, cannot parse "nan"/"inf" (libstdc++'s operator>> refuses them),
// allocate whatever sizes a file announces, and some accept broken files or misbehave on them (see
// each parser). So sizes are checked before CGAL reads, and a refused file is re-scanned to say
// what is wrong and where.
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string_view>

#include "core/errors.h"
#include "core/limits.h"
#include "surface/formats.h"

namespace volts::surface::detail {
namespace {

constexpr std::size_t npos = std::string_view::npos;

// Rough memory per declared vertex and face through reading, welding and the mesh (for
// core::check_declared_count): a point in the soup, its copy, the mesh's vertex and halfedges.
constexpr std::size_t kBytesPerVertex = 128, kBytesPerFace = 160;

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw core::InvalidInputError(path + ": " + problem);
}

// ---- Locating problems in text files --------------------------------------------------------

/// A line of the file: 1-based number and its text.
struct Line {
  std::size_t number = 0;
  std::string_view text;
};

/// The line containing byte `pos`.
Line line_at(std::string_view text, std::size_t pos) {
  pos = std::min(pos, text.size());
  std::size_t begin = 0;
  if (pos > 0) {
    const std::size_t newline = text.rfind('\n', pos - 1);
    if (newline != npos) begin = newline + 1;
  }
  std::size_t end = text.find('\n', begin);
  if (end == npos) end = text.size();
  const auto number = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + begin, '\n'));
  return {number, text.substr(begin, end - begin)};
}

/// The line of the byte before `pos`: readers that consume whole lines stop just after the bad one.
Line line_before(std::string_view text, std::size_t pos) { return line_at(text, pos == 0 ? 0 : pos - 1); }

/// True if `line` is the file's unterminated last line, the mark of a file cut mid-line.
bool cut_mid_line(const Line& line, std::string_view text) {
  return line.text.data() + line.text.size() == text.data() + text.size() && !line.text.empty();
}

/// The last line that is not blank.
Line last_line(std::string_view text) {
  const std::size_t last = text.find_last_not_of(" \t\r\n\f\v");
  return line_at(text, last == npos ? 0 : last);
}

/// "line 12: '3 0 1 9'" with non-printable bytes shown as '?' and long lines cut.
std::string quote(const Line& line) {
  constexpr std::size_t max_chars = 60;
  std::string_view t = line.text;
  while (!t.empty() && (t.back() == '\r' || t.back() == ' ')) t.remove_suffix(1);
  std::string s;
  for (const char c : t.substr(0, max_chars)) s += c == '\t' ? ' ' : (c >= 0x20 && c < 0x7f ? c : '?');
  if (t.size() > max_chars) s += "...";
  return "line " + std::to_string(line.number) + ": '" + s + "'";
}

/// True if only whitespace (and, with `hash_comments`, '#' comments) follows `pos`.
bool only_blank_after(std::string_view text, std::size_t pos, bool hash_comments) {
  while (pos < text.size()) {
    const char c = text[pos];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++pos;
    } else if (hash_comments && c == '#') {
      pos = text.find('\n', pos);
      if (pos == npos) return true;
    } else {
      return false;
    }
  }
  return true;
}

/// Where the stream stopped, after clearing its error state.
std::size_t stream_pos(std::istringstream& in, std::size_t size) {
  in.clear();
  const std::streamoff p = in.tellg();
  return p < 0 ? size : std::min(size, static_cast<std::size_t>(p));
}

/// Calls f(line) for each line of text from byte `begin` on.
template <class F>
void for_each_line(std::string_view text, std::size_t begin, F&& f) {
  std::size_t number = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + std::min(begin, text.size()), '\n'));
  for (std::size_t pos = begin; pos < text.size(); ++number) {
    std::size_t end = text.find('\n', pos);
    if (end == npos) end = text.size();
    f(Line{number, text.substr(pos, end - pos)});
    pos = end + 1;
  }
}

std::vector<std::string_view> tokens_of(std::string_view line, bool hash_comments) {
  if (hash_comments) line = line.substr(0, line.find('#'));
  std::vector<std::string_view> tokens;
  std::size_t pos = 0;
  while (true) {
    const std::size_t b = line.find_first_not_of(" \t\r\f\v", pos);
    if (b == npos) break;
    const std::size_t e = std::min(line.find_first_of(" \t\r\f\v", b), line.size());
    tokens.push_back(line.substr(b, e - b));
    pos = e;
  }
  return tokens;
}

enum class Number { finite, non_finite, invalid };

Number parse_number(std::string_view token) {
  // strtod, unlike operator>>, reads nan/inf and turns an overflow such as 1e999 into inf.
  const std::string s(token);
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return Number::invalid;
  return std::isfinite(value) ? Number::finite : Number::non_finite;
}

bool parse_integer(std::string_view token, long long& value) {
  const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
  return r.ec == std::errc() && r.ptr == token.data() + token.size();
}

/// Problems found while scanning a text file; raise() throws for the most fundamental one.
class TextProblems {
 public:
  explicit TextProblems(std::string_view text) : text_(text) {}

  /// Checks the coordinate tokens of vertex `index` (read from `line`).
  void vertex(std::size_t index, const std::vector<std::string_view>& coords, const Line& line) {
    const std::string name = "vertex " + std::to_string(index);
    if (coords.size() < 3) return short_line(name + ": fewer than 3 coordinates", line);
    for (std::size_t i = 0; i < 3; ++i) {
      const Number n = parse_number(coords[i]);
      if (n == Number::non_finite) return non_finite_.add([&] { return name + " (" + quote(line) + ")"; });
      if (n == Number::invalid) return malformed(name + ": '" + std::string(coords[i]) + "' is not a number", line);
    }
  }
  void index_out_of_range(std::size_t face, long long index, std::size_t vertices, const Line& line) {
    out_of_range_.add([&] {
      return "face " + std::to_string(face) + " (vertex index " + std::to_string(index) + ", but there are " +
             count_of(vertices, "vertex", "vertices") + "; " + quote(line) + ")";
    });
  }
  void malformed(const std::string& what, const Line& line) {
    if (malformed_.empty()) malformed_ = "malformed " + what + " (" + quote(line) + ")";
  }
  /// A line with too few entries: malformed, or the file's unterminated last line (the file was cut).
  void short_line(const std::string& what, const Line& line) {
    malformed(what, line);
    cut_ = cut_ || cut_mid_line(line, text_);
  }
  bool file_cut() const { return cut_; }

  void raise_non_finite(const std::string& path) const {
    if (non_finite_.count() > 0)
      fail(path, count_of(non_finite_.count(), "vertex", "vertices") +
                     " with non-finite coordinates (NaN/Inf), first at " + non_finite_.first());
  }
  void raise(const std::string& path) const {
    raise_non_finite(path);
    if (!malformed_.empty()) fail(path, malformed_);
    if (out_of_range_.count() > 0)
      fail(path, count_of(out_of_range_.count(), "face", "faces") + " with a vertex index out of range, first is " +
                     out_of_range_.first());
  }

 private:
  std::string_view text_;
  Tally non_finite_, out_of_range_;
  std::string malformed_;
  bool cut_ = false;
};

// ---- OFF ------------------------------------------------------------------------------------

/// The colour tokens t[first..] of an OFF vertex or face line (`what`). CGAL converts a colour to
/// unsigned char without a range check (undefined behaviour for 33 or 1.5: found by fuzz_off) and
/// looks a single value up in a 149-entry colour map without a lower bound, so: 0, 1, 3 or 4
/// numbers; one value an index in [0, 2^31); three or four values integers in [0, 255] or
/// fractions in [0, 1] (CGAL's two conventions, told apart as CGAL does).
/// `seen`: an earlier line of the same kind had a colour. CGAL's "has colours" flag is sticky, so
/// a later line without one makes it read the previous line's values (fuzz_off): refused.
void check_off_color(TextProblems& problems, const std::string& what, const std::vector<std::string_view>& t, std::size_t first,
                     const Line& line, bool& seen) {
  const std::size_t n = t.size() > first ? t.size() - first : 0;
  if (n == 0 && seen) return problems.malformed(what + ": no colour, where earlier lines have one", line);
  seen = seen || n > 0;
  if (n != 0 && n != 1 && n != 3 && n != 4)
    return problems.malformed(what + ": " + std::to_string(n) + " values where a colour needs 0, 1, 3 or 4", line);
  std::vector<double> v;
  for (std::size_t k = first; k < t.size(); ++k) {
    const std::string s(t[k]);
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || !std::isfinite(x))
      return problems.malformed(what + ": colour value '" + s + "' is not a finite number", line);
    v.push_back(x);
  }
  if (n == 1 && !(v[0] >= 0 && v[0] < 2147483648.0))
    return problems.malformed(what + ": colour-map index " + std::string(t[first]) + " out of range", line);
  if (n >= 3) {
    const bool integers = std::floor(v[0]) == v[0] && std::floor(v[1]) == v[1] && std::floor(v[2]) == v[2];
    for (int c = 0; c < 3; ++c)
      if (!(v[c] >= 0 && v[c] <= (integers ? 255 : 1)))
        return problems.malformed(what + ": colour value " + std::string(t[first + c]) + " out of range (" +
                                      (integers ? "0 to 255" : "0 to 1") + ")",
                                  line);
  }
}

/// Hand-written pre-check of the data lines (the non-blank, non-comment lines after the header:
/// nv vertices, then nf faces), run before CGAL reads them: CGAL allocates every array a count
/// announces (header or face line) before reading it, so a truncated or corrupt file could make
/// it allocate gigabytes, and it reports no problem beyond "false".
/// `color_tokens_at`: for COFF-like headers, how many tokens precede a vertex's colour (else 0).
/// CGAL reads the colour as the tokens left after the coordinates (and normals, texture) and reads
/// three of them unless one is left, without checking they exist (found by fuzz_off: a short
/// CNOFF vertex line reads freed memory), so a colour of other than 0, 1, 3 or 4 values is refused.
void check_off_lines(const std::string& path, const std::string& text, std::size_t header_end, std::size_t nv,
                     std::size_t nf, std::size_t color_tokens_at) {
  TextProblems problems(text);
  std::size_t items = 0;
  bool vertex_color_seen = false, face_color_seen = false;
  // Like CGAL, read on from the end of the counts: the rest of their line is data if not blank.
  for_each_line(text, header_end, [&](const Line& line) {
    const auto t = tokens_of(line.text, true);
    if (t.empty()) return;
    if (items < nv) {
      problems.vertex(items, t, line);
      if (color_tokens_at > 0 && t.size() >= color_tokens_at)
        check_off_color(problems, "vertex " + std::to_string(items) + " (after the coordinates and normals)", t, color_tokens_at, line,
                        vertex_color_seen);
      else if (color_tokens_at > 0)
        problems.short_line("vertex " + std::to_string(items) + ": " + std::to_string(t.size()) + " values where the header's coordinates and normals need " +
                                std::to_string(color_tokens_at),
                            line);
    } else if (items < nv + nf) {
      const std::size_t face = items - nv;
      long long n = 0;
      if (!parse_integer(t[0], n) || n < 0) {
        problems.malformed("face " + std::to_string(face) + ": '" + std::string(t[0]) + "' is not a vertex count", line);
      } else if (t.size() < static_cast<std::size_t>(n) + 1) {
        problems.short_line("face " + std::to_string(face) + ": " + std::to_string(n) + " vertex indices announced, " +
                                std::to_string(t.size() - 1) + " given", line);
      } else {
        for (std::size_t k = 1; k <= static_cast<std::size_t>(n); ++k) {
          long long index = 0;
          if (!parse_integer(t[k], index)) {
            problems.malformed("face " + std::to_string(face) + ": '" + std::string(t[k]) + "' is not a vertex index", line);
            break;
          }
          if (index < 0 || static_cast<std::size_t>(index) >= nv) {
            problems.index_out_of_range(face, index, nv, line);
            break;
          }
        }
        // CGAL reads the rest of a face line as its colour when the header announces colours.
        if (color_tokens_at > 0) check_off_color(problems, "face " + std::to_string(face), t, static_cast<std::size_t>(n) + 1, line, face_color_seen);
      }
    }
    ++items;
  });
  problems.raise_non_finite(path);
  if (items < nv + nf || problems.file_cut()) {
    const std::string read = items <= nv ? count_of(std::min(items, nv), "vertex", "vertices")
                                         : std::to_string(nv) + " vertices and " + count_of(items - nv, "face", "faces");
    fail(path, "truncated OFF file: the header announces " + count_of(nv, "vertex", "vertices") + " and " +
                   count_of(nf, "face", "faces") + ", the file ends after " + read + " (" + quote(last_line(text)) + ")");
  }
  problems.raise(path);
}

/// The integer a stream's >> would read from the start of `token` (sign, digits), saturated at 2^40.
bool leading_integer(std::string_view token, long long& value) {
  std::size_t i = 0;
  const bool negative = !token.empty() && token[0] == '-';
  if (!token.empty() && (token[0] == '+' || token[0] == '-')) ++i;
  if (i >= token.size() || !std::isdigit(static_cast<unsigned char>(token[i]))) return false;
  long long v = 0;
  for (; i < token.size() && std::isdigit(static_cast<unsigned char>(token[i])); ++i)
    v = std::min(v * 10 + (token[i] - '0'), 1LL << 40);
  value = negative ? -v : v;
  return true;
}

/// Hand-written pre-scan of the header counts: CGAL's OFF header scanner computes 2 * edges and
/// int((vertices + faces + 10) * 2.1) in int, undefined for huge counts (found by fuzz_off). So the
/// first tokens of the file are read here first: counts the machine cannot hold are refused by
/// name, and any number there beyond kMaxCount (whatever CGAL takes it for) as malformed.
void check_off_header_counts(const std::string& path, std::string_view text) {
  std::vector<std::string_view> tokens;  // keyword (optional), [dimension,] vertices, faces, edges
  for (std::size_t pos = 0; tokens.size() < 6 && pos < text.size();) {
    const char c = text[pos];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++pos;
    } else if (c == '#') {
      pos = std::min(text.find('\n', pos), text.size());
    } else {
      std::size_t end = std::min(text.find_first_of(" \t\r\n\f\v#", pos), text.size());
      if (tokens.empty()) {
        // CGAL reads the keyword as letters and digits and swallows the one character after it, so
        // "OFF&1999999998" is the keyword OFF and a count (fuzz_off: CGAL then overflowed an int).
        std::size_t k = pos;
        while (k < end && std::isalnum(static_cast<unsigned char>(text[k]))) ++k;
        if (k > pos && k < end) {
          tokens.push_back(text.substr(pos, k - pos));
          end = k + 1;
        } else {
          tokens.push_back(text.substr(pos, end - pos));
        }
      } else {
        tokens.push_back(text.substr(pos, end - pos));
      }
      pos = end;
    }
  }
  // CGAL finds a binary marker in "BINARY" wherever its header scan meets it — glued to the
  // keyword, after bytes it skips, after a second keyword — and then reads binary counts we cannot
  // pre-scan (three variants found by fuzz_off). volts reads ASCII OFF only, so any BINARY in the
  // file is taken for a marker.
  if (text.find("BINARY") != npos)
    fail(path, "binary OFF is not supported, use ASCII OFF or PLY (" + quote(line_at(text, 0)) + ")");
  std::size_t first = 0;
  if (!tokens.empty() && tokens[0].size() >= 3 && tokens[0].substr(tokens[0].size() - 3) == "OFF") {
    first = 1;
    if (tokens[0].find('n') != npos) first = 2;  // nOFF: a dimension comes first
  }
  long long count = 0;
  const char* const what[2] = {"vertices", "faces"};
  const std::size_t bytes[2] = {kBytesPerVertex, kBytesPerFace};
  for (std::size_t k = 0; k < 2 && first + k < tokens.size(); ++k)
    if (leading_integer(tokens[first + k], count) && count > 0)
      core::check_declared_count(path, static_cast<std::size_t>(count), what[k], bytes[k]);
  constexpr long long kMaxCount = 500000000;  // (2 * kMaxCount + 10) * 2.1 and 2 * kMaxCount fit an int
  for (const std::string_view t : tokens)
    if (leading_integer(t, count) && (count > kMaxCount || count < -kMaxCount))
      fail(path, "malformed OFF header: count " + std::to_string(count) + " out of range (at most " +
                     std::to_string(kMaxCount) + ") (" + quote(line_at(text, static_cast<std::size_t>(t.data() - text.data()))) + ")");
}

}  // namespace

RawSoup parse_off(const std::string& path, const std::string& text) {
  check_off_header_counts(path, text);
  std::istringstream in(text);
  const CGAL::File_scanner_OFF header(in, /*verbose=*/false);
  if (in.fail())
    fail(path, "not an OFF file: missing or malformed header (" + quote(line_before(text, stream_pos(in, text.size()))) + ")");
  const std::size_t header_end = stream_pos(in, text.size());
  const Line header_line = line_before(text, header_end);
  if (header.skel()) fail(path, "SKEL file, not an OFF surface (" + quote(header_line) + ")");
  if (header.binary()) fail(path, "binary OFF is not supported, use ASCII OFF or PLY (" + quote(header_line) + ")");

  // CGAL keeps the header's int counts in size_t, where a negative count becomes huge.
  const std::size_t nv = header.size_of_vertices(), nf = header.size_of_facets();
  if (nv > INT_MAX || nf > INT_MAX) fail(path, "malformed OFF header: negative vertex or face count (" + quote(header_line) + ")");
  core::check_declared_count(path, nv, "vertices", kBytesPerVertex);
  core::check_declared_count(path, nf, "faces", kBytesPerFace);
  std::size_t color_tokens_at = 0;
  if (header.has_colors()) {
    const std::size_t h = header.is_homogeneous() ? 1 : 0;
    color_tokens_at = 3 + h + (header.has_normals() ? 3 + h : 0) + (header.has_textures() ? 2 + h : 0);
  }
  check_off_lines(path, text, header_end, nv, nf, color_tokens_at);

  in.clear();
  in.seekg(0);
  RawSoup soup;
  const bool ok = CGAL::IO::read_OFF(in, soup.points, soup.faces, CGAL::parameters::verbose(false));
  const std::size_t stop = stream_pos(in, text.size());
  if (!ok) fail(path, "malformed OFF file: CGAL's reader stopped at " + quote(line_before(text, stop)));
  // CGAL stops after the announced faces; anything but comments after them means wrong counts.
  if (!only_blank_after(text, stop, true))
    fail(path, "malformed OFF file: data after the " + count_of(nf, "face", "faces") + " the header announces (" +
                   quote(line_at(text, text.find_first_not_of(" \t\r\n\f\v", stop))) + ")");
  return soup;
}

// ---- OBJ ------------------------------------------------------------------------------------

RawSoup parse_obj(const std::string& path, const std::string& text_in) {
  // CGAL skips from one face index to the next up to a ' ' only, so "f 1\t2\t3" would lose two
  // indices; tabs are plain whitespace in OBJ (and positions stay the same for messages).
  std::string text = text_in;
  std::replace(text.begin(), text.end(), '\t', ' ');
  std::istringstream in(text);
  RawSoup soup;
  const bool ok = CGAL::IO::read_OBJ(in, soup.points, soup.faces, CGAL::parameters::verbose(false));
  if (ok) return soup;
  const std::size_t stop = stream_pos(in, text.size());

  TextProblems problems(text);
  std::size_t vertices = 0;
  for_each_line(text, 0, [&](const Line& line) {
    const auto t = tokens_of(line.text, true);
    if (!t.empty() && t[0] == "v") problems.vertex(vertices++, std::vector<std::string_view>(t.begin() + 1, t.end()), line);
  });
  problems.raise(path);
  // CGAL also refuses, after reading everything, a file without vertices or faces or with a face
  // index beyond the vertices; the soup checks report those precisely. (Its bound is off by one:
  // index == number of vertices passes, the soup checks catch it.)
  const bool explained = only_blank_after(text, stop, true) &&
                         (soup.faces.empty() || soup.points.empty() ||
                          std::any_of(soup.faces.begin(), soup.faces.end(), [&](const Polygon& f) {
                            return std::any_of(f.begin(), f.end(), [&](std::size_t v) { return v >= soup.points.size(); });
                          }));
  if (!explained) fail(path, "malformed or unsupported OBJ statement (" + quote(line_before(text, stop)) + ")");
  return soup;
}

// ---- STL ------------------------------------------------------------------------------------

namespace {

std::uint32_t little_endian_u32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}

float little_endian_float(const char* p) {
  static_assert(std::numeric_limits<float>::is_iec559 && sizeof(float) == 4, "STL stores IEEE floats");
  const std::uint32_t bits = little_endian_u32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

/// Hand-written: CGAL's binary STL reader neither checks the triangle count against the file size
/// (it accepts trailing garbage, and a short count silently drops triangles) nor lets NaN corners be
/// seen before it merges them in a std::map, where NaN breaks the ordering.
RawSoup parse_binary_stl(const std::string& text, std::size_t triangles) {
  RawSoup soup;
  soup.points_are_corners = true;
  soup.points.reserve(3 * triangles);
  soup.faces.reserve(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const char* corner = text.data() + 84 + 50 * t + 12;  // 12 bytes of normal, then 3 corners
    for (int c = 0; c < 3; ++c, corner += 12)
      soup.points.emplace_back(little_endian_float(corner), little_endian_float(corner + 4), little_endian_float(corner + 8));
    soup.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  return soup;
}

/// Re-scans an ASCII STL file CGAL refused.
[[noreturn]] void diagnose_ascii_stl(const std::string& path, const std::string& text) {
  TextProblems problems(text);
  std::size_t vertices = 0, facet = 0, corners = 0;
  for_each_line(text, 0, [&](const Line& line) {
    const auto t = tokens_of(line.text, false);
    if (t.empty()) return;
    if (t[0] == "facet") {
      corners = 0;
    } else if (t[0] == "vertex") {
      problems.vertex(vertices++, std::vector<std::string_view>(t.begin() + 1, t.end()), line);
      ++corners;
    } else if (t[0] == "endfacet") {
      if (corners != 3)
        problems.malformed("facet " + std::to_string(facet) + ": " + count_of(corners, "vertex", "vertices") + ", STL needs 3", line);
      ++facet;
    }
  });
  problems.raise_non_finite(path);
  const Line last = last_line(text);
  if (tokens_of(last.text, false).empty() || tokens_of(last.text, false)[0] != "endsolid")
    fail(path, "truncated ASCII STL file: it does not end with 'endsolid' (" + quote(last) + ")");
  problems.raise(path);
  fail(path, "malformed ASCII STL file (CGAL's reader refused it)");
}

}  // namespace

RawSoup parse_stl(const std::string& path, const std::string& text) {
  const std::size_t size = text.size();
  // Binary STL: 80-byte header, triangle count, 50 bytes per triangle. Its header may well start
  // with "solid", so the size decides, not the first word.
  const std::size_t triangles = size >= 84 ? little_endian_u32(text.data() + 80) : 0;
  if (size >= 84 && size == 84 + 50 * triangles) {
    core::check_declared_count(path, triangles, "triangles", 3 * kBytesPerVertex + kBytesPerFace);
    return parse_binary_stl(text, triangles);
  }

  const std::size_t first = text.find_first_not_of(" \t\r\n\f\v");
  if (first == npos || text.compare(first, 5, "solid") != 0) {
    if (size < 84)
      fail(path, "not an STL file: no 'solid' keyword (ASCII) and only " + std::to_string(size) +
                     " bytes, less than a binary STL header (84)");
    const std::size_t expected = 84 + 50 * triangles;
    fail(path, std::string(size < expected ? "truncated" : "malformed") + " binary STL file: its header announces " +
                   count_of(triangles, "triangle", "triangles") + ", i.e. " + std::to_string(expected) +
                   " bytes, but the file has " + std::to_string(size) + " bytes");
  }

  std::istringstream in(text);
  RawSoup merged;
  // On failure CGAL retries the text as binary STL and appends whatever that yields: the result
  // of a failed read is never used.
  if (!CGAL::IO::read_STL(in, merged.points, merged.faces, CGAL::parameters::verbose(false)))
    diagnose_ascii_stl(path, text);
  const Line last = last_line(text);
  const auto last_tokens = tokens_of(last.text, false);
  if (last_tokens.empty() || last_tokens[0] != "endsolid")
    fail(path, "truncated ASCII STL file: it does not end with 'endsolid' (" + quote(last) + ")");

  // CGAL merges equal corners while reading; undo that so every format reaches the welding step
  // in the same form (points = corners in file order).
  RawSoup soup;
  soup.points_are_corners = true;
  soup.points.reserve(3 * merged.faces.size());
  for (const Polygon& f : merged.faces) {
    soup.faces.push_back({soup.points.size(), soup.points.size() + 1, soup.points.size() + 2});
    for (const std::size_t v : f) soup.points.push_back(merged.points[v]);
  }
  return soup;
}

// ---- PLY ------------------------------------------------------------------------------------

namespace {

struct PlyProperty {
  std::string type, name;   // for a list: type is the index type
  bool list = false;
  std::string count_type;   // for a list
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  Line line;
  const PlyProperty* property(const std::string& n) const {
    for (const auto& p : properties)
      if (p.name == n) return &p;
    return nullptr;
  }
};
struct PlyHeader {
  bool ascii = true;
  bool big_endian = false;
  std::vector<PlyElement> elements;
  std::size_t data_begin = 0;
};

/// Bytes of a PLY scalar type, 0 for an unknown type.
std::size_t ply_type_size(std::string_view t) {
  for (const char* k : {"char", "int8", "uchar", "uint8"})
    if (t == k) return 1;
  for (const char* k : {"short", "int16", "ushort", "uint16"})
    if (t == k) return 2;
  for (const char* k : {"int", "int32", "uint", "uint32", "float", "float32"})
    if (t == k) return 4;
  return t == "double" || t == "float64" ? 8 : 0;
}
bool is_ply_type(std::string_view t) { return ply_type_size(t) > 0; }

/// Hand-written header check: CGAL's PLY reader dereferences a null pointer when x/y/z are not
/// float or double, silently uses 0 for a missing coordinate and cannot say what is unsupported.
PlyHeader parse_ply_header(const std::string& path, const std::string& text) {
  PlyHeader h;
  std::size_t pos = 0;
  for (std::size_t number = 1;; ++number) {
    if (pos >= text.size()) fail(path, "malformed PLY header: no 'end_header' line");
    std::size_t end = text.find('\n', pos);
    if (end == npos) end = text.size();
    const Line line{number, std::string_view(text).substr(pos, end - pos)};
    pos = end + 1;
    const auto t = tokens_of(line.text, false);
    const auto bad = [&](const std::string& what) { fail(path, what + " (" + quote(line) + ")"); };
    if (number == 1) {
      if (t.size() != 1 || t[0] != "ply") bad("not a PLY file: the first line must be 'ply'");
      continue;
    }
    if (number == 2) {  // CGAL expects the format exactly here
      if (t.size() != 3 || t[0] != "format") bad("malformed PLY header: line 2 must be 'format <encoding> 1.0'");
      if (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") bad("unsupported PLY encoding");
      h.ascii = t[1] == "ascii";
      h.big_endian = t[1] == "binary_big_endian";
      continue;
    }
    if (t.empty()) bad("malformed PLY header: blank line");
    if (t[0] == "end_header") {
      h.data_begin = std::min(pos, text.size());
      break;
    }
    if (t[0] == "element") {
      long long count = 0;
      if (t.size() != 3 || !parse_integer(t[2], count) || count < 0) bad("malformed PLY element");
      h.elements.push_back({std::string(t[1]), static_cast<std::size_t>(count), {}, line});
    } else if (t[0] == "property") {
      if (h.elements.empty()) bad("malformed PLY header: property before any element");
      if (t.size() == 5 && t[1] == "list" && is_ply_type(t[2]) && is_ply_type(t[3]))
        h.elements.back().properties.push_back({std::string(t[3]), std::string(t[4]), true, std::string(t[2])});
      else if (t.size() == 3 && is_ply_type(t[1]))
        h.elements.back().properties.push_back({std::string(t[1]), std::string(t[2]), false, ""});
      else
        bad("malformed or unsupported PLY property");
    }  // comment, obj_info and unknown keywords: ignored, as CGAL does
  }

  const auto find = [&](const char* a, const char* b) -> const PlyElement* {
    for (const auto& e : h.elements)
      if (e.name == a || e.name == b) return &e;
    return nullptr;
  };
  const PlyElement* vertex = find("vertex", "vertices");
  if (!vertex) fail(path, "PLY file without a 'vertex' element");
  for (const char* c : {"x", "y", "z"}) {
    const PlyProperty* p = vertex->property(c);
    if (!p || p->list) fail(path, "PLY vertex element without a '" + std::string(c) + "' coordinate (" + quote(vertex->line) + ")");
    if (p->type != "float" && p->type != "float32" && p->type != "double" && p->type != "float64")
      fail(path, "unsupported PLY: vertex coordinate '" + std::string(c) + "' is of type " + p->type +
                     "; only float and double are read");
  }
  if (const PlyElement* face = find("face", "faces")) {
    const PlyProperty* p = face->property("vertex_indices");
    if (!p) p = face->property("vertex_index");
    if (!p || !p->list || (p->type != "int" && p->type != "int32" && p->type != "uint" && p->type != "uint32"))
      fail(path, "unsupported PLY: the face element needs a 'vertex_indices' list of int or uint (" + quote(face->line) + ")");
  }  // no face element: the soup checks report "no faces"
  return h;
}

/// Hand-written: CGAL sizes a list from its count before reading the entries, so a corrupt 32-bit
/// count could make it allocate gigabytes. Walks the data checking each count against what is
/// left of the file; only needed (and only run) when some list has a 32-bit count. A file that
/// ends early is left to CGAL and diagnose_ply.
void check_ply_list_counts(const std::string& path, const std::string& text, const PlyHeader& h) {
  bool wide = false;
  for (const auto& e : h.elements)
    for (const auto& p : e.properties) wide = wide || (p.list && ply_type_size(p.count_type) > 2);
  if (!wide) return;
  const auto too_long = [&](const PlyElement& e, std::size_t item, unsigned long long count) {
    fail(path, "malformed PLY file: " + e.name + " " + std::to_string(item) + " announces a list of " +
                   std::to_string(count) + " entries, more than the rest of the file holds");
  };
  if (h.ascii) {
    std::vector<std::string_view> tokens;
    for_each_line(text, h.data_begin, [&](const Line& line) {
      const auto t = tokens_of(line.text, false);
      tokens.insert(tokens.end(), t.begin(), t.end());
    });
    std::size_t next = 0;
    for (const auto& e : h.elements)
      for (std::size_t item = 0; item < e.count; ++item)
        for (const auto& p : e.properties) {
          if (next >= tokens.size()) return;
          long long count = 1;
          if (p.list && (!parse_integer(tokens[next], count) || count < 0)) return;  // CGAL reports it
          if (p.list && static_cast<std::size_t>(count) > tokens.size() - next - 1) too_long(e, item, count);
          next += p.list ? 1 + static_cast<std::size_t>(count) : 1;
        }
    return;
  }
  std::size_t pos = h.data_begin;
  for (const auto& e : h.elements)
    for (std::size_t item = 0; item < e.count; ++item)
      for (const auto& p : e.properties) {
        const std::size_t size = ply_type_size(p.list ? p.count_type : p.type);
        if (pos + size > text.size()) return;
        if (!p.list) {
          pos += size;
          continue;
        }
        unsigned long long count = 0;
        for (std::size_t b = 0; b < size; ++b) {  // assemble the count in the file's byte order
          const auto byte = static_cast<unsigned char>(text[pos + (h.big_endian ? b : size - 1 - b)]);
          count = count << 8 | byte;
        }
        const bool is_signed = p.count_type[0] != 'u';
        if (is_signed && count >> (8 * size - 1)) too_long(e, item, count);  // negative
        const std::size_t entry = ply_type_size(p.type);
        pos += size;
        if (count > (text.size() - pos) / entry) too_long(e, item, count);
        pos += count * entry;
      }
}

/// Re-scans a PLY file CGAL refused.
[[noreturn]] void diagnose_ply(const std::string& path, const std::string& text, const PlyHeader& h, std::size_t stop) {
  std::size_t items = 0;
  for (const auto& e : h.elements) items += e.count;
  const std::string announced = "the header announces " + count_of(items, "element item", "element items");
  if (!h.ascii) {
    if (stop >= text.size()) fail(path, "truncated binary PLY file: it ends before the " + std::to_string(items) + " element items the header announces");
    fail(path, "malformed binary PLY file: CGAL's reader stopped at byte " + std::to_string(stop));
  }
  // ASCII PLY stores one item per line. Coordinates can be located when vertices come first.
  TextProblems problems(text);
  const PlyElement& first = h.elements.front();
  std::vector<std::size_t> coordinate_column;
  const bool vertices_first = (first.name == "vertex" || first.name == "vertices") &&
                              std::none_of(first.properties.begin(), first.properties.end(), [](const PlyProperty& p) { return p.list; });
  if (vertices_first)
    for (const char* c : {"x", "y", "z"})
      coordinate_column.push_back(static_cast<std::size_t>(first.property(c) - first.properties.data()));
  std::size_t lines = 0;
  for_each_line(text, h.data_begin, [&](const Line& line) {
    const auto t = tokens_of(line.text, false);
    if (t.empty()) return;
    if (vertices_first && lines < first.count) {
      std::vector<std::string_view> coords;
      for (const std::size_t c : coordinate_column)
        if (c < t.size()) coords.push_back(t[c]);
      problems.vertex(lines, coords, line);
    }
    ++lines;
  });
  problems.raise_non_finite(path);
  if (lines < items || only_blank_after(text, stop, false))
    fail(path, "truncated ASCII PLY file: " + announced + " (one per line), the data ends at " + quote(last_line(text)));
  problems.raise(path);
  fail(path, "malformed ASCII PLY file: CGAL's reader stopped at " + quote(line_at(text, stop)));
}

}  // namespace

RawSoup parse_ply(const std::string& path, const std::string& text) {
  const PlyHeader header = parse_ply_header(path, text);
  for (const auto& e : header.elements)
    core::check_declared_count(path, e.count, e.name + " elements", e.name == "face" ? kBytesPerFace : kBytesPerVertex);
  check_ply_list_counts(path, text, header);
  std::istringstream in(text);
  RawSoup soup;
  const bool ok = CGAL::IO::read_PLY(in, soup.points, soup.faces, CGAL::parameters::verbose(false));
  const std::size_t stop = stream_pos(in, text.size());
  if (!ok) diagnose_ply(path, text, header, stop);
  if (header.ascii ? !only_blank_after(text, stop, false) : stop != text.size())
    fail(path, "malformed PLY file: " + std::to_string(text.size() - stop) +
                   " bytes after the elements the header announces (wrong counts or property types?)");
  return soup;
}

}  // namespace volts::surface::detail
