#!/usr/bin/env bash
# Copies the header-only dependencies from this machine's Debian packages into .deps/include
# (git-ignored), so a machine without them (the GPU machine) can build when .deps travels along;
# and the optional `tetgen` program with its library into .deps/bin and .deps/lib, which
# scripts/gpu-check.sh and scripts/gallery.sh put on PATH / LD_LIBRARY_PATH when present.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p .deps/include
for d in toml++ stb CLI; do
  [ -d "/usr/include/$d" ] && rm -rf ".deps/include/$d" && cp -r "/usr/include/$d" .deps/include/
done
for f in nanoflann.hpp; do
  [ -f "/usr/include/$f" ] && cp "/usr/include/$f" .deps/include/
done
if command -v tetgen >/dev/null; then
  mkdir -p .deps/bin .deps/lib
  cp "$(command -v tetgen)" .deps/bin/
  ldd "$(command -v tetgen)" | awk '/libtet/ {print $3}' | xargs -r -I{} cp {} .deps/lib/
fi
du -sh .deps
