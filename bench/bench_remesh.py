#!/usr/bin/env python3
"""Benchmark of `anisurf adapt` on the shared bench cases, measured by the
independent evaluator (../shared/bench/eval.py), next to the reference peer's
figures (Mmg 5.8.0 mmgs, from ../shared/bench/README.md).

usage: bench_remesh.py [--anisurf BIN] [--shared DIR] [--out DIR] [--large]
                       [--cases a,b] [--profiles default,paper] [-- extra adapt options]

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
    # the report's section 7.2: the smooth surface of the coarse input, whole
    "hemi_iso": ("hemi.mesh", "hemi_iso.sol", ["--free-surface"], "iso:0.085", True),
    "square3d": ("square3d.mesh", "square3d.sol", [], "f100x2:0.01", False),
    # the report's Table 1: the metric from the Hessian of f = 100 x^2 (195 V: 4.4573e-3)
    "square3d_hessian": ("square3d.mesh", None, ["--hessian-of", "100*x^2", "--error", "0.01"], "f100x2:0.01", False),
}
LARGE = {
    "sphere20k_isofine": ("sphere20k.mesh", "sphere20k_isofine.sol", [], "iso:0.007", True),
    "sphere20k_bandfine": ("sphere20k.mesh", "sphere20k_bandfine.sol", [], "bandfine", True),
    "sphere500k_band": ("@out/sphere500k.mesh", "@out/sphere500k_band.sol", ["-hgrad", "-1"], "band", True),
}


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
    ap.add_argument("extra", nargs="*", help="extra options for anisurf adapt (after --)")
    a = ap.parse_args()
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
