// volts::models — generated test solids: closed, outward-oriented, manifold triangle meshes of
// known volume, genus and sharp features, at any resolution (for tests, demos and benchmarks).
//
// Dimensions (lengths in model units, all centred at the origin):
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
// Curved surfaces are interpolated: vertices lie on the exact surface (the hole: on its prism), so
// volumes converge as O(1/resolution^2). Sharp edges (dihedral angle deviating from flat by more than
// 30 degrees at resolution >= 16): the box-like models' edges, the hole's two rims, the cone's rim and
// apex region; torus and sphere have none.
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
  int resolution = 16;
  /// bulged-box only: outward bulge of each face centre relative to half the face's shorter side; in [0, 0.35].
  double bulge = 0.15;
};

/// Names of all models, in a fixed order: box, bulged-box, torus, cube-with-hole, sphere, tetrahedron, cone.
std::vector<std::string> model_names();

/// One line describing the model (for --help). Throws core::ConfigError for an unknown name.
std::string model_description(const std::string& name);

/// Builds the model. The same parameters always give the same mesh, vertex for vertex.
/// Throws core::ConfigError for an unknown name ("unknown model 'x'; known: box, bulged-box, ...") or a
/// resolution or bulge out of range; core::NumericalError if the Boolean operation of cube-with-hole fails.
surface::Mesh make_model(const ModelParams& params);

}  // namespace volts::models
