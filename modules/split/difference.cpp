// Difference components (Liu et al. 2013, §4.3, Fig. 7): a through hole with sharp rims becomes a
// virtual component subtracted from a cube.
#include "core/errors.h"
#include "split/split_internal.h"

namespace volts::split::detail {

Decomposition split_difference(const surface::Mesh&, const classify::Classification&, const Params&) {
  throw core::TopologyError("split: difference components are not implemented yet");
}

}  // namespace volts::split::detail
