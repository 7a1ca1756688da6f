#!/bin/bash
# The generated C tables are their generators' output (issue 39): each
# generator run again on its committed or shared source reproduces the
# committed file byte for byte, and refuses bad input by name
# (check_generated_tables.py).
. "$(dirname "$0")/lib.sh"
if "$py" "$SRC/tests/cli/check_generated_tables.py" "$SRC" "$WORK" >"$WORK/log" 2>&1; then
  cat "$WORK/log"
else
  fail "generated tables: $(cat "$WORK/log")"
fi
finish
