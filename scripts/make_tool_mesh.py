#!/usr/bin/env python3
"""Writes assets/spatula_tool.off: a closed sculpting tool mesh made here (no outside source).

A profile revolved about +y (the tool axis, tip at y = 0, hand toward +y): a rounded tip, a cone flank, a
shoulder and a short shank with a flat top; its cross-section is an ellipse (z squeezed to 0.6), so the tool
is not symmetric about its axis and its roll matters. 24 segments around, 384 triangles, CCW from outside.
Units are arbitrary: a scene scales the longest side to tool.size_m.
"""
import math
import sys

N = 24
TIP_R = 0.15
prof = []
for i in range(1, 5):  # rounded tip: part of a circle of radius TIP_R centred on the axis at y = TIP_R
    a = -math.pi / 2 + (math.pi / 2 * 0.6) * i / 4
    prof.append((TIP_R * math.cos(a), TIP_R + TIP_R * math.sin(a)))
prof += [(0.45, 1.0), (0.5, 1.6), (0.5, 2.4), (0.35, 2.6)]

verts = [(0.0, 0.0, 0.0)]
for r, y in prof:
    for k in range(N):
        t = 2 * math.pi * k / N
        verts.append((r * math.cos(t), y, 0.6 * r * math.sin(t)))
top = len(verts)
verts.append((0.0, 2.6, 0.0))


def v(i, k):
    return 1 + i * N + (k % N)


tris = [(0, v(0, k + 1), v(0, k)) for k in range(N)]
for i in range(len(prof) - 1):
    for k in range(N):
        a, b, c, d = v(i, k), v(i, k + 1), v(i + 1, k), v(i + 1, k + 1)
        tris += [(a, b, d), (a, d, c)]
tris += [(top, v(len(prof) - 1, k), v(len(prof) - 1, k + 1)) for k in range(N)]


def signed_volume():
    s = 0.0
    for a, b, c in tris:
        A, B, C = verts[a], verts[b], verts[c]
        s += (A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0]) + A[2] * (B[0] * C[1] - B[1] * C[0])) / 6
    return s


if signed_volume() < 0:
    tris = [(a, c, b) for a, b, c in tris]
out = sys.argv[1] if len(sys.argv) > 1 else "assets/spatula_tool.off"
with open(out, "w") as f:
    f.write("OFF\n%d %d 0\n" % (len(verts), len(tris)))
    for p in verts:
        f.write("%.6f %.6f %.6f\n" % p)
    for t in tris:
        f.write("3 %d %d %d\n" % t)
