#!/usr/bin/env python3
"""Interoperability of the .msh / .vtu / .vtp / .vtk files with Gmsh, VTK and
meshio (optional: each tool is used only if present; exit 77 = skipped when
none is).

Usage: python3 tests/interop_formats.py ANISURF_BINARY DEMO.mesh DEMO.sol WORKDIR
(ctest runs it as interop_formats with the Python CMake finds; configure with
-DPython3_EXECUTABLE=/usr/bin/python3 to use Debian's python3-vtk9 and python3-meshio)

1. anisurf writes the demo with its metric in every layout; VTK's XML and
   legacy readers, meshio and `gmsh -check` read them: point and cell counts,
   coordinates, triangle refs and the metric as 9 components are compared with
   the Medit input (read by meshio) bit for bit.
2. meshio writes the demo (scalar, vector and 3x3 tensor point data, physical
   tags) as .vtu, .vtk, .msh 2.2 and 4.1 (ASCII and binary), and Gmsh writes
   .msh 2.2 / 4.1 (ASCII and binary) of a geometry with physical groups;
   anisurf converts each to an ASCII .vtu that meshio reads back and compares.
3. Gmsh reads anisurf's .msh with the metric as $NodeData and saves it (mesh
   and view) as 2.2 / 4.1, ASCII / binary; anisurf reads the metric back.
"""
import os
import shutil
import subprocess
import sys

try:
    import numpy as np
except ImportError:
    print("interop: numpy missing, skipped")
    sys.exit(77)

try:
    import meshio
except ImportError:
    meshio = None
try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError:
    vtk = None
GMSH = shutil.which("gmsh")

failures = []


def check(cond, what):
    print(("ok     " if cond else "FAILED ") + what)
    if not cond:
        failures.append(what)


def run(*args):
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(" ".join(args) + ":\n" + r.stdout + r.stderr)
    return r.stdout + r.stderr


def read_sol_tensors(path):
    """The demo's SolAtVertices of one tensor field: m11 m12 m22 m13 m23 m33."""
    tokens = [t for line in open(path) for t in line.split("#")[0].split()]
    i = tokens.index("SolAtVertices")
    n = int(tokens[i + 1])
    vals = np.array([float(t) for t in tokens[i + 4:i + 4 + 6 * n]]).reshape(n, 6)
    m11, m12, m22, m13, m23, m33 = vals.T
    return np.stack([m11, m12, m13, m12, m22, m23, m13, m23, m33], axis=1)


def vtk_read(path):
    ext = os.path.splitext(path)[1]
    r = {".vtu": vtk.vtkXMLUnstructuredGridReader, ".vtp": vtk.vtkXMLPolyDataReader}.get(
        ext, vtk.vtkDataSetReader)()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def anisurf_writes(anisurf, mesh, sol, work):
    ref = meshio.read(mesh) if meshio else None
    tensors = read_sol_tensors(sol)
    layouts = [("m41b.msh", []), ("m41a.msh", ["--ascii"]), ("m22b.msh", ["--msh-version", "2.2"]),
               ("m22a.msh", ["--msh-version", "2.2", "--ascii"])]
    for ext in (".vtu", ".vtp"):
        layouts += [("appended" + ext, []), ("binary" + ext, ["--vtk-encoding", "binary"]),
                    ("ascii" + ext, ["--ascii"]), ("appb64" + ext, ["--vtk-encoding", "appended-base64"]),
                    ("zlib" + ext, ["--zlib"]), ("zlibb64" + ext, ["--zlib", "--vtk-encoding", "binary"])]
    layouts.append(("legacy.vtk", []))
    for name, opts in layouts:
        path = os.path.join(work, name)
        run(anisurf, "convert", mesh, path, "--sol", sol, *opts)
        if name.endswith(".msh") and GMSH:
            out = run(GMSH, "-check", path)
            check("Error" not in out and "162 nodes" in out and "320 elements" in out, "gmsh -check " + name)
        if vtk and not name.endswith(".msh"):
            o = vtk_read(path)
            pts = vtk_to_numpy(o.GetPoints().GetData())
            metric = vtk_to_numpy(o.GetPointData().GetArray("sol0"))
            check(o.GetNumberOfPoints() == 162 and o.GetNumberOfCells() == 320, "vtk reads %s: 162 points, 320 cells" % name)
            if ref is not None:
                check(np.array_equal(pts, ref.points), "vtk reads %s: coordinates bit-exact" % name)
            check(np.array_equal(metric, tensors), "vtk reads %s: metric (9 components) exact" % name)
        if meshio and not name.endswith((".vtp", ".vtk")):  # meshio reads neither .vtp nor legacy POLYDATA
            m = meshio.read(path)
            tri = np.concatenate([c.data for c in m.cells if c.type == "triangle"])
            # MSH 4.1 nodes come in entity blocks: compare the triangles' corners.
            ref_tri = ref.cells_dict["triangle"]
            check(len(tri) == len(ref_tri) and np.array_equal(m.points[tri], ref.points[ref_tri]),
                  "meshio reads %s: triangles and their coordinates bit-exact" % name)
            key = "sol0"
            if key in m.point_data:
                got = m.point_data[key].reshape(-1, 9)
                check(np.array_equal(got[tri], tensors[ref_tri]), "meshio reads %s: metric exact" % name)
            else:
                check(False, "meshio reads %s: point data sol0 (found %s)" % (name, list(m.point_data)))


def anisurf_reads(anisurf, mesh, work):
    ref = meshio.read(mesh)
    n = len(ref.points)
    x = ref.points
    point_data = {"s": x[:, 0] + 2 * x[:, 1], "v": x.copy(),
                  "t": np.array([[1, 0.5, 0.25, 0.5, 2, 0.125, 0.25, 0.125, 3]] * n, dtype=float)}
    tri = ref.cells_dict["triangle"]
    phys = (np.arange(len(tri)) % 3 + 1).astype(np.int32)
    m = meshio.Mesh(ref.points, [("triangle", tri)], point_data=point_data,
                    cell_data={"gmsh:physical": [phys], "gmsh:geometrical": [phys]})
    cases = [("mio.vtu", "vtu", {}), ("mio_ascii.vtu", "vtu", {"binary": False}), ("mio.vtk", "vtk", {}),
             ("mio_ascii.vtk", "vtk", {"binary": False}),
             ("mio22b.msh", "gmsh22", {}), ("mio22a.msh", "gmsh22", {"binary": False}),
             ("mio41b.msh", "gmsh", {}), ("mio41a.msh", "gmsh", {"binary": False})]
    for name, fmt, kw in cases:
        path = os.path.join(work, name)
        mm = m
        if name.endswith(".msh"):  # meshio writes point data of .msh as $NodeData
            mm = meshio.Mesh(ref.points, [("triangle", tri)], point_data=point_data,
                             cell_data={"gmsh:physical": [phys], "gmsh:geometrical": [phys]})
        meshio.write(path, mm, file_format=fmt, **kw)
        back = os.path.join(work, name + ".back.vtu")
        run(anisurf, "convert", path, back, "--ascii")
        b = meshio.read(back)
        # meshio's ASCII .vtu holds 12 significant digits: equal up to that.
        same = np.array_equal if "ascii.vtu" not in name else (lambda a, c: np.allclose(a, c, rtol=1e-11, atol=1e-300))
        check(same(b.points, ref.points), "anisurf reads meshio's %s: coordinates exact" % name)
        check(np.array_equal(b.cells_dict["triangle"], tri), "anisurf reads meshio's %s: triangles equal" % name)
        if "41" not in name:  # meshio's MSH 4.1 writer has no $Entities: its physical tags are not in the file
            check(np.array_equal(b.cell_data["medit:ref"][0], phys), "anisurf reads meshio's %s: physical tags as refs"
                  % name)
        check(same(b.point_data["s"], point_data["s"]) and same(b.point_data["v"], point_data["v"])
              and same(b.point_data["t"].reshape(-1, 9), point_data["t"]),
              "anisurf reads meshio's %s: scalar, vector, tensor exact" % name)


def gmsh_writes(anisurf, work):
    geo = os.path.join(work, "box.geo")
    with open(geo, "w") as f:
        f.write('SetFactory("OpenCASCADE");\nBox(1) = {0,0,0, 1,1,1};\nPhysical Surface(7) = {1,2,3};\n'
                'Physical Surface(9) = {4,5,6};\nPhysical Curve(3) = {1,2};\nPhysical Point(5) = {1};\n'
                'Mesh.MeshSizeMax = 0.3;\n')
    for fmt in ("msh22", "msh41"):
        for binary in (False, True):
            path = os.path.join(work, "gmsh_%s%s.msh" % (fmt, "_bin" if binary else ""))
            run(GMSH, geo, "-2", "-format", fmt, *(["-bin"] if binary else []), "-o", path)
            back = os.path.join(work, os.path.basename(path) + ".back.vtu")
            out = run(anisurf, "convert", path, back, "--ascii")
            if meshio:
                g = meshio.read(path)
                b = meshio.read(back)
                tri = g.cells_dict["triangle"]
                check(len(b.cells_dict["triangle"]) == len(tri), "anisurf reads gmsh's %s: %d triangles"
                      % (os.path.basename(path), len(tri)))
                refs = set(b.cell_data["medit:ref"][0].tolist())
                check({7, 9} <= refs, "anisurf reads gmsh's %s: physical surfaces 7 and 9 as refs"
                      % os.path.basename(path))
            check("wrote" in out, "anisurf converts gmsh's " + os.path.basename(path))


def gmsh_rewrites_fields(anisurf, mesh, sol, work):
    """Gmsh reads anisurf's .msh with its $NodeData and saves the view with the
    mesh in every layout; anisurf reads the metric back (exact in binary, to
    Gmsh's 16 digits in ASCII)."""
    src = os.path.join(work, "fields41.msh")
    run(anisurf, "convert", mesh, src, "--sol", sol)
    ref = os.path.join(work, "fields41.ref.vtu")
    run(anisurf, "convert", src, ref, "--ascii")
    r = meshio.read(ref)
    for version in ("2.2", "4.1"):
        for binary in (0, 1):
            out = os.path.join(work, "gmsh_view_%s_%d.msh" % (version, binary))
            geo = os.path.join(work, "view.geo")
            with open(geo, "w") as f:
                f.write('Merge "%s";\nPostProcessing.Format = 5;\nMesh.MshFileVersion = %s;\nMesh.Binary = %d;\n'
                        'PostProcessing.SaveMesh = 1;\nSave View[0] "%s";\n' % (src, version, binary, out))
            run(GMSH, geo, "-0")
            back = out + ".back.vtu"
            run(anisurf, "convert", out, back, "--ascii")
            b = meshio.read(back)
            same = np.array_equal if binary else (lambda a, c: np.allclose(a, c, rtol=1e-15, atol=0))
            tri, rtri = b.cells_dict["triangle"], r.cells_dict["triangle"]
            name = os.path.basename(out)
            check(same(b.points[tri], r.points[rtri]), "anisurf reads gmsh's view file %s: coordinates" % name)
            check(same(b.point_data["sol0"][tri], r.point_data["sol0"][rtri]),
                  "anisurf reads gmsh's view file %s: the metric $NodeData" % name)


def main():
    if len(sys.argv) != 5:
        print(__doc__)
        return 2
    anisurf, mesh, sol, work = sys.argv[1:]
    if not (meshio or vtk or GMSH):
        print("interop: none of gmsh, python3 vtk, meshio found: skipped")
        return 77
    os.makedirs(work, exist_ok=True)
    print("interop: gmsh %s, vtk %s, meshio %s" % (bool(GMSH), bool(vtk), bool(meshio)))
    if meshio:
        anisurf_writes(anisurf, mesh, sol, work)
        anisurf_reads(anisurf, mesh, work)
    if GMSH:
        gmsh_writes(anisurf, work)
    if GMSH and meshio:
        gmsh_rewrites_fields(anisurf, mesh, sol, work)
    print("interop: %d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
