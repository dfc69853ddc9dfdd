# Plots of bench/accuracy/accuracy.csv (scripts/bench-accuracy.sh): call with
#   gnuplot -e "csv='PATH'; out='DIR'[; backend='cuda']" scripts/plot/accuracy.gp
# pareto.png: relative error against wall time, every run; convergence.png: relative error
# against resolution at dt = 0.5 dt_c, float build on `backend` (default cpu), delta/lambda 3
# (solid) and 4 (dashed) with
# each model's default surface correction (on for bond-based, off for state-based), and 3 the
# other way (dotted), and the ghost correction at delta = 3 lambda (dash-dot).
set datafile separator ','
if (!exists("backend")) backend = 'cpu'
set linetype cycle 12
set terminal pngcairo size 1200,800 noenhanced font ',10'
problems = system("tail -n +2 '".csv."' | cut -d, -f1 | sort -u | tr '\\n' ' '")
set logscale xy
set grid
set key outside right top
set ylabel 'relative error |measured - reference| / |reference|'
pos(e) = e > 0 ? e : NaN

set output out.'/pareto.png'
set title 'Error against wall time (every run; lower left is better)'
set xlabel 'wall time per run [s]'
plot for [i=1:words(problems)] csv skip 1 using (strcol(1) eq word(problems, i) ? $9 : NaN):(pos($12)) \
  with points pt (i % 13 + 1) ps 1.3 title word(problems, i)

set output out.'/convergence.png'
set title 'Error against resolution (dt = 0.5 dt_c, float, '.backend.'; solid: delta = 3 lambda, dashed: 4 lambda, dotted: 3 lambda, surface correction the other way; dash-dot: ghosts at 0.3 dt_c)'
set xlabel 'resolution (particles across the width; plate: across the height)'
# One series per figure and horizon, filtered by awk so that lines join consecutive resolutions.
series(p, d, s) = sprintf("< awk -F, '$1 == \"%s\" && $5 == %d && $6 == 0.5 && $3 == \"float\" && $2 == \"%s\" && ($13 == \"default\") == (\"%s\" == \"default\")' '%s'", p, d, backend, s, csv)
ghosts(p) = sprintf("< awk -F, '$1 == \"%s\" && $5 == 3 && $3 == \"float\" && $2 == \"%s\" && $13 == \"ghosts\"' '%s'", p, backend, csv)
plot for [i=1:words(problems)] series(word(problems, i), 3, "default") using 4:(pos($12)) \
       with linespoints lc i pt (i % 13 + 1) ps 1.3 dt 1 title word(problems, i), \
     for [i=1:words(problems)] series(word(problems, i), 4, "default") using 4:(pos($12)) \
       with linespoints lc i pt (i % 13 + 1) ps 1.3 dt 2 notitle, \
     for [i=1:words(problems)] series(word(problems, i), 3, "other") using 4:(pos($12)) \
       with linespoints lc i pt (i % 13 + 1) ps 1.3 dt 3 notitle, \
     for [i=1:words(problems)] ghosts(word(problems, i)) using 4:(pos($12)) \
       with linespoints lc i pt (i % 13 + 1) ps 1.3 dt 4 notitle
