#!/usr/bin/env bash
# Regenerates the README gallery (docs/gallery/*.png): Munich, 21 June 2024,
# all-sky fisheye (North up, East left) and a western equirect panorama band,
# automatic exposure. Run from the repository root:  bash tools/gallery.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p himmel-cli
himmel=./target/release/himmel
out=docs/gallery
mkdir -p "$out"
common=(--lat 48.14 --lon 11.58 --width 320 --height 320 --projection fisheye)
"$himmel" render --time 2024-06-21T11:15:00Z "${common[@]}" --output "$out/noon.png"            # Sun +65°
"$himmel" render --time 2024-06-21T19:05:00Z "${common[@]}" --output "$out/sunset.png"          # Sun +1.2°
"$himmel" render --time 2024-06-21T19:45:00Z "${common[@]}" --output "$out/civil-twilight.png"  # Sun −4.3°
# Perspective view towards the sunset (azimuth 300°, 60° field of view).
"$himmel" render --time 2024-06-21T19:05:00Z --lat 48.14 --lon 11.58 --width 480 --height 240 \
  --projection perspective --yaw 300 --pitch 12 --fov 40 --output "$out/sunset-west.png"
# Eclipses (fixed exposure): totality over Dallas 2024-04-08 (3° on the Sun);
# the lunar eclipse of 2025-03-14 from Mexico City, partial and at greatest.
"$himmel" render --time 2024-04-08T18:42:39Z --lat 32.7767 --lon -96.797 --effects atmosphere,sun,moon \
  --exposure 8 --projection perspective --fov 3 --yaw 188.019 --pitch 64.625 --width 320 --height 320 \
  --output "$out/solar-eclipse-dallas.png"
"$himmel" render --time 2025-03-14T05:35:00Z --lat 19.43 --lon -99.13 --projection perspective --fov 0.6 \
  --yaw 132.0785 --pitch 66.1103 --effects moon,atmosphere --exposure 7 --width 320 --height 320 \
  --output "$out/lunar-eclipse-2025-partial.png"
"$himmel" render --time 2025-03-14T06:58:43Z --lat 19.43 --lon -99.13 --projection perspective --fov 0.6 \
  --yaw 190.657 --pitch 72.716 --effects moon,atmosphere --exposure 3 --width 320 --height 320 \
  --output "$out/lunar-eclipse-2025.png"
# Night: stars, planets, Milky Way (Munich, 15 January 2024, 22:00 local time), fixed exposure.
"$himmel" render --time 2024-01-15T21:00:00Z --lat 48.14 --lon 11.58 --width 480 --height 480 \
  --effects stars,planets,milkyway,atmosphere --exposure -6 --output "$out/night.png"
ls -l "$out"
