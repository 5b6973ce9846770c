// volts::split — level sets of a piecewise-linear field inserted into the surface mesh, so that
// cross sections (Liu et al. 2013, §4.1 step 3: "the level-set curves through the saddles are the
// cross sections") become chains of mesh edges that later cuts and patches can follow exactly.
#pragma once

#include <array>
#include <vector>

#include "surface/surface.h"

namespace volts::split {

/// A per-vertex field that insert_isoline() extends to the vertices it creates (linear
/// interpolation along the split edge). With period > 0 the field is circle-valued: its difference
/// along an edge is taken modulo the period, in (-period/2, period/2].
struct CarriedField {
  std::vector<double>* values = nullptr;
  double period = 0;
};

/// Options of insert_isoline().
struct IsolineOptions {
  double snap = 1e-6;    ///< vertices closer than snap × (field range) to the level are put on it [relative]
  double period = 0;     ///< > 0: the field is circle-valued with this period (see CarriedField)
  std::vector<CarriedField> carried;       ///< other fields to extend to new vertices
  std::vector<char>* face_mask = nullptr;  ///< if set: only faces with mask 1 are cut; updated for the new faces
  std::vector<std::array<int, 3>>* splits = nullptr;  ///< if set: receives (a, b, new vertex) per split edge
};

/// Difference b − a of a circle-valued quantity with the given period, in (−period/2, period/2];
/// the plain difference if period is 0.
double circle_difference(double a, double b, double period);

/// Inserts the level set {field = value} into `mesh`: every edge it crosses is split at the
/// crossing (the new vertex gets the linearly interpolated position and field value), every crossed
/// triangle is split along it. Vertices lying closer than `snap` (relative to the field's range) to
/// the level are moved onto it instead of creating slivers. Returns the level set as closed loops
/// of vertex ids (each loop once, not repeating its first vertex), in a deterministic order.
/// `field` is extended to the new vertices. Throws core::InvalidInputError if the field size does
/// not match the mesh, core::TopologyError if the level set is not a set of disjoint simple loops
/// (e.g. it passes through a saddle: choose a value away from critical values).
std::vector<std::vector<int>> insert_isoline(surface::Mesh& mesh, std::vector<double>& field, double value,
                                             double snap = 1e-6);
/// The same with options: a circle-valued field, fields carried along, a face mask (the level is
/// inserted only inside the masked faces; loops then may be open chains ending on the mask's
/// border, returned as chains), a record of the split edges.
std::vector<std::vector<int>> insert_isoline(surface::Mesh& mesh, std::vector<double>& field, double value,
                                             const IsolineOptions& options);

/// Connected components of faces when the given vertex loops are cuts: faces on different sides of
/// a loop edge get different labels. Returns one label per face (0, 1, ...) in order of first face.
std::vector<int> regions_cut_by(const surface::Mesh& mesh, const std::vector<std::vector<int>>& loops);

}  // namespace volts::split
