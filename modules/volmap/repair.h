// volts::volmap — connectivity repair of a volume map (Liu et al. 2013 §4.3: the map must have no
// flipped tet). Untangling moves points; where the connectivity admits no positive map with the
// surface fixed, these change it. harmonic_volume_map() calls them; they are public for tests and
// for maps built elsewhere.
#pragma once

#include "volmap/volmap.h"

namespace volts::volmap {

/// Removes tets that are flat or inverted in parameter space by collapsing one of their edges (the
/// shortest in parameter space first) that has a free end: the edge's tets go, its free end merges
/// into the other (a surface end keeps its id and positions), at whichever of the two ends'
/// positions and their midpoint is best, in each space independently. Done only if the link
/// condition holds and every changed tet is positive in physical space (6 x volume above 1e-9 x the
/// mean) and in parameter space (a changed tet that was already flat or inverted may stay so but
/// not get worse; each collapse removes at least one bad tet). The dropped point's slot takes the
/// last point. Collapsing onto a surface vertex can bring back an interior edge between two surface
/// vertices (a chord); its tets are positive, checked. Returns the number of edges collapsed.
int collapse_flat_tet_edges(VolumeMap& map);

/// Where no collapse helps, changes the connectivity around tets that are flat or inverted in
/// parameter space by flips: 3-2 (an interior edge of such a tet with exactly three tets becomes the
/// triangle of its link) and 2-3 (a face shared with one other tet becomes three tets around the
/// edge between their opposite vertices). A flip is made only if its new tets are positive in
/// physical space (6 x volume above 1e-9 x the mean) and fewer of them are flat or inverted in
/// parameter space than of the tets they replace. Points do not change. Returns the number of flips.
int flip_flat_tets(VolumeMap& map);

}  // namespace volts::volmap
