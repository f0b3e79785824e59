# gnuplot docs/results/default-run-secure-vs-open.gp, run from docs/results/ (the figure in docs/results.md)
set datafile separator ','
set terminal pngcairo size 900,500 font ',11'
set output 'default-run-secure-vs-open.png'
set title 'Default run (Relational Rearrange 2), open vs DDS Security, one seed each'
set xlabel 'env steps'
set ylabel 'avg object distance (m), 20 evaluation episodes'
set key top right
set grid
plot 'default-run-relational-2-eval.csv' every ::1 using 6:($4 > 0 ? $9 : 1/0) with linespoints lw 2 title 'open (AVX2 EPYC)', \
     'default-run-relational-2-secure-eval.csv' every ::1 using 6:($4 > 0 ? $9 : 1/0) with linespoints lw 2 title 'secure: transport.security.keystore (AVX-512 EPYC)', \
     0.1423 with lines dt 2 lc rgb 'gray40' title 'passive policy (0.142)'
