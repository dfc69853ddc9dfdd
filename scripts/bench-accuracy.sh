#!/usr/bin/env bash
# Accuracy benchmark of the validation problems (docs/validation.md): sweeps resolution, horizon
# delta/lambda (3, 4), precision (float build; double build with -DPERIFRAC_DOUBLE=ON), backend
# (cpu; cuda when the binary has it and a GPU answers), dt / dt_c and the surface correction (each
# model's default, the other way at delta = 3 lambda: off for bond-based problems, on for
# state-based ones, and the ghost correction at 0.3 dt_c), through `perifrac validate`.
# Writes to bench/accuracy/ (or --out): accuracy.csv, pareto.png (error against wall time),
# convergence.png (error against resolution) and summary.md (Pareto-optimal and recommended
# settings per measured figure, with the device, CPU and date). Not a test: nothing is asserted.
#
#   scripts/bench-accuracy.sh BUILD [--double BUILD2] [--quick] [--out DIR] [--problems "a b"]
#                             [--backends "cpu cuda"]
# BUILD, BUILD2: a build folder holding `perifrac`, or the binary itself. --quick: coarse
# resolutions only (fits ~3 minutes on a GPU machine; well over 10 minutes on 2 CPU cores). --backends:
# the backends to sweep (default: cpu, and cuda when the binary has it and a GPU answers).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
binary() { if [[ -d $1 ]]; then echo "$1/perifrac"; else echo "$1"; fi; }

[[ $# -ge 1 ]] || usage
BIN=$(binary "$1"); shift
BIN_DOUBLE="" QUICK=0 OUT=bench/accuracy PROBLEMS="" BACKENDS=""
while [[ $# -gt 0 ]]; do
  case $1 in
    --double) BIN_DOUBLE=$(binary "$2"); shift 2 ;;
    --quick) QUICK=1; shift ;;
    --out) OUT=$2; shift 2 ;;
    --problems) PROBLEMS=$2; shift 2 ;;
    --backends) BACKENDS=$2; shift 2 ;;
    *) usage ;;
  esac
done
[[ -x $BIN ]] || { echo "error: no perifrac binary at '$BIN'" >&2; exit 2; }
[[ -z $BIN_DOUBLE || -x $BIN_DOUBLE ]] || { echo "error: no perifrac binary at '$BIN_DOUBLE'" >&2; exit 2; }
if ! command -v gnuplot >/dev/null; then
  echo "installing gnuplot-nox" >&2
  (apt-get install -y -q gnuplot-nox || (apt-get update -q && apt-get install -y -q gnuplot-nox)) >/dev/null ||
    echo "warning: gnuplot unavailable: no plots" >&2
fi
mkdir -p "$OUT"
CSV=$OUT/accuracy.csv
rm -f "$CSV"

# Sweep settings: resolution lists per problem (particles across the width / plate height).
if [[ $QUICK == 1 ]]; then
  declare -A RES=([wave_bar]=4,6,8 [tension_bar_pmb]=4,6,8 [tension_bar_lps]=4,6,8 [cantilever_pmb]=4
                  [cantilever_lps]=4 [bar_twist_lps]=4,6 [bar_spin_lps]=4,6 [crack_branching]=20
                  [notched_bar_pmb]=10 [crack_tip_pmb]=30)
  DELTAS="3 4" DTS="0.5"
else
  declare -A RES=([wave_bar]=4,6,8,12 [tension_bar_pmb]=4,6,8,12 [tension_bar_lps]=4,6,8,12
                  [cantilever_pmb]=4,6 [cantilever_lps]=4,6 [bar_twist_lps]=4,6,8
                  [bar_spin_lps]=4,6,8 [crack_branching]=20,40 [notched_bar_pmb]=10,20
                  [crack_tip_pmb]=30,60)
  DELTAS="3 4" DTS="0.25 0.5 0.9"
fi
PROBLEMS=${PROBLEMS:-"wave_bar tension_bar_pmb tension_bar_lps cantilever_pmb cantilever_lps bar_twist_lps bar_spin_lps
  crack_branching notched_bar_pmb crack_tip_pmb"}

backends="cpu"
"$BIN" info 2>/dev/null | grep -q '^cuda *available' && backends="cpu cuda"
if [[ -n $BACKENDS ]]; then
  for b in $BACKENDS; do
    [[ $b == cpu || $b == cuda ]] || { echo "error: --backends '$BACKENDS' (allowed: cpu, cuda)" >&2; exit 2; }
  done
  backends=$BACKENDS
fi
run() {  # binary backend problem resolutions delta dt [surface correction: default | on | off | ghosts]
  echo "$(basename "$(dirname "$1")") $2 $3 res $4 delta/lambda $5 dt $6 dt_c surface ${7:-default}" >&2
  "$1" validate --problem "$3" --resolution "$4" --delta-over-lambda "$5" --dt-fraction "$6" --backend "$2" \
    --surface-correction "${7:-default}" --csv "$CSV" --quiet || echo "warning: $3 at $4 exited with $?" >&2
}
BOND_BASED="wave_bar tension_bar_pmb cantilever_pmb crack_branching notched_bar_pmb crack_tip_pmb"
for bin in "$BIN" ${BIN_DOUBLE:+"$BIN_DOUBLE"}; do
  for backend in $backends; do
    for p in $PROBLEMS; do
      for d in $DELTAS; do run "$bin" "$backend" "$p" "${RES[$p]}" "$d" 0.5; done
      # dt sweep at the problem's second resolution (its first when it has one).
      res=${RES[$p]#*,}; res=${res%%,*}
      for dt in $DTS; do
        [[ $dt == 0.5 ]] || run "$bin" "$backend" "$p" "$res" 3 "$dt"
      done
      if [[ " $BOND_BASED " == *" $p "* ]]; then other=off; else other=on; fi
      run "$bin" "$backend" "$p" "${RES[$p]}" 3 0.5 "$other"
      # The ghost correction (docs/scene-reference.md#ghost-correction) at its default dt / dt_c:
      # the elastic problems (the fracture problems' ghosts go with their first broken bonds).
      [[ $p == crack_branching || $p == notched_bar_pmb || $p == crack_tip_pmb ]] || run "$bin" "$backend" "$p" "${RES[$p]}" 3 0.3 ghosts
    done
  done
done

# Plots and summary.
if command -v gnuplot >/dev/null; then
  plotted=cpu
  [[ " $backends " == *" cpu "* ]] || plotted=${backends%% *}
  gnuplot -e "csv='$CSV'; out='$OUT'; backend='$plotted'" scripts/plot/accuracy.gp
fi
DEVICE=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)
GPU=$(command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 || true)
scripts/plot/accuracy-summary.sh "$CSV" "${DEVICE:-unknown CPU} ($(nproc) cores)${GPU:+; GPU: $GPU}" \
  "$([[ $QUICK == 1 ]] && echo quick || echo full)" >"$OUT/summary.md"
echo "results in $OUT: accuracy.csv, pareto.png, convergence.png, summary.md"
