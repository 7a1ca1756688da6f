#!/usr/bin/env python3
"""Checks that src/ includes run with the data flow (docs/architecture.md).

Each folder under src/ is a stage; a file may include headers of its own
stage and of earlier ones, never of a later one, so that a stage can be read
and tested knowing only what comes before it. Also fails on a folder that is
not in the order below (a new stage must be placed) and on an include of a
header that does not exist.

A stage may have sub-folders (SUBFOLDERS): a file in one includes the
headers of its stage's top folder (the stage's shared interface), of its own
sub-folder and of the sub-folders listed for it, never another's; a file in
the top folder includes none of its sub-folders (they build on it). Later
stages may include any of them.

In the stages listed in NO_CIRCLES, no module (a .c file and its .h) may
include another's header while that one, through any chain, includes its
own: such a circle means neither can be read or changed without the other.
The driver (render/) and the splat pass (pass/) are kept free of circles;
a type several modules share goes in a header of its own (render/report.h).

    python3 scripts/check_includes.py [SRC_DIR]
"""
import os
import re
import sys

# The data flow, earliest first.
STAGES = ["core", "particles", "source", "frame", "stars", "splat", "reduce", "dust", "post",
          "encode", "pass", "scene", "render", "insitu", "mpi", "cli"]
# The sub-folders of a stage, each with the sibling sub-folders it may
# include: source/'s readers, built-in models and writers share source.h;
# a writer may write what a model makes (zeldovich_hdf5.c).
SUBFOLDERS = {
    "source": {"readers": [], "models": [], "writers": ["models"]},
}
# Stages whose modules include one another in one direction only.
NO_CIRCLES = ["pass", "render"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([A-Za-z0-9_]+)/([^"]+)"')


def part_of(stage, header):
    """The sub-folder of stage that header (a path inside the stage) is in, or ""."""
    head, sep, _ = header.partition("/")
    return head if sep and head in SUBFOLDERS.get(stage, {}) else ""


def check_within_stage(stage, part, target_part, where, target, header):
    """A problem with an include inside one stage, or None."""
    if target_part == part or (part and not target_part):
        return None
    if part and target_part in SUBFOLDERS[stage][part]:
        return None
    if not part:
        return f"{where}: {stage}/ includes {target}/{header}, from its sub-folder {target_part}/"
    return f"{where}: {stage}/{part}/ includes {target}/{header}, from the sibling sub-folder {target_part}/"


def stage_files(src, stage, problems):
    """(part, path) of the stage's sources: its top folder's and its sub-folders'."""
    folder = os.path.join(src, stage)
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if os.path.isdir(path):
            if name not in SUBFOLDERS.get(stage, {}):
                problems.append(f"{path}: a sub-folder not placed (add it to SUBFOLDERS in {__file__})")
                continue
            for sub in sorted(os.listdir(path)):
                if os.path.isdir(os.path.join(path, sub)):
                    problems.append(f"{os.path.join(path, sub)}: sub-folders go one level deep")
                elif sub.endswith((".c", ".h", ".cpp")):
                    yield name, os.path.join(path, sub)
        elif name.endswith((".c", ".h", ".cpp")):
            yield "", path


def module_graph(src, stage):
    """Each module of the stage (a file's name without .c or .h) -> the
    stage's modules whose headers it includes."""
    graph = {}
    for _, path in stage_files(src, stage, []):
        module = os.path.splitext(os.path.basename(path))[0]
        with open(path, encoding="utf-8") as f:
            for line in f:
                m = INCLUDE.match(line)
                if m and m.group(1) == stage:
                    other = os.path.splitext(os.path.basename(m.group(2)))[0]
                    if other != module:
                        graph.setdefault(module, set()).add(other)
    return graph


def circles(graph):
    """One circle of each strongly connected set of modules larger than one
    (Tarjan's algorithm), as lists of module names."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1:
                found.append(sorted(part))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def check_circles(src, problems):
    for stage in NO_CIRCLES:
        for part in circles(module_graph(src, stage)):
            problems.append(f"{os.path.join(src, stage)}: its modules {', '.join(part)} include one another "
                            f"in a circle (move what they share to a header of its own)")


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
        for part, path in stage_files(src, stage, problems):
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
                    elif target == stage:
                        p = check_within_stage(stage, part, part_of(stage, header), where, target, header)
                        if p:
                            problems.append(p)
    check_circles(src, problems)
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
