#!/usr/bin/env bash
# Plots the GPU speed history of the issue-5 workloads from the benchmark results in
# bench/results (perifrac bench JSON): bond-updates/s of the 1M-lattice bond-based springforces,
# the full step of the glass plate at >= 1M particles and of the plastic lattice, one point per
# result in date order, against their targets and the DRAM roof of 4 bytes per bond (design
# notes). gnuplot (Debian gnuplot-nox) is installed with apt-get if missing.
#   scripts/plot-speed.sh [RESULTS_DIR] [OUT.png]
set -euo pipefail
dir=${1:-bench/results} png=${2:-bench/speed.png}
if ! command -v gnuplot >/dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get install -y -qq gnuplot-nox >/dev/null || { echo "plot-speed: needs gnuplot" >&2; exit 1; }
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# One data file per series: index, bond-updates/s, label (date and git revision, device).
python3 - "$dir" "$tmp" <<'PY'
import glob, json, os, sys
src, out = sys.argv[1], sys.argv[2]
series = {"springforces": [], "glass": [], "plastic": []}
runs = []  # (date, git, device), in file (date) order
for f in sorted(glob.glob(os.path.join(src, "*_cuda_*.json"))):
    d = json.load(open(f))
    if "kernels" not in d or d.get("particles", 0) < 1000000:
        continue
    k = {e["name"]: e for e in d["kernels"]}
    run = "%s %s %s" % (d["date"][:10], d["git"], "H100" if "H100" in d["device"] else "H200")
    w = d["workload"]
    # Instantiations are summed in "pd/springforces (all)" (one name before that).
    spring = k.get("pd/springforces (all)", k.get("pd/springforces"))
    if w.endswith("bond_based") and spring:
        name, v = "springforces", spring["bond_updates_per_s"]
    elif w == "glass_plate_projectile":
        name, v = "glass", k["step (all kernels)"]["bond_updates_per_s"]
    elif w.endswith("plastic"):
        name, v = "plastic", k["step (all kernels)"]["bond_updates_per_s"]
    else:
        continue
    if run not in runs:
        runs.append(run)
    series[name].append((runs.index(run), v))
for name, pts in series.items():
    with open(os.path.join(out, name + ".dat"), "w") as o:
        for x, v in pts:
            o.write("%d %g\n" % (x, v))
with open(os.path.join(out, "runs.dat"), "w") as o:
    for x, run in enumerate(runs):
        o.write('%d 1.2e10 "%s"\n' % (x, run))
PY
runs=$(wc -l <"$tmp/runs.dat")
gnuplot <<GP
set terminal pngcairo size 1200,700 noenhanced
set output '$png'
set title 'GPU speed, issue-5 workloads (float32, delta = 3 lambda, >= 1M particles; bench/results)'
set ylabel 'bond-updates/s'
set logscale y
set yrange [1e10:2e12]
set xlabel 'benchmark run (date, git revision, device)'
set xrange [-0.5:$runs - 0.5]  # half a run's width on both sides, for the last run's label
set key outside right
set grid
roof = 3.35e12 / 4
plot roof with lines dt 2 lw 2 lc rgb '#555555' title 'DRAM roof, 4 B/bond, H100 (3.35 TB/s)', \
     5e11 with lines dt 3 lw 2 lc rgb '#1f77b4' title 'target: springforces 5e11', \
     2.5e11 with lines dt 3 lw 2 lc rgb '#2ca02c' title 'target: glass step 2.5e11', \
     1.5e11 with lines dt 3 lw 2 lc rgb '#d62728' title 'target: plastic step 1.5e11', \
     '$tmp/springforces.dat' using 1:2 with linespoints pt 7 lw 2 lc rgb '#1f77b4' title 'springforces, lattice 1M bond-based', \
     '$tmp/glass.dat' using 1:2 with linespoints pt 7 lw 2 lc rgb '#2ca02c' title 'full step, glass plate 1M', \
     '$tmp/plastic.dat' using 1:2 with linespoints pt 7 lw 2 lc rgb '#d62728' title 'full step, plastic lattice 1M', \
     '$tmp/runs.dat' using 1:2:3 with labels rotate by 90 left font ',7' notitle
GP
echo "plot       $png"
