#!/usr/bin/env bash
# The whole test suite on a fresh machine: install what is needed, then build
# and run every test twice: a normal optimised build, and one under
# AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
"$here/scripts/install-deps.sh"

echo "== sanitizer build (AddressSanitizer + UndefinedBehaviorSanitizer)"
"$here/scripts/build.sh" "$here/build-sanitize" -DORRERY_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$here/build-sanitize" --output-on-failure -j "$(nproc)"

echo "== reader fuzzing smoke run (clang + libFuzzer + sanitizers)"
CC=clang CXX=clang++ "$here/scripts/build.sh" "$here/build-fuzz" -DORRERY_FUZZ=ON -DORRERY_SANITIZE=ON -DORRERY_MPI=OFF
ctest --test-dir "$here/build-fuzz" --output-on-failure -j "$(nproc)" -R '^fuzz_'

echo "== release build"
"$here/scripts/build.sh" "$here/build"
ctest --test-dir "$here/build" --output-on-failure -j "$(nproc)"
