#!/bin/sh
# Made-up GPX tracks for make route-demo: three roads between the same two
# places, written as a navigation system's track log would hold them: a
# point every 10 m along the meridian 16 deg E northwards from 58 deg N,
# elevations with GNSS-like noise (uniform +-3 m from a fixed-seed
# Park-Miller generator, exact in double precision, so every run writes the
# same files).
#
#   scripts/demo_gpx.sh OUT_DIR
#
#   pass.gpx    18 km: 3 km flat, 3 km at +4 %, 3 km at -4 %, 9 km flat
#   valley.gpx  22 km: rolling, grade 2.5 % sin(2 pi x / 4 km)
#   coast.gpx   26 km: grade 0.8 % sin(2 pi x / 6 km), nearly flat
set -eu
out=$1
mkdir -p "$out"
gen() {
    name=$1 length=$2 shape=$3
    awk -v name="$name" -v L="$length" -v shape="$shape" 'BEGIN {
        pi = 3.14159265358979; R = 6371008.8; step = 10; s = 4242;
        printf "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<gpx version=\"1.1\" creator=\"demo_gpx.sh\">\n";
        printf "<trk><name>%s</name><trkseg>\n", name;
        h = 120;
        for (x = 0; x <= L; x += step) {
            if (shape == "pass") g = (x < 3000) ? 0 : (x < 6000) ? 0.04 : (x < 9000) ? -0.04 : 0;
            else if (shape == "valley") g = 0.025 * sin(2 * pi * x / 4000);
            else g = 0.008 * sin(2 * pi * x / 6000);
            s = (s * 16807) % 2147483647;
            noise = (s / 2147483647) * 6 - 3;
            lat = 58 + (x / R) * 180 / pi;
            printf "  <trkpt lat=\"%.7f\" lon=\"16.0000000\"><ele>%.1f</ele></trkpt>\n", lat, h + noise;
            h += g * step;
        }
        printf "</trkseg></trk>\n</gpx>\n" }' > "$out/$name.gpx"
}
gen pass 18000 pass
gen valley 22000 valley
gen coast 26000 coast
echo "demo_gpx: $out/pass.gpx $out/valley.gpx $out/coast.gpx"
