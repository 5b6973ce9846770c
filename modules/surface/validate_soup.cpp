#include <CGAL/Union_find.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <tuple>

#include "core/errors.h"
#include "surface/soup_checks.h"
#include "surface/surface.h"

namespace volts::surface {
namespace detail {
namespace {

[[noreturn]] void fail(const std::string& source, const std::string& problem) {
  throw core::InvalidInputError(source + ": " + problem);
}

/// One side of a polygon edge, seen from the undirected edge {lo, hi}.
struct EdgeUse {
  std::size_t lo, hi;         // vertex indices, lo < hi
  std::size_t face;
  std::size_t from, to;       // global corner ids (offset of the face + position) of the edge's ends
  bool forward;               // traversed lo -> hi
};

std::string edge_name(std::size_t a, std::size_t b, const VertexNamer& name) {
  return name(a) + " and " + name(b);
}

}  // namespace

std::string count_of(std::size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string format_point(const Point& p) {
  std::string s = "(";
  for (int i = 0; i < 3; ++i) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, p[i]);  // shortest round-trip form
    s.append(buf, r.ptr);
    s += i < 2 ? ", " : ")";
  }
  return s;
}

std::string name_vertex(const std::vector<Point>& points, std::size_t i) {
  return "vertex " + std::to_string(i) + " " + format_point(points[i]);
}

void check_soup_indices(const std::vector<Point>& points, const std::vector<Polygon>& faces,
                        const std::string& source, const VertexNamer& name) {
  if (faces.empty()) fail(source, "no faces (volts needs a closed triangle surface)");

  Tally non_finite;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      non_finite.add([&] { return name(i); });
  }
  if (non_finite.count() > 0)
    fail(source, count_of(non_finite.count(), "vertex", "vertices") +
                     " with non-finite coordinates (NaN/Inf), first at " + non_finite.first());

  Tally small;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (faces[f].size() < 3)
      small.add([&] { return "face " + std::to_string(f) + " (" + count_of(faces[f].size(), "vertex", "vertices") + ")"; });
  if (small.count() > 0)
    fail(source, count_of(small.count(), "face", "faces") + " with fewer than 3 vertices, first is " +
                     small.first());

  Tally out_of_range;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto bad = std::find_if(faces[f].begin(), faces[f].end(), [&](std::size_t v) { return v >= points.size(); });
    if (bad != faces[f].end())
      out_of_range.add([&] {
        // Indices read from signed fields (OBJ, PLY int32) arrive here as huge unsigned values.
        const auto index = static_cast<long long>(*bad);
        return "face " + std::to_string(f) + " (vertex index " + std::to_string(index) + ", but there are " +
               count_of(points.size(), "vertex", "vertices") + ")";
      });
  }
  if (out_of_range.count() > 0)
    fail(source, count_of(out_of_range.count(), "face", "faces") + " with a vertex index out of range, first is " +
                     out_of_range.first());
}

void check_soup_surface(const std::vector<Point>& points, const std::vector<Polygon>& faces,
                        const std::string& source, const VertexNamer& name) {
  Tally repeated;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    Polygon sorted = faces[f];
    std::sort(sorted.begin(), sorted.end());
    const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end())
      repeated.add([&] { return "face " + std::to_string(f) + " (" + name(*twice) + " twice)"; });
  }
  if (repeated.count() > 0)
    fail(source, count_of(repeated.count(), "face uses", "faces use") + " a vertex twice, first is " + repeated.first());

  // Zero area: every three consecutive corners collinear (exact predicate), i.e. all on one line.
  Tally flat;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Polygon& poly = faces[f];
    const std::size_t n = poly.size();
    bool all_collinear = true;
    for (std::size_t i = 0; i < n && all_collinear; ++i)
      all_collinear = CGAL::collinear(points[poly[i]], points[poly[(i + 1) % n]], points[poly[(i + 2) % n]]);
    if (all_collinear) flat.add([&] { return "face " + std::to_string(f); });
  }
  if (flat.count() > 0)
    fail(source, count_of(flat.count(), "zero-area face", "zero-area faces") + ", first is " + flat.first());

  // Edges, grouped by their undirected vertex pair. Sorting keeps "first" deterministic.
  std::vector<std::size_t> corner_offset(faces.size() + 1, 0);
  for (std::size_t f = 0; f < faces.size(); ++f) corner_offset[f + 1] = corner_offset[f] + faces[f].size();
  std::vector<EdgeUse> uses;
  uses.reserve(corner_offset.back());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Polygon& poly = faces[f];
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const std::size_t j = (i + 1) % poly.size();
      const std::size_t a = poly[i], b = poly[j];
      uses.push_back({std::min(a, b), std::max(a, b), f, corner_offset[f] + i, corner_offset[f] + j, a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& u, const EdgeUse& v) {
    return std::tie(u.lo, u.hi, u.face) < std::tie(v.lo, v.hi, v.face);
  });
  std::vector<std::pair<std::size_t, std::size_t>> groups;  // [begin, end) in uses
  for (std::size_t b = 0; b < uses.size();) {
    std::size_t e = b + 1;
    while (e < uses.size() && uses[e].lo == uses[b].lo && uses[e].hi == uses[b].hi) ++e;
    groups.emplace_back(b, e);
    b = e;
  }

  Tally non_manifold, boundary, misoriented;
  for (const auto& group : groups) {
    // Plain variables, not a structured binding: C++17 lambdas cannot capture those (clang refuses).
    const std::size_t b = group.first, e = group.second;
    const EdgeUse& u = uses[b];
    if (e - b > 2)
      non_manifold.add([&] { return "the edge between " + edge_name(u.lo, u.hi, name) + " (" + std::to_string(e - b) + " faces)"; });
    else if (e - b == 1)
      boundary.add([&] {
        const std::size_t from = u.forward ? u.lo : u.hi, to = u.forward ? u.hi : u.lo;
        return name(from) + ", edge to " + name(to) + " of face " + std::to_string(u.face);
      });
    else if (uses[b].forward == uses[b + 1].forward)
      misoriented.add([&] {
        return "between " + edge_name(u.lo, u.hi, name) + " (faces " + std::to_string(u.face) + " and " +
               std::to_string(uses[b + 1].face) + ")";
      });
  }
  if (non_manifold.count() > 0)
    fail(source, count_of(non_manifold.count(), "non-manifold edge", "non-manifold edges") +
                     " (used by more than 2 faces), first is " + non_manifold.first());
  if (boundary.count() > 0)
    fail(source, "open surface: " + count_of(boundary.count(), "boundary edge", "boundary edges") + ", first at " +
                     boundary.first());
  if (misoriented.count() > 0)
    fail(source, "inconsistent orientation: " + count_of(misoriented.count(), "edge", "edges") +
                     " traversed twice in the same direction, first " + misoriented.first());

  // Every edge now has exactly two oppositely oriented uses. Corners of one vertex that are linked
  // through shared edges form a fan; more than one fan around a vertex is a pinch. CGAL's
  // is_polygon_soup_a_polygon_mesh() detects this too but cannot say where, hence the hand-written pass.
  CGAL::Union_find<std::size_t> corner_sets;
  std::vector<CGAL::Union_find<std::size_t>::handle> corner(corner_offset.back());
  for (std::size_t c = 0; c < corner.size(); ++c) corner[c] = corner_sets.make_set(c);
  CGAL::Union_find<std::size_t> face_sets;
  std::vector<CGAL::Union_find<std::size_t>::handle> face(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) face[f] = face_sets.make_set(f);
  for (const auto& group : groups) {
    const std::size_t b = group.first;
    const EdgeUse& u = uses[b];
    const EdgeUse& v = uses[b + 1];
    corner_sets.unify_sets(corner[u.from], corner[v.to]);  // opposite directions: u.from and v.to are one vertex
    corner_sets.unify_sets(corner[u.to], corner[v.from]);
    face_sets.unify_sets(face[u.face], face[v.face]);
  }
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> fan_of_vertex(points.size(), none);
  std::vector<bool> pinched(points.size(), false);
  Tally non_manifold_vertex;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t i = 0; i < faces[f].size(); ++i) {
      const std::size_t v = faces[f][i];
      const std::size_t fan = *corner_sets.find(corner[corner_offset[f] + i]);
      if (fan_of_vertex[v] == none)
        fan_of_vertex[v] = fan;
      else if (fan_of_vertex[v] != fan)
        pinched[v] = true;
    }
  for (std::size_t v = 0; v < points.size(); ++v)
    if (pinched[v]) non_manifold_vertex.add([&] { return name(v); });
  if (non_manifold_vertex.count() > 0)
    fail(source, count_of(non_manifold_vertex.count(), "non-manifold vertex", "non-manifold vertices") +
                     (non_manifold_vertex.count() == 1 ? " (the faces around it" : " (the faces around each") +
                     " form more than one fan), first is " + non_manifold_vertex.first());

  if (face_sets.number_of_sets() > 1) {
    std::vector<std::pair<std::size_t, std::size_t>> components;  // (first face, face count), by first face
    std::map<std::size_t, std::size_t> seen;                        // root -> first face
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (seen.emplace(*face_sets.find(face[f]), f).second) components.emplace_back(f, face_sets.size(face[f]));
    std::string sizes;
    for (std::size_t k = 0; k < components.size() && k < 5; ++k)
      sizes += (k ? ", " : "") + std::to_string(components[k].second) + " faces from face " +
               std::to_string(components[k].first);
    if (components.size() > 5) sizes += ", ...";
    fail(source, std::to_string(face_sets.number_of_sets()) +
                     " connected components; volts needs one closed solid (" + sizes + ")");
  }
}

}  // namespace detail

void validate_soup(const std::vector<Point>& points, const std::vector<std::vector<std::size_t>>& faces,
                   const std::string& source) {
  const detail::VertexNamer name = [&](std::size_t i) { return detail::name_vertex(points, i); };
  detail::check_soup_indices(points, faces, source, name);
  detail::check_soup_surface(points, faces, source, name);
}

}  // namespace volts::surface
