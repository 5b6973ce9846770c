#include "polycube/cube_frame.h"

#include "core/errors.h"

namespace volts::polycube::detail {

std::vector<int> cube_codes(const std::vector<std::set<int>>& adj) {
  const int n = static_cast<int>(adj.size());
  std::vector<int> code(adj.size(), -1);
  bool ok = n == 8;
  if (ok) {
    // Breadth-first from corner 0: a corner at distance k has k bits, the OR of its neighbours at
    // distance k - 1 (a neighbour at distance k + 1 would add a bit too many).
    std::vector<int> depth(adj.size(), -1);
    std::vector<int> order{0};
    depth[0] = 0;
    for (std::size_t i = 0; i < order.size(); ++i)
      for (int w : adj[static_cast<std::size_t>(order[i])])
        if (w >= 0 && w < n && depth[static_cast<std::size_t>(w)] < 0)
          depth[static_cast<std::size_t>(w)] = depth[static_cast<std::size_t>(order[i])] + 1, order.push_back(w);
    code[0] = 0;
    int bit = 1;
    for (int v : order) {
      if (depth[static_cast<std::size_t>(v)] == 1) {
        code[static_cast<std::size_t>(v)] = bit <= 4 ? bit : -1;
        bit <<= 1;
      } else if (depth[static_cast<std::size_t>(v)] > 1) {
        int acc = 0;
        for (int w : adj[static_cast<std::size_t>(v)])
          if (w >= 0 && w < n && depth[static_cast<std::size_t>(w)] == depth[static_cast<std::size_t>(v)] - 1)
            acc |= code[static_cast<std::size_t>(w)];
        code[static_cast<std::size_t>(v)] = acc;
      }
    }
    const std::set<int> distinct(code.begin(), code.end());
    ok = distinct.size() == 8 && !distinct.count(-1);
    for (const auto& a : adj) ok = ok && a.size() == 3;  // a cube's 12 edges, 3 at each corner
  }
  for (int v = 0; v < n && ok; ++v)
    for (int w : adj[static_cast<std::size_t>(v)]) {
      const int x = w >= 0 && w < n ? code[static_cast<std::size_t>(v)] ^ code[static_cast<std::size_t>(w)] : 0;
      ok = ok && (x == 1 || x == 2 || x == 4);
    }
  if (!ok) throw core::TopologyError("polycube: the corners and curves do not form the graph of a cube");
  return code;
}

}  // namespace volts::polycube::detail
