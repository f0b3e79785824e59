set terminal pngcairo size 1000,650 font 'sans,11'
set output 'relational-4-750k-distance.png'
set title 'relational-4-750k: average distance of all entities, arm included (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 7
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'relational-4-750k-distance.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'hac (1 seed)', 'relational-4-750k-distance.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'sac_her (1 seed)', 'relational-4-750k-distance.dat' index 2 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#2ca02c' notitle, '' index 2 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#2ca02c' title 'smorl (3 seeds)', 'relational-4-750k-distance.dat' index 3 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#9467bd' notitle, '' index 3 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#9467bd' title 'srics (3 seeds)', 0.150139 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output 'relational-4-750k-object_distance.png'
set title 'relational-4-750k: average object distance (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 7
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'relational-4-750k-object_distance.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'hac (1 seed)', 'relational-4-750k-object_distance.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'sac_her (1 seed)', 'relational-4-750k-object_distance.dat' index 2 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#2ca02c' notitle, '' index 2 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#2ca02c' title 'smorl (3 seeds)', 'relational-4-750k-object_distance.dat' index 3 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#9467bd' notitle, '' index 3 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#9467bd' title 'srics (3 seeds)', 0.187673 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output 'relational-4-750k-selectivity.png'
set title 'relational-4-750k: selectivity of training episodes, the table''s ancestor sets (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'selectivity' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 5
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'relational-4-750k-selectivity.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'smorl (3 seeds)', 'relational-4-750k-selectivity.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'srics (3 seeds)'
set output 'relational-4-750k-undone.png'
set title 'relational-4-750k: solved non-ancestor objects an attempt undid (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'share undone' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 5
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'relational-4-750k-undone.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'smorl (2 seeds)', 'relational-4-750k-undone.dat' index 1 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#d62728' notitle, '' index 1 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#d62728' title 'srics (3 seeds)'
set output 'relational-4-750k-subgoal_success.png'
set title 'relational-4-750k: success per subgoal at the final evaluation (mean, bars ±1 sd over seeds)' noenhanced
set xlabel ''
set ylabel 'success rate'
set yrange [0:1.05]
set grid ytics
set format x '% h'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 6
set style data histograms
set style histogram errorbars gap 2 lw 1
set style fill solid 0.8 border -1
set bars 2
plot 'relational-4-750k-subgoal_success.dat' using 2:3:4:xtic(1) lc rgb '#1f77b4' title 'hac (1 seed)', 'relational-4-750k-subgoal_success.dat' using 5:6:7 lc rgb '#d62728' title 'sac_her (1 seed)', 'relational-4-750k-subgoal_success.dat' using 8:9:10 lc rgb '#2ca02c' title 'smorl (3 seeds)', 'relational-4-750k-subgoal_success.dat' using 11:12:13 lc rgb '#9467bd' title 'srics (3 seeds)'
