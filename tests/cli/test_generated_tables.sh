#!/bin/bash
# The generated C tables are their generators' output (issue 39): each
# generator run again on its committed or shared source reproduces the
# committed file byte for byte, and refuses bad input by name
# (check_generated_tables.py).
. "$(dirname "$0")/lib.sh"
run_checker "generated tables" check_generated_tables.py
finish
