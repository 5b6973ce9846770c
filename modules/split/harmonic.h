// volts::split — harmonic fields on a triangle surface and their critical points (Liu et al. 2013,
// §4.1, steps 1–4: "a harmonic field with proper boundary conditions ... critical points ... cross
// sections").
//
// The field solves the cotangent Laplace equation with Dirichlet values on chosen vertices. The
// sparse Cholesky factorization depends only on which vertices are constrained, so one
// HarmonicSolver serves any number of fields with the same constrained set.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "surface/surface.h"

namespace volts::split {

/// A Dirichlet value on one vertex.
struct Constraint {
  int vertex = -1;
  double value = 0;
};

/// Cotangent-Laplacian solver for a fixed set of constrained vertices.
class HarmonicSolver {
 public:
  /// Factorizes the Laplacian restricted to the free vertices. Throws core::InvalidInputError for
  /// no constrained vertex or an index out of range, core::NumericalError if the factorization fails.
  HarmonicSolver(const surface::Mesh& mesh, const std::vector<int>& constrained_vertices);
  ~HarmonicSolver();
  HarmonicSolver(HarmonicSolver&&) noexcept;
  /// The field with values[i] on constrained_vertices[i] (same order as the constructor).
  std::vector<double> solve(const std::vector<double>& values) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One harmonic field (factorize + solve). Throws as HarmonicSolver; InvalidInputError if a vertex
/// is constrained twice.
std::vector<double> harmonic_field(const surface::Mesh& mesh, const std::vector<Constraint>& constraints);

/// Circle-valued harmonic function with period 1 around a closed loop `cut` of mesh vertices
/// (consecutive ones joined by edges; not repeating the first): minimizes the cotangent Dirichlet
/// energy on the surface cut open along the loop, where values jump by 1 across it. On a torus cut
/// along a meridian its level sets are meridians; along a longitude, longitudes (Liu et al. §4.1,
/// step 5: the lines that close around the ring; gradient lines of a ring field do not close when
/// the torus is twisted). Values are returned modulo 1, in [0, 1); the difference along an edge is
/// circle_difference(a, b, 1). Throws core::InvalidInputError for a loop that is not an edge loop
/// of simple vertices, core::NumericalError if the solve fails (e.g. the loop separates the surface).
/// With constraints (vertices off the cut, values lifted consistently on the surface cut open
/// along the loop), those are Dirichlet values instead of one pinned vertex; a constrained vertex
/// returns exactly its value modulo 1, so a level set can pass through it.
std::vector<double> periodic_harmonic_field(const surface::Mesh& mesh, const std::vector<int>& cut,
                                            const std::vector<Constraint>& constraints = {});

/// Critical points of a piecewise-linear field, from the sign pattern of f(u) - f(v) around each
/// vertex's link (ties broken by vertex index, i.e. symbolic perturbation, so every vertex is
/// classified). A saddle with 2k sign changes has multiplicity k - 1 (a monkey saddle counts 2).
struct CriticalPoints {
  std::vector<int> minima;
  std::vector<int> maxima;
  std::vector<std::pair<int, int>> saddles;  ///< (vertex, multiplicity)
  int saddle_count() const;                  ///< with multiplicity
  /// Euler characteristic by Morse counts: #max - #saddle + #min (= 2 - 2g on a closed surface).
  int euler_characteristic() const { return static_cast<int>(maxima.size()) - saddle_count() + static_cast<int>(minima.size()); }
};
CriticalPoints critical_points(const surface::Mesh& mesh, const std::vector<double>& field);

}  // namespace volts::split
