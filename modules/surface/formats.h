// volts::surface internals (not API) — one parser per file format, each returning the polygon
// soup exactly as the file stores it (no welding, no validation) or throwing InvalidInputError for
// a file it cannot read, with the line or byte where reading stopped.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "surface/soup_checks.h"

namespace volts::surface::detail {

struct RawSoup {
  std::vector<Point> points;
  std::vector<Polygon> faces;
  /// STL: points[k] is corner k % 3 of triangle k / 3 (duplicates not yet merged).
  bool points_are_corners = false;
};

/// `text` is the whole file; `path` is only used in messages.
RawSoup parse_off(const std::string& path, const std::string& text);
RawSoup parse_obj(const std::string& path, const std::string& text);
RawSoup parse_stl(const std::string& path, const std::string& text);
RawSoup parse_ply(const std::string& path, const std::string& text);

}  // namespace volts::surface::detail
