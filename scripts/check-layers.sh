#!/usr/bin/env bash
# The module layering, checked (a ctest): includes of the project's own headers are written from
# the repository root, never with `../`, and a module's sources compile against its own include
# root (the build's modules/<target>) and those below it only, so a reverse include fails.
#   scripts/check-layers.sh CXX BUILD/modules
set -euo pipefail
cd "$(dirname "$0")/.."
cxx=$1 modules=$(cd "$2" && pwd)
probe_dir=$(mktemp -d)
trap 'rm -rf "$probe_dir"' EXIT
status=0
if grep -rnE '#\s*include\s+"\.\./' cuda host render; then
  echo "check-layers: the includes above climb out of their folder; write them from the repository root" >&2
  status=1
fi
# probe MODULE_TARGETS... -- HEADER: compiles a file that includes HEADER with those include roots.
probe() {
  local flags=() t
  while [ "$1" != -- ]; do flags+=("-I$modules/$1"); shift; done
  shift
  printf '#include "%s"\n' "$1" >"$probe_dir/probe.cpp"
  # From an empty folder, so that nothing but the include roots can resolve the header.
  (cd "$probe_dir" && "$cxx" -std=c++17 -fsyntax-only -I/usr/include/eigen3 "${flags[@]}" probe.cpp 2>"$probe_dir/log")
}
# The order of the modules, lowest first: each may include its own headers and those before it.
order=(perifrac_engine perifrac_render perifrac_io perifrac_geometry perifrac_fragments perifrac_scene
       perifrac_validation perifrac_app)
header=(cuda/vec3.h render/camera.h host/io/checksum.h host/geometry/random.h host/fragments/obj_text.h
        host/scene/scene.h host/validation/validation.h host/app/run.h)
for ((k = 0; k < ${#order[@]}; ++k)); do
  below=("${order[@]:0:k+1}")
  if ! probe "${below[@]}" -- "${header[k]}"; then
    echo "check-layers: ${header[k]} does not compile with the include roots of ${below[*]}" >&2
    status=1
  fi
  if ((k + 1 < ${#order[@]})) && probe "${below[@]}" -- "${header[k + 1]}"; then
    echo "check-layers: ${order[k]} can include ${header[k + 1]}, a header of the module above it" >&2
    status=1
  fi
done
[ $status -eq 0 ] && echo "check-layers: ${#order[@]} modules layered one way, no ../ includes"
exit $status
