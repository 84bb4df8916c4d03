#!/usr/bin/env bash
# Interrupt `tear run` at pseudo-random moments (SIGKILL; every fourth time SIGINT or SIGTERM)
# and resume it, on an explicit-damage, an implicit-damage and a plastic scene; each must end
# byte-identical to an uninterrupted run (docs/long-runs.md "Kill"). The test suite runs the
# first scene with 6 interruptions; this runs the full count.
#   scripts/interrupt-anywhere.sh [KILLS=20] [SEED=1]     (after building ./build/tear)
set -euo pipefail
cd "$(dirname "$0")/.."
kills=${1:-20}
seed=${2:-1}
tear=./build/tear
[[ -x $tear ]] || { echo "build tear first: cmake --build build --target tear_cli" >&2; exit 2; }
work=$(mktemp -d /tmp/tear-interrupt.XXXXXX)
trap 'rm -rf "$work"' EXIT
scene=examples/block_tear_2d.json
status=0
run() {
  local name=$1; shift
  echo "== $name: $kills interruptions"
  python3 tests/cli/interrupt_anywhere.py --tear "$tear" --scene "$scene" --frames 12 \
    --kills "$kills" --seed "$seed" --work "$work/$name" "$@" || status=1
}
run explicit_damage
run implicit_damage --set damage.solver=implicit
# The block without damage, plastic (von Mises): the plastic state must survive each resume.
run plastic --set damage.solver=none \
  --set 'materials.fibrous.plasticity={"type":"von_mises","yield_stress":20}'
exit $status
