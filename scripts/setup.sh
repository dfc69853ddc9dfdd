#!/usr/bin/env bash
# Installs what perifrac needs and builds it. Safe to run again: what is present is skipped
# and the build is incremental.
#   scripts/setup.sh                          build the preset that fits this machine (cuda with a GPU, else cpu)
#   PERIFRAC_PRESET=cpu-asan scripts/setup.sh build a named preset from CMakePresets.json
# Needs: a C++17 compiler, CMake >= 3.24, Ninja, and the headers of GoogleTest, Eigen, toml++,
# CLI11 and stb, and Open MPI (runs over several ranks). Missing ones are installed with apt-get
# (Debian/Ubuntu package names below); header-only ones may instead be staged in .deps/include
# (scripts/stage-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

# What the build needs, and the package that provides it: "kind:name:package".
needs=(
  "cmd:g++:build-essential" "cmd:cmake:cmake" "cmd:ninja:ninja-build"
  "hdr:gtest/gtest.h:libgtest-dev" "hdr:eigen3/Eigen/Dense:libeigen3-dev" "hdr:toml++/toml.h:libtomlplusplus-dev"
  "hdr:CLI/CLI.hpp:libcli11-dev" "hdr:stb/stb_image_write.h:libstb-dev"
  "cmd:mpicxx:libopenmpi-dev" "cmd:mpirun:openmpi-bin"
)
# Optional: tetrahedral particles run the TetGen program (AGPL, kept as a separate program);
# ffmpeg turns rendered frames into movie.mp4; Embree (Apache-2.0) is the renderer's test oracle
# and benchmark baseline, built only when present.
optional=("cmd:tetgen:tetgen" "cmd:ffmpeg:ffmpeg" "hdr:embree3/rtcore.h:libembree-dev")
have() {
  local kind=$1 name=$2
  if [ "$kind" = cmd ]; then command -v "$name" >/dev/null 2>&1; return; fi
  [ -e "/usr/include/$name" ] || [ -e "/usr/local/include/$name" ] || [ -e ".deps/include/$name" ]
}
missing=()
for need in "${needs[@]}"; do
  IFS=: read -r kind name package <<<"$need"
  have "$kind" "$name" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  if ! { $sudo apt-get update -qq &&
         DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; }; then
    echo "setup: could not install ${missing[*]} with apt-get; install them (Debian/Ubuntu package names) and run again" >&2
    exit 1
  fi
fi

for need in "${optional[@]}"; do
  IFS=: read -r kind name package <<<"$need"
  have "$kind" "$name" && continue
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$package" >/dev/null 2>&1 ||
    echo "setup: optional $package not installed: what needs it will say so or skip"
done

# Preset: CUDA only where a GPU answers (a CUDA build without a device would only skip).
if [ -z "${PERIFRAC_PRESET:-}" ]; then
  PERIFRAC_PRESET=cpu
  if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >/dev/null 2>&1; then
    export PATH="$PATH:/usr/local/cuda/bin"
    command -v nvcc >/dev/null 2>&1 && PERIFRAC_PRESET=cuda
  fi
fi
echo "setup: building preset '$PERIFRAC_PRESET'"
# PERIFRAC_WERROR=1 (CI) makes compiler warnings errors; the cache keeps the last choice otherwise.
werror=()
[ -n "${PERIFRAC_WERROR:-}" ] && werror=("-DPERIFRAC_WERROR=$([ "$PERIFRAC_WERROR" = 0 ] && echo OFF || echo ON)")
cmake --preset "$PERIFRAC_PRESET" "${werror[@]}" >/dev/null
cmake --build --preset "$PERIFRAC_PRESET" -j "$(nproc)"
echo "$PERIFRAC_PRESET" >"build/.last-preset"
