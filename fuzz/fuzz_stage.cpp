// libFuzzer target of one stage file reader (VOLTS_FUZZ_STAGE: classify, split, polycube, tmesh):
// the header check and every payload reader the next stage's executable runs on it, in the same
// order. Any bytes must end in the payload or a core::Error.
#include <cstring>

#include "classify/classify.h"
#include "core/errors.h"
#include "core/stage_file.h"
#include "fuzz_util.h"
#include "polycube/polycube.h"
#include "split/split.h"
#include "surface/mesh_json.h"
#include "tmesh/tmesh.h"

using namespace volts;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string stage = VOLTS_FUZZ_STAGE;
  const std::string& path = fuzz::write_input(data, size, "." + stage + ".stage.json");
  try {
    const core::Json j = core::read_stage_file(path, "volts-" + stage, 1);
    (void)surface::mesh_from_json(core::require(j, "surface", path), path);
    if (stage != "tmesh") (void)classify::from_json(core::require(j, "classification", path), path);
    if (stage == "split" || stage == "polycube") (void)split::from_json(core::require(j, "decomposition", path), path);
    if (stage == "polycube") (void)polycube::from_json(core::require(j, "polycube", path), path);
    if (stage == "tmesh") (void)tmesh::from_json(core::require(j, "tmesh", path), path);
  } catch (const core::Error&) {
  }
  return 0;
}
