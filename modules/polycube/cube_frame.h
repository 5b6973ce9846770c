// volts::polycube — the frame of a cube component: which corner of the unit cube each of its eight
// corners is, from the graph of its edges (Liu et al. 2013, §4.2: every cube of the polycube is an
// axis-aligned box). Internal to the polycube module.
#pragma once

#include <set>
#include <vector>

namespace volts::polycube::detail {

/// Cube corner codes (bit a = coordinate a) of 8 corners from their edge graph (adjacency[i] = the
/// corners joined to corner i by a cube edge): corner 0 is the origin, its three neighbours the
/// unit vectors, every other corner the OR of its assigned neighbours. Throws core::TopologyError
/// "polycube: the corners and curves do not form the graph of a cube" for any other graph.
std::vector<int> cube_codes(const std::vector<std::set<int>>& adjacency);

}  // namespace volts::polycube::detail
