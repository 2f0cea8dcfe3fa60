"""Shared helpers of the anisurf module's tests: meshes made with numpy, and
where the third-party meshes and the command line are (set by CTest)."""
import os
import pathlib

import numpy as np
import pytest

import anisurf  # noqa: F401  (a failed import fails every test at collection)

SOURCE_DIR = pathlib.Path(os.environ.get("ANISURF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SHARED_DIR = pathlib.Path(os.environ.get("ANISURF_SHARED_DIR", SOURCE_DIR.parent / "shared"))


def shared_file(relative):
    """Path of a file of ../shared, or skip the test when it is absent."""
    path = SHARED_DIR / relative
    if not path.exists():
        pytest.skip(f"{path} absent (third-party data)")
    return path


def cli_binary():
    """The anisurf executable CTest names, or skip."""
    binary = os.environ.get("ANISURF_BINARY")
    if not binary or not pathlib.Path(binary).exists():
        pytest.skip("ANISURF_BINARY not set (run through CTest)")
    return binary


def icosphere(subdivisions):
    """Unit icosphere: the icosahedron, each triangle split in 4 and the new
    vertices pushed onto the sphere, `subdivisions` times; outward triangles."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [np.array(p, float) / np.linalg.norm(p) for p in v]
    triangles = f
    for _ in range(subdivisions):
        midpoint = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                p = vertices[a] + vertices[b]
                vertices.append(p / np.linalg.norm(p))
                midpoint[key] = len(vertices) - 1
            return midpoint[key]

        refined = []
        for a, b, c in triangles:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        triangles = refined
    return np.array(vertices), np.array(triangles, dtype=np.int64)


def square_grid(n, size=1.0):
    """The square [0, size]^2 in the plane z = 0 as an n x n grid of
    vertices, each cell cut into two triangles (counter-clockwise)."""
    x, y = np.meshgrid(np.linspace(0, size, n), np.linspace(0, size, n), indexing="xy")
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="xy")
    a = (j * n + i).ravel()
    b, c, d = a + 1, a + n + 1, a + n
    triangles = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return vertices, triangles


def edge_lengths(vertices, triangles):
    """Euclidean length of every edge once."""
    e = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    return np.linalg.norm(vertices[e[:, 1]] - vertices[e[:, 0]], axis=1)
