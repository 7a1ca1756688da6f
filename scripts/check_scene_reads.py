#!/usr/bin/env python3
"""Counts the reads of orr_scene's fields outside scene/ and the plan
(render/plan.c and render/plan_view.c).

The plan is meant to be the only reader of the scene (issue 39): it compiles
each view's settings into what the stages take (pass/splat_settings.h for
the splat pass), and the stages read those, never the scene. This check
finds every variable, parameter or struct field declared as an orr_scene
(or a pointer or array of them) in a file, and counts the places where one
is followed by -> or . and a member of struct orr_scene (read from
src/scene/scene.h), comments and strings left out: `s->input.weight`,
`v->scene->path`, `eyes->scene[k]->stereo`. A helper that takes the scene
whole (`orr_scene_has_sequence(s)`) is not counted; the fields it reads are
counted in its own file.

It also checks that the plan keeps no scene: struct orr_plan (render/plan.c)
and the structs of render/'s and pass/'s headers, which the plan holds per
view, declare no member that is a scene or points to one. The plan copies
what it needs when it is made, so the caller's scenes may go.

CEILINGS held what each file read while the reads were being moved into
the plan; it is empty now. The check fails when a file reads more than its
ceiling (or a file not listed reads any), and says which files now read
fewer, so the ceilings can be lowered with them; it prints the total left.

    python3 scripts/check_scene_reads.py [SRC_DIR]
"""
import os
import re
import sys

# Where the scene may be read: its own stage, and the plan.
ALLOWED = {"scene", os.path.join("render", "plan.c"), os.path.join("render", "plan_view.c")}

# Reads per file, as counted when they were last lowered. None is left
# (issue 39): every file outside scene/ and the plan reads none, and a new
# read fails the check.
CEILINGS = {}

COMMENT_OR_STRING = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
DECLARED = re.compile(r'\borr_scene\b(?:\s|const\b|\*)*(\w+)\b(?!\s*\()')
FIELD = re.compile(r'^\s+(?:const\s+)?orr_scene\b(?:\s|const\b|\*)*(\w+)\s*;', re.M)
DECLARED_VIEWS = re.compile(r'\borr_scene_views\b(?:\s|const\b|\*)*(\w+)\b(?!\s*\()')


def scene_members(src):
    """The names of struct orr_scene's members, from scene/scene.h."""
    with open(os.path.join(src, "scene", "scene.h"), encoding="utf-8") as f:
        text = COMMENT_OR_STRING.sub(" ", f.read())
    body = re.search(r'typedef struct orr_scene \{(.*?)\} orr_scene;', text, re.S).group(1)
    return set(re.findall(r'(\w+)\s*(?:\[[^\]]*\])*\s*;', body))


def scene_fields(texts):
    """Struct members declared as scenes in any header (view_state.scene):
    read through -> or . in every file."""
    fields = set()
    for text in texts:
        fields |= set(FIELD.findall(text))
    return fields


def reads_in(text, members, fields):
    """How many scene-field reads text (comments and strings gone) holds."""
    scenes = {r'\b' + n for n in DECLARED.findall(text) if n != "const"}
    # orr_scene_views: its scenes are .view[k]
    scenes |= {r'\b' + n + r'\s*(?:->|\.)\s*view' for n in DECLARED_VIEWS.findall(text) if n != "const"}
    scenes |= {r'(?:->|\.)\s*' + n for n in fields}
    if not scenes:
        return 0
    read = re.compile(r'(?:' + "|".join(sorted(scenes)) + r')\b(?:\s*\[[^\]]*\])?\s*(?:->|\.)\s*(\w+)')
    return sum(1 for m in read.finditer(text) if m.group(1) in members)


def sources(src):
    """(path relative to src, text without comments and strings) of every source."""
    for root, _, files in os.walk(src):
        for name in sorted(files):
            if name.endswith((".c", ".h", ".cpp")):
                path = os.path.join(root, name)
                with open(path, encoding="utf-8") as f:
                    yield os.path.relpath(path, src), COMMENT_OR_STRING.sub(" ", f.read())


def count(src):
    members = scene_members(src)
    files = dict(sources(src))
    fields = scene_fields(text for rel, text in files.items() if rel.endswith(".h"))
    counts = {}
    for rel, text in files.items():
        if rel.split(os.sep)[0] in ALLOWED or rel in ALLOWED:
            continue
        n = reads_in(text, members, fields)
        if n:
            counts[rel.replace(os.sep, "/")] = n
    return counts


def scenes_kept(src):
    """The members that are scenes (or point to them) in struct orr_plan and
    in the structs of render/'s and pass/'s headers: "file: name" each."""
    files = dict(sources(src))
    kept = []
    plan = re.search(r'struct orr_plan \{(.*?)\n\};', files[os.path.join("render", "plan.c")], re.S)
    kept += [f"render/plan.c: struct orr_plan.{n}" for n in FIELD.findall(plan.group(1) if plan else "")]
    for rel, text in sorted(files.items()):
        if rel.split(os.sep)[0] in ("render", "pass") and rel.endswith(".h"):
            kept += [f"{rel.replace(os.sep, '/')}: {n}" for n in FIELD.findall(text)]
    return kept


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "src")
    counts = count(src)
    problems = [f"{k}: the plan keeps a scene; copy what the frames need when the plan is made"
                for k in scenes_kept(src)]
    for rel, n in sorted(counts.items()):
        ceiling = CEILINGS.get(rel, 0)
        if n > ceiling:
            problems.append(f"{rel}: reads the scene's fields {n} times, more than its {ceiling}: "
                            "take them from the settings the plan compiles (render/plan.c)")
        elif n < ceiling:
            print(f"{rel}: {n} reads, below its ceiling of {ceiling}: lower CEILINGS in {__file__}")
    for rel in sorted(set(CEILINGS) - set(counts)):
        print(f"{rel}: no reads left: drop it from CEILINGS in {__file__}")
    for p in problems:
        print(p)
    print(f"check_scene_reads: {sum(counts.values())} scene-field reads in {len(counts)} files outside scene/ "
          f"and the plan (render/plan.c, plan_view.c); scenes kept by the plan: {len(scenes_kept(src))}; {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
