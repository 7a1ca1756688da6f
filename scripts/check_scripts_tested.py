#!/usr/bin/env python3
"""Checks that a test runs every script in scripts/ (issue 39).

The scripts are part of the product: the generators of the tables in src/
and data/, the analyses the docs quote, the jobs the README and the docs
tell a reader to run. One no test runs breaks unseen when the code or the
outputs under it change. A script counts as run when the code of a test
(a file under tests/, tests/fuzz/corpus left out, comments left out) names
it: its file name (`scripts/gallery.sh`, "gen_ssp_table.py"), or for a
Python script its module (`import box_stats`). A script named or imported
by a script a test runs is run too (snapshot_disc.py, read by
disc_churn.py). The scripts CI runs itself, outside any test, are listed
in CI_RUNS with the reason; the check fails on every other script no test
runs, naming it, and on a name in CI_RUNS that is not in scripts/.

    python3 scripts/check_scripts_tested.py [SOURCE_DIR]
"""
import os
import re
import sys

# Scripts CI runs around the tests, not inside one: each is run on every
# CI run, so a test running it too would only run it again.
CI_RUNS = {
    "test.sh": "the README's test command: .ci/run calls it, and it runs every test",
    "build.sh": "scripts/test.sh builds the sanitizer and release builds with it",
    "install-deps.sh": "scripts/test.sh runs it first, on every CI machine",
}

# The test files' fuzzing corpus: inputs, not code.
CORPUS = os.path.join("tests", "fuzz", "corpus")

HASH_COMMENT = re.compile(r'(?:^|(?<=\s))#.*$', re.M)
C_COMMENT = re.compile(r'/\*.*?\*/|//[^\n]*', re.S)


def code_of(path):
    """A file's text without its comments (# for shell, Python and CMake,
    /* */ and // for C); None for a file that is not code."""
    ext = os.path.splitext(path)[1]
    if ext not in (".sh", ".py", ".c", ".h", ".txt", ".cmake"):
        return None
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    return C_COMMENT.sub(" ", text) if ext in (".c", ".h") else HASH_COMMENT.sub("", text)


def names(text, script):
    """Whether text runs script: its file name as a whole word, not part of
    a longer name (test.sh is not in test_shared.sh), or its module
    imported."""
    stem, ext = os.path.splitext(script)
    if stem not in text:  # the quick answer for most files
        return False
    if re.search(r'(?<![\w.-])' + re.escape(script) + r'(?![\w.-])', text):
        return True
    return ext == ".py" and re.search(r'^[ \t]*(?:from|import)[ \t]+' + re.escape(stem) + r'\b', text, re.M) is not None


def test_texts(root):
    """The code of every test file: tests/ without its corpus."""
    texts = []
    for folder, dirs, files in os.walk(os.path.join(root, "tests")):
        if os.path.relpath(folder, root) == CORPUS:
            dirs[:] = []
            continue
        for name in files:
            text = code_of(os.path.join(folder, name))
            if text is not None:
                texts.append(text)
    return texts


def run_by_tests(root, scripts):
    """The scripts a test runs, directly or through a script it runs."""
    texts = test_texts(root)
    run = {s for s in scripts if any(names(t, s) for t in texts)}
    grown = True
    while grown:  # scripts run by scripts that are run
        grown = False
        for s in scripts - run:
            if any(names(code_of(os.path.join(root, "scripts", r)) or "", s) for r in run):
                run.add(s)
                grown = True
    return run


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    folder = os.path.join(root, "scripts")
    scripts = {n for n in os.listdir(folder) if os.path.isfile(os.path.join(folder, n))}
    problems = []
    for name in sorted(set(CI_RUNS) - scripts):
        problems.append(f"scripts/{name}: listed in CI_RUNS but not in scripts/; remove it from the list")
    run = run_by_tests(root, scripts - set(CI_RUNS))
    for name in sorted(scripts - set(CI_RUNS) - run):
        problems.append(f"scripts/{name}: no test runs it (no file under tests/ names it outside comments); "
                        "add a test that runs it, or, if CI runs it itself, list it in CI_RUNS with the reason")
    for p in problems:
        print(p, file=sys.stderr)
    print(f"check_scripts_tested: {len(run)} script(s) run by tests, {len(CI_RUNS)} by CI itself, "
          f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
