"""anisurf.adapt on numpy arrays: the measured properties of the output, and
the same mesh as the command line."""
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import anisurf
from conftest import cli_binary, edge_lengths, icosphere, shared_file, square_grid


def test_sphere_from_arrays_meets_the_size():
    vertices, triangles = icosphere(3)  # 642 vertices, edges ~0.19
    h = 0.1
    r = anisurf.adapt(vertices, triangles, size=h)
    # Edge lengths in the metric h^-2 I are the Euclidean ones over h.
    lengths = edge_lengths(r.vertices, r.triangles) / h
    # The band as the engine counts it, [1/sqrt 2, sqrt 2] (a symmetric
    # input puts whole families of edges between 1/sqrt 2 and 0.71).
    in_band = np.mean((lengths >= 1 / np.sqrt(2)) & (lengths <= np.sqrt(2)))
    assert in_band >= 0.9, f"{100 * in_band:.1f}% of the edges in band"
    assert r.lengths["in_band_pct"] == pytest.approx(100 * in_band, abs=0.5)
    # No inverted triangle: every normal points away from the centre.
    p = r.vertices[r.triangles]
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert np.all(np.einsum("ij,ij->i", normals, p.mean(axis=1)) > 0)
    assert r.quality["inverted"] == 0
    # Vertex count near the prediction 2 C / sqrt 3, C = area / h^2.
    predicted = 2 * 4 * np.pi / (np.sqrt(3) * h * h)
    assert abs(len(r.vertices) - predicted) < 0.15 * predicted
    assert r.reports[-1]["predicted_vertices"] == pytest.approx(predicted, rel=0.05)
    # On the surface: the smooth surface of the input stays within its sag.
    assert np.abs(np.linalg.norm(r.vertices, axis=1) - 1).max() < 0.01
    assert r.triangles.shape[1] == 3 and r.vertices.dtype == np.float64
    assert r.metric.shape == (len(r.vertices), 6)
    assert np.allclose(r.metric, [1 / h**2, 0, 1 / h**2, 0, 0, 1 / h**2])


def test_reports_per_cycle_and_pass():
    vertices, triangles = square_grid(3)
    r = anisurf.adapt(vertices, triangles, hessian_of="100*x^2", error=0.01, cycles=3, hgrad=-1,
                      measure_every_pass=True)
    assert 1 <= len(r.reports) <= 3
    for k, cycle in enumerate(r.reports, start=1):
        assert cycle["cycle"] == k
        assert cycle["error_estimate"] is not None and cycle["error_estimate"] > 0
        assert cycle["passes"] and all(p["measured"] for p in cycle["passes"])
        assert cycle["passes"][-1]["vertices"] == cycle["vertices"]
    assert r.reports[-1]["vertices"] == len(r.vertices)
    assert r.reports[-1]["triangles"] == len(r.triangles)
    # A Hessian of 100 x^2 stretches along y: sizes differ by far in x and y.
    m = r.metric
    assert np.median(m[:, 0] / m[:, 2]) > 10


@pytest.mark.parametrize("shape", ["tensors", "matrices", "sizes"])
def test_a_given_metric_array_equals_the_size(shape):
    vertices, triangles = icosphere(2)
    h = 0.2
    n = len(vertices)
    metric = {
        "tensors": np.tile([1 / h**2, 0, 1 / h**2, 0, 0, 1 / h**2], (n, 1)),
        "matrices": np.tile(np.eye(3) / h**2, (n, 1, 1)),
        "sizes": np.full(n, h),
    }[shape]
    # hausd=0: a given metric without the geometry protection, as a size has none.
    given = anisurf.adapt(vertices, triangles, metric=metric, hausd=0)
    sized = anisurf.adapt(vertices, triangles, size=h)
    assert np.array_equal(given.vertices, sized.vertices)
    assert np.array_equal(given.triangles, sized.triangles)


def test_linear_fields_stay_linear_on_a_flat_mesh():
    vertices, triangles = square_grid(6)
    x, y = vertices[:, 0], vertices[:, 1]
    fields = {"x": x.copy(), "v": np.column_stack([x, y, 2 * x - y]), "t": np.column_stack([x, y, x + y, 1 + x, y, x])}
    r = anisurf.adapt(vertices, triangles, size=0.07, fields=fields)
    assert len(r.vertices) > 3 * len(vertices)  # new vertices, interpolated
    X, Y = r.vertices[:, 0], r.vertices[:, 1]
    assert np.abs(r.fields["x"] - X).max() < 1e-9
    assert np.abs(r.fields["v"] - np.column_stack([X, Y, 2 * X - Y])).max() < 1e-9
    assert np.abs(r.fields["t"] - np.column_stack([X, Y, X + Y, 1 + X, Y, X])).max() < 1e-9
    assert r.fields["x"].shape == (len(r.vertices),) and r.fields["v"].shape == (len(r.vertices), 3)
    assert np.abs(r.vertices[:, 2]).max() == 0


def x_extent(vertices, triangles):
    """The largest x-extent of a triangle."""
    x = vertices[triangles, 0]
    return (x.max(axis=1) - x.min(axis=1)).max()


def test_adapt_takes_a_result_to_carry_the_fields_on():
    vertices, triangles = square_grid(5)
    first = anisurf.adapt(vertices, triangles, size=0.2, fields={"u": vertices[:, 0] ** 2})
    second = anisurf.adapt(first, size=0.1)
    assert len(second.vertices) > len(first.vertices)
    # P1 interpolation of the convex x^2 lies above it, by at most (x-extent)^2 / 4
    # per interpolation (the variance of the corners' x): once from the grid, once
    # from the first mesh.
    error = second.fields["u"] - second.vertices[:, 0] ** 2
    bound = (x_extent(vertices, triangles) ** 2 + x_extent(first.vertices, first.triangles) ** 2) / 4
    assert error.min() > -1e-12
    assert error.max() <= bound
    assert error.max() > 0


def test_hessian_of_a_field_array():
    vertices, triangles = square_grid(33)
    u = np.tanh(20 * (vertices[:, 0] - 0.5))
    r = anisurf.adapt(vertices, triangles, hessian_of_field="u", fields={"u": u}, error=0.01, hgrad=-1)
    near_front = np.abs(r.vertices[:, 0] - 0.5) < 0.1
    # Finer across the front (a fifth of the square) than far from it.
    assert near_front.mean() > 0.4
    assert set(r.fields) == {"u"}


CLI_CASES = {
    "size": (["--size", "0.05"], lambda m: {"size": 0.05}),
    "sol metric": (["-sol", "bench/inputs/sphere20k_band.sol"], lambda m: {"metric": m.fields["sol0"]}),
    "curvature": (["--hausd", "0.005"], lambda m: {"hausd": 0.005}),
}


@pytest.mark.parametrize("case", CLI_CASES)
def test_same_mesh_as_the_command_line(tmp_path, case):
    mesh = shared_file("bench/inputs/sphere20k.mesh")
    binary = cli_binary()
    flags, keywords = CLI_CASES[case]
    flags = [str(shared_file(f)) if f.endswith(".sol") else f for f in flags]
    out = tmp_path / "out.mesh"
    subprocess.run([binary, "adapt", str(mesh), *flags, "-o", str(out), "-v", "0"], check=True,
                   stdout=subprocess.DEVNULL)
    sol = [f for f in flags if f.endswith(".sol")]
    m = anisurf.load(str(mesh), sol=sol[0] if sol else "")
    r = anisurf.adapt(m.vertices, m.triangles, **keywords(m))
    cli = anisurf.load(str(out), sol=str(out.with_suffix(".sol")), build=False)
    assert len(r.vertices) == len(cli.vertices) > 500
    assert np.array_equal(r.vertices, cli.vertices)
    assert np.array_equal(r.triangles, cli.triangles)
    assert np.array_equal(r.metric, cli.fields["metric"])


def test_the_gil_is_released_while_adapting():
    vertices, triangles = icosphere(3)
    results = {}

    def work(name):
        start = time.perf_counter()
        results[name] = anisurf.adapt(vertices, triangles, size=0.04)
        results["seconds"] = time.perf_counter() - start

    worker = threading.Thread(target=work, args=("thread",))
    # This loop runs only while the worker does not hold the GIL: held through
    # the adaptation, it would stop for the whole of it (start() included).
    longest_gap, last = 0.0, time.perf_counter()
    worker.start()
    while worker.is_alive():
        now = time.perf_counter()
        longest_gap, last = max(longest_gap, now - last), now
    worker.join()
    assert results["seconds"] > 0.1
    assert longest_gap < results["seconds"] / 2, (longest_gap, results["seconds"])
    # Two at once give what one alone gives.
    with ThreadPoolExecutor(max_workers=2) as pool:
        both = list(pool.map(lambda h: anisurf.adapt(vertices, triangles, size=h), [0.04, 0.04]))
    for r in both:
        assert np.array_equal(r.vertices, results["thread"].vertices)
        assert np.array_equal(r.triangles, results["thread"].triangles)


def test_threads_remesh_by_regions_with_the_serial_figures():
    vertices, triangles = icosphere(4)  # 5120 triangles, refined to ~80k
    h = 0.02
    serial = anisurf.adapt(vertices, triangles, size=h, threads=1)
    both = anisurf.adapt(vertices, triangles, size=h, threads=2)
    again = anisurf.adapt(vertices, triangles, size=h, threads=2)
    regions = {p["region"] for p in both.reports[-1]["passes"]}
    assert len(regions) >= 3 and regions == set(range(len(regions)))  # the regions, then the band
    assert {p["region"] for p in serial.reports[-1]["passes"]} == {-1}
    assert both.quality["inverted"] == 0
    assert both.lengths["in_band_pct"] >= serial.lengths["in_band_pct"] - 0.5
    assert abs(len(both.vertices) - len(serial.vertices)) < 0.03 * len(serial.vertices)
    # The same output for the same thread count.
    assert np.array_equal(both.vertices, again.vertices)
    assert np.array_equal(both.triangles, again.triangles)
    # Closed: every edge shared by two triangles.
    edges = np.sort(both.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2)
    with pytest.raises(ValueError, match="threads"):
        anisurf.adapt(vertices, triangles, size=h, threads=-1)


def thin_slab(t, n):
    """The closed slab [0, 1] x [0, 1] x [0, t], each face a grid of squares (sides n x 1) in two triangles."""
    index, vertices, triangles = {}, [], []

    def vertex(p):
        key = tuple(round(x * 1e9) for x in p)
        if key not in index:
            index[key] = len(vertices)
            vertices.append(p)
        return index[key]

    def face(o, u, v, nu, nv):
        o, u, v = (np.asarray(x, dtype=float) for x in (o, u, v))
        for i in range(nu):
            for j in range(nv):
                p = [vertex(o + (a / nu) * u + (b / nv) * v) for a, b in ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1))]
                triangles.extend([(p[0], p[1], p[2]), (p[0], p[2], p[3])])

    x, y, z = (1, 0, 0), (0, 1, 0), (0, 0, t)
    face((0, 0, 0), y, x, n, n)
    face((0, 0, t), x, y, n, n)
    face((0, 0, 0), x, z, n, 1)
    face((0, 1, 0), z, x, 1, n)
    face((0, 0, 0), z, y, 1, n)
    face((1, 0, 0), y, z, n, 1)
    return np.array(vertices), np.array(triangles, dtype=np.int32)


def test_strip_width_lets_the_ridges_of_a_thin_plate_coarsen():
    vertices, triangles = thin_slab(0.01, 40)
    default = anisurf.adapt(vertices, triangles, size=0.1, threads=1)
    off = anisurf.adapt(vertices, triangles, size=0.1, threads=1, strip_width=0)
    assert default.quality["inverted"] == 0
    assert default.lengths["in_band_pct"] >= 90
    assert off.lengths["in_band_pct"] < default.lengths["in_band_pct"] - 20
    with pytest.raises(ValueError, match="strip_width"):
        anisurf.adapt(vertices, triangles, size=0.1, strip_width=-1)


def test_repair_quality_keyword_as_the_command_line_option():
    vertices, triangles = icosphere(4)
    default = anisurf.adapt(vertices, triangles, size=0.02, threads=2)
    off = anisurf.adapt(vertices, triangles, size=0.02, threads=2, repair_quality=0)

    def final_collapses(r):
        return sum(p["collapses"] for rep in r.reports for p in rep["passes"] if p["pass"] == "final")

    assert final_collapses(off) == 0
    assert final_collapses(default) > 0
    assert default.quality["q_min"] >= off.quality["q_min"]
    with pytest.raises(ValueError, match="repair_quality"):
        anisurf.adapt(vertices, triangles, size=0.1, repair_quality=1.5)
