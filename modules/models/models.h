// volts::models — generated test solids: closed, outward-oriented, manifold triangle meshes of
// known volume, genus and sharp features, at any resolution (for tests, demos and benchmarks).
//
// Dimensions (lengths in model units, centred at the origin but for the flanged ring):
//   box            [-1,1] x [-0.75,0.75] x [-0.5,0.5]; each face a regular grid of squares split in two.
//   bulged-box     the box, each face pushed out by  a * sin(pi s) * sin(pi t)  (s, t in [0,1] across the
//                  face, a = bulge * half the face's shorter side), so the 12 edges stay straight and sharp.
//   torus          axis z, major radius 2, minor radius 0.75.
//   cube-with-hole [-1,1]^3 minus a through hole along z of radius 0.7 (Liu et al. 2013, Fig. 3): a
//                  Boolean difference (CGAL corefinement), remeshed. The hole is the prism inscribed in
//                  the cylinder, with a multiple of 8 sides (at least 16) of about the segment length.
//   sphere         radius 1 (a cube grid projected onto the sphere).
//   tetrahedron    regular, corners (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1); each face a triangle grid.
//   cone           axis z, base radius 1 at z = -0.5, apex at z = 1.
//   plate          the assembly's base alone: plate [-2,2] x [-1.5,1.5] x [-0.25,0.25] minus four through
//                  holes along z of radius 0.3 centred at (+-1.5, +-1). Genus 4. Holes as the assembly's
//                  (their vertical edges are sharp below resolution 16: 45 degrees at 8).
//   assembly       Liu et al. 2013, Fig. 1: plate [-2,2] x [-1.5,1.5] x [-0.25,0.25] minus four through holes
//                  along z of radius 0.3 centred at (+-1.5, +-1), union a ring: the torus about the y axis
//                  through (0, 0, 0.95), major radius 0.8, minor 0.3 (x in [-1.1,1.1], top at z = 2.05; its
//                  tube's centre circle dips 0.1 into the plate, the ring's hole stays 0.2 above it). Genus 5.
//                  Boolean operations (CGAL corefinement) then remeshing, as cube-with-hole; the holes are
//                  prisms inscribed in the cylinders, with a multiple of 4 sides of about the segment length.
//                  Smallest triangle angle 20-25 degrees up to resolution 32; finer, slivers appear where the
//                  ring meets the plate (17 degrees at 48, 7 at 64: the remesher keeps short edges there).
//   washer         ring about z whose cross section in the (r, z) half-plane is a plus sign (a flanged washer):
//                  flange r in [0.7,1.3], |z| <= 0.1, union hub r in [0.9,1.1], |z| <= 0.3; 12 sides, 8 convex
//                  and 4 concave corners. Area 0.2, centroid at r = 1: volume 0.4 pi. Genus 1.
//   flanged-ring   ring about z with an L-shaped cross section: tube wall r in [1,1.2], z in [0,0.6], union
//                  flange r in [1,1.6], z in [0,0.2]; 6 sides, 5 convex and 1 concave corner. Volume
//                  2 pi (0.12 x 1.1 + 0.08 x 1.4) = 0.488 pi. Genus 1.
//                  Both: the profile revolved in n sectors (ModelParams::resolution), each side split into
//                  equal segments of about the inner rim's segment length (at least one); every face is a planar
//                  quad (the sides are vertical or horizontal) split in two, so the volume is exactly the
//                  solid's times sin(2 pi / n) / (2 pi / n).
// Curved surfaces are interpolated: vertices lie on the exact surface (the hole: on its prism; the
// assembly's ring: on a torus polyhedron interpolating it, as remeshing projects onto it), so
// volumes converge as O(1/resolution^2). Sharp edges (dihedral angle deviating from flat by more than
// 30 degrees at resolution >= 16): the box-like models' edges, the hole's two rims, the cone's rim and
// apex region, the assembly's plate edges, eight rims and the ring's foot (the closed curve where it
// meets the top face, 55 to 130 degrees); washer and flanged-ring: one ring of n edges (90 degrees) per
// profile corner, 12 and 6 rings (every other edge turns 360 / n <= 22.5 degrees at most); torus and sphere
// have none.
#pragma once

#include <string>
#include <vector>

#include "surface/surface.h"

namespace volts::models {

/// Parameters of make_model.
struct ModelParams {
  std::string name = "bulged-box";  ///< one of model_names()
  /// Segments along the longest edge (box, bulged-box, cube-with-hole, tetrahedron) or around the
  /// smallest circle (torus, cone; sphere: rounded to a multiple of 4); in [4, 512]. The box's shorter
  /// edges get 0.75 and 0.5 times as many, so all segments are equal when it is a multiple of 4.
  /// plate, assembly: segment length 2 / resolution, as cube-with-hole's (the plate's long edge gets 2 x
  /// resolution segments, each hole about 0.94 x resolution sides, as many around the ring's tube).
  /// washer, flanged-ring: n segments around the axis (its smallest circle is the inner rim), n the multiple
  /// of 4 at least resolution and 16, and enough that the outer rim's segment is at most 2.7 times the
  /// shortest profile side (0.2), so no triangle angle is below 20 degrees: washer n >= 16, flanged-ring
  /// n >= 20.
  int resolution = 16;
  /// bulged-box only: outward bulge of each face centre relative to half the face's shorter side; in [0, 0.35].
  double bulge = 0.15;
};

/// Names of all models, in a fixed order: box, bulged-box, torus, cube-with-hole, sphere, tetrahedron, cone,
/// plate, assembly, washer, flanged-ring.
std::vector<std::string> model_names();

/// One line describing the model (for --help). Throws core::ConfigError for an unknown name.
std::string model_description(const std::string& name);

/// Builds the model. The same parameters always give the same mesh, vertex for vertex.
/// Throws core::ConfigError for an unknown name ("unknown model 'x'; known: box, bulged-box, ...") or a
/// resolution or bulge out of range; core::NumericalError if a Boolean operation of cube-with-hole, plate
/// or assembly fails.
surface::Mesh make_model(const ModelParams& params);

}  // namespace volts::models
