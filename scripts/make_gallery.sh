#!/usr/bin/env bash
# Runs every example and renders its last frame into docs/gallery/NAME.png, the stills of
# docs/gallery.md. Usage: bash scripts/make_gallery.sh [NAME ...]   (default: every example)
#   THREADS=2 (tear run/render threads), OUT=out/gallery (run folders), SIZE=480x270,
#   TEAR=./build/tear (the executable)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${OUT:-out/gallery}
threads=${THREADS:-2}
size=${SIZE:-480x270}
tear=${TEAR:-./build/tear}
names=("$@")
if ((${#names[@]} == 0)); then
  for f in examples/*.json; do names+=("$(basename "$f" .json)"); done
fi
mkdir -p docs/gallery
for n in "${names[@]}"; do
  scene=examples/$n.json
  [[ -f $scene ]] || { echo "make_gallery: $scene: no such example" >&2; exit 1; }
  # Damage where the scene can crack, otherwise the fibers where they are stiffer than the
  # matrix (a non-zero fiber_scale), otherwise the speed.
  if grep -q '"sigma_c"' "$scene"; then color=damage
  elif grep -q '"fiber_scale": *\[[^]]*[1-9]' "$scene"; then color=fibers
  else color=velocity; fi
  echo "== $n ($color)"
  "$tear" run "$scene" -o "$out/$n" --threads "$threads" -q
  last=$(ls "$out/$n/frames" | sed -n 's/^\([0-9]*\)\.[a-z]*$/\1/p' | sort -n | tail -1)
  "$tear" render "$out/$n" --frames "$((10#$last))" --color "$color" \
    --width "${size%x*}" --height "${size#*x}" --threads "$threads" --no-video
  # 256-colour palette: a third of the size, no visible change at this size.
  ffmpeg -loglevel error -y -i "$out/$n/render/$last.png" \
    -vf "split[a][b];[a]palettegen=max_colors=256[p];[b][p]paletteuse=dither=none" \
    "docs/gallery/$n.png"
done
