# Draws the bench report's plots from frames.csv (run from the report's directory).
set terminal pngcairo size 960,300 font 'sans,9'
set datafile separator comma
set datafile missing 'NaN'
set key top left opaque
set grid ytics lc rgb '#dddddd'
set xlabel 'frame'
set yrange [0:*]
set xrange [0:6799]
set output 'frame_time.png'
set ylabel 'ms'
plot 'frames.csv' skip 1 using 1:2 with lines lc rgb '#1f77b4' title 'frame time', \
  90.2417 with lines dt 2 lc rgb '#2ca02c' title 'p50 90.2 ms', \
  155.088 with lines dt 2 lc rgb '#d62728' title 'p99 155.1 ms', \
  '' skip 1 using 1:4 with lines lc rgb '#ff7f0e' title 'uploads'
set output 'selection_time.png'
set ylabel 'µs'
plot 'frames.csv' skip 1 using 1:3 with lines lc rgb '#9467bd' title 'selection'
set output 'triangles.png'
set ylabel 'triangles'
set y2label 'draw calls'
set y2tics
set y2range [0:*]
plot 'frames.csv' skip 1 using 1:5 with lines lc rgb '#1f77b4' title 'triangles', \
  '' skip 1 using 1:6 axes x1y2 with lines lc rgb '#ff7f0e' title 'draw calls'
unset y2tics
unset y2label
set output 'resident_mb.png'
set ylabel 'MB'
plot 'frames.csv' skip 1 using 1:10 with lines lc rgb '#1f77b4' title 'resident', \
  256 with lines dt 2 lc rgb '#d62728' title 'budget 256 MB', \
  '' skip 1 using 1:($11 > 0 ? 0 : NaN) with points pt 7 ps 0.3 lc rgb '#ff7f0e' title 'frames coarser than wanted'
set output 'error_px.png'
set ylabel 'pixels'
set yrange [0:3]
plot 'frames.csv' skip 1 using 1:($11 > 0 ? NaN : $16) with lines lc rgb '#1f77b4' title 'screen-space error', \
  '' skip 1 using 1:17 with lines lc rgb '#2ca02c' title 'pop', \
  2 with lines dt 2 lc rgb '#d62728' title 'τ = 2', \
  '' skip 1 using 1:($11 > 0 ? $16 : NaN) with points pt 7 ps 0.3 lc rgb '#aaaaaa' title 'error while streaming (coarser than wanted)'
