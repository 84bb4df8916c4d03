#!/usr/bin/env bash
# The test suite under sanitizers (docs/architecture.md "Sanitizers"), each in its own build folder:
#   scripts/sanitize.sh address        build-asan: AddressSanitizer + UndefinedBehaviorSanitizer,
#                                      every test
#   scripts/sanitize.sh address --ci   build-asan-ci (-O1 -g1): the subset CI runs (the readers
#                                      and their fuzz corpus, the math, exec, geometry,
#                                      particle, io and grid tests)
#   scripts/sanitize.sh thread         build-tsan (-O1 -g1): ThreadSanitizer, the threaded tests
#   scripts/sanitize.sh address --clang
#                                      build-asan-clang: the same with clang++ at -O3 -g1: the
#                                      physics runs about 10 times slower than Release, against
#                                      20 times with GCC's -O2 -g build; needs Debian's clang
# Extra arguments go to ctest (e.g. -R Cli). Exit status: ctest's.
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-address}
shift || true
ci=0 clang=0
while [[ ${1:-} == --ci || ${1:-} == --clang ]]; do
  [[ $1 == --ci ]] && ci=1
  [[ $1 == --clang ]] && clang=1
  shift
done
jobs=$(nproc)
case "$kind" in
  address)
    dir=build-asan
    flags="address,undefined"
    export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
    export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
    ;;
  thread)
    dir=build-tsan
    flags="thread"
    # oneTBB is not instrumented: its own synchronisation is invisible to TSan, so races
    # inside the library are suppressed (scripts/tsan.supp); tear's code is checked.
    export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$(pwd)/scripts/tsan.supp"
    ;;
  *)
    echo "usage: scripts/sanitize.sh address|thread [--ci] [--clang] [ctest arguments]" >&2
    exit 2
    ;;
esac
# CI's subset (in its own folder) and the thread build are compiled at -O1 with line tables
# only (-g1): half the compile time of -O2 -g, and reports still name file and line.
optimise=()
if [[ $ci == 1 ]]; then dir=$dir-ci; fi
if [[ $ci == 1 || $kind == thread ]]; then
  optimise=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG")
fi
if [[ $clang == 1 ]]; then
  dir=$dir-clang
  # -O3 and a higher inlining threshold, so that more of Eigen's small fixed-size expressions
  # inline and fewer of their temporaries are instrumented: 10 times Release, against 14 at
  # clang's -O2 (CrackFields.PiecesSeparateFreelyAcrossACutBand3D). The threshold is a compile
  # option only; the linker driver would warn that it is unused.
  optimise=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
            -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O3 -g1 -DNDEBUG -mllvm -inline-threshold=1000"
            -DCMAKE_EXE_LINKER_FLAGS="-Wno-unused-command-line-argument")
fi
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEAR_SANITIZE="$flags" \
  -DTEAR_BUILD_BENCH=OFF "${optimise[@]}" >/dev/null
# The subsets: what CI has time for (address), what runs threads (thread).
subset_targets=()
subset_regex=""
if [[ $kind == address && $ci == 1 ]]; then
  subset_targets=(test_math test_exec test_geometry test_particles test_kernels test_io test_grid
                  replay_ply replay_obj replay_stl replay_bgeo replay_vtu replay_frame_range
                  replay_gmsh replay_tetgen replay_volume_vtu)
  subset_regex='^((AtomicFile|BSpline|Bgeo|Binary|BlockWindow|Cofactor|Collider|Exec|FieldIo|FieldRegistry|Frames|Gmsh|Memory|MeshIo|MeshSolid|Ply|PointGroups|Polar|Pvd|Qr|ReadVolumeMesh|RoundShapes|ShapeSdf|SignedSvd|SparseGrid|Stencil|Tetgen|Vtu|VolumeVtu)\.|Fuzz\.replay_(ply|obj|stl|bgeo|vtu|frame_range|gmsh|tetgen|volume_vtu)$)'
elif [[ $kind == thread ]]; then
  subset_targets=(test_exec test_grid test_solvers test_mpm tear_cli test_cli)
  subset_regex='^(Exec\.|SparseGrid\.|Apic\.|Implicit\.Conserves|Determinism\.|Cli\.OutputIsBitIdentical|Stability|StepGuard|CrackFields\.SameBits|Implicit\.MultigridStepsGiveTheSameBits|ImplicitDamage\.SameBits|Inextensibility\.SameBits|Multigrid\.SameBits)'
fi
if ((${#subset_targets[@]})); then
  echo "== building ${subset_targets[*]} with -fsanitize=$flags in $dir"
  cmake --build "$dir" --target "${subset_targets[@]}"
  echo "== ctest -R '$subset_regex' $*"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" -R "$subset_regex" "$@"
else
  echo "== building everything with -fsanitize=$flags in $dir"
  cmake --build "$dir"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" "$@"
fi
