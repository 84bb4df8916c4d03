#!/usr/bin/env bash
# Runs examples and renders their last frame into the stills of docs/gallery.md:
# docs/gallery/NAME.png for examples/NAME.json, and for the paper's demos (examples/paper/)
# docs/gallery/paper/NAME.png (world space) and NAME_rest.png (material space), and for the
# cloth, yarn and hair scenes (examples/codimensional/) docs/gallery/codimensional/NAME.png,
# and likewise for the FEM scenes (examples/fem/) docs/gallery/fem/NAME.png.
# Usage: bash scripts/make_gallery.sh [NAME | paper/NAME | paper | codimensional/NAME |
#   codimensional | fem/NAME | fem ...] (default: every example in examples/; "paper",
#   "codimensional", "fem": every scene in that folder)
#   THREADS=2 (tear run/render threads), OUT=out/gallery (run folders), SIZE=480x270,
#   TEAR=./build/tear (the executable), NO_RUN=1 (render runs already in OUT, run only the
#   missing ones)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${OUT:-out/gallery}
threads=${THREADS:-2}
size=${SIZE:-480x270}
tear=${TEAR:-./build/tear}
names=()
for a in "$@"; do
  if [[ $a == paper || $a == codimensional || $a == fem ]]; then
    for f in examples/$a/*.json; do names+=("$a/$(basename "$f" .json)"); done
  else
    names+=("$a")
  fi
done
if ((${#names[@]} == 0)); then
  for f in examples/*.json; do names+=("$(basename "$f" .json)"); done
fi
still() {  # still RUN_DIR FRAME COLOR OUT.png [render options]
  local run=$1 frame=$2 color=$3 png=$4
  shift 4
  "$tear" render "$run" --frames "$((10#$frame))" --color "$color" \
    --width "${size%x*}" --height "${size#*x}" --threads "$threads" --no-video -q "$@"
  # 256-colour palette: a third of the size, no visible change at this size.
  ffmpeg -loglevel error -y -i "$run/render/$frame.png" \
    -vf "split[a][b];[a]palettegen=max_colors=256[p];[b][p]paletteuse=dither=none" "$png"
}
mkdir -p docs/gallery/paper docs/gallery/codimensional docs/gallery/fem
for n in "${names[@]}"; do
  scene=examples/$n.json
  [[ -f $scene ]] || { echo "make_gallery: $scene: no such example" >&2; exit 1; }
  # The scene's render.color if it has one; else damage where the scene can crack, otherwise
  # the fibers where they are stiffer than the matrix (a non-zero fiber_scale), otherwise the
  # speed.
  color=$(sed -n 's/.*"color": *"\([a-z_]*\)".*/\1/p' "$scene" | head -1)
  if [[ -n $color ]]; then :
  elif grep -q '"sigma_c"' "$scene"; then color=damage
  elif grep -q '"fiber_scale": *\[[^]]*[1-9]' "$scene"; then color=fibers
  else color=velocity; fi
  run=$out/$(basename "$n")
  echo "== $n ($color)"
  if [[ ${NO_RUN:-0} != 1 || ! -f $run/stats.jsonl ]]; then
    "$tear" run "$scene" -o "$run" --threads "$threads" -q
  fi
  last=$(ls "$run/frames" | sed -n 's/^\([0-9]*\)\.[a-z]*$/\1/p' | sort -n | tail -1)
  if [[ $n == paper/* ]]; then
    still "$run" "$last" "$color" "docs/gallery/$n.png"
    still "$run" "$last" "$color" "docs/gallery/${n}_rest.png" --space rest
  else
    still "$run" "$last" "$color" "docs/gallery/$n.png"
  fi
done
