#!/usr/bin/env bash
# FEM against MPM on one object (docs/fem.md "Speed"): a 1 m x 20 cm x 20 cm neo-Hookean bar
# clamped at one end, sagging under gravity, meshed by netgen at the mesh sizes given (about
# 10K, 50K and 200K tetrahedra at 0.029, 0.017 and 0.0105 m), run implicitly (dt 2 ms) and
# explicitly (the elastic limit), and the same bar as MPM particles (8 a cell) at grid.dx = the
# mesh size. Prints, per run: elements or particles, steps, wall seconds per step and per
# simulated second, Newton and CG iterations a step.
#   bash scripts/fem_bench.sh [MESH_SIZE ...]   (default 0.029 0.017)
#   TEAR=./build/tear THREADS=2 STEPS=10 OUT=out/fem_bench
set -euo pipefail
cd "$(dirname "$0")/.."
tear=${TEAR:-./build/tear}
threads=${THREADS:-2}
steps=${STEPS:-10}
out=${OUT:-out/fem_bench}
sizes=("$@")
((${#sizes[@]})) || sizes=(0.029 0.017)
mkdir -p "$out"

scene() {  # scene SIMULATION INTEGRATOR H DT FRAMES
  local sim=$1 integrator=$2 h=$3 dt=$4 frames=$5 object
  if [[ $sim == fem ]]; then
    object="\"simulation\": \"fem\", \"mesh_size\": $h,"
  else
    object="\"ppc\": 8,"
  fi
  cat <<EOF
{"name": "fem_bench", "dim": 3,
 "grid": {"dx": $h, "domain_min": [0, 0, 0], "domain_max": [1.4, 1.0, 0.6], "walls": "separate"},
 "time": {"frame_dt": $dt, "frames": $frames, "max_dt": $dt},
 "gravity": [0, -9.81, 0], "integrator": "$integrator",
 "materials": {"rubber": {"model": "neo_hookean", "E": 2e6, "nu": 0.3, "rho": 1100}},
 "objects": [{$object "material": "rubber",
              "shape": {"type": "box", "min": [0.2, 0.6, 0.2], "max": [1.2, 0.8, 0.4]}}],
 "boundaries": [{"type": "sticky", "shape": {"type": "box", "min": [0.1, 0.5, 0.1], "max": [0.26, 0.9, 0.5]}}],
 "output": {"every": 1000000, "checkpoint_every": 0}}
EOF
}

report() {  # report LABEL RUN_DIR
  python3 - "$1" "$2" <<'EOF'
import json, sys
label, run = sys.argv[1], sys.argv[2]
rows = [json.loads(l) for l in open(run + "/stats.jsonl")]
first, last = rows[0], rows[-1]
steps = sum(r["steps"] for r in rows[1:])  # per frame; wall_s and time are running totals
wall = last["wall_s"] - first["wall_s"]
sim = last["time"] - first["time"]
newton = sum(r.get("newton_iterations", 0) for r in rows[1:])
cg = sum(r.get("cg_iterations", 0) for r in rows[1:])
print(f"{label:34s} {last['particles']:8d} nodes/particles  {steps:5d} steps  "
      f"{wall / steps * 1e3:9.2f} ms/step  {wall / sim:9.1f} s per simulated s  "
      f"Newton {newton / steps:5.2f}/step  CG {cg / max(newton, 1):6.1f}/Newton")
EOF
}

for h in "${sizes[@]}"; do
  scene fem implicit "$h" 0.002 1 >"$out/check.json"
  echo "== mesh_size $h: $("$tear" check "$out/check.json" | grep -o "FEM mesh of [0-9]* nodes, [0-9]* tetrahedra")"
  for run in "fem implicit 0.002" "fem explicit 0" "mpm explicit 0"; do
    read -r sim integrator dt <<<"$run"
    if [[ $dt == 0 ]]; then
      # One frame of `steps` elastic-limit steps: the limit from tear check.
      scene "$sim" "$integrator" "$h" 1 1 >"$out/check.json"
      limit=$("$tear" check "$out/check.json" | sed -n 's/^time .*; dt \([0-9.e+-]*\) s at rest.*/\1/p')
      dt=$(python3 -c "print('%.4g' % ($limit * 0.999))")
    fi
    file=$out/${sim}_${integrator}_$h.json
    scene "$sim" "$integrator" "$h" "$dt" "$((steps + 1))" >"$file"
    rm -rf "$out/run"
    "$tear" run "$file" -o "$out/run" --threads "$threads" -q >/dev/null
    report "$sim $integrator h=$h dt=$dt" "$out/run"
  done
done
