#!/usr/bin/env bash
# The whole test suite, as CI runs it: sets up with the tests
# (scripts/setup.sh --tests), runs `ctest --test-dir build
# --output-on-failure -j2` (further arguments go to ctest, e.g. -L quick)
# and fails when a test was skipped: after setup, everything a test needs
# (Open MPI, Chromium, Debian's model corpus) is installed, so a skip is a
# broken machine, not a pass.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --tests
log=$(mktemp)
trap 'rm -f "$log"' EXIT
ctest --test-dir build --output-on-failure -j2 --no-tests=error "$@" | tee "$log"
if grep -q "(Skipped)" "$log"; then
  echo "test: $(grep -c '(Skipped)' "$log") test(s) skipped (listed above): everything they need should be installed" >&2
  exit 1
fi
