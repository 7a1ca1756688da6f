"""The Python package's overhead and the .npy reader's speed (docs/python.md#measured).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [N] [--cli build/orrery] [--python-only]

Renders N particles (default 10^7, float32 positions and masses in numpy)
from Python and reports the wall time of scene.render against the library's
own time for the same frame (orrery_render_seconds), the peak memory of the
process, then writes the particles as a structured .npy file and times the
CLI rendering it against `cat FILE > /dev/null` of the same file
(--python-only: not that; 10^8 particles take 1.5 GB of memory then)."""
import argparse
import json
import os
import resource
import subprocess
import tempfile
import time

import numpy as np

import orrery

SCENE = {"camera": {"projection": "orthographic", "width": 8}, "image": {"width": 1024, "height": 1024},
         "deposit": "ngp"}


def best_of(k, f):
    best = None
    for _ in range(k):
        t0 = time.perf_counter()
        result = f()
        t = time.perf_counter() - t0
        best = t if best is None or t < best else best
    return best, result


def main():
    p = argparse.ArgumentParser()
    p.add_argument("n", nargs="?", type=int, default=10**7)
    p.add_argument("--cli", default=os.path.join(os.path.dirname(__file__), "..", "build", "orrery"))
    p.add_argument("--python-only", action="store_true", help="only the render from Python")
    args = p.parse_args()
    rng = np.random.default_rng(1)
    pos = np.empty((args.n, 3), np.float32)
    for start in range(0, args.n, 10**6):  # drawn in slices: no temporary as large as the array
        pos[start:start + 10**6] = rng.standard_normal((min(10**6, args.n - start), 3), dtype=np.float32)
    mass = np.ones(args.n, dtype=np.float32)
    scene = orrery.Scene(SCENE)
    scene.render(pos[:1000], mass[:1000])  # warm up: threads, tables
    libs = []  # the library's own time of each render: the best against the best wall time
    wall, _ = best_of(3, lambda: (scene.render(pos, mass), libs.append(scene.seconds)))
    lib = min(libs)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    data = pos.nbytes + mass.nbytes
    print(f"python render of {args.n} particles: {wall:.3f} s wall, library {lib:.3f} s, "
          f"overhead {100 * (wall - lib) / lib:.1f} %; peak RSS {peak:.0f} MiB with {data / 2**20:.0f} MiB of arrays")
    if args.python_only:
        return
    with tempfile.TemporaryDirectory() as tmp:
        table = np.zeros(args.n, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4"), ("mass", "f4")])
        for k, c in enumerate("xyz"):
            table[c] = pos[:, k]
        table["mass"] = mass
        path = os.path.join(tmp, "p.npy")
        np.save(path, table)
        del table
        with open(os.path.join(tmp, "s.yaml"), "w") as f:  # JSON is YAML
            json.dump({**SCENE, "input": {"file": path}, "output": {"png": False}}, f)
        cat, _ = best_of(3, lambda: subprocess.run(f"cat {path} > /dev/null", shell=True, check=True))
        info, _ = best_of(3, lambda: subprocess.run([args.cli, "info", path], check=True, capture_output=True))
        cli, _ = best_of(3, lambda: subprocess.run([args.cli, "render", os.path.join(tmp, "s.yaml"), "-o", tmp,
                                                    "--quiet"], check=True))
        tiny = os.path.join(tmp, "tiny.npy")
        np.save(tiny, pos[:3])
        start, _ = best_of(3, lambda: subprocess.run([args.cli, "info", tiny], check=True, capture_output=True))
        size = os.path.getsize(path) / 2**20
        # The CLI's render of the file less its start-up (dynamic linking) and
        # less the same render from memory: what reading the file cost.
        reading = cli - start - lib
        print(f".npy of {size:.0f} MiB: cat {cat:.3f} s ({size / cat:.0f} MiB/s); orrery render of it {cli:.3f} s = "
              f"start-up {start:.3f} s + render {lib:.3f} s + reading {reading:.3f} s ({size / reading:.0f} MiB/s); "
              f"orrery info {info:.3f} s (its statistics dominate)")


main()
