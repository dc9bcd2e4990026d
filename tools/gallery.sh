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
# The same sky with the chart overlay (figures, constellation, star and planet names).
"$himmel" render --time 2024-01-15T21:00:00Z --lat 48.14 --lon 11.58 --width 480 --height 480 \
  --effects stars,planets,milkyway,atmosphere --exposure -6 --overlay constellations,labels \
  --output "$out/night-overlay.png"
ls -l "$out"

# 3D worlds (wgpu; lavapipe without a GPU): the sun room at noon and in a
# low winter Sun, the atrium in the afternoon, plane + boxes and Marienplatz
# under a full Moon.
w=tests/fixtures/worlds
world=(--backend wgpu --projection perspective --fov 60 --width 480 --height 270)
# The sun room with its cases' sky-light settings (cells in parts for the
# window, 3 x 3 sets of 192 directions: tools/sun_room_lighting.json).
room=(--scene tools/sun_room_lighting.json --world $w/sun_room.glb)
"$himmel" render "${world[@]}" "${room[@]}" --time 2024-04-15T11:45:00Z --lat 48.14 --lon 11.58 \
  --camera-pos=-2.2,1.6,-2 --look-at=0.2,0,1.3 --exposure 12 --output "$out/world-sun-room-noon.png"
"$himmel" render "${world[@]}" "${room[@]}" --time 2024-12-21T11:45:00Z --lat 56.5 --lon 10 \
  --camera-pos=2.4,1.6,2.1 --look-at=-0.6,0.6,-2.5 --output "$out/world-sun-room-winter.png"
"$himmel" render "${world[@]}" --world $w/atrium.glb --time 2024-06-21T15:00:00Z --lat 48.14 --lon 11.58 \
  --camera-pos=8,1.7,8 --look-at=-5,3,-5 --exposure 14 --output "$out/world-atrium.png"
"$himmel" render "${world[@]}" --world $w/plane_and_boxes.glb --time 2024-10-17T23:30:00Z --lat 48.14 --lon 11.58 \
  --camera-pos=8,3,8 --look-at=0,0.5,-2 --output "$out/world-moonlit.png"
# Munich's Marienplatz (OpenStreetMap via sionna-rt, tools/sionna_world.py)
# under the same full Moon, looking at the Neues Rathaus' tower.
"$himmel" render "${world[@]}" --world $w/munich_marienplatz.glb --time 2024-10-17T23:30:00Z \
  --lat 48.1372 --lon 11.5755 --camera-pos=-35,1.7,15 --look-at=15,25,-20 --output "$out/world-marienplatz-moonlit.png"
