# Helpers for the command-line tests. Each test script gets the orrery binary
# as $1 and the source folder as $2, works in a fresh temporary folder, and
# exits non-zero on the first failed expectation.
set -u
ORRERY=$1
SRC=$2
WORK=$(mktemp -d /tmp/orrery-cli-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"
failures=0
# The example N-body program built beside the CLI, and the Python that has
# numpy, h5py and astropy (Debian's).
NBODY=$(dirname "$ORRERY")/examples/orrery-nbody
py=/usr/bin/python3
[ -x "$py" ] || py=python3

fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# need_mpi PROGRAM: skips the test (exit 77) when PROGRAM, built only where
# MPI was found, is not there; else sets mpirun up as the MPI tests run it:
# as root (CI), more ranks than cores, and no leak checks in the ranks
# (OpenMPI's own start-up allocations are not freed at exit: not ours).
need_mpi() {
  if [ ! -x "$1" ]; then
    echo "$(basename "$1") was not built (MPI not found): skipping"
    exit 77
  fi
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
}

# rank_pid PATTERN RANK: the process id of MPI rank RANK of a run started
# from this test's own folder whose command line matches PATTERN (pgrep -f),
# or nothing. The folder tells this test's run from another test's running
# the same command at the same time (ctest runs tests in parallel): picking
# by the command alone once killed the other test's rank.
rank_pid() {
  local p
  for p in $(pgrep -f "$1"); do
    [ "$(readlink "/proc/$p/cwd" 2>/dev/null)" = "$(pwd -P)" ] || continue
    tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2" && echo "$p"
  done
}

# expect_fail CODE PATTERN OUTDIR -- orrery args...
# Runs orrery, expects exit CODE, a stderr line matching PATTERN (grep -E),
# and no file at all in OUTDIR afterwards (no output, no temporary file).
expect_fail() {
  local code=$1 pattern=$2 outdir=$3
  shift 4
  local got=0
  "$ORRERY" "$@" >"$WORK/stdout" 2>"$WORK/stderr" || got=$?
  if [ "$got" -ne "$code" ]; then
    fail "orrery $* exited $got, expected $code; stderr: $(cat "$WORK/stderr")"
  elif ! grep -Eq -- "$pattern" "$WORK/stderr"; then
    fail "orrery $*: stderr does not match /$pattern/: $(cat "$WORK/stderr")"
  fi
  if grep -q "AddressSanitizer\|runtime error" "$WORK/stderr"; then
    fail "orrery $*: sanitizer report: $(cat "$WORK/stderr")"
  fi
  if [ -d "$outdir" ] && [ -n "$(ls -A "$outdir")" ]; then
    fail "orrery $* left files in $outdir: $(ls -A "$outdir")"
  fi
}

finish() {
  if [ "$failures" -ne 0 ]; then
    echo "$failures failed" >&2
    exit 1
  fi
  echo "all passed"
}

# A small valid scene around a particle table; extra lines are appended.
write_scene() {
  local file=$1 table=$2
  shift 2
  {
    echo "input:"
    echo "  file: $table"
    echo "camera:"
    echo "  projection: orthographic"
    echo "  width: 10"
    echo "image:"
    echo "  width: 64"
    echo "  height: 48"
    echo "output:"
    echo "  dir: out"
    for line in "$@"; do echo "$line"; done
  } >"$file"
}

# python_with MODULE PACKAGE: sets $py to the Python that has the
# independent reader MODULE (Debian's /usr/bin/python3 first), or skips the
# test (exit 77) naming the Debian PACKAGE that provides it.
python_with() {
  py=/usr/bin/python3
  [ -x "$py" ] || py=python3
  if ! "$py" -c "import $1" 2>/dev/null; then
    echo "skipped: no $1 ($2)"
    exit 77
  fi
}

# run_checker LABEL CHECKER: runs tests/cli/CHECKER (a Python script taking
# the source and work folders) with $py; its report is printed when it
# passes and is the failure's message when it does not.
run_checker() {
  if "$py" "$SRC/tests/cli/$2" "$SRC" "$WORK" >"$WORK/log" 2>&1; then
    cat "$WORK/log"
  else
    fail "$1: $(cat "$WORK/log")"
  fi
}
