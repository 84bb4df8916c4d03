#!/usr/bin/env bash
# Set up tear on a Debian machine and either run the default demo or the whole test suite.
#   bash scripts/bootstrap.sh demo   install packages, build Release, run and render the 2D
#                                    block tear (a video and a still)
#   bash scripts/bootstrap.sh test   install packages, build Release (with tear's own
#                                    assertions), run every test with ctest, then the
#                                    sanitizer subset (scripts/sanitize.sh address --ci)
# Packages are installed only when missing; the build goes to ./build.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-demo}
packages=(cmake ninja-build g++ pkg-config libeigen3-dev libtbb-dev nlohmann-json3-dev
          libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev python3
          libembree-dev libpng-dev ffmpeg
          libopenvdb-dev libboost-iostreams-dev libnglib-dev libsuitesparse-dev libopenblas0-pthread)
# libboost-iostreams-dev: Debian's libopenvdb-dev does not pull in the Boost headers that the
# OpenVDB headers include, nor the Boost iostreams that its CMake find module requires.
# libnglib-dev: netgen, the FEM bodies' mesher (docs/fem.md). libsuitesparse-dev: CHOLMOD, the
# implicit FEM solve's factor; libopenblas0-pthread: a blocked BLAS under it (with the reference
# BLAS CHOLMOD is no faster than Eigen's own factor; held to one thread, docs/fem.md "Speed").

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "== installing Debian packages: ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  # Without the packages' recommendations: ffmpeg's and netgen's pull in GPU drivers (mesa,
  # VA-API, VDPAU, Vulkan), speech models and more that tear never loads, a large share of a
  # fresh machine's install time.
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
# The demo needs the tear executable only; the tests and benchmarks are built by `test`.
if [[ $mode == demo ]]; then
  echo "== building tear (Release) in ./build"
  cmake --build build --target tear_cli
else
  echo "== building tear, its tests and benchmarks (Release) in ./build"
  cmake --build build
fi
echo "== $SECONDS s so far"

case "$mode" in
  demo)
    echo "== running the default demo: examples/block_tear_2d.json (a block torn along its fibers)"
    ./build/tear run examples/block_tear_2d.json -o out/block_tear_2d --render
    last=$(ls out/block_tear_2d/render | sort | tail -1)
    echo "== output: $(pwd)/out/block_tear_2d (frames/, stats.jsonl, scene.json; see docs/outputs.md)"
    if [[ -f out/block_tear_2d/preview.mp4 ]]; then
      echo "== video: $(pwd)/out/block_tear_2d/preview.mp4"
    fi
    echo "== still: $(pwd)/out/block_tear_2d/render/$last"
    ;;
  test)
    echo "== running the test suite"
    status=0
    ctest --test-dir build --output-on-failure -j "$(nproc)" -LE study || status=1
    echo "== $SECONDS s so far"
    # The readers and their corpus, the math, particle, io and grid tests again under ASan and
    # UndefinedBehaviorSanitizer (docs/architecture.md "Sanitizers"; the whole suite:
    # scripts/sanitize.sh address).
    echo "== the sanitizer subset (scripts/sanitize.sh address --ci)"
    bash scripts/sanitize.sh address --ci || status=1
    echo "== $SECONDS s in all"
    exit $status
    ;;
  *)
    echo "usage: bash scripts/bootstrap.sh [demo|test]" >&2
    exit 2
    ;;
esac
