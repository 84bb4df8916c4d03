#!/usr/bin/env bash
# Regenerates the shipped meshes of examples/meshes/ (docs/meshes.md) with tools/make_meshes
# and prints their table. Usage: bash scripts/make_meshes.sh [NAME ...]   (default: every mesh)
#   BUILD=build (the CMake build folder, configured if missing), THREADS=2
# The output is the same bytes for any thread count: after a change to tools/make_meshes.cpp,
# `git diff --stat examples/meshes` shows which meshes changed.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build}
[[ -f $build/build.ninja || -f $build/Makefile ]] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" --target make_meshes -j "${THREADS:-2}"
"$build/make_meshes" examples/meshes --threads "${THREADS:-2}" "$@"
