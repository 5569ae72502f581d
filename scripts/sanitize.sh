#!/bin/sh
# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer:
# a separate build in build-sanitize/ (RelWithDebInfo, -O2 -g), then ctest.
# Any report fails the run (UBSan does not recover; ASan aborts).
# Usage: scripts/sanitize.sh   (after scripts/setup.sh has installed the packages)
set -eu
cd "$(dirname "$0")/.."
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPRINTLIGHT_SANITIZE=ON >/dev/null
cmake --build build-sanitize -j2
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-sanitize --output-on-failure -j2
