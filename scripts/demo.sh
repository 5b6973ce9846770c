#!/usr/bin/env bash
# The main job: install what is missing, build, run the whole pipeline on a model volts generates
# itself (configs/demo.yaml), print the summary and the file to open in ParaView.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
BUILD_DIR=${VOLTS_BUILD_DIR:-build}
"$BUILD_DIR/pipeline/volts" run configs/demo.yaml --workdir runs/demo "$@"
