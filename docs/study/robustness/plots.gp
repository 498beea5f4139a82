set datafile separator ','
set terminal svg size 900,560 dynamic
set key outside right
set grid
set output 'step_vs_triangles.svg'
set logscale x
set xlabel 'triangles'
set ylabel 'step median without metrics (us)'
set title 'Step time vs organ size (every motion)'
plot 'robustness.csv' using 4:((strcol(6) eq 'project') ? $8 : NaN) with points pt 7 title 'project', \
     'robustness.csv' using 4:((strcol(6) eq 'sdf') ? $8 : NaN) with points pt 7 title 'sdf', 1000 with lines dt 2 title '1 ms'
set output 'penetration_p99.svg'
set ylabel 'p99 penetration (mm)'
set logscale y
set title 'p99 penetration vs organ size (every motion; runs at 0 not drawn on the log scale)'
plot 'robustness.csv' using 4:((strcol(6) eq 'project' && $18 > 0) ? $18 : NaN) with points pt 7 title 'project', \
     'robustness.csv' using 4:((strcol(6) eq 'sdf' && $18 > 0) ? $18 : NaN) with points pt 7 title 'sdf', 0.5 with lines dt 2 title '0.5 mm'
