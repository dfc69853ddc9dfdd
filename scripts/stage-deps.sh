#!/usr/bin/env bash
# Copies the header-only dependencies from this machine's Debian packages into .deps/include
# (git-ignored), so a machine without them (the GPU machine) can build when .deps travels along.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p .deps/include
for d in toml++ stb CLI; do
  [ -d "/usr/include/$d" ] && rm -rf ".deps/include/$d" && cp -r "/usr/include/$d" .deps/include/
done
for f in nanoflann.hpp; do
  [ -f "/usr/include/$f" ] && cp "/usr/include/$f" .deps/include/
done
du -sh .deps
