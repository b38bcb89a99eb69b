#!/usr/bin/env python3
"""Writes M.mtx and K.mtx of two reference beams (examples/beam.toml's steel
beam: 6 Euler-Bernoulli elements, clamped at node 0) side by side, with no
coupling: dofs 1-12 are beam A (w1, theta1, ..., w6, theta6), 13-24 beam B.
The case file joins them (a cubic spring between the tips, dofs 11 and 23).
Element matrices: lib/include/podid/core/beam_model.hpp. Run from this folder."""
import numpy as np

L, N, E, RHO, A = 0.593, 6, 2.05e11, 7800.0, 0.196e-3
I = A * A / 12.0
l = L / N
ke = E * I / l**3 * np.array([[12, 6 * l, -12, 6 * l], [6 * l, 4 * l * l, -6 * l, 2 * l * l],
                              [-12, -6 * l, 12, -6 * l], [6 * l, 2 * l * l, -6 * l, 4 * l * l]])
me = RHO * A * l / 420.0 * np.array([[156, 22 * l, 54, -13 * l], [22 * l, 4 * l * l, 13 * l, -3 * l * l],
                                     [54, 13 * l, 156, -22 * l], [-13 * l, -3 * l * l, -22 * l, 4 * l * l]])


def beam(e):
    m = np.zeros((2 * N + 2, 2 * N + 2))
    for i in range(N):
        m[2 * i:2 * i + 4, 2 * i:2 * i + 4] += e
    return m[2:, 2:]  # clamp node 0


def write(path, blocks):
    n = sum(b.shape[0] for b in blocks)
    entries = []
    offset = 0
    for b in blocks:
        for j in range(b.shape[1]):
            for i in range(j, b.shape[0]):
                if b[i, j] != 0.0:
                    entries.append((offset + i + 1, offset + j + 1, b[i, j]))
        offset += b.shape[0]
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write("% two reference beams, uncoupled (make_matrices.py)\n")
        f.write("%d %d %d\n" % (n, n, len(entries)))
        for i, j, v in entries:
            f.write("%d %d %.17g\n" % (i, j, v))


write("M.mtx", [beam(me), beam(me)])
write("K.mtx", [beam(ke), beam(ke)])
