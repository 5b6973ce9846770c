// Connectivity repair of a volume map (Liu et al. 2013 §4.3 asks for a map without flipped tets;
// untangling by moving points cannot reach one when the connectivity forbids it): edge collapses
// and 2-3/3-2 flips around tets that stay flat or inverted in parameter space. Written by hand:
// CGAL's tetrahedral remeshing collapses and flips for one embedding; these must keep two (physical
// and parameter) valid at once.
#include "volmap/repair.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace volts::volmap {
namespace {

using Vec = Eigen::Vector3d;
using Tet = std::array<int, 4>;

double volume6(const std::vector<Vec>& p, const Tet& t) { return tetmesh::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]); }

// Point -> the tets holding it (rebuilt after every change: the scans restart).
std::vector<std::vector<int>> tets_of_points(const VolumeMap& vm) {
  std::vector<std::vector<int>> of(vm.physical.size());
  for (int t = 0; t < static_cast<int>(vm.tets.size()); ++t)
    for (int v : vm.tets[t]) of[v].push_back(t);
  return of;
}

}  // namespace

// Why (measured on the washer): an interior edge's link alternated between interior vertices and
// vertices of one planar polycube face, so the edge would have to cross that face for its link to
// wind around it; with the surface fixed the LPs end with one end on the other (6 x volume exactly
// 0, not negative), and no joint move helps. Such configurations need a change of connectivity;
// an edge collapse is the smallest one, and the link condition keeps the mesh a manifold
// tetrahedralization.
int collapse_flat_tet_edges(VolumeMap& vm) {
  const int n = vm.surface_vertices;
  if (vm.tets.empty()) return 0;
  double mean6_phys = 0, mean6_param = 0;
  for (const Tet& t : vm.tets) mean6_phys += volume6(vm.physical, t), mean6_param += volume6(vm.parameter, t);
  mean6_phys /= static_cast<double>(vm.tets.size());
  mean6_param /= static_cast<double>(vm.tets.size());
  int collapsed = 0;
  for (bool again = true; again;) {
    again = false;
    const std::vector<std::vector<int>> of = tets_of_points(vm);
    for (std::size_t b = 0; b < vm.tets.size() && !again; ++b) {
      const Tet bad = vm.tets[b];  // a copy: a collapse replaces vm.tets
      if (volume6(vm.parameter, bad) > 0) continue;
      // Its edges, shortest in parameter space first.
      std::vector<std::pair<double, std::pair<int, int>>> edges;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
          edges.push_back({(vm.parameter[bad[i]] - vm.parameter[bad[j]]).norm(), {bad[i], bad[j]}});
      std::sort(edges.begin(), edges.end());
      for (const auto& [length, e] : edges) {
        // keep: the surface end, else the lower id (so the last point, moved into drop's slot, is never keep)
        const int keep = std::min(e.first, e.second), drop = std::max(e.first, e.second);
        if (drop < n) continue;  // two surface ends: their positions are fixed
        // Link condition: vertices and edges linked to both ends are exactly the edge's link.
        std::set<int> star, lk_v[2];
        std::set<std::pair<int, int>> lk_e[2];
        const int ends[2] = {keep, drop};
        for (int k = 0; k < 2; ++k)
          for (int t : of[ends[k]]) {
            std::vector<int> opp;
            for (int v : vm.tets[t])
              if (v != ends[k]) opp.push_back(v);
            if (std::find(vm.tets[t].begin(), vm.tets[t].end(), ends[1 - k]) != vm.tets[t].end()) star.insert(t);
            for (int a = 0; a < 3; ++a) {
              lk_v[k].insert(opp[a]);
              lk_e[k].insert({std::min(opp[a], opp[(a + 1) % 3]), std::max(opp[a], opp[(a + 1) % 3])});
            }
          }
        std::set<int> edge_v, common_v;
        std::set<std::pair<int, int>> edge_e, common_e;
        for (int t : star) {
          std::vector<int> opp;
          for (int v : vm.tets[t])
            if (v != keep && v != drop) opp.push_back(v);
          edge_v.insert(opp.begin(), opp.end());
          edge_e.insert({std::min(opp[0], opp[1]), std::max(opp[0], opp[1])});
        }
        std::set_intersection(lk_v[0].begin(), lk_v[0].end(), lk_v[1].begin(), lk_v[1].end(), std::inserter(common_v, common_v.end()));
        std::set_intersection(lk_e[0].begin(), lk_e[0].end(), lk_e[1].begin(), lk_e[1].end(), std::inserter(common_e, common_e.end()));
        common_v.erase(keep), common_v.erase(drop);
        if (common_v != edge_v || common_e != edge_e) continue;
        // The merged point: keep's position, or (both ends free) drop's or the midpoint, in each
        // space independently; the one whose changed tets are most positive (relative to the mean).
        std::vector<int> changed;
        for (int k = 0; k < 2; ++k)
          for (int t : of[ends[k]])
            if (!star.count(t)) changed.push_back(t);
        // In parameter space a changed tet that was already flat or inverted may stay so if it gets
        // no worse (three coincident points need two collapses); the star's flat tets go, so every
        // collapse lowers the count.
        const auto best_position = [&](std::vector<Vec>& pos, double mean6, bool tolerate_bad) {
          std::vector<Vec> choices{pos[keep]};
          if (keep >= n) choices.insert(choices.end(), {pos[drop], 0.5 * (pos[keep] + pos[drop])});
          const Vec old = pos[keep];
          std::pair<double, Vec> best{-HUGE_VAL, old};
          for (const Vec& c : choices) {
            pos[keep] = c;
            double w = HUGE_VAL;
            for (int t : changed) {
              Tet nt = vm.tets[t];
              std::replace(nt.begin(), nt.end(), drop, keep);
              const double now = volume6(pos, nt);
              if (tolerate_bad) {
                pos[keep] = old;
                const double before = volume6(pos, vm.tets[t]);
                pos[keep] = c;
                if (!(before > 0)) {
                  if (now < before) w = -1;
                  continue;
                }
              }
              w = std::min(w, now / mean6);
            }
            if (w > best.first) best = {w, c};
          }
          pos[keep] = old;
          return best;
        };
        const auto [phys_w, phys_at] = best_position(vm.physical, mean6_phys, false);
        const auto [param_w, param_at] = best_position(vm.parameter, mean6_param, true);
        if (!(phys_w > 1e-9) || !(param_w > 0)) continue;
        // Collapse: drop the star, rename drop -> keep, move the last point into drop's slot.
        vm.physical[keep] = phys_at;
        vm.parameter[keep] = param_at;
        std::vector<Tet> kept;
        for (int t = 0; t < static_cast<int>(vm.tets.size()); ++t)
          if (!star.count(t)) kept.push_back(vm.tets[t]);
        const int last = static_cast<int>(vm.physical.size()) - 1;
        for (Tet& t : kept)
          for (int& v : t) {
            if (v == drop) v = keep;
            else if (v == last) v = drop;
          }
        vm.physical[drop] = vm.physical[last];
        vm.parameter[drop] = vm.parameter[last];
        vm.physical.pop_back();
        vm.parameter.pop_back();
        vm.tets.swap(kept);
        ++collapsed;
        again = true;
        break;
      }
    }
  }
  return collapsed;
}

namespace {

// The tet on vertices q, positively oriented in physical space, or nullopt if it is not positive
// (6 x volume above 1e-9 x mean6) with either orientation.
std::optional<Tet> oriented(const VolumeMap& vm, Tet q, double mean6) {
  const double v = volume6(vm.physical, q);
  if (v < 0) std::swap(q[2], q[3]);
  if (!(std::abs(v) > 1e-9 * mean6)) return std::nullopt;
  return q;
}

}  // namespace

int flip_flat_tets(VolumeMap& vm) {
  const int n = vm.surface_vertices;
  if (vm.tets.empty()) return 0;
  double mean6 = 0;
  for (const Tet& t : vm.tets) mean6 += volume6(vm.physical, t);
  mean6 /= static_cast<double>(vm.tets.size());
  const auto bad = [&](const Tet& t) { return !(volume6(vm.parameter, t) > 0); };
  int flips = 0;
  for (bool again = true; again;) {
    again = false;
    const std::vector<std::vector<int>> of = tets_of_points(vm);
    const auto sharing = [&](std::vector<int> vs) {
      std::vector<int> r = of[vs[0]];
      for (std::size_t k = 1; k < vs.size(); ++k) {
        std::vector<int> x;
        for (int t : r)
          if (std::find(vm.tets[t].begin(), vm.tets[t].end(), vs[k]) != vm.tets[t].end()) x.push_back(t);
        r.swap(x);
      }
      return r;
    };
    // Replaces tets `old` by `repl` if every new tet is positive in physical space and fewer are bad
    // in parameter space. Each new tet is oriented on its own, so the new tets must also fill the
    // old ones' volume exactly: a fold (a 2-3 flip whose new edge misses the shared face) overlaps
    // and has more.
    const auto try_replace = [&](const std::vector<int>& old, const std::vector<Tet>& quads) {
      std::vector<Tet> repl;
      int bad_before = 0, bad_after = 0;
      double volume_before = 0, volume_after = 0;
      for (int t : old) bad_before += bad(vm.tets[t]), volume_before += volume6(vm.physical, vm.tets[t]);
      for (const Tet& q : quads) {
        const auto t = oriented(vm, q, mean6);
        if (!t) return false;
        bad_after += bad(*t);
        volume_after += volume6(vm.physical, *t);
        repl.push_back(*t);
      }
      if (bad_after >= bad_before || std::abs(volume_after - volume_before) > 1e-9 * volume_before) return false;
      std::vector<Tet> kept;
      for (int t = 0; t < static_cast<int>(vm.tets.size()); ++t)
        if (std::find(old.begin(), old.end(), t) == old.end()) kept.push_back(vm.tets[t]);
      kept.insert(kept.end(), repl.begin(), repl.end());
      vm.tets.swap(kept);
      return true;
    };
    for (std::size_t b = 0; b < vm.tets.size() && !again; ++b) {
      const Tet t = vm.tets[b];  // a copy: a flip replaces vm.tets
      if (!bad(t)) continue;
      // 3-2: an interior edge of t with exactly three tets becomes the triangle of its link.
      for (int i = 0; i < 4 && !again; ++i)
        for (int j = i + 1; j < 4 && !again; ++j) {
          const int u = t[i], v = t[j];
          if (u < n && v < n) continue;  // a surface edge or a chord: its ring is not closed
          const std::vector<int> ring = sharing({u, v});
          if (ring.size() != 3) continue;
          std::set<int> link;
          for (int r : ring)
            for (int x : vm.tets[r])
              if (x != u && x != v) link.insert(x);
          if (link.size() != 3) continue;
          const std::vector<int> l(link.begin(), link.end());
          if (!sharing(l).empty()) continue;  // the triangle exists already
          if (l[2] < n) continue;            // an interior face of three surface vertices (see split_chords)
          // The triangle must separate u from v in physical space.
          if (volume6(vm.physical, {l[0], l[1], l[2], u}) * volume6(vm.physical, {l[0], l[1], l[2], v}) >= 0) continue;
          if (try_replace(ring, {Tet{l[0], l[1], l[2], u}, Tet{l[0], l[1], l[2], v}})) ++flips, again = true;
        }
      // 2-3: a face of t shared with one other tet becomes three tets around the edge between their
      // opposite vertices.
      for (int k = 0; k < 4 && !again; ++k) {
        std::vector<int> f;
        for (int i = 0; i < 4; ++i)
          if (i != k) f.push_back(t[i]);
        const std::vector<int> two = sharing(f);
        if (two.size() != 2) continue;  // a surface face
        const int other = two[0] == static_cast<int>(b) ? two[1] : two[0];
        int a = t[k], c = -1;
        for (int x : vm.tets[other])
          if (std::find(f.begin(), f.end(), x) == f.end()) c = x;
        if (!sharing({a, c}).empty()) continue;  // the edge exists already
        if (a < n && c < n) continue;           // a chord (see split_chords)
        if (try_replace({static_cast<int>(b), other}, {Tet{a, c, f[0], f[1]}, Tet{a, c, f[1], f[2]}, Tet{a, c, f[2], f[0]}}))
          ++flips, again = true;
      }
    }
  }
  return flips;
}

}  // namespace volts::volmap
