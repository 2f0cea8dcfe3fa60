"""Bad arguments and the engine's refusals raise Python exceptions carrying
the message; the interpreter keeps running."""
import numpy as np
import pytest

import anisurf
from conftest import icosphere, square_grid


@pytest.fixture
def sphere():
    return icosphere(1)


def test_bad_shapes_are_value_errors(sphere):
    vertices, triangles = sphere
    with pytest.raises(ValueError, match=r"vertices must have shape \(N, 3\), got \(42, 2\)"):
        anisurf.adapt(vertices[:, :2], triangles, size=0.3)
    with pytest.raises(ValueError, match=r"triangles must have shape \(M, 3\)"):
        anisurf.adapt(vertices, triangles[:, :2], size=0.3)
    with pytest.raises(ValueError, match=r"metric must have shape \(42, 6\)"):
        anisurf.adapt(vertices, triangles, metric=np.ones((41, 6)))
    with pytest.raises(ValueError, match=r"fields\['u'\] must have shape"):
        anisurf.adapt(vertices, triangles, size=0.3, fields={"u": np.ones(5)})


def test_indices_out_of_range(sphere):
    vertices, triangles = sphere
    bad = triangles.copy()
    bad[7, 1] = -1
    with pytest.raises(ValueError, match=r"triangles\[7\] holds the vertex index -1, expected an index in \[0, 42\)"):
        anisurf.adapt(vertices, bad, size=0.3)
    bad[7, 1] = 42
    with pytest.raises(ValueError, match=r"triangles\[7\] holds the vertex index 42"):
        anisurf.quality(vertices, bad, np.full(42, 0.3))
    with pytest.raises(TypeError, match="integer array"):
        anisurf.adapt(vertices, triangles.astype(float), size=0.3)


def test_a_metric_not_positive_definite(sphere):
    vertices, triangles = sphere
    metric = np.tile([1.0, 0, 1, 0, 0, 1], (len(vertices), 1))
    metric[5] = [1, 2, 1, 0, 0, 1]  # eigenvalue -1
    with pytest.raises(anisurf.MetricError, match="vertex 6") as error:
        anisurf.adapt(vertices, triangles, metric=metric)
    assert isinstance(error.value, ValueError) and isinstance(error.value, anisurf.Error)
    with pytest.raises(anisurf.MetricError, match="vertex 6"):
        anisurf.quality(vertices, triangles, metric)
    asymmetric = np.tile(np.eye(3), (len(vertices), 1, 1))
    asymmetric[3, 0, 1] = 0.5
    with pytest.raises(ValueError, match=r"metric\[3\] is not symmetric"):
        anisurf.adapt(vertices, triangles, metric=asymmetric)


def test_keywords_are_checked(sphere):
    vertices, triangles = sphere
    with pytest.raises(TypeError, match="unexpected keyword argument 'hmni'"):
        anisurf.adapt(vertices, triangles, size=0.3, hmni=0.1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'eror'"):
        anisurf.metric.hessian(vertices, triangles, vertices[:, 0], eror=0.1)
    with pytest.raises(ValueError, match="give one metric source .* got metric and size"):
        anisurf.adapt(vertices, triangles, size=0.3, metric=np.full(len(vertices), 0.3))
    with pytest.raises(ValueError, match="give a metric source"):
        anisurf.adapt(vertices, triangles)
    with pytest.raises(ValueError, match="exactly one of error, complexity, target_vertices"):
        anisurf.adapt(vertices, triangles, hessian_of="x^2")
    with pytest.raises(ValueError, match="hgrad expects a ratio > 1"):
        anisurf.adapt(vertices, triangles, size=0.3, hgrad=0.5)
    with pytest.raises(ValueError, match="surface expects one of auto, g1, g1-closest, polyhedral"):
        anisurf.adapt(vertices, triangles, size=0.3, surface="smooth")
    with pytest.raises(TypeError, match="hmin expects a number"):
        anisurf.adapt(vertices, triangles, size=0.3, hmin="small")


def test_engine_errors_carry_the_engine_message(sphere):
    vertices, triangles = sphere
    with pytest.raises(anisurf.ExpressionError, match="x\\*\\*2|parse|Unexpected"):
        anisurf.adapt(vertices, triangles, size="x**2+")
    with pytest.raises(anisurf.MetricError, match="no solution field named 'u'"):
        anisurf.adapt(vertices, triangles, hessian_of_field="u", error=0.1, fields={"v": vertices[:, 0]})
    with pytest.raises(anisurf.ExpressionError, match="expected h > 0"):
        anisurf.metric.iso(vertices, triangles, "x")
    with pytest.raises(anisurf.TopologyError):
        anisurf.adapt(np.zeros((0, 3)), np.zeros((0, 3), dtype=int), size=0.3)


def test_files_refused_as_io_errors(tmp_path):
    with pytest.raises(anisurf.IoError) as error:
        anisurf.load(str(tmp_path / "absent.mesh"))
    assert isinstance(error.value, OSError) and "absent.mesh" in str(error.value)
    broken = tmp_path / "broken.mesh"
    broken.write_text("MeshVersionFormatted 2\nDimension 3\nVertices\n3\n0 0 0 0\n1 0\n")
    with pytest.raises(anisurf.IoError, match="broken.mesh"):
        anisurf.load(str(broken))
    with pytest.raises(anisurf.IoError, match="unknown mesh format"):
        anisurf.save(square_grid(2), str(tmp_path / "mesh.unknown"))


def test_the_interpreter_goes_on_after_errors(sphere):
    vertices, triangles = sphere
    for size in (-1, "1/0", "-x", "0.3"):
        with pytest.raises(ValueError):
            anisurf.adapt(vertices[:, :2] if size == "0.3" else vertices, triangles, size=size)
    r = anisurf.adapt(vertices, triangles, size=0.3)
    assert len(r.vertices) > 0


def test_a_metric_the_surface_cannot_carry_stops_with_the_prediction():
    vertices, triangles = icosphere(3)
    needle = np.tile([0.0078, 0, 0.0078, 0, 0, 7.8e5], (len(vertices), 1))
    # hausd=0: without the geometry protection, which would shorten the needles.
    with pytest.raises(anisurf.Error, match=r"adaptation stopped .* the metric predicts"):
        anisurf.adapt(vertices, triangles, metric=needle, hgrad=0, hausd=0)
    with pytest.raises(ValueError, match=r"max_growth expects a factor >= 0"):
        anisurf.adapt(vertices, triangles, metric=needle, max_growth=-1)
