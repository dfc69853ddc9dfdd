#!/usr/bin/env bash
# Markdown summary of an accuracy CSV (scripts/bench-accuracy.sh): per measured figure, the
# Pareto-optimal runs (no other run is both faster and more accurate) and the recommended
# setting: the cheapest run whose error is within 1.5x of the smallest error measured.
#   scripts/plot/accuracy-summary.sh CSV "DEVICE" MODE > summary.md
set -euo pipefail
csv=$1 device=$2 mode=$3
cat <<HEAD
# Accuracy benchmark ($mode sweep)

- date: $(date -u '+%Y-%m-%d %H:%M UTC')
- device: $device
- runs: $(($(wc -l <"$csv") - 1)) rows in \`accuracy.csv\`; plots \`pareto.png\` (error against wall time) and
  \`convergence.png\` (error against resolution); the problems and references are in docs/validation.md.

HEAD
for fig in $(tail -n +2 "$csv" | cut -d, -f1 | sort -u); do
  echo "## $fig"
  echo
  echo "| backend | precision | resolution | delta/lambda | dt/dt_c | surface correction | particles | steps | wall s | measured | reference | rel. error |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  # Pareto front: sort by wall time, keep runs that improve on every faster run's error.
  awk -F, -v f="$fig" '$1 == f' "$csv" | sort -t, -k9,9g | awk -F, '
    NR == 1 || $12 < best { best = $12; printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %.5g | %.5g | %.2f%% |\n",
      $2, $3, $4, $5, $6, $13, $7, $8, $9, $10, $11, 100 * $12 }'
  echo
  awk -F, -v f="$fig" '$1 == f' "$csv" | sort -t, -k9,9g | awk -F, '
    { wall[NR] = $9; err[NR] = $12; row[NR] = $0; if (NR == 1 || $12 < min) min = $12 }
    END { for (k = 1; k <= NR; ++k) if (err[k] <= 1.5 * min + 1e-12) { split(row[k], r, ",");
      printf "Recommended (cheapest within 1.5x of the best error, %.2f%%): %s %s, resolution %s, delta/lambda %s, dt %s dt_c, surface correction %s: %.2f%% in %s s.\n\n",
        100 * min, r[2], r[3], r[4], r[5], r[6], r[13], 100 * r[12], r[9]; exit } }'
done
