set datafile separator ','
set terminal svg size 900,560 dynamic
set logscale x
set xlabel 'instrument speed (m/s)'
set key outside right
set grid
set output 'probe_press_slide_penetration_max.svg'
set ylabel 'max penetration (mm)'
set title 'probe_press_slide: max penetration (mm) vs speed'
plot 'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 1) ? $6 : NaN) with linespoints title 'normal 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 2) ? $6 : NaN) with linespoints title 'normal 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 5) ? $6 : NaN) with linespoints title 'normal 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 1) ? $6 : NaN) with linespoints title 'obb 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 2) ? $6 : NaN) with linespoints title 'obb 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 5) ? $6 : NaN) with linespoints title 'obb 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 1) ? $6 : NaN) with linespoints title 'obb-uncapped 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 2) ? $6 : NaN) with linespoints title 'obb-uncapped 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 5) ? $6 : NaN) with linespoints title 'obb-uncapped 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 1) ? $6 : NaN) with linespoints title 'primitive 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 2) ? $6 : NaN) with linespoints title 'primitive 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 5) ? $6 : NaN) with linespoints title 'primitive 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 1) ? $6 : NaN) with linespoints title 'primitive-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 2) ? $6 : NaN) with linespoints title 'primitive-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 5) ? $6 : NaN) with linespoints title 'primitive-ungated 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 1) ? $6 : NaN) with linespoints title 'project 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 2) ? $6 : NaN) with linespoints title 'project 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 5) ? $6 : NaN) with linespoints title 'project 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 1) ? $6 : NaN) with linespoints title 'project-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 2) ? $6 : NaN) with linespoints title 'project-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 5) ? $6 : NaN) with linespoints title 'project-ungated 5 ms'
set output 'probe_press_slide_penetration_p99.svg'
set ylabel 'p99 penetration (mm)'
set title 'probe_press_slide: p99 penetration (mm) vs speed'
plot 'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 1) ? $7 : NaN) with linespoints title 'normal 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 2) ? $7 : NaN) with linespoints title 'normal 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 5) ? $7 : NaN) with linespoints title 'normal 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 1) ? $7 : NaN) with linespoints title 'obb 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 2) ? $7 : NaN) with linespoints title 'obb 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 5) ? $7 : NaN) with linespoints title 'obb 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 1) ? $7 : NaN) with linespoints title 'obb-uncapped 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 2) ? $7 : NaN) with linespoints title 'obb-uncapped 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 5) ? $7 : NaN) with linespoints title 'obb-uncapped 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 1) ? $7 : NaN) with linespoints title 'primitive 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 2) ? $7 : NaN) with linespoints title 'primitive 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 5) ? $7 : NaN) with linespoints title 'primitive 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 1) ? $7 : NaN) with linespoints title 'primitive-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 2) ? $7 : NaN) with linespoints title 'primitive-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 5) ? $7 : NaN) with linespoints title 'primitive-ungated 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 1) ? $7 : NaN) with linespoints title 'project 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 2) ? $7 : NaN) with linespoints title 'project 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 5) ? $7 : NaN) with linespoints title 'project 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 1) ? $7 : NaN) with linespoints title 'project-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 2) ? $7 : NaN) with linespoints title 'project-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 5) ? $7 : NaN) with linespoints title 'project-ungated 5 ms'
set output 'probe_press_slide_tunneling.svg'
set ylabel 'tunneling events'
set title 'probe_press_slide: tunneling events vs speed'
plot 'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 1) ? $8 : NaN) with linespoints title 'normal 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 2) ? $8 : NaN) with linespoints title 'normal 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'normal' && $3 == 5) ? $8 : NaN) with linespoints title 'normal 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 1) ? $8 : NaN) with linespoints title 'obb 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 2) ? $8 : NaN) with linespoints title 'obb 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb' && $3 == 5) ? $8 : NaN) with linespoints title 'obb 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 1) ? $8 : NaN) with linespoints title 'obb-uncapped 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 2) ? $8 : NaN) with linespoints title 'obb-uncapped 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'obb-uncapped' && $3 == 5) ? $8 : NaN) with linespoints title 'obb-uncapped 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 1) ? $8 : NaN) with linespoints title 'primitive 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 2) ? $8 : NaN) with linespoints title 'primitive 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive' && $3 == 5) ? $8 : NaN) with linespoints title 'primitive 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 1) ? $8 : NaN) with linespoints title 'primitive-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 2) ? $8 : NaN) with linespoints title 'primitive-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'primitive-ungated' && $3 == 5) ? $8 : NaN) with linespoints title 'primitive-ungated 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 1) ? $8 : NaN) with linespoints title 'project 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 2) ? $8 : NaN) with linespoints title 'project 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project' && $3 == 5) ? $8 : NaN) with linespoints title 'project 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 1) ? $8 : NaN) with linespoints title 'project-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 2) ? $8 : NaN) with linespoints title 'project-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'probe_press_slide' && strcol(2) eq 'project-ungated' && $3 == 5) ? $8 : NaN) with linespoints title 'project-ungated 5 ms'
set output 'stab_penetration_max.svg'
set ylabel 'max penetration (mm)'
set title 'stab: max penetration (mm) vs speed'
plot 'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 1) ? $6 : NaN) with linespoints title 'normal 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 2) ? $6 : NaN) with linespoints title 'normal 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 5) ? $6 : NaN) with linespoints title 'normal 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 1) ? $6 : NaN) with linespoints title 'obb 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 2) ? $6 : NaN) with linespoints title 'obb 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 5) ? $6 : NaN) with linespoints title 'obb 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 1) ? $6 : NaN) with linespoints title 'obb-uncapped 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 2) ? $6 : NaN) with linespoints title 'obb-uncapped 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 5) ? $6 : NaN) with linespoints title 'obb-uncapped 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 1) ? $6 : NaN) with linespoints title 'primitive 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 2) ? $6 : NaN) with linespoints title 'primitive 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 5) ? $6 : NaN) with linespoints title 'primitive 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 1) ? $6 : NaN) with linespoints title 'primitive-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 2) ? $6 : NaN) with linespoints title 'primitive-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 5) ? $6 : NaN) with linespoints title 'primitive-ungated 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 1) ? $6 : NaN) with linespoints title 'project 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 2) ? $6 : NaN) with linespoints title 'project 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 5) ? $6 : NaN) with linespoints title 'project 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 1) ? $6 : NaN) with linespoints title 'project-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 2) ? $6 : NaN) with linespoints title 'project-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 5) ? $6 : NaN) with linespoints title 'project-ungated 5 ms'
set output 'stab_penetration_p99.svg'
set ylabel 'p99 penetration (mm)'
set title 'stab: p99 penetration (mm) vs speed'
plot 'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 1) ? $7 : NaN) with linespoints title 'normal 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 2) ? $7 : NaN) with linespoints title 'normal 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 5) ? $7 : NaN) with linespoints title 'normal 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 1) ? $7 : NaN) with linespoints title 'obb 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 2) ? $7 : NaN) with linespoints title 'obb 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 5) ? $7 : NaN) with linespoints title 'obb 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 1) ? $7 : NaN) with linespoints title 'obb-uncapped 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 2) ? $7 : NaN) with linespoints title 'obb-uncapped 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 5) ? $7 : NaN) with linespoints title 'obb-uncapped 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 1) ? $7 : NaN) with linespoints title 'primitive 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 2) ? $7 : NaN) with linespoints title 'primitive 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 5) ? $7 : NaN) with linespoints title 'primitive 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 1) ? $7 : NaN) with linespoints title 'primitive-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 2) ? $7 : NaN) with linespoints title 'primitive-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 5) ? $7 : NaN) with linespoints title 'primitive-ungated 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 1) ? $7 : NaN) with linespoints title 'project 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 2) ? $7 : NaN) with linespoints title 'project 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 5) ? $7 : NaN) with linespoints title 'project 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 1) ? $7 : NaN) with linespoints title 'project-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 2) ? $7 : NaN) with linespoints title 'project-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 5) ? $7 : NaN) with linespoints title 'project-ungated 5 ms'
set output 'stab_tunneling.svg'
set ylabel 'tunneling events'
set title 'stab: tunneling events vs speed'
plot 'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 1) ? $8 : NaN) with linespoints title 'normal 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 2) ? $8 : NaN) with linespoints title 'normal 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'normal' && $3 == 5) ? $8 : NaN) with linespoints title 'normal 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 1) ? $8 : NaN) with linespoints title 'obb 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 2) ? $8 : NaN) with linespoints title 'obb 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb' && $3 == 5) ? $8 : NaN) with linespoints title 'obb 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 1) ? $8 : NaN) with linespoints title 'obb-uncapped 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 2) ? $8 : NaN) with linespoints title 'obb-uncapped 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'obb-uncapped' && $3 == 5) ? $8 : NaN) with linespoints title 'obb-uncapped 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 1) ? $8 : NaN) with linespoints title 'primitive 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 2) ? $8 : NaN) with linespoints title 'primitive 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive' && $3 == 5) ? $8 : NaN) with linespoints title 'primitive 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 1) ? $8 : NaN) with linespoints title 'primitive-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 2) ? $8 : NaN) with linespoints title 'primitive-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'primitive-ungated' && $3 == 5) ? $8 : NaN) with linespoints title 'primitive-ungated 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 1) ? $8 : NaN) with linespoints title 'project 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 2) ? $8 : NaN) with linespoints title 'project 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project' && $3 == 5) ? $8 : NaN) with linespoints title 'project 5 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 1) ? $8 : NaN) with linespoints title 'project-ungated 1 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 2) ? $8 : NaN) with linespoints title 'project-ungated 2 ms', \
     'penetration.csv' using 4:((strcol(1) eq 'stab' && strcol(2) eq 'project-ungated' && $3 == 5) ? $8 : NaN) with linespoints title 'project-ungated 5 ms'
