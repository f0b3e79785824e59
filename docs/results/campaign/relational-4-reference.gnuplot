set terminal pngcairo size 1000,650 font 'sans,11'
set output '/work/main/docs/results/campaign/relational-4-reference-distance.png'
set title 'relational-4-reference: average distance of all entities, arm included (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 8
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_alpha1 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'srics_chain9 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 2 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#2ca02c' notitle, '' index 2 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#2ca02c' title 'srics_disturb10 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 3 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#9467bd' notitle, '' index 3 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#9467bd' title 'srics_one_way (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 4 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#ff7f0e' notitle, '' index 4 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#ff7f0e' title 'srics_reference_init (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-distance.dat' index 5 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#8c564b' notitle, '' index 5 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#8c564b' title 'srics_two_way (3 seeds)', 0.150183 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output '/work/main/docs/results/campaign/relational-4-reference-object_distance.png'
set title 'relational-4-reference: average object distance (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 8
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_alpha1 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'srics_chain9 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 2 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#2ca02c' notitle, '' index 2 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#2ca02c' title 'srics_disturb10 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 3 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#9467bd' notitle, '' index 3 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#9467bd' title 'srics_one_way (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 4 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#ff7f0e' notitle, '' index 4 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#ff7f0e' title 'srics_reference_init (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-object_distance.dat' index 5 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#8c564b' notitle, '' index 5 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#8c564b' title 'srics_two_way (3 seeds)', 0.187729 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output '/work/main/docs/results/campaign/relational-4-reference-selectivity.png'
set title 'relational-4-reference: selectivity of training episodes, the table''s ancestor sets (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'selectivity' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 7
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_alpha1 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'srics_chain9 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 2 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#2ca02c' notitle, '' index 2 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#2ca02c' title 'srics_disturb10 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 3 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#9467bd' notitle, '' index 3 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#9467bd' title 'srics_one_way (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 4 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#ff7f0e' notitle, '' index 4 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#ff7f0e' title 'srics_reference_init (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-selectivity.dat' index 5 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#8c564b' notitle, '' index 5 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#8c564b' title 'srics_two_way (3 seeds)'
set output '/work/main/docs/results/campaign/relational-4-reference-undone.png'
set title 'relational-4-reference: solved non-ancestor objects an attempt undid (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'share undone' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 7
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot '/work/main/docs/results/campaign/relational-4-reference-undone.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics_alpha1 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-undone.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'srics_chain9 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-undone.dat' index 2 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#2ca02c' notitle, '' index 2 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#2ca02c' title 'srics_disturb10 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-undone.dat' index 3 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#9467bd' notitle, '' index 3 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#9467bd' title 'srics_one_way (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-undone.dat' index 4 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#ff7f0e' notitle, '' index 4 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#ff7f0e' title 'srics_reference_init (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-undone.dat' index 5 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#8c564b' notitle, '' index 5 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#8c564b' title 'srics_two_way (2 seeds)'
set output '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.png'
set title 'relational-4-reference: success per subgoal at the final evaluation (mean, bars ±1 sd over seeds)' noenhanced
set xlabel ''
set ylabel 'success rate'
set yrange [0:1.05]
set grid ytics
set format x '% h'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 7
set style data histograms
set style histogram errorbars gap 2 lw 1
set style fill solid 0.8 border -1
set bars 2
plot '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 2:3:4:xtic(1) lc rgb '#1f77b4' title 'srics_alpha1 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 5:6:7 lc rgb '#d62728' title 'srics_chain9 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 8:9:10 lc rgb '#2ca02c' title 'srics_disturb10 (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 11:12:13 lc rgb '#9467bd' title 'srics_one_way (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 14:15:16 lc rgb '#ff7f0e' title 'srics_reference_init (3 seeds)', '/work/main/docs/results/campaign/relational-4-reference-subgoal_success.dat' using 17:18:19 lc rgb '#8c564b' title 'srics_two_way (3 seeds)'
