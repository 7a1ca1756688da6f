#!/usr/bin/env python3
"""Writes plummer-sphere.txt: a Plummer (1911) sphere, scale radius a = 1,
total mass 1, 2000 equal-mass particles, positions only, truncated at 20 a.
Radii come from inverting the cumulative mass M(<r) = r^3 / (r^2 + 1)^(3/2):
r = 1 / sqrt(u^(-2/3) - 1) for u uniform in (0, 1)."""
import math
import random

random.seed(2)
N = 2000
rows = ["x y z mass"]
for _ in range(N):
    u = max(random.random(), 1e-6)
    r = min(1.0 / math.sqrt(u ** (-2.0 / 3.0) - 1.0), 20.0)
    cos_t = 2 * random.random() - 1
    sin_t = math.sqrt(1 - cos_t * cos_t)
    phi = 2 * math.pi * random.random()
    rows.append("%.6f %.6f %.6f %.6g" % (r * sin_t * math.cos(phi), r * sin_t * math.sin(phi), r * cos_t, 1.0 / N))
with open("plummer-sphere.txt", "w") as f:
    f.write("\n".join(rows) + "\n")
