"""The example commands of README.md and docs/gallery.md that make images,
as a user would type them, each with overrides that make it tiny:
python3 readme_examples.py SRC prints one command a line (NUL-free shell
words, as written in the docs, then the overrides).

Taken: every `build/orrery render` and `build/orrery ics` in a ```sh block
(continuation lines joined, trailing # comments dropped), once each, but
not those in a shell loop (their inputs come from an N-body run). The overrides come
from the scene itself (read with PyYAML): every view's image at most 96
pixels wide (its height in proportion, at least 8), a built-in model at
12 000 particles (Nightfall larger: LARGER), one frame of an animation (the middle one, so a path's
mid-run frame is tried); an `ics` at 16^3 particles on a 32^3 mesh."""
import re
import shlex
import sys

import yaml

SRC = sys.argv[1]

# Scenes that need more than the tiny size, and why. Nightfall's stars are
# points whose peak surface brightness grows with the pixel count, over a
# black floor set for its 960x540 frame: at 96 pixels every star falls
# below it. A third of the width with the frame's crowding (about 1.9 stars
# a pixel, as tests/cli/test_nightfall.sh) shows them.
LARGER = {"configs/nightfall.yaml": (320, 111000)}


def commands(path):
    text = open(f"{SRC}/{path}").read()
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = re.sub(r"\s+#.*$", "", line).strip()  # a comment after the command
            if line.startswith(("build/orrery render ", "build/orrery ics ")):
                yield line


def value_of(words, key):
    """The last --set KEY=VALUE the command gives, or None."""
    found = None
    for a, b in zip(words, words[1:]):
        if a == "--set" and b.startswith(key + "="):
            found = b.split("=", 1)[1]
    return found


def tiny_size(image, words, prefix, width=96):
    w = int(value_of(words, prefix + "image.width") or image.get("width", 256))
    h = int(value_of(words, prefix + "image.height") or image.get("height", 256))
    tw = min(w, width)
    th = max(8, round(h * tw / w))
    return ["--set", f"{prefix}image.width={tw}", "--set", f"{prefix}image.height={th}"]


def overrides(words):
    if words[1] == "ics":
        return ["--grid", "16", "--pm-grid", "32"]
    scene = yaml.safe_load(open(f"{SRC}/{words[2]}"))
    width, particles = LARGER.get(words[2], (96, 12000))
    extra = []
    views = scene.get("views") or {}
    if views:
        for name, view in views.items():
            extra += tiny_size({**scene.get("image", {}), **(view or {}).get("image", {})}, words, f"views.{name}.",
                               width)
    else:
        extra += tiny_size(scene.get("image", {}), words, "", width)
    if "model" in (scene.get("input") or {}):
        extra += ["--set", f"input.model.particles={particles}"]
    frames = value_of(words, "animation.frames") or (scene.get("animation") or {}).get("frames")
    if frames and "--frames" not in words:
        extra += ["--frames", str(int(frames) // 2)]
    return extra


seen = set()
for doc in ("README.md", "docs/gallery.md"):
    for line in commands(doc):
        if "$" in line or line in seen:  # a loop's variable (its inputs come from a run); or said before
            continue
        seen.add(line)
        words = shlex.split(line)
        print(doc + "\t" + " ".join(shlex.quote(w) for w in words + overrides(words)))
