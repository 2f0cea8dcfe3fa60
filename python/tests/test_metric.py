"""anisurf.metric builders and anisurf.quality, against closed forms."""
import numpy as np
import pytest

import anisurf
from conftest import icosphere, square_grid


def test_iso_is_h_to_the_minus_2():
    vertices, triangles = icosphere(1)
    m = anisurf.metric.iso(vertices, triangles, 0.25)
    assert m.shape == (len(vertices), 6)
    assert np.array_equal(m, np.tile([16.0, 0, 16, 0, 0, 16], (len(vertices), 1)))
    h = anisurf.metric.iso(vertices, triangles, "0.1 + 0.1 * (z > 0)")
    assert np.allclose(h[:, 0], np.where(vertices[:, 2] > 0, 25.0, 100.0))
    bounded = anisurf.metric.iso(vertices, triangles, 0.25, hmax=0.2)
    assert np.allclose(bounded[:, 0], 25.0)


def test_a_vertex_without_triangle_gets_nan():
    vertices, triangles = square_grid(3)
    vertices = np.vstack([vertices, [5.0, 5, 5]])
    m = anisurf.metric.iso(vertices, triangles, 0.5)
    assert np.all(np.isnan(m[-1])) and np.allclose(m[:-1, 0], 4.0)


def test_hessian_of_values_equals_the_expression_for_a_quadratic():
    # The recovery is exact for a quadratic on a flat mesh.
    vertices, triangles = square_grid(9)
    x, y = vertices[:, 0], vertices[:, 1]
    from_values = anisurf.metric.hessian(vertices, triangles, 100 * x**2 + 10 * x * y, error=0.01)
    from_expression = anisurf.metric.hessian_of(vertices, triangles, "100*x^2 + 10*x*y", error=0.01)
    assert np.allclose(from_values, from_expression, rtol=1e-6)
    with pytest.raises(ValueError, match=r"values must have shape \(81,\)"):
        anisurf.metric.hessian(vertices, triangles, x[:5], error=0.01)


def test_curvature_of_the_unit_sphere():
    vertices, triangles = icosphere(4)
    # 1e-2: the facets (edges 0.1) sag by 1.2e-3, below hausd / 4, so the
    # curvature decides (at 1e-3 the creases between the facets ask for more).
    hausd = 0.01
    m = anisurf.metric.curvature(vertices, triangles, hausd=hausd)
    # Tangent sizes sqrt(8 hausd / kappa), kappa = 1: eigenvalue 1 / (8 hausd).
    normal = vertices / np.linalg.norm(vertices, axis=1)[:, None]
    tensors = np.stack([m[:, [0, 1, 3]], m[:, [1, 2, 4]], m[:, [3, 4, 5]]], axis=1)
    t = np.cross(normal, [0.3, 0.5, 0.8])
    t /= np.linalg.norm(t, axis=1)[:, None]
    along = np.einsum("ni,nij,nj->n", t, tensors, t)
    assert np.allclose(along, 1 / (8 * hausd), rtol=0.05)


def test_tensor_expression():
    vertices, triangles = square_grid(3)
    m = anisurf.metric.tensor(vertices, triangles, "100, 0, 4, 0, 0, 1")
    assert np.allclose(m, [100, 0, 4, 0, 0, 1])


def test_quality_of_equilateral_and_flat_triangles():
    s = np.sqrt(3) / 2
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0.5, s, 0], [1.5, s, 0], [3, 0, 0], [4, 0, 0], [3.5, 0.01, 0]])
    triangles = np.array([[0, 1, 2], [1, 3, 2], [4, 5, 6]])
    q = anisurf.quality(vertices, triangles, np.full(len(vertices), 0.5))
    # Eq. 17 from the side lengths (in units of the size 0.5).
    sides = np.linalg.norm(vertices[triangles] - vertices[np.roll(triangles, 1, axis=1)], axis=2) / 0.5
    half = sides.sum(axis=1) / 2
    eq17 = 27 * np.prod(half[:, None] - sides, axis=1) / half**3
    assert q["quality"] == pytest.approx(eq17, rel=1e-9)
    assert q["quality"][:2] == pytest.approx([1, 1]) and q["quality"][2] < 0.001
    assert q["edges"].shape == (8, 2)
    expected = np.linalg.norm(vertices[q["edges"][:, 1]] - vertices[q["edges"][:, 0]], axis=1) / 0.5
    assert np.allclose(q["lengths"], expected)
    # Lengths 2 but the flat triangle's two short sides (1.0002).
    assert q["in_band_pct"] == pytest.approx(100 * 2 / 8)
    # Stretched along y by 10: the equilateral triangles become needles.
    m = np.tile([1.0, 0, 100, 0, 0, 1], (len(vertices), 1))
    assert np.all(anisurf.quality(vertices, triangles, m)["quality"][:2] < 0.5)
