#!/usr/bin/env python3
"""A FreeFEM- / Gmsh-style adaptation loop in Python with the anisurf module.

usage: PYTHONPATH=build/python python3 bench/python_loop.py [--cycles N] [--error EPS]
                                                             [--grid N] [--out FILE.vtu]

Each cycle
  solve:   u = the toy solution, an analytic front evaluated at the mesh vertices;
  metric:  M = anisurf.metric.hessian(V, T, u, error=EPS)  (the Hessian recovered from
           the array, the L2-optimal metric);
  adapt:   anisurf.adapt(V, T, metric=M, fields={"u": u})  (u interpolated onto the
           new mesh, as a solver's previous solution would be);
and prints one line: vertices, triangles, the L2 and max error of the P1 interpolant
of the solution on the adapted mesh (sampled at 7 points per triangle), and how far
the interpolated u is from the solution at the new vertices. Starts from a grid of the
unit square (z = 0). With meshio or PyVista installed, --out writes the last mesh and
its solution through them (skipped otherwise).
"""
import argparse
import sys

import numpy as np

import anisurf

# Barycentric sample points of a triangle: corners, edge midpoints, centroid.
SAMPLES = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0.5, 0], [0, 0.5, 0.5], [0.5, 0, 0.5],
                    [1 / 3, 1 / 3, 1 / 3]])


def solve(points):
    """The toy solver: a steep front along a sine curve."""
    x, y = points[:, 0], points[:, 1]
    return np.tanh(30 * (y - 0.5 - 0.2 * np.sin(2 * np.pi * x)))


def grid(n):
    """The unit square as an n x n grid, two triangles per cell."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    a = (np.arange(n - 1)[None, :] + n * np.arange(n - 1)[:, None]).ravel()
    triangles = np.concatenate([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])])
    return vertices, triangles


def interpolation_error(vertices, triangles, u):
    """L2 and max error of the P1 interpolant of u against solve() on the triangles."""
    corners = vertices[triangles]                         # (M, 3, 3)
    points = np.einsum("sk,mkd->msd", SAMPLES, corners)   # (M, 7, 3)
    p1 = np.einsum("sk,mk->ms", SAMPLES, u[triangles])    # (M, 7)
    error = np.abs(p1 - solve(points.reshape(-1, 3)).reshape(p1.shape))
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    return np.sqrt(np.sum(area * np.mean(error**2, axis=1))), error.max()


def write_with_meshio_or_pyvista(path, vertices, triangles, u):
    """The mesh and its solution through meshio or PyVista, whichever is installed."""
    try:
        import meshio
        meshio.write(path, meshio.Mesh(vertices, [("triangle", triangles)], point_data={"u": u}))
        return "meshio"
    except ImportError:
        pass
    try:
        import pyvista
        faces = np.column_stack([np.full(len(triangles), 3), triangles]).ravel()
        mesh = pyvista.PolyData(vertices, faces)
        mesh.point_data["u"] = u
        mesh.save(path)
        return "pyvista"
    except ImportError:
        return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cycles", type=int, default=6)
    parser.add_argument("--error", type=float, default=0.005, help="interpolation error target of the metric")
    parser.add_argument("--grid", type=int, default=11, help="vertices per side of the starting grid")
    parser.add_argument("--out", help="write the last mesh and u (.vtu ...) with meshio or PyVista")
    args = parser.parse_args()

    vertices, triangles = grid(args.grid)
    u = solve(vertices)
    l2, worst = interpolation_error(vertices, triangles, u)
    print(f"cycle 0: V {len(vertices):6d}  T {len(triangles):6d}  L2 {l2:.3e}  max {worst:.3e}")
    for cycle in range(1, args.cycles + 1):
        metric = anisurf.metric.hessian(vertices, triangles, u, error=args.error)
        result = anisurf.adapt(vertices, triangles, metric=metric, fields={"u": u})
        vertices, triangles = result.vertices, result.triangles
        carried = result.fields["u"]
        u = solve(vertices)
        l2, worst = interpolation_error(vertices, triangles, u)
        print(f"cycle {cycle}: V {len(vertices):6d}  T {len(triangles):6d}  L2 {l2:.3e}  max {worst:.3e}  "
              f"carried u off by {np.abs(carried - u).max():.2e}  "
              f"in band {result.reports[-1]['in_band_pct']:.1f}%")
    if args.out:
        used = write_with_meshio_or_pyvista(args.out, vertices, triangles, u)
        print(f"wrote {args.out} with {used}" if used else "meshio and PyVista absent: --out skipped")
    return 0


if __name__ == "__main__":
    sys.exit(main())
