#!/usr/bin/env bash
# The README's main command: install dependencies, build, and run the end-to-end drop
# scenario on the simulated rig with the embedded default board.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${AMB_BUILD_DIR:-$PWD/build}
bash scripts/setup-debian.sh
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD" -j"${AMB_JOBS:-2}" --target amb-host amb-firmware
"$BUILD/host-tools/amb-host" scenario "$@"
