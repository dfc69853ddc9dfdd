#!/usr/bin/env bash
# The test command: sets up, builds and runs every test suite (GPU-labelled tests skip
# themselves where no GPU answers).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
preset=$(cat build/.last-preset)
ctest --test-dir "build/$preset" --output-on-failure -j "$(nproc)" "$@"
