#!/usr/bin/env python3
"""Benchmark of `anisurf adapt` on the shared bench cases, measured by the
independent evaluator (../shared/bench/eval.py), next to the reference peer's
figures (Mmg 5.8.0 mmgs, from ../shared/bench/README.md).

usage: bench_remesh.py [--anisurf BIN] [--shared DIR] [--out DIR] [--large]
                       [--cases a,b] [--profiles default,paper] [-- extra adapt options]
       bench_remesh.py --peer [--mmgs BIN] [--repeat N] [--cases a,b] [--scaling]
       bench_remesh.py --threads-series [--threads 1,2] [--repeat N] [--cases a,b]

--peer: the performance table of issue #16, anisurf and Mmg 5.8.0's mmgs run side
by side in this run on the same inputs (the only meaningful ratio on a shared
machine): isotropic refinements of sphere20k to size 0.02 (~80k triangles) and
0.004 (~1.8M; mmgs given a scalar .sol, its isotropic code), the coarsening
sphere500k_band -hgrad -1 and the anisotropic sphere20k_bandfine. Per tool: T,
wall time and peak RSS (the median of --repeat runs), bytes per output triangle,
% of edges in band and q min / mean by eval.py; the ratio mmgs time / anisurf
time. --scaling adds the isotropic series of sphere20k at sizes giving about
10k, 100k, 1M and 3M triangles, with the time per triangle and its spread.

--threads-series: `anisurf adapt --threads N` for each N of --threads (default
1 and every core) on sphere20k_isofine and sphere20k_bandfine (--cases picks
others of --peer's), the runs of each case interleaved (1, 2, 1, 2 ...: the
machine's drift hits both alike): wall time (median), the speedup over the
first N, T, % in band and q min / mean by eval.py.

Profiles: `default` runs `anisurf adapt` with its defaults (lmin 0.72, lmax 1.4:
the edges end in eval.py's band [1/sqrt2, sqrt2]); `paper` with the report's
lmin 0.6 (edges of 0.6-0.707 then count as adapted for the algorithm).
Each case runs once per profile with the options of the table (plus the extra ones); the
time is the wall time of the whole command (load, metric, adaptation,
writing), the peak RSS that of the process. --large adds the ~500k-triangle
refinements (sphere20k_isofine, sphere20k_bandfine) and the 500k-triangle
coarsening case sphere500k_band (its input is made by ../shared/bench/gen.py
into --out when missing). The square3d_hessian case also reports the L2
interpolation error of the report's Table 1 (interp_error.py --f case1).
"""
import argparse
import json
import os
import subprocess
import sys
import time

from mmg_peer import find_mmgs

# Mmg 5.8.0 mmgs on these cases (bench/README.md): V, T, time s, RSS MB,
# % in band, q min, q mean, qc mean, max distance to the sphere (vertices, centroids).
MMGS = {
    "sphere20k_iso": (6300, 12596, 0.29, 103, 98.3, 0.497, 0.968, 0.968, 2.7e-5, 9.0e-4),
    "sphere20k_band_nograd": (3990, 7976, 2.57, 104, 94.2, 0.013, 0.872, 0.863, 5.6e-5, 4.6e-3),
    "sphere20k_band": (4435, 8866, 2.93, 104, 82.0, 0.020, 0.863, 0.855, 6.2e-5, 2.7e-3),
    "sphere20k_bandfine": (393758, 787512, 232.8, 229, 98.2, 0.000, 0.944, 0.944, 5.7e-5, 6.9e-5),
    "sphere20k_isofine": (265053, 530102, 13.3, 159, 95.4, 0.389, 0.948, 0.948, 9.5e-6, 3.3e-5),
    "hemi_iso": (983, 1868, 0.10, 102, 96.3, 0.612, 0.947, 0.947, 1.4e-2, 1.5e-2),
    "square3d": (283, 368, 0.12, 102, 62.0, 0.003, 0.601, 0.601, None, None),
    "sphere500k_band": (3969, 7934, 5.37, 164, 93.7, 0.017, 0.874, 0.864, 4.2e-5, 3.4e-3),
}

# name: (mesh, sol, adapt options, eval metric spec, sphere distances?)
CASES = {
    "sphere20k_iso": ("sphere20k.mesh", "sphere20k_iso.sol", [], "iso:0.05", True),
    "sphere20k_band_nograd": ("sphere20k.mesh", "sphere20k_band.sol", ["-hgrad", "-1"], "band", True),
    "sphere20k_band": ("sphere20k.mesh", "sphere20k_band.sol", [], "band", True),
    # the report's section 7.2: the smooth surface of the coarse input, whole, for the metric
    # alone (no geometry protection: it would follow the input's 20-degree facets, 5.7x the vertices)
    "hemi_iso": ("hemi.mesh", "hemi_iso.sol", ["--free-surface", "--hausd", "0"], "iso:0.085", True),
    "square3d": ("square3d.mesh", "square3d.sol", [], "f100x2:0.01", False),
    # the report's Table 1: the metric from the Hessian of f = 100 x^2 (195 V: 4.4573e-3)
    "square3d_hessian": ("square3d.mesh", None, ["--hessian-of", "100*x^2", "--error", "0.01"], "f100x2:0.01", False),
}
LARGE = {
    "sphere20k_isofine": ("sphere20k.mesh", "sphere20k_isofine.sol", [], "iso:0.007", True),
    "sphere20k_bandfine": ("sphere20k.mesh", "sphere20k_bandfine.sol", [], "bandfine", True),
    "sphere500k_band": ("@out/sphere500k.mesh", "@out/sphere500k_band.sol", ["-hgrad", "-1"], "band", True),
}


# Issue #16's cases: name -> (mesh, sol or None, isotropic size or None, adapt / mmgs options, eval spec).
PEER_CASES = {
    "iso80k": ("sphere20k.mesh", None, 0.02, [], "iso:0.02"),
    "iso1.8M": ("sphere20k.mesh", None, 0.004, [], "iso:0.004"),
    "sphere500k_band_nograd": ("@out/sphere500k.mesh", "@out/sphere500k_band.sol", None, ["-hgrad", "-1"], "band"),
    "sphere20k_bandfine": ("sphere20k.mesh", "sphere20k_bandfine.sol", None, [], "bandfine"),
    "sphere20k_isofine": ("sphere20k.mesh", "sphere20k_isofine.sol", None, [], "iso:0.007"),
}
THREAD_CASES = ["sphere20k_isofine", "sphere20k_bandfine"]
# Sizes of the scaling series on sphere20k (the unit sphere: about 29 / h^2 triangles).
SCALING_SIZES = [0.054, 0.017, 0.0054, 0.0031]


def mesh_vertex_count(path):
    """The vertex count of a Medit .mesh (the number after the Vertices keyword)."""
    with open(path) as f:
        words = iter(f.read(1 << 22).split())
        for w in words:
            if w == "Vertices":
                return int(next(words))
    raise ValueError(path + ": no Vertices")


def write_scalar_sol(path, n, h):
    """A SolAtVertices of type 1 (scalar sizes): mmgs's isotropic code."""
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n%d\n1 1\n\n" % n)
        f.write(("%.17g\n" % h) * n)
        f.write("\nEnd\n")


def median(xs):
    xs = sorted(xs)
    return xs[len(xs) // 2] if len(xs) % 2 else 0.5 * (xs[len(xs) // 2 - 1] + xs[len(xs) // 2])


def run_measured(cmd):
    """Runs cmd; returns (wall seconds, peak RSS MB, stdout)."""
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    out = p.stdout.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.monotonic() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited with {p.returncode}")
    return seconds, usage.ru_maxrss / 1024.0, out.decode()


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def evaluate(evaluator, mesh, spec, sphere=True):
    ev = [sys.executable, evaluator, mesh, "--metric", spec, "--json"] + (["--sphere"] if sphere else [])
    return json.loads(subprocess.run(ev, check=True, capture_output=True, text=True).stdout)


def peer_tables(a):
    """Issue #16's table: anisurf and mmgs side by side, then the scaling series."""
    mmgs = a.mmgs or find_mmgs()
    if not mmgs:
        sys.exit("no mmgs: build it with ../shared/peers/build-mmg.sh /tmp/mmg-peer or pass --mmgs")
    os.makedirs(a.out, exist_ok=True)
    inputs = os.path.join(a.shared, "bench", "inputs")
    evaluator = os.path.join(a.shared, "bench", "eval.py")
    names = a.cases.split(",") if a.cases else [n for n in PEER_CASES if n not in THREAD_CASES or n == "sphere20k_bandfine"]
    if any(PEER_CASES[n][0].startswith("@out/") for n in names) and not os.path.exists(
            os.path.join(a.out, "sphere500k_band.sol")):
        print("making sphere500k with gen.py ...", file=sys.stderr)
        subprocess.run([sys.executable, os.path.join(a.shared, "bench", "gen.py"), a.out, "sphere500k"], check=True,
                       stdout=subprocess.DEVNULL)

    def path_of(name):
        return os.path.join(a.out, name[5:]) if name.startswith("@out/") else os.path.join(inputs, name)

    def measure(cmd, out_mesh, spec):
        runs = [run_measured(cmd) for _ in range(a.repeat)]
        e = evaluate(evaluator, out_mesh, spec)
        return {"seconds": median([r[0] for r in runs]), "rss_mb": median([r[1] for r in runs]), "nt": e["nt"],
                "nv": e["nv"], "in_band_pct": e["len_in_range_pct"], "q_min": e["q_min"], "q_mean": e["q_mean"]}

    print("| case | tool | T | time s | RSS MB | bytes/T | % in band | q min / mean | mmgs time / anisurf time |")
    print("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for name in names:
        mesh, sol, size, opts, spec = PEER_CASES[name]
        mesh = path_of(mesh)
        base = os.path.join(a.out, "peer_" + name)
        an_cmd = [a.anisurf, "adapt", mesh, "-o", base + "_anisurf.mesh", "-v", "0"] + opts + a.extra
        if size is not None:
            an_cmd += ["--size", "%.17g" % size]
            sol_path = base + "_scalar.sol"
            write_scalar_sol(sol_path, mesh_vertex_count(mesh), size)
        else:
            sol_path = path_of(sol)
            an_cmd += ["-sol", sol_path]
        mm_cmd = [mmgs, mesh, "-sol", sol_path, "-out", base + "_mmgs.mesh", "-v", "0"] + opts
        an = measure(an_cmd, base + "_anisurf.mesh", spec)
        mm = measure(mm_cmd, base + "_mmgs.mesh", spec)
        for tool, r in (("anisurf", an), ("mmgs", mm)):
            ratio = "%.2f" % (mm["seconds"] / an["seconds"]) if tool == "anisurf" else ""
            print(f"| {name} | {tool} | {r['nt']} | {r['seconds']:.2f} | {r['rss_mb']:.0f} | "
                  f"{r['rss_mb'] * 1048576 / max(r['nt'], 1):.0f} | {r['in_band_pct']:.1f} | "
                  f"{r['q_min']:.3f} / {r['q_mean']:.3f} | {ratio} |", flush=True)
        rows.append({"case": name, "anisurf": an, "mmgs": mm})
    if a.scaling:
        print()
        print("| size | T | time s | us / triangle | RSS MB | bytes/T | % in band |")
        print("|---|---|---|---|---|---|---|")
        per = []
        for h in SCALING_SIZES:
            out_mesh = os.path.join(a.out, "scaling_%g.mesh" % h)
            cmd = [a.anisurf, "adapt", os.path.join(inputs, "sphere20k.mesh"), "--size", "%.17g" % h, "-o", out_mesh,
                   "-v", "0"] + a.extra
            r = measure(cmd, out_mesh, "iso:%.17g" % h)
            per.append(1e6 * r["seconds"] / r["nt"])
            print(f"| {h} | {r['nt']} | {r['seconds']:.2f} | {per[-1]:.2f} | {r['rss_mb']:.0f} | "
                  f"{r['rss_mb'] * 1048576 / r['nt']:.0f} | {r['in_band_pct']:.1f} |", flush=True)
            rows.append({"case": "scaling_%g" % h, "anisurf": r})
        print(f"\ntime per triangle: largest / smallest over the series = {max(per) / min(per):.2f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


def thread_series(a):
    """The speedup of --threads N over the first N, runs interleaved."""
    os.makedirs(a.out, exist_ok=True)
    inputs = os.path.join(a.shared, "bench", "inputs")
    evaluator = os.path.join(a.shared, "bench", "eval.py")
    counts = [int(x) for x in a.threads.split(",")] if a.threads else [1, os.cpu_count() or 1]
    names = a.cases.split(",") if a.cases else THREAD_CASES
    print("| case | threads | T | time s (median of %d) | speedup | %% in band | q min / mean |" % a.repeat)
    print("|---|---|---|---|---|---|---|")
    rows = []
    for name in names:
        mesh, sol, size, opts, spec = PEER_CASES[name]
        if mesh.startswith("@out/"):
            mesh = os.path.join(a.out, mesh[5:])
            sol = sol and sol.replace("@out/", a.out + os.sep)
        else:
            mesh = os.path.join(inputs, mesh)
            sol = sol and os.path.join(inputs, sol)
        cmds, times = {}, {n: [] for n in counts}
        for n in counts:
            out_mesh = os.path.join(a.out, "threads_%s_%d.mesh" % (name, n))
            cmds[n] = (out_mesh, [a.anisurf, "adapt", mesh, "-o", out_mesh, "-v", "0", "--threads", str(n)] + opts +
                       (["--size", "%.17g" % size] if size is not None else ["-sol", sol]) + a.extra)
        for _ in range(a.repeat):
            for n in counts:
                times[n].append(run_measured(cmds[n][1])[0])
        base = median(times[counts[0]])
        for n in counts:
            e = evaluate(evaluator, cmds[n][0], spec)
            t = median(times[n])
            print(f"| {name} | {n} | {e['nt']} | {t:.2f} | {base / t:.2f} | {e['len_in_range_pct']:.1f} | "
                  f"{e['q_min']:.3f} / {e['q_mean']:.3f} |", flush=True)
            rows.append({"case": name, "threads": n, "seconds": t, "runs": times[n], "speedup": base / t,
                         "nt": e["nt"], "in_band_pct": e["len_in_range_pct"], "q_min": e["q_min"],
                         "q_mean": e["q_mean"]})
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--anisurf", default=os.path.join(here, "..", "build", "app", "anisurf"))
    ap.add_argument("--shared", default=os.path.join(here, "..", "..", "shared"))
    ap.add_argument("--out", default=os.path.join(os.environ.get("TMPDIR", "/tmp"), "bench_remesh_out"))
    ap.add_argument("--large", action="store_true")
    ap.add_argument("--cases", default="")
    ap.add_argument("--json", default="", help="also write the rows as JSON to this file")
    ap.add_argument("--profiles", default="default")
    ap.add_argument("--peer", action="store_true", help="issue #16's table: anisurf and mmgs side by side")
    ap.add_argument("--mmgs", default=None, help="mmgs_O3 (default: on PATH, then /tmp/mmg-peer/mmg/build/bin)")
    ap.add_argument("--repeat", type=int, default=1, help="--peer: runs per tool and case (the median is printed)")
    ap.add_argument("--scaling", action="store_true", help="--peer: also the isotropic scaling series")
    ap.add_argument("--threads-series", action="store_true", help="the speedup of --threads N over the first N")
    ap.add_argument("--threads", default="", help="--threads-series: the counts (default 1 and every core)")
    ap.add_argument("extra", nargs="*", help="extra options for anisurf adapt (after --)")
    a = ap.parse_args()
    if a.threads_series:
        thread_series(a)
        return
    if a.peer:
        peer_tables(a)
        return
    cases = dict(CASES)
    if a.large:
        cases.update(LARGE)
    if a.cases:
        cases = {k: v for k, v in {**CASES, **LARGE}.items() if k in a.cases.split(",")}
    os.makedirs(a.out, exist_ok=True)
    inputs = os.path.join(a.shared, "bench", "inputs")
    evaluator = os.path.join(a.shared, "bench", "eval.py")
    if "sphere500k_band" in cases and not os.path.exists(os.path.join(a.out, "sphere500k_band.sol")):
        print("making sphere500k with gen.py ...", file=sys.stderr)
        subprocess.run([sys.executable, os.path.join(a.shared, "bench", "gen.py"), a.out, "sphere500k"], check=True,
                       stdout=subprocess.DEVNULL)
    interp = os.path.join(a.shared, "bench", "interp_error.py")

    def path_of(name):
        return None if name is None else (os.path.join(a.out, name[5:]) if name.startswith("@out/") else
                                          os.path.join(inputs, name))

    profiles = {"default": [], "paper": ["--lmin", "0.6"]}
    runs = [(name, case, p) for name, case in cases.items() for p in a.profiles.split(",")]
    rows = []
    for name, (mesh, sol, case_opts, spec, sphere), profile in runs:
        opts = case_opts + profiles[profile]
        out_mesh = os.path.join(a.out, name + "_" + profile + ".mesh")
        cmd = [a.anisurf, "adapt", path_of(mesh)] + (["-sol", path_of(sol)] if sol else []) + ["-o", out_mesh,
               "-v", "0"] + opts + a.extra
        seconds, rss, _ = run_measured(cmd)
        ev = [sys.executable, evaluator, out_mesh, "--metric", spec, "--json"] + (["--sphere"] if sphere else [])
        e = json.loads(subprocess.run(ev, check=True, capture_output=True, text=True).stdout)
        row = {
            "case": name, "options": profile + (": " + " ".join(opts + a.extra) if opts or a.extra else ""), "nv": e["nv"], "nt": e["nt"], "seconds": seconds,
            "rss_mb": rss, "in_band_pct": e["len_in_range_pct"], "q_min": e["q_min"], "q_mean": e["q_mean"],
            "qc_mean": e["qc_mean"], "geo_vert_max": e.get("geo_vert_max"),
            "geo_centroid_max": e.get("geo_centroid_max"),
            "bytes_per_triangle": rss * 1024 * 1024 / max(e["nt"], 1),
        }
        if name.startswith("square3d"):
            out = subprocess.run([sys.executable, interp, out_mesh, "--f", "case1"], check=True, capture_output=True,
                                 text=True).stdout
            row["l2_error"] = next((l.split()[-1] for l in out.splitlines() if l.startswith("L2")), "?")
        rows.append(row)
        print(f"{name} ({profile}): done in {seconds:.2f} s", file=sys.stderr)

    print("| case | options | who | V / T | time s | RSS MB | bytes/T | % in band | q min / mean | qc mean | dist. vertices / centroids |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    last = None
    for r in rows:
        m = MMGS.get(r["case"]) if r["case"] != last else None
        if m:
            print(f"| {r['case']} | mmgs | mmgs | {m[0]} / {m[1]} | {m[2]:.2f} | {m[3]} | {m[3] * 1048576 / m[1]:.0f} | {m[4]:.1f} | {m[5]:.3f} / {m[6]:.3f} | "
                  f"{m[7]:.3f} | {fmt(m[8], '.1e')} / {fmt(m[9], '.1e')} |")
        last = r["case"]
        print(f"| {r['case']} | {r['options']} | anisurf | {r['nv']} / {r['nt']} | {r['seconds']:.2f} | "
              f"{r['rss_mb']:.0f} | {r['bytes_per_triangle']:.0f} | {r['in_band_pct']:.1f} | {r['q_min']:.3f} / {r['q_mean']:.3f} | "
              f"{r['qc_mean']:.3f} | {fmt(r['geo_vert_max'], '.1e')} / {fmt(r['geo_centroid_max'], '.1e')} |")
    for r in rows:
        if "l2_error" in r:
            print(f"{r['case']} ({r['options']}): {r['nv']} vertices, interp_error.py --f case1: L2 {r['l2_error']}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
