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
# Night: stars, planets, Milky Way (Munich, 15 January 2024, 22:00 local time), fixed exposure.
"$himmel" render --time 2024-01-15T21:00:00Z --lat 48.14 --lon 11.58 --width 480 --height 480 \
  --effects stars,planets,milkyway,atmosphere --exposure -6 --output "$out/night.png"
ls -l "$out"
