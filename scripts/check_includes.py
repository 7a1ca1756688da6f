#!/usr/bin/env python3
"""Checks that src/ includes run with the data flow (docs/architecture.md).

Each folder under src/ is a stage; a file may include headers of its own
stage and of earlier ones, never of a later one, so that a stage can be read
and tested knowing only what comes before it. Also fails on a folder that is
not in the order below (a new stage must be placed) and on an include of a
header that does not exist.

    python3 scripts/check_includes.py [SRC_DIR]
"""
import os
import re
import sys

# The data flow, earliest first.
STAGES = ["core", "particles", "source", "frame", "splat", "reduce", "dust", "post",
          "encode", "scene", "render", "insitu", "mpi", "cli"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([A-Za-z0-9_]+)/([^"]+)"')


def check(src):
    rank = {s: i for i, s in enumerate(STAGES)}
    problems = []
    for stage in sorted(os.listdir(src)):
        folder = os.path.join(src, stage)
        if not os.path.isdir(folder):
            continue
        if stage not in rank:
            problems.append(f"{folder}: a stage not placed in the data flow (add it to STAGES in {__file__})")
            continue
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".c", ".h", ".cpp")):
                continue
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as f:
                for line_no, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target, header = m.groups()
                    where = f"{path}:{line_no}"
                    if not os.path.exists(os.path.join(src, target, header)):
                        problems.append(f"{where}: includes {target}/{header}, which does not exist")
                    elif target not in rank:
                        problems.append(f"{where}: includes from {target}/, not a stage")
                    elif rank[target] > rank[stage]:
                        problems.append(f"{where}: {stage}/ includes {target}/{header}, a later stage")
    return problems


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "src")
    problems = check(src)
    for p in problems:
        print(p)
    print(f"check_includes: {len(problems)} problem(s) in {os.path.normpath(src)}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
