#!/usr/bin/env python3
"""Checks that each generated table in src/ is its generator's output:

- src/core/ssp_data.c is scripts/gen_ssp_table.py run on the committed
  data/ssp/default_ssp.txt, byte for byte, and that file is still the
  pynbody blob it was copied from (git blob 04af418f, data/ssp/README.md);
- src/core/cie_data.c is scripts/gen_colour_tables.py run on the shared
  colour data (ORRERY_SHARED_DATA/colour, by default ../shared/data beside
  the checkout), byte for byte; when that folder is absent the check is
  skipped and says so;
- both generators refuse bad input (a missing file, a table with a row
  short, a hole in its grid) with a message naming the file and a non-zero
  exit, writing nothing to stdout.

usage: check_generated_tables.py SOURCE_DIR WORK_DIR
"""
import hashlib
import os
import subprocess
import sys

SRC, WORK = sys.argv[1], sys.argv[2]
PY = sys.executable
SSP_BLOB = "04af418fae93492344d54d70aba0407e01bd767e"
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what, file=sys.stderr)


def generate(script, *args):
    p = subprocess.run([PY, os.path.join(SRC, "scripts", script), *args], capture_output=True)
    return p.returncode, p.stdout, p.stderr.decode()


def same_as_committed(script, source, target):
    """The generator's output against the committed file: byte for byte, or
    the first line that differs."""
    code, out, err = generate(script, source)
    committed = open(os.path.join(SRC, target), "rb").read()
    if code != 0 or out != committed:
        new, old = out.decode().splitlines(), committed.decode().splitlines()
        where = next((i for i, (a, b) in enumerate(zip(new, old)) if a != b), min(len(new), len(old)))
        check(False, f"{target} is not what {script} makes of {source} (exit {code}, {err.strip()}): "
                     f"line {where + 1}: generated {new[where:where + 1]}, committed {old[where:where + 1]}")
    else:
        print(f"{target}: {script} reproduces it from {source} ({len(out)} bytes)")


def git_blob(path):
    data = open(path, "rb").read()
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def test_ssp():
    source = os.path.join(SRC, "data", "ssp", "default_ssp.txt")
    check(git_blob(source) == SSP_BLOB, f"{source} is not pynbody's blob {SSP_BLOB}: it was changed")
    same_as_committed("gen_ssp_table.py", source, "src/core/ssp_data.c")


def test_colour():
    shared = os.environ.get("ORRERY_SHARED_DATA") or os.path.join(SRC, "..", "shared", "data")
    colour = os.path.join(shared, "colour")
    if not os.path.isdir(colour):
        print(f"{colour} absent: src/core/cie_data.c is not checked against its sources (skipped)")
        return
    same_as_committed("gen_colour_tables.py", colour, "src/core/cie_data.c")


def refused(script, args, pattern):
    code, out, err = generate(script, *args)
    check(code != 0 and pattern in err and not out, f"{script} {args}: exit {code}, stdout {len(out)} bytes, "
                                                     f"stderr {err!r} (expected {pattern!r})")


def test_bad_input():
    source = open(os.path.join(SRC, "data", "ssp", "default_ssp.txt")).read().splitlines(keepends=True)
    rows = [i for i, line in enumerate(source) if not line.startswith("#")]
    short = os.path.join(WORK, "short_row.txt")  # one row missing its K magnitude
    with open(short, "w") as f:
        f.writelines(source[:rows[3]] + [source[rows[3]].rsplit(maxsplit=1)[0] + "\n"] + source[rows[3] + 1:])
    holed = os.path.join(WORK, "holed.txt")  # one (age, Z) left out of the 25 x 11 grid
    with open(holed, "w") as f:
        f.writelines(source[:rows[7]] + source[rows[7] + 1:])
    refused("gen_ssp_table.py", [short], "short_row.txt: expected 11 columns")
    refused("gen_ssp_table.py", [holed], "holed.txt: 274 rows do not fill a grid of 25 ages by 11 metallicities")
    refused("gen_ssp_table.py", [os.path.join(WORK, "none.txt")], "none.txt: cannot read")
    refused("gen_colour_tables.py", [os.path.join(WORK, "no_colour")], "no_colour/ciexyz31_1.csv: cannot read")


for test in (test_ssp, test_colour, test_bad_input):
    test()
sys.exit(1 if failures else 0)
