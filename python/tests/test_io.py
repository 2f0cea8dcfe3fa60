"""anisurf.load / anisurf.save: round trips keep every array exactly."""
import numpy as np
import pytest

import anisurf
from conftest import icosphere, shared_file, square_grid


def test_mesh_round_trip_keeps_arrays_exactly(tmp_path):
    vertices, triangles = icosphere(2)
    vertices = vertices * np.pi  # digits beyond a float's
    refs = np.arange(len(triangles)) % 3 + 1
    path = str(tmp_path / "sphere.mesh")
    anisurf.save((vertices, triangles, refs), path)
    back = anisurf.load(path, build=False)
    assert np.array_equal(back.vertices, vertices)
    assert np.array_equal(back.triangles, triangles)
    assert np.array_equal(back.refs, refs)
    assert back.triangles.dtype == np.int32


@pytest.mark.parametrize("extension", ["mesh", "meshb", "ply", "obj", "off"])
def test_tags_and_formats_round_trip(tmp_path, extension):
    vertices, triangles = square_grid(4)
    mesh = anisurf.Mesh(vertices, triangles, refs=np.ones(len(triangles), dtype=int))
    if extension == "off":  # written by no writer: refused with the engine's message
        with pytest.raises(anisurf.IoError):
            anisurf.save(mesh, str(tmp_path / f"m.{extension}"))
        return
    mesh.edges = np.array([[0, 1], [1, 2]])
    mesh.ridges = np.array([1])
    mesh.corners = np.array([0, 3])
    path = str(tmp_path / f"m.{extension}")
    anisurf.save(mesh, path)
    back = anisurf.load(path, build=False)
    assert np.array_equal(back.vertices, vertices) if extension in ("mesh", "meshb", "ply") else np.allclose(
        back.vertices, vertices, rtol=1e-6)
    assert np.array_equal(back.triangles, triangles)
    if extension in ("mesh", "meshb"):
        assert np.array_equal(back.edges, mesh.edges)
        assert np.array_equal(back.ridges, mesh.ridges)
        assert np.array_equal(back.corners, mesh.corners)
        assert np.array_equal(back.refs, mesh.refs)


def test_fields_round_trip_through_sol(tmp_path):
    vertices, triangles = icosphere(1)
    n = len(vertices)
    rng = np.random.default_rng(3)
    fields = {"s": rng.random(n), "v": rng.random((n, 3)), "metric": rng.random((n, 6))}
    anisurf.save((vertices, triangles), str(tmp_path / "m.mesh"))
    anisurf.save((vertices, triangles), str(tmp_path / "m.sol"), fields=fields)
    back = anisurf.load(str(tmp_path / "m.mesh"), sol=str(tmp_path / "m.sol"))
    assert set(back.fields) == set(fields)
    for name, values in fields.items():
        assert np.array_equal(back.fields[name], values), name
    with pytest.raises(ValueError, match="no field to write"):
        anisurf.save((vertices, triangles), str(tmp_path / "none.sol"))


def test_a_result_saves_and_loads(tmp_path):
    vertices, triangles = square_grid(3)
    r = anisurf.adapt(vertices, triangles, size=0.3, fields={"x": vertices[:, 0]})
    anisurf.save(r, str(tmp_path / "r.mesh"))
    anisurf.save(r, str(tmp_path / "r.sol"), fields={"metric": r.metric})
    back = anisurf.load(str(tmp_path / "r.mesh"), sol=str(tmp_path / "r.sol"), build=False)
    assert np.array_equal(back.vertices, r.vertices) and np.array_equal(back.triangles, r.triangles)
    assert np.array_equal(back.fields["x"], r.fields["x"])
    assert np.array_equal(back.fields["metric"], r.metric)


def test_load_builds_as_the_command_line():
    path = shared_file("meshes/torus.STL")
    raw = anisurf.load(str(path), build=False)
    built = anisurf.load(str(path))
    # STL stores a vertex per triangle corner: the build merges them.
    assert len(raw.vertices) == 3 * len(raw.triangles)
    assert len(built.vertices) < len(raw.vertices) / 3
    assert len(built.vertices) - len(built.triangles) / 2 == 0  # a torus: V - E + T = 0


def test_a_meshio_mesh_adapts_and_goes_back(tmp_path):
    meshio = pytest.importorskip("meshio")
    vertices, triangles = icosphere(2)
    meshio.write(str(tmp_path / "in.vtu"), meshio.Mesh(vertices, [("triangle", triangles)]))
    m = meshio.read(str(tmp_path / "in.vtu"))
    r = anisurf.adapt(m.points, m.cells_dict["triangle"], size=0.15, fields={"z": m.points[:, 2]})
    meshio.write(str(tmp_path / "out.vtu"),
                 meshio.Mesh(r.vertices, [("triangle", r.triangles)], point_data={"metric": r.metric, **r.fields}))
    back = meshio.read(str(tmp_path / "out.vtu"))
    assert np.array_equal(back.points, r.vertices)
    assert np.array_equal(back.cells_dict["triangle"], r.triangles)
    assert np.array_equal(back.point_data["metric"], r.metric)
    assert np.abs(back.point_data["z"] - r.vertices[:, 2]).max() < 0.05
