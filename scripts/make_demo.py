#!/usr/bin/env python3
"""Makes the bundled demo: assets/demo.mesh (a geodesic unit sphere) and
assets/demo.sol (an anisotropic metric: fine across a wavy band
z = 0.3 sin(3 phi), stretched along it, isotropic elsewhere).

Usage: python3 scripts/make_demo.py [OUTDIR]   (default: assets/)
"""
import math
import os
import sys


def icosphere(levels):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [unit(p) for p in v]
    for _ in range(levels):
        mid = {}
        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                mid[k] = len(v)
                v.append(unit(tuple((v[a][i] + v[b][i]) / 2 for i in range(3))))
            return mid[k]
        nf = []
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, f


def unit(p):
    n = math.sqrt(sum(x * x for x in p))
    return tuple(x / n for x in p)


def metric(p):
    """3x3 tensor (m11 m12 m22 m13 m23 m33) at a point of the unit sphere."""
    x, y, z = p
    phi = math.atan2(y, x)
    g = z - 0.3 * math.sin(3 * phi)          # the band is g = 0
    # gradient of g in space, projected onto the tangent plane
    r2 = max(x * x + y * y, 1e-12)
    dphi = (-y / r2, x / r2, 0.0)
    grad = tuple((1.0 if i == 2 else 0.0) - 0.9 * math.cos(3 * phi) * dphi[i] for i in range(3))
    n = p
    gn = sum(grad[i] * n[i] for i in range(3))
    t = tuple(grad[i] - gn * n[i] for i in range(3))
    if sum(c * c for c in t) < 1e-20:         # at the poles: any tangent direction
        t = (n[1] * 0 - n[2] * 1, n[2] * 1 - n[0] * 0, n[0] * 0 - n[1] * 1) if abs(n[0]) < 0.9 else (0, 1, 0)
        t = tuple(t[i] - sum(t[j] * n[j] for j in range(3)) * n[i] for i in range(3))
    e1 = unit(t)
    e2 = unit((n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]))
    hmax = 0.1
    w = math.exp(-(g / 0.15) ** 2)            # 1 on the band, 0 away
    h1 = hmax * (1 - w) + 0.015 * w           # across the band
    h2 = hmax                                 # along the band
    h3 = hmax                                 # normal direction
    M = [[0.0] * 3 for _ in range(3)]
    for h, e in ((h1, e1), (h2, e2), (h3, n)):
        for i in range(3):
            for j in range(3):
                M[i][j] += e[i] * e[j] / (h * h)
    return (M[0][0], M[0][1], M[1][1], M[0][2], M[1][2], M[2][2])


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "assets")
    os.makedirs(out, exist_ok=True)
    v, f = icosphere(2)
    with open(os.path.join(out, "demo.mesh"), "w") as fh:
        fh.write("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n%d\n" % len(v))
        for p in v:
            fh.write("%.17g %.17g %.17g 0\n" % p)
        fh.write("\nTriangles\n%d\n" % len(f))
        for a, b, c in f:
            fh.write("%d %d %d 1\n" % (a + 1, b + 1, c + 1))
        fh.write("\nEnd\n")
    with open(os.path.join(out, "demo.sol"), "w") as fh:
        fh.write("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n%d\n1 3\n" % len(v))
        for p in v:
            fh.write("%.17g %.17g %.17g %.17g %.17g %.17g\n" % metric(p))
        fh.write("\nEnd\n")
    print("wrote %s/demo.mesh (%d vertices, %d triangles) and demo.sol" % (out, len(v), len(f)))


if __name__ == "__main__":
    main()
