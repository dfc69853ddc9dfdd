#!/usr/bin/env bash
# TetGen alone against TetGen inside a run's set-up, interleaved: is a scene's first-run TetGen
# time the machine's or the run's? Captures the input perifrac hands TetGen (its .smesh, the
# inserted points and the switches), then per round times `tetgen` by itself on that input and a
# `perifrac run --frames 0` with an empty tet cache, printing the run's TetGen stage beside it.
# A benchmark, not a test (bench/NOTES.md, "TetGen alone on the GPU machine").
#   scripts/tetgen-alone.sh [BIN] [SCENE] [SCALE] [ROUNDS]
#   default: build/cpu/perifrac scenes/vase_drop.toml 4.27 3; BACKEND=cuda for the GPU build;
#   TETGEN_KEEP_INPUT=DIR keeps a copy of the captured input (scripts/tetgen-surface.py reads it)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/cpu/perifrac}
scene=${2:-scenes/vase_drop.toml}
scale=${3:-4.27}
rounds=${4:-3}
backend=${BACKEND:-auto}
[ -x "$bin" ] || { echo "tetgen-alone: no $bin (build it, or name the binary)" >&2; exit 2; }
real_tetgen=$(command -v tetgen) || { echo "tetgen-alone: no tetgen on PATH" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# A `tetgen` ahead on PATH that keeps a copy of its input and switches, then runs the real one.
mkdir -p "$work/wrapper" "$work/input"
cat >"$work/wrapper/tetgen" <<WRAP
#!/usr/bin/env bash
dir=\$(dirname "\${@: -1}")
cp "\$dir"/in.smesh "$work/input/" && { cp "\$dir"/in.a.node "$work/input/" 2>/dev/null || true; }
printf '%s\n' "\$1" >"$work/input/switches"
exec "$real_tetgen" "\$@"
WRAP
chmod +x "$work/wrapper/tetgen"
run_setup() {  # $1: PATH to use; prints the run's set-up line
  PATH="$1" PERIFRAC_TET_CACHE="$(mktemp -d -p "$work")" "$bin" run "$scene" --scale "$scale" --frames 0 \
    --backend "$backend" --out "$work/run" --overwrite 2>&1 | grep '^set-up'
}
run_setup "$work/wrapper:$PATH" >/dev/null
[ -f "$work/input/in.smesh" ] || { echo "tetgen-alone: $scene ran no TetGen (no tet body)" >&2; exit 2; }
switches=$(cat "$work/input/switches")
[[ -n "${TETGEN_KEEP_INPUT:-}" ]] && mkdir -p "$TETGEN_KEEP_INPUT" && cp "$work/input"/* "$TETGEN_KEEP_INPUT/"
echo "tetgen-alone: $scene --scale $scale, tetgen $switches, $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
for r in $(seq "$rounds"); do
  rm -rf "$work/alone" && mkdir -p "$work/alone" && cp "$work/input"/in.* "$work/alone/"
  start=$(date +%s.%N)
  "$real_tetgen" "$switches" "$work/alone/in.smesh" >/dev/null
  echo "round $r: tetgen alone $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }') s"
  echo "round $r: in the run, $(run_setup "$PATH" | grep -o 'tetgen -[^ ]* [0-9.]* s')"
done
