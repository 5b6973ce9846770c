// volts::surface internals (not API) — the polygon-soup checks behind validate_soup, split in two
// so that read_surface can run the index checks before welding (welding needs valid indices) and
// name vertices by their index in the file rather than in the welded soup.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "surface/surface.h"

namespace volts::surface::detail {

using Polygon = std::vector<std::size_t>;

/// Counts the offenders of one check and keeps a description of the first for the message.
class Tally {
 public:
  template <class Describe>
  void add(Describe&& describe) {
    if (count_++ == 0) first_ = describe();
  }
  std::size_t count() const { return count_; }
  const std::string& first() const { return first_; }

 private:
  std::size_t count_ = 0;
  std::string first_;
};

/// "1 face" / "2 faces".
std::string count_of(std::size_t n, const std::string& one, const std::string& many);

/// Describes vertex i for a message, e.g. "vertex 17 (1.5, 2, 3)".
using VertexNamer = std::function<std::string(std::size_t)>;

/// "(x, y, z)" with the shortest representation that reads back as the same doubles.
std::string format_point(const Point& p);

/// "vertex i (x, y, z)" for points[i].
std::string name_vertex(const std::vector<Point>& points, std::size_t i);

/// No faces, non-finite coordinates, faces with fewer than 3 vertices, indices out of range.
/// Throws core::InvalidInputError.
void check_soup_indices(const std::vector<Point>& points, const std::vector<Polygon>& faces,
                        const std::string& source, const VertexNamer& name);

/// The remaining validate_soup checks (repeated vertices, zero area, edges, vertex fans,
/// components). Requires check_soup_indices to have passed. Throws core::InvalidInputError.
void check_soup_surface(const std::vector<Point>& points, const std::vector<Polygon>& faces,
                        const std::string& source, const VertexNamer& name);

}  // namespace volts::surface::detail
