#!/usr/bin/env bash
# Compare two tear builds on every example: run each for a few frames with both and check that
# the frames are byte-identical and stats.jsonl is identical except wall times. For
# restructurings that must not change results (and to see what a change does change).
#   bash scripts/compare_builds.sh OLD_TEAR NEW_TEAR [FRAMES] [EXAMPLE.json ...]
# FRAMES defaults to 6 (the damage examples crack from frame 3 to 9); the examples default to
# examples/*.json. Exit status 0 when every example matches, 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
if (($# < 2)); then
  echo "usage: bash scripts/compare_builds.sh OLD_TEAR NEW_TEAR [FRAMES] [EXAMPLE.json ...]" >&2
  exit 2
fi
old=$(realpath "$1") new=$(realpath "$2")
frames=${3:-6}
shift $(($# < 3 ? $# : 3))
scenes=("$@")
((${#scenes[@]})) || scenes=(examples/*.json)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# stats.jsonl without the wall times, one line per frame.
strip_wall() { python3 -c '
import json, sys
for line in open(sys.argv[1]):
    d = json.loads(line); d.pop("wall_s", None); print(json.dumps(d, sort_keys=True))' "$1"; }

status=0
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  for which in old new; do
    bin=$old; [[ $which == new ]] && bin=$new
    start=$EPOCHREALTIME
    "$bin" run "$scene" -o "$work/$which/$name" --frames "$frames" --quiet --threads 2 >/dev/null
    awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }' \
      > "$work/$which/$name.seconds"
  done
  a=$work/old/$name b=$work/new/$name
  why=()
  for f in "$a"/frames/*; do
    cmp -s "$f" "$b/frames/$(basename "$f")" || why+=("frames/$(basename "$f")")
  done
  [[ $(ls "$a/frames" | wc -l) == $(ls "$b/frames" | wc -l) ]] || why+=("frame count")
  cmp -s <(strip_wall "$a/stats.jsonl") <(strip_wall "$b/stats.jsonl") || why+=("stats.jsonl")
  cmp -s "$a/scene.json" "$b/scene.json" || why+=("scene.json")
  times="$(cat "$a.seconds") s -> $(cat "$b.seconds") s"
  if ((${#why[@]})); then
    status=1
    echo "DIFFERS  $name ($times): ${why[*]:0:6}"
  else
    echo "same     $name ($frames frames, $(ls "$a/frames" | wc -l) files; $times)"
  fi
done
exit $status
