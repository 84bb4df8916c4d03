#!/usr/bin/env bash
# Fuzz the readers of untrusted input (tests/fuzz/fuzz_NAME.cpp) with libFuzzer, AddressSanitizer
# and UndefinedBehaviorSanitizer:
#   scripts/fuzz.sh [SECONDS] [NAME...]
# SECONDS per target (default $TEAR_FUZZ_SECONDS, else 60); NAMEs default to every target. Builds
# the fuzz_NAME executables with clang++ in build-fuzz (TEAR_FUZZ=ON; the first build compiles
# the libraries again, instrumented: slow), then runs each from a copy of its seed corpus in
# build-fuzz/corpus/NAME, where new inputs collect across runs (tests/fuzz/corpus is left as it
# is). A crash, leak, sanitizer report, timeout (-timeout=10 s an input) or an allocation over
# -rss_limit_mb=2048 is written to build-fuzz/findings/NAME/; add the (minimised) file to
# tests/fuzz/corpus/NAME/ with the fix, so that ctest's Fuzz.replay_NAME keeps it fixed.
# Prints the figures of each target; exit status 1 when any target found something.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${TEAR_FUZZ_SECONDS:-60}}
(($# > 0)) && shift
targets=("$@")
if ((${#targets[@]} == 0)); then
  for f in tests/fuzz/fuzz_*.cpp; do
    name=$(basename "$f" .cpp)
    targets+=("${name#fuzz_}")
  done
fi
build=${TEAR_FUZZ_BUILD:-build-fuzz}
jobs=${TEAR_FUZZ_JOBS:-2}

if [[ ! -f $build/build.ninja ]]; then
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # -O1 and debug info: readable sanitizer reports at a fraction of -O0's cost.
  cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS="-O1" -DTEAR_FUZZ=ON -DTEAR_BUILD_TESTS=OFF -DTEAR_BUILD_BENCH=OFF \
    "${launcher[@]}"
fi
nice -n 19 cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"

# The longest input worth trying: room for a few hundred rows of a point or mesh file, a scene,
# a checkpoint of the tiny scene (3 kB); a frame range is a few characters.
max_len() {
  case $1 in
    frame_range) echo 64 ;;
    *) echo 16384 ;;
  esac
}

status=0
printf '%-12s %10s %8s %10s %8s %8s %s\n' target executions seconds exec/s corpus rss_mb findings
for t in "${targets[@]}"; do
  corpus=$build/corpus/$t findings=$build/findings/$t
  mkdir -p "$corpus" "$findings"
  cp -n tests/fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
  dict=()
  [[ -f tests/fuzz/dict/$t.dict ]] && dict=(-dict=tests/fuzz/dict/"$t".dict)
  log=$build/findings/$t.log
  start=$SECONDS
  rc=0
  nice -n 19 "$build/tests/fuzz/fuzz_$t" "$corpus" "${dict[@]}" -max_total_time="$seconds" \
    -max_len="$(max_len "$t")" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$findings/" >"$log" 2>&1 || rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -1)
  found=$(find "$findings" -type f | wc -l)
  printf '%-12s %10s %8s %10s %8s %8s %s\n' "$t" "${runs:-?}" $((SECONDS - start)) "${rate:-?}" \
    "$(find "$corpus" -type f | wc -l)" "${rss:-?}" "$found"
  if ((rc != 0 || found > 0)); then
    status=1
    echo "  $t: exit status $rc; see $log and $findings/" >&2
  fi
done
exit $status
