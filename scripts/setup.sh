#!/usr/bin/env bash
# Installs what perifrac needs (Debian/Ubuntu packages) and builds it. Safe to run again:
# installed packages are skipped and the build is incremental.
#   scripts/setup.sh            build the preset that fits this machine (cuda with a GPU, else cpu)
#   PERIFRAC_PRESET=cpu-asan scripts/setup.sh   build a named preset from CMakePresets.json
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake ninja-build pkg-config libgtest-dev libeigen3-dev libtomlplusplus-dev
          libcli11-dev libstb-dev libnanoflann-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Preset: CUDA only where a GPU answers (a CUDA build without a device would only skip).
if [ -z "${PERIFRAC_PRESET:-}" ]; then
  PERIFRAC_PRESET=cpu
  if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >/dev/null 2>&1; then
    export PATH="$PATH:/usr/local/cuda/bin"
    command -v nvcc >/dev/null 2>&1 && PERIFRAC_PRESET=cuda
  fi
fi
echo "setup: building preset '$PERIFRAC_PRESET'"
cmake --preset "$PERIFRAC_PRESET" >/dev/null
cmake --build --preset "$PERIFRAC_PRESET" -j "$(nproc)"
echo "$PERIFRAC_PRESET" > "build/.last-preset"
