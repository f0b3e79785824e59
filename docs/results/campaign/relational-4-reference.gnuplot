set terminal pngcairo size 1000,600 font 'sans,11'
set output '/work/main/docs/results/campaign/relational-4-reference-distance.png'
set title 'relational-4-reference: average distance of all entities, arm included (mean, band min-max over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set key outside right top noenhanced
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 0 using 1:3:4 with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_two_way (1 seed)', 0.150004 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output '/work/main/docs/results/campaign/relational-4-reference-object_distance.png'
set title 'relational-4-reference: average object distance (mean, band min-max over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set key outside right top noenhanced
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 0 using 1:3:4 with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_two_way (1 seed)', 0.187505 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output '/work/main/docs/results/campaign/relational-4-reference-selectivity.png'
set title 'relational-4-reference: selectivity of training episodes, the table''s ancestor sets (mean, band min-max over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'selectivity' noenhanced
set key outside right top noenhanced
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 0 using 1:3:4 with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_two_way (1 seed)'
set output '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.png'
set title 'relational-4-reference: success per subgoal at the final evaluation (mean over seeds, bars min-max)' noenhanced
set xlabel ''
set ylabel 'success rate'
set yrange [0:1.05]
set grid ytics
set key noenhanced
set style data histograms
set style histogram errorbars gap 2 lw 1
set style fill solid 0.8 border -1
set bars 2
plot '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 2:3:4:xtic(1) lc rgb '#1f77b4' title 'srics_two_way (1 seed)'
