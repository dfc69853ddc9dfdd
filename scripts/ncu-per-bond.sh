#!/usr/bin/env bash
# What bounds a bond loop: per kernel of `perifrac bench`'s timed steps, Nsight Compute's
# instructions executed (and per bond), issue slots busy, active threads per warp, warp cycles
# per issued instruction split by stall reason, achieved occupancy, registers, DRAM share of peak
# and cache hit rates. An issue-bound loop (its warps mostly "not selected") gets faster only
# with fewer instructions a bond; a latency-bound one (long scoreboard: waiting on L1TEX) with
# more loads in flight. Needs a GPU, ncu and a CUDA build. Prints a Markdown table.
#   scripts/ncu-per-bond.sh [BINARY] [WORKLOAD...]
# A workload is NAME=BENCH_ARGS; the defaults are the issue-27 workloads: the plastic lattice,
# the explicit bond-based lattice, and the vase at Levine's size.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PATH:/usr/local/cuda/bin"
bin=${1:-build/cuda/perifrac}
shift || true
workloads=("$@")
if [ ${#workloads[@]} -eq 0 ]; then
  workloads=(
    "plastic-lattice=--lattice 100 --model plastic --steps 2 --warmup 30"
    "explicit-lattice=--lattice 100 --model bond_based --explicit-families --steps 2 --warmup 10"
    "vase=--scene scenes/vase_drop.toml --scale 4.27 --steps 2 --warmup 10"
  )
fi
command -v ncu >/dev/null || { echo "ncu-per-bond: ncu (Nsight Compute) not found" >&2; exit 1; }
[ -x "$bin" ] || { echo "ncu-per-bond: no $bin (build the cuda preset, or name the binary)" >&2; exit 2; }
out=${OUT:-out}/ncu-per-bond
mkdir -p "$out"
stalls=long_scoreboard,not_selected,short_scoreboard,wait,math_pipe_throttle,lg_throttle,mio_throttle,branch_resolving,barrier,no_instruction,dispatch_stall,selected
metrics=gpu__time_duration.sum,smsp__inst_executed.sum,smsp__issue_active.avg.pct_of_peak_sustained_active
metrics+=,smsp__thread_inst_executed_per_inst_executed.ratio,smsp__average_warp_latency_per_inst_issued.ratio
metrics+=,sm__warps_active.avg.pct_of_peak_sustained_active,launch__registers_per_thread
metrics+=,gpu__dram_throughput.avg.pct_of_peak_sustained_elapsed,l1tex__t_sector_hit_rate.pct,lts__t_sector_hit_rate.pct
for s in ${stalls//,/ }; do metrics+=,smsp__average_warps_issue_stalled_${s}_per_issue_active.ratio; done
device=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -n 1)
echo "# Bond loops under Nsight Compute: $device, $(date -u +%Y-%m-%dT%H:%MZ), $("$bin" --version 2>/dev/null | head -n 1)"
echo
for w in "${workloads[@]}"; do
  name=${w%%=*} args=${w#*=}
  # The bond count, from an unprofiled run of the same workload.
  # shellcheck disable=SC2086
  bonds=$("$bin" bench $args --backend cuda --out "$out/bench" | awk '/^size/ {print $4; exit}')
  # shellcheck disable=SC2086
  ncu --nvtx --nvtx-include "pd-bench-timed/" --metrics "$metrics" --csv --print-units base \
    "$bin" bench $args --backend cuda --out "$out/bench" >"$out/$name.csv" 2>"$out/$name.err"
  echo "## $name ($bonds bonds; perifrac bench $args)"
  echo
  python3 scripts/ncu_per_bond.py "$out/$name.csv" "$bonds"
  echo
done
