#!/usr/bin/env python3
"""The solution-driven adaptation loop by hand: metric -> adapt -> metric on the output -> ...

usage: hessian_loop.py MESH --f EXPR --error EPS [--cycles N] [--case CASE] [--norm P]
                       [--anisurf BIN] [--workdir DIR] [--metric-arg A ...] [--adapt-arg A ...]

Each cycle runs
    anisurf metric MESH_k --hessian-of EXPR --error EPS --norm P [metric args] -o k.sol
    anisurf adapt  MESH_k -sol k.sol -hgrad -1 [adapt args] -o MESH_{k+1}
and measures MESH_{k+1} with ../shared/bench/interp_error.py (L2 error of the P1
interpolant of CASE: case1 | case2 | case3 or a Python expression in x, y). Prints one
row per cycle: vertices, triangles, L2 and Linf errors, and the predicted vertex count
of the metric. MESH may be "square2": the unit square in 2 triangles (the report's
figure 17 start for case 1), written into the work directory. --norm defaults to 2, the
p of cycle_metric_defaults() (engine/metric/hessian.h); the Hessian is whatever the
binary's `metric --hessian-of` computes (recovered from the vertex values, or the
expression's own with hessian_of_expression).

examples:
  bench/hessian_loop.py square2 --f "100*x^2" --case case1 --error 0.01 --cycles 6
  bench/hessian_loop.py ../shared/bench/inputs/square3d.mesh --f "(x<0.3)?100*x^2:5" \\
      --case case2 --error 0.0022 --cycles 6
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_BIN = os.path.join(HERE, "..", "build", "app", "anisurf")
# The shared directory beside the repository (--shared to change it).
DEFAULT_SHARED = os.path.join(HERE, "..", "..", "shared")

SQUARE2 = """MeshVersionFormatted 2
Dimension 3
Vertices
4
0 0 0 1
1 0 0 1
1 1 0 1
0 1 0 1
Triangles
2
1 2 3 1
1 3 4 1
End
"""


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    return r.stdout


def measure(evaluator, mesh, case):
    out = run([sys.executable, evaluator, mesh, "--f", case, "--json"])
    return json.loads(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh")
    ap.add_argument("--f", required=True, help="muParser expression of the field (x, y, z)")
    ap.add_argument("--case", help="evaluator case (default: case1/2/3 guessed from --f, else --f in Python)")
    ap.add_argument("--error", required=True)
    ap.add_argument("--cycles", type=int, default=6)
    ap.add_argument("--norm", default="2", help="p of the L^p metric (default 2), or inf")
    ap.add_argument("--anisurf", default=DEFAULT_BIN)
    ap.add_argument("--shared", default=DEFAULT_SHARED, help="the shared directory (bench/interp_error.py)")
    ap.add_argument("--workdir")
    ap.add_argument("--metric-arg", action="append", default=[])
    ap.add_argument("--adapt-arg", action="append", default=[])
    a = ap.parse_args()
    evaluator = os.path.join(a.shared, "bench", "interp_error.py")
    if not os.path.exists(evaluator):
        sys.exit("hessian_loop.py: no evaluator at %s (give --shared DIR)" % evaluator)

    work = a.workdir or tempfile.mkdtemp(prefix="hessian_loop_")
    os.makedirs(work, exist_ok=True)
    mesh = a.mesh
    if mesh == "square2":
        mesh = os.path.join(work, "square2.mesh")
        with open(mesh, "w") as f:
            f.write(SQUARE2)
    case = a.case or a.f.replace("^", "**")

    m0 = measure(evaluator, mesh, case)
    print("# %s  f = %s  error %s  norm %s  metric args %s" % (a.mesh, a.f, a.error, a.norm,
                                                              " ".join(a.metric_arg) or "-"))
    print("%5s %7s %7s %12s %12s %10s" % ("cycle", "V", "T", "L2", "Linf", "predicted"))
    print("%5d %7d %7d %12.4e %12.4e %10s" % (0, m0["vertices"], m0["triangles"], m0["L2"], m0["Linf"], "-"))
    for k in range(1, a.cycles + 1):
        sol = os.path.join(work, "c%d.sol" % k)
        out_mesh = os.path.join(work, "c%d.mesh" % k)
        log = run([a.anisurf, "metric", mesh, "--hessian-of", a.f, "--error", a.error, "--norm", a.norm] + a.metric_arg + ["-o", sol])
        pred = re.search(r"predicted vertices (\d+)", log)
        run([a.anisurf, "adapt", mesh, "-sol", sol, "-hgrad", "-1"] + a.adapt_arg + ["-o", out_mesh])
        m = measure(evaluator, out_mesh, case)
        print("%5d %7d %7d %12.4e %12.4e %10s" % (k, m["vertices"], m["triangles"], m["L2"], m["Linf"],
                                                  pred.group(1) if pred else "?"), flush=True)
        mesh = out_mesh
    print("# meshes in %s" % work)


if __name__ == "__main__":
    main()
