#!/usr/bin/env bash
# Plots a run's fragment statistics (DIR/fragments.csv, host/fragments/fragment_log.h) against
# simulated time: the number of pieces and of single-particle pieces (log scale), and the shares
# of the mass in single particles (dust), in free particles (no bond left; logs from before that
# column have none) and in the heaviest piece. For tuning how a breakage looks.
# gnuplot (Debian gnuplot-nox) is installed with apt-get if missing.
#   scripts/plot-fragments.sh RUN_DIR [OUT.png]      default RUN_DIR/fragments.png
set -euo pipefail
[[ $# -ge 1 ]] || { sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
dir=$1 png=${2:-$1/fragments.png}
csv=$dir/fragments.csv
[[ -f $csv ]] || { echo "plot-fragments: no $csv (a run of this perifrac writes one)" >&2; exit 2; }
free=""
head -n 1 "$csv" | grep -q ',free_mass_share' &&
  free=', "" using 3:(100 * column("free_mass_share")) with linespoints title "in free particles"'

if ! command -v gnuplot >/dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get install -y -qq gnuplot-nox >/dev/null || { echo "plot-fragments: needs gnuplot" >&2; exit 1; }
fi
gnuplot <<GP
set terminal pngcairo size 1200,500 font ",11"
set output "$png"
set datafile separator ","
set key autotitle columnhead top left
set multiplot layout 1,2 title "fragments of $(basename "$dir")"
set xlabel "time [s]"
set logscale y
set ylabel "pieces"
plot "$csv" using 3:(\$4 > 0 ? \$4 : 1/0) with linespoints title "pieces", \
     "" using 3:(\$5 > 0 ? \$5 : 1/0) with linespoints title "single particles"
unset logscale y
set ylabel "share of the mass [%]"
set yrange [0:100]
plot "$csv" using 3:(100 * \$6) with linespoints title "in single particles", \
     "" using 3:(100 * \$7) with linespoints title "in the heaviest piece"$free
unset multiplot
GP
echo "plot-fragments: $png"
