#!/usr/bin/env bash
# Runs the Python package's pytest tests (tests/python) with Debian's python3,
# which has numpy and astropy (a pyenv python3 on PATH may not). ctest sets
# PYTHONPATH to the build tree's package, ORRERY_CLI, ORRERY_SHARED_DATA and
# ORRERY_SANITIZE. Exit 77 (skipped) when pytest, numpy or astropy is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
py=/usr/bin/python3
[ -x "$py" ] || py=python3
if ! "$py" -c "import pytest, numpy, astropy" 2>/dev/null; then
  echo "python tests: $py lacks pytest, numpy or astropy (scripts/install-deps.sh installs them); skipped"
  exit 77
fi
if [ "${ORRERY_SANITIZE:-OFF}" = ON ]; then
  # A Python process loading an ASan-built liborrery.so needs the sanitizer
  # runtimes loaded first. Python itself is not instrumented, and keeps
  # memory to its exit that LeakSanitizer would report: leaks are not checked.
  cc=${CC:-cc}
  asan=$("$cc" -print-file-name=libasan.so)
  ubsan=$("$cc" -print-file-name=libubsan.so)
  if [ ! -e "$asan" ] || [ ! -e "$ubsan" ]; then
    echo "python tests: no libasan.so/libubsan.so from $cc to preload; skipped"
    exit 77
  fi
  export LD_PRELOAD="$asan $ubsan"
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
fi
exec "$py" -m pytest -q -p no:cacheprovider "$here" "$@"
