#!/usr/bin/env bash
# Frame times of two `himmel` builds in the same run: each scene × size ×
# backend is rendered by OLD and NEW alternately, RUNS times, and the
# median of `--stats` `render_ms` (the frame with read-back) and of
# `total_ms` is printed; the EXR outputs of the last runs are compared
# (bit identity and relative luminance differences, examples/exr_diff.rs).
#
#   tools/bench_compare.sh OLD/himmel NEW/himmel [RUNS]
#
# SIZES and BACKENDS (space-separated) restrict the table. With FORMAT=png
# the timed frames are written as PNG (`write_ms`: camera model, encoding,
# sync) and one more EXR frame of each build is rendered for the comparison.
# The LUT disk cache lives in a scratch directory, warmed by a first
# render of each binary, so no run includes a LUT precompute.
set -euo pipefail
old=$1 new=$2 runs=${3:-5}
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
export HIMMEL_CACHE_DIR=$work/cache NODEVICE_SELECT=1
diff_tool=${CARGO_TARGET_DIR:-$root/target}/release/examples/exr_diff
format=${FORMAT:-exr}
[ -x "$diff_tool" ] || cargo build -q --release -p himmel-cpu --example exr_diff --manifest-path "$root/Cargo.toml"
median() { sort -g | awk '{v[NR]=$1} END {print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }
scenes=(
  "day|--time 2024-06-21T11:00:00Z --lat 48.14 --lon 11.58"
  "moonlit night|--time 2024-01-25T20:00:00Z --lat 48.14 --lon 11.58"
)
printf '| scene | size | backend | old render_ms | new render_ms | old write_ms (%s) | new write_ms (%s) | old total_ms | new total_ms | images |\n|---|---|---|---|---|---|---|---|---|---|\n' "$format" "$format"
for entry in "${scenes[@]}"; do
  name=${entry%%|*}; args=${entry#*|}
  for size in ${SIZES:-1024x1024 1920x1080}; do
    w=${size%x*}; h=${size#*x}
    for backend in ${BACKENDS:-cpu wgpu}; do
      for bin in "$old" "$new"; do  # warm the cache and the shader cache
        "$bin" render $args --width "$w" --height "$h" --backend "$backend" --output "$work/warm.exr" >/dev/null 2>&1
      done
      : >"$work/old_r" >"$work/new_r" >"$work/old_t" >"$work/new_t" >"$work/old_w" >"$work/new_w"
      for _ in $(seq "$runs"); do
        for tag in old new; do
          bin=$old; [ $tag = new ] && bin=$new
          "$bin" render $args --width "$w" --height "$h" --backend "$backend" \
            --output "$work/$tag.$format" --stats "$work/$tag.json" >/dev/null 2>&1
          field "$work/$tag.json" render_ms >>"$work/${tag}_r"
          field "$work/$tag.json" write_ms >>"$work/${tag}_w"
          field "$work/$tag.json" total_ms >>"$work/${tag}_t"
        done
      done
      if [ "$format" != exr ]; then
        for tag in old new; do
          bin=$old; [ $tag = new ] && bin=$new
          "$bin" render $args --width "$w" --height "$h" --backend "$backend" --output "$work/$tag.exr" >/dev/null 2>&1
        done
      fi
      cmp=$("$diff_tool" "$work/old.exr" "$work/new.exr" | sed 's/^[0-9]*×[0-9]*: //')
      printf '| %s | %s | %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %s |\n' "$name" "$size" "$backend" \
        "$(median <"$work/old_r")" "$(median <"$work/new_r")" \
        "$(median <"$work/old_w")" "$(median <"$work/new_w")" \
        "$(median <"$work/old_t")" "$(median <"$work/new_t")" "$cmp"
    done
  done
done
rm -rf "$work"
