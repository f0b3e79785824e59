set terminal pngcairo size 1000,650 font 'sans,11'
set output 'different-6-distance.png'
set title 'different-6: average distance of all entities, arm included (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 5
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'different-6-distance.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics (1 seed)', 0.169965 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output 'different-6-object_distance.png'
set title 'different-6: average object distance (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'final distance to goal (m)' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 5
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'different-6-object_distance.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics (1 seed)', 0.198292 with lines dt 2 lw 2 lc rgb 'gray' title 'passive policy'
set output 'different-6-selectivity.png'
set title 'different-6: selectivity of training episodes, the table''s ancestor sets (mean, band ±1 sd over seeds)' noenhanced
set xlabel 'environment steps'
set ylabel 'selectivity' noenhanced
set format x '%.0s%c'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 5
set grid
set yrange [0:*]
set style fill transparent solid 0.2 noborder
plot 'different-6-selectivity.dat' index 0 using 1:($2-$6):($2+$6) with filledcurves lc rgb '#1f77b4' notitle, '' index 0 using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4' title 'srics (1 seed)'
set output 'different-6-subgoal_success.png'
set title 'different-6: success per subgoal at the final evaluation (mean, bars ±1 sd over seeds)' noenhanced
set xlabel ''
set ylabel 'success rate'
set yrange [0:1.05]
set grid ytics
set format x '% h'
set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced
set bmargin 5
set style data histograms
set style histogram errorbars gap 2 lw 1
set style fill solid 0.8 border -1
set bars 2
plot 'different-6-subgoal_success.dat' using 2:3:4:xtic(1) lc rgb '#1f77b4' title 'srics (1 seed)'
