#!/usr/bin/env python3
"""The geometry of the report's section 7.3 ("hemi-sphere and half-circle
intersection", figures 24-26), as coarse Medit meshes, and optionally the
whole 7.3 chain through the anisurf CLI.

Reading of the figure (the report gives no dimensions): a hemisphere (dome,
z >= 0) of radius R standing on a flat half-disc (z = 0, y >= 0) of radius
RD whose diameter passes through the dome's centre. The two surfaces meet
along the half of the dome's base circle with y >= 0: that half circle is a
crease (dihedral 90 degrees, a feature curve the engine detects). The part
of the half-disc under the dome is left out, so that the surface is a
manifold (the engine's builder cuts edges shared by more than two
triangles): the half annulus R <= r <= RD, y >= 0, glued to the dome along
the crease. The other half of the dome's base (y < 0) is an open boundary,
and so are the two straight pieces of the diameter (R <= |x| <= RD) and the
outer half circle. Corners: (+-R, 0, 0), where the crease, the dome's open
base and the straight boundary meet, and (+-RD, 0, 0), where the boundary
turns by 90 degrees.

Scale: R = 6.4 and RD = 9.05 (the flat part a quarter of the dome's area, the
share that makes the report's suppression figures, 1116 triangles down to
480, plausible: the dome coarsened from size 0.8 to 1.118 keeps about half
of its triangles, the flat part at size 4 almost none). The isotropic
refinement to size 0.8 (M = 1.5625 I) then gives about 1100 triangles, as
the report's 1116. The levels of the section's metrics: the flat part, the
crease and the dome's open base lie at z = 0 (the suppression metric's
z <= 0: size 4 there, 1.118 on the dome); z <= 0.2 is the band at the foot
of the dome (about 0.2 / R = 2 degrees of latitude) where the discontinuous
anisotropic metric asks for h_z = 0.125.

Usage:
  python3 scripts/paper/hemisphere_halfdisc.py OUT.mesh
      writes T_i (the coarse mesh: 16 segments around the base, 4 rings).
  python3 scripts/paper/hemisphere_halfdisc.py --chain DIR [--anisurf BIN]
      writes DIR/T_i.mesh, runs `anisurf adapt` with the isotropic size 0.8
      to DIR/T_r.mesh, and writes the three metrics of section 7.3 on T_r's
      vertices: DIR/iso.sol (1.5625 I), DIR/aniso.sol (diag(1.5625, 1.5625,
      64) where z <= 0.2, 1.5625 I elsewhere), DIR/suppress.sol (0.0625 I
      where z <= 0, 0.8 I elsewhere). Tensors in the .sol order m11 m12 m22
      m13 m23 m33.
  Then, for each metric:
      build/app/anisurf adapt DIR/T_r.mesh -sol DIR/suppress.sol -o out.mesh -hgrad -1
      build/app/anisurf quality out.mesh --sol out.sol   (edges in [1/sqrt2, sqrt2])
  tests/data/paper73_Ti.mesh is this script's T_i (tests/test_remesh_paper73.cpp
  runs the same chain through the engine).

Standard library only.
"""
import math
import os
import subprocess
import sys

R = 6.4     # dome radius
RD = 9.05   # half-disc radius
N_BASE = 16  # segments around the dome's base (even: the crease is half of them)
N_RINGS = 4  # latitude rings of the dome below its pole
N_ANNULUS = 2  # rings of the flat half annulus beyond the crease

# The metrics of section 7.3 at a point (z only), as (m11 m12 m22 m13 m23 m33).
Z_SUPPRESS = 0.0
Z_ANISO = 0.2


def iso_metric(p):
    return (1.5625, 0, 1.5625, 0, 0, 1.5625)


def aniso_metric(p):
    return (1.5625, 0, 1.5625, 0, 0, 64.0) if p[2] <= Z_ANISO else iso_metric(p)


def suppress_metric(p):
    m = 6.25e-2 if p[2] <= Z_SUPPRESS else 0.8
    return (m, 0, m, 0, 0, m)


def zip_rings(a, b, closed):
    """Triangles between two rings of vertex ids a (lower / inner) and b,
    each with its points at increasing parameters in [0, 1] (closed: the
    ring wraps, the parameter of point i is i / len). Advances along the
    ring whose next point comes first. Orientation: (a_i, a_i+1, b_j) and
    (a_i+1, b_j+1, b_j), as seen with the ring running counter-clockwise and
    b on the far side."""
    na, nb = len(a), len(b)
    if closed:
        ta = [i / na for i in range(na + 1)]
        tb = [j / nb for j in range(nb + 1)]
        ida = a + [a[0]]
        idb = b + [b[0]]
    else:
        ta = [i / (na - 1) for i in range(na)]
        tb = [j / (nb - 1) for j in range(nb)]
        ida, idb = a, b
    tris = []
    i = j = 0
    while i < len(ida) - 1 or j < len(idb) - 1:
        advance_a = j == len(idb) - 1 or (i < len(ida) - 1 and ta[i + 1] <= tb[j + 1])
        if advance_a:
            tris.append((ida[i], ida[i + 1], idb[j]))
            i += 1
        else:
            tris.append((ida[i], idb[j + 1], idb[j]))
            j += 1
    return tris


def build():
    """Vertices (x, y, z) and triangles (0-based, with a reference: 1 the
    dome, 2 the half annulus) of T_i."""
    verts = []
    tris = []

    def add(p):
        verts.append(p)
        return len(verts) - 1

    # Dome: rings at latitudes k / N_RINGS * 90 degrees, then the pole.
    rings = []
    for k in range(N_RINGS):
        phi = 0.5 * math.pi * k / N_RINGS
        n = N_BASE if k == 0 else max(3, round(N_BASE * math.cos(phi)))
        shift = 0.0 if k == 0 else 0.5 * k / n  # staggered rings
        ring = []
        for i in range(n):
            th = 2 * math.pi * (i + shift) / n
            # z = 0 exactly on the base ring (the levels of the metrics)
            z = 0.0 if k == 0 else R * math.sin(phi)
            ring.append(add((R * math.cos(phi) * math.cos(th), R * math.cos(phi) * math.sin(th), z)))
        rings.append(ring)
    for k in range(N_RINGS - 1):
        tris += [(t, 1) for t in zip_rings(rings[k], rings[k + 1], True)]
    pole = add((0.0, 0.0, R))
    top = rings[-1]
    for i in range(len(top)):
        tris.append(((top[i], top[(i + 1) % len(top)], pole), 1))

    # Half annulus: open arcs from angle 0 to pi; the first is the crease,
    # the dome's base points with y >= 0.
    arcs = [rings[0][: N_BASE // 2 + 1]]
    for j in range(1, N_ANNULUS + 1):
        r = R + (RD - R) * j / N_ANNULUS
        m = max(2, round(0.5 * N_BASE * r / R))
        arcs.append([add((r * math.cos(math.pi * i / m), r * math.sin(math.pi * i / m), 0.0)) for i in range(m + 1)])
    for j in range(N_ANNULUS):
        # Seen from +z the arcs run counter-clockwise with the outer one
        # beyond: (inner_i, inner_i+1, outer) faces -z, so reverse.
        for t in zip_rings(arcs[j], arcs[j + 1], False):
            tris.append(((t[0], t[2], t[1]), 2))
    return verts, tris


def write_mesh(path, verts, tris):
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\n\nDimension 3\n\n")
        f.write("Vertices\n%d\n" % len(verts))
        for p in verts:
            f.write("%.17g %.17g %.17g 0\n" % p)
        f.write("\nTriangles\n%d\n" % len(tris))
        for (a, b, c), ref in tris:
            f.write("%d %d %d %d\n" % (a + 1, b + 1, c + 1, ref))
        f.write("\nEnd\n")


def read_vertices(path):
    """The vertex positions of an ASCII Medit mesh."""
    tokens = open(path).read().split()
    i = tokens.index("Vertices")
    n = int(tokens[i + 1])
    out = []
    for k in range(n):
        x, y, z = (float(t) for t in tokens[i + 2 + 4 * k: i + 5 + 4 * k])
        out.append((x, y, z))
    return out


def write_sol(path, points, metric):
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n%d\n1 3\n" % len(points))
        for p in points:
            f.write(" ".join("%.17g" % v for v in metric(p)) + "\n")
        f.write("\nEnd\n")


def chain(out_dir, anisurf):
    os.makedirs(out_dir, exist_ok=True)
    ti = os.path.join(out_dir, "T_i.mesh")
    tr = os.path.join(out_dir, "T_r.mesh")
    write_mesh(ti, *build())
    subprocess.run([anisurf, "adapt", ti, "--size", "0.8", "-v", "0", "-o", tr], check=True)
    points = read_vertices(tr)
    for name, metric in (("iso", iso_metric), ("aniso", aniso_metric), ("suppress", suppress_metric)):
        write_sol(os.path.join(out_dir, name + ".sol"), points, metric)
    print("%s: T_i, T_r (%d vertices), iso.sol, aniso.sol, suppress.sol" % (out_dir, len(points)))


def main(argv):
    if len(argv) >= 2 and argv[0] == "--chain":
        anisurf = "build/app/anisurf"
        if "--anisurf" in argv:
            anisurf = argv[argv.index("--anisurf") + 1]
        chain(argv[1], anisurf)
        return 0
    if len(argv) != 1 or argv[0].startswith("-"):
        print(__doc__, file=sys.stderr)
        return 2
    verts, tris = build()
    write_mesh(argv[0], verts, tris)
    print("%s: %d vertices, %d triangles" % (argv[0], len(verts), len(tris)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
