#!/bin/sh
# The route demo's plot: each imported route's elevation (the track's points
# and the profile its smoothed grades add up to) and route_choice's
# predicted fuel with its lower and upper bound.
#
#   scripts/route_demo_plot.sh DIR NAME...
#
# Reads DIR/NAME.elevation.csv (roadimport --elevation-out) and
# DIR/choice.txt (route_choice's output); writes DIR/bounds.dat,
# DIR/route_demo.gp and DIR/route_demo.png. Exit status 0, 1 when a file is
# missing or gnuplot fails.
set -eu
dir=$1
shift
awk '$1 ~ /^[0-9]+$/ && $2 ~ /\.csv$/ { sub(/\.csv$/, "", $2); print NR, $2, $4, $5, $7 }' \
    "$dir/choice.txt" > "$dir/bounds.dat"
[ -s "$dir/bounds.dat" ] || { echo "route_demo_plot: no routes in $dir/choice.txt" >&2; exit 1; }
gp=$dir/route_demo.gp
{
    echo "set terminal pngcairo noenhanced size 1100,900 font 'sans,10'"
    echo "set output '$dir/route_demo.png'"
    echo "set datafile separator ','"
    echo "set multiplot layout 2,1 title 'Imported routes (roadimport) and route_choice: predicted fuel and bounds' font 'sans,12'"
    echo "set grid; set key top left opaque box"
    echo "set xlabel 'distance (km)'; set ylabel 'elevation (m)'"
    printf "plot "
    sep=""
    c=0
    for r in "$@"; do
        c=$((c + 1))
        printf "%s'%s/%s.elevation.csv' skip 1 every 20 using (\$1/1000):2 with points pt 7 ps 0.3 lc %d notitle, \\\\\n" \
            "$sep" "$dir" "$r" "$c"
        printf "     '%s/%s.elevation.csv' skip 1 using (\$1/1000):3 with lines lw 2 lc %d title '%s (track points; its smoothed grades added up)'" \
            "$dir" "$r" "$c" "$r"
        sep=", \\
     "
    done
    echo
    echo "set datafile separator whitespace"
    echo "set xlabel 'route'; set ylabel 'platoon fuel (L)'; set key top left"
    echo "set style fill solid 0.4; set boxwidth 0.5; set xrange [-0.5:$(($# - 1)).5]; set yrange [0:*]"
    echo "plot '$dir/bounds.dat' using (\$0):3:xtic(2) with boxes lc rgb '#1f77b4' title 'predicted (object model)', \\"
    echo "     '' using (\$0):3:4:5 with yerrorbars lc rgb '#000000' lw 2 pt 0 title 'lower and upper bound'"
    echo "unset multiplot"
} > "$gp"
gnuplot "$gp"
echo "route_demo_plot: $dir/route_demo.png (gnuplot script $gp)"
