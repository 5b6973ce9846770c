// volts::config — the run's YAML configuration (yaml-cpp), bound to every stage's parameter struct.
//
// Strict on purpose: an unknown key is an error naming its path ("tmesh.levle"), so a typo never
// silently falls back to a default; a wrong type or an out-of-range value is an error naming the
// key, the value and the allowed range. configs/default.yaml documents every key.
#pragma once

#include <string>

#include "classify/classify.h"
#include "polycube/polycube.h"
#include "split/split.h"
#include "tmesh/tmesh.h"
#include "extract/extract.h"
#include "fit/route.h"
#include "tet2hex/tet2hex.h"

namespace volts::config {

/// Where the input surface comes from: a file, or a model volts generates itself.
struct InputParams {
  std::string file;           ///< surface file (OFF/OBJ/STL/PLY); relative to the config file's folder
  std::string generate;       ///< or: a volts-make-model name (box, bulged-box, torus, cube-with-hole, ...)
  int resolution = 16;        ///< generated model: segments along the longest edge
  double bulge = 0.15;        ///< generated bulged-box: face bulge relative to the half-size
};

struct Config {
  std::string source;  ///< path of the file it was read from ("" for defaults)
  /// pipeline route: "polycube" (the five stages), "tet" (volts-tet2hex) or "fit" (classify, then volts-fit)
  std::string route = "polycube";
  InputParams input;
  classify::Params classify;
  split::Params split;
  polycube::Params polycube;
  tmesh::Params tmesh;
  extract::Params extract;
  tet2hex::Params tet2hex;  ///< route "tet"
  fit::Params fit;          ///< route "fit"
};

/// Reads and checks a config file. Throws core::ConfigError ("FILE: key.path: problem") or
/// core::InvalidInputError if the file is missing or not YAML.
Config load_config(const std::string& path);

/// Parses config text (for tests); `source` names it in messages.
Config parse_config(const std::string& yaml_text, const std::string& source);

/// The config as YAML with every key (what a run actually used), for the work directory.
std::string to_yaml(const Config& c);

}  // namespace volts::config
