#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (CTest summary last).
# --sanitize: the same in build-asan/, built with AddressSanitizer (leaks
# included) and UBSan, any report failing its test; a few tests are left out
# (see below and README).
# Usage: scripts/test.sh [--sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    *) echo "usage: scripts/test.sh [--sanitize]" >&2; exit 2 ;;
  esac
done
scripts/install-deps.sh
if ((sanitize == 0)); then
  scripts/build.sh
  build_dir="${ANISURF_BUILD_DIR:-build}"
  ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)"
  exit
fi

# The default compiler, or $CXX on the first configuration (CXX=clang++
# builds this code base about twice as fast with the sanitizers); -O1, the
# sanitizers' usual level.
build_dir=build-asan
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all"
ANISURF_BUILD_DIR=$build_dir scripts/build.sh -DCMAKE_BUILD_TYPE=None -DANISURF_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Leaks inside the system's OpenGL stack (Mesa, GLFW, X) are not ours.
export LSAN_OPTIONS=suppressions=$PWD/scripts/lsan_suppressions.txt:print_suppressions=0
# Left out: the slowest shared-mesh tests (minutes each under the sanitizers)
# and the window under Xvfb (the GL driver leaks from a module it unloads
# before exit, which no suppression can name).
left_out='every shared mesh|sliver CAD parts|under xvfb-run|under Xvfb'
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -E "$left_out"
