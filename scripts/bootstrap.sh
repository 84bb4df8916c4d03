#!/usr/bin/env bash
# Set up tear on a Debian machine and either run the default demo or the whole test suite.
#   bash scripts/bootstrap.sh demo   install packages, build Release, run the 2D tube pull
#   bash scripts/bootstrap.sh test   install packages, build Release (with tear's own
#                                    assertions), run every test with ctest
# Packages are installed only when missing; the build goes to ./build.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-demo}
packages=(cmake ninja-build g++ pkg-config libeigen3-dev libtbb-dev nlohmann-json3-dev
          libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev python3)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "== installing Debian packages: ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq "${missing[@]}"
fi

echo "== building (Release) in ./build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build

case "$mode" in
  demo)
    echo "== running the default demo: examples/tube_pull_2d.json"
    ./build/tear run examples/tube_pull_2d.json -o out/tube_pull_2d
    echo "== output: $(pwd)/out/tube_pull_2d (frames/NNNNN.ply, stats.jsonl, scene.json; see docs/outputs.md)"
    ;;
  test)
    echo "== running the test suite"
    ctest --test-dir build --output-on-failure -j "$(nproc)"
    ;;
  *)
    echo "usage: bash scripts/bootstrap.sh [demo|test]" >&2
    exit 2
    ;;
esac
