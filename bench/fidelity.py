#!/usr/bin/env python3
"""Geometric fidelity on real inputs (issue #13): anisurf beside mmgs (Mmg 5.8.0), measured side by
side in one run, on the shared meshes (../shared/meshes).

usage: fidelity.py [--anisurf BIN] [--mmgs BIN] [--shared DIR] [--out DIR] [--cases a,b]
                   [--table 1|2|both] [--repeat N] [--json FILE]

Table 1, "size diagonal/60": each input is converted to Medit (`anisurf convert IN in.mesh`;
the evaluators and mmgs read only .mesh), h = diagonal / 60 (bbox.diagonal of `anisurf info IN
--json`), then `anisurf adapt in.mesh --size h` and `mmgs_O3 in.mesh -hsiz h`. Both detect
ridges at 45 deg by default: mmgs is left at its default (MMG5_ANGEDG = 0.707106781186548, a hair
above cos 45 deg, so edges at exactly 45 deg are ridges), not given `-ar 45`, which it turns into
cos(45 deg) exactly and which loses CAD edges at exactly 45 deg to rounding (chamfer_cube: 4.3%
of the diagonal off the input with `-ar 45`, 0.28% without). Per tool:
V, T, wall time, the maximum distance output -> input in % of the diagonal (the largest of
surfdist.py's vert_max, mid_max, cen_max: output vertices, edge midpoints, triangle centroids),
the share of edges in [0.71, 1.41] and the longest edge in the metric (eval.py --metric iso:h),
and "sharp kept": the share of the input's sharp-edge length (dihedral >= 44.5 deg, i.e. the
issue's 45 deg with half a degree of tolerance for CAD edges at exactly 45 deg whose normals round
either way) whose sample points (1/4, 1/2, 3/4 of each edge) lie within h/4 of an output feature
edge (dihedral >= 25 deg, a boundary or a non-manifold edge). Pass: distance <= 0.5% of the
diagonal, band >= 90% (95% on the chamfer cube), longest edge <= 2, sharp kept 100%.

Table 2, "--hausd": falcon, bunny, fixed_top with D = 1e-3 and 3e-4 x diagonal, gradation on
(the default 1.3) and off: `anisurf adapt in.mesh --curvature --hausd D [--hgrad -1]` against
`mmgs_O3 in.mesh -hausd D [-hgrad -1]` (no -hsiz: mmgs's default hmax fits the model).
Per tool: T, wall time (the median of --repeat runs, 3 by default, the two tools run in turn:
anisurf, mmgs, anisurf, mmgs, ...), the maximum deviation (as above) / D. Pass: anisurf's
deviation <= 1.2 D, fewer triangles than mmgs and less time.

Each command is timed (wall clock, os.wait4 for the peak RSS); one that fails or runs over
300 s gets "failed" / "timeout" in its row and the table goes on. The anisurf binary is
copied into --out first and every row runs that copy (the build may be redone meanwhile). Rows are printed as they
finish. Cases run one at a time (the machines are shared: a ratio measured in the same run is
the figure to trust). Outputs and logs stay in --out (one directory per input).
"""
import argparse
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import threading
import time

import numpy as np
from scipy.spatial import cKDTree

from mmg_peer import find_mmgs

TABLE1 = ["chamfer_cube.mesh", "featuretype.STL", "fixed_top.ply", "fandisk.off", "falcon.mesh", "beetle.off",
          "Duck.glb", "Suzanne.gltf", "thinker.mesh"]
TABLE2 = ["falcon.mesh", "bunny.off", "fixed_top.ply", "fandisk.off", "featuretype.STL"]
HAUSD_FACTORS = [1e-3, 3e-4]
TIMEOUT = 300.0          # seconds, per remeshing command
EVAL_TIMEOUT = 1200.0    # seconds, per evaluator run
SHARP_IN_DEG = 44.5      # input sharp edges: dihedral >= 45 deg less half a degree of rounding
SHARP_OUT_DEG = 25.0     # output feature edges
DIST_MAX_PCT = 0.5
BAND_MIN = {"chamfer_cube": 95.0}
BAND_MIN_DEFAULT = 90.0
LEN_MAX = 2.0
HAUSD_RATIO_MAX = 1.2


# ------------------------------------------------------------------------------------ running
class Run:
    """Outcome of one command: status ok | failed | timeout | missing, wall seconds, peak RSS MB."""

    def __init__(self, status, seconds=None, rss_mb=None, detail=""):
        self.status, self.seconds, self.rss_mb, self.detail = status, seconds, rss_mb, detail

    @property
    def ok(self):
        return self.status == "ok"


def run_measured(cmd, log_path, timeout=TIMEOUT):
    """Runs cmd with stdout and stderr into log_path; the wall time and peak RSS from os.wait4.
    Never raises: a non-zero exit is "failed", a run over `timeout` s is killed and "timeout"."""
    with open(log_path, "w") as log:
        log.write("$ " + " ".join(cmd) + "\n")
        log.flush()
        t0 = time.monotonic()
        try:
            p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        except OSError as e:
            return Run("failed", detail=str(e))
        timed_out = threading.Event()

        def kill():
            timed_out.set()
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except OSError:
                pass

        timer = threading.Timer(timeout, kill)
        timer.start()
        try:
            _, status, usage = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        seconds = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
    rss = usage.ru_maxrss / 1024.0
    if timed_out.is_set():
        return Run("timeout", seconds, rss, "killed after %.0f s" % timeout)
    if p.returncode != 0:
        return Run("failed", seconds, rss, "exit %d, see %s" % (p.returncode, log_path))
    return Run("ok", seconds, rss)


def run_alternating(jobs, repeat):
    """Runs each (tool, cmd, log_path) of `jobs` `repeat` times, the tools in turn (a, b, a, b, ...)
    so that a slow minute of the shared machine weighs on both alike. Returns {tool: Run} with the
    median wall time (and the largest RSS) of its runs and .times holding every time; a failed or
    timed-out run is returned as it is, and that tool is not run again."""
    times = {tool: [] for tool, _, _ in jobs}
    out = {}
    for _ in range(max(1, repeat)):
        for tool, cmd, log_path in jobs:
            if tool in out and not out[tool].ok:
                continue
            run = run_measured(cmd, log_path)
            if not run.ok:
                out[tool] = run
                continue
            times[tool].append(run.seconds)
            rss = max(run.rss_mb, out[tool].rss_mb) if tool in out else run.rss_mb
            out[tool] = Run("ok", float(np.median(times[tool])), rss)
    for tool in out:
        out[tool].times = times[tool]
    return out


def run_json(cmd, log_path, timeout=EVAL_TIMEOUT):
    """Runs an evaluator printing one JSON object on stdout; returns (dict or None, detail)."""
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, "evaluator timeout"
    with open(log_path, "w") as log:
        log.write("$ " + " ".join(cmd) + "\n" + r.stdout + r.stderr)
    if r.returncode != 0:
        return None, "evaluator failed (%s)" % log_path
    try:
        return json.loads(r.stdout.strip().splitlines()[-1]), ""
    except (ValueError, IndexError):
        return None, "evaluator output unreadable (%s)" % log_path


def wait_for(path, seconds=180):
    """The anisurf binary may be rebuilt meanwhile: wait for it to come back."""
    t0 = time.monotonic()
    while not os.access(path, os.X_OK) and time.monotonic() - t0 < seconds:
        time.sleep(5)
    return os.access(path, os.X_OK)


# ------------------------------------------------------------------------------- Medit reader
# entries' widths of the Medit keywords (Vertices: dim + 1)
WIDTH = {"Edges": 3, "Triangles": 4, "Quadrilaterals": 5, "Tetrahedra": 5, "Prisms": 7, "Hexahedra": 9,
         "Corners": 1, "RequiredVertices": 1, "Ridges": 1, "RequiredEdges": 1, "RequiredTriangles": 1,
         "Normals": 3, "NormalAtVertices": 2, "Tangents": 3, "TangentAtVertices": 2,
         "NormalAtTriangleVertices": 3, "TangentAtEdgeVertices": 3}


def read_mesh(path):
    """Vertices (n, 3) and triangles (m, 3, 0-based) of an ASCII Medit file; quadrilaterals are
    split in two triangles."""
    with open(path) as f:
        tok = " ".join(l.split("#", 1)[0] for l in f).split()
    i, dim, P, tris = 0, 3, None, []
    while i < len(tok):
        k = tok[i]
        if k == "Dimension":
            dim = int(tok[i + 1])
            i += 2
        elif k == "Vertices":
            n = int(tok[i + 1])
            i += 2
            P = np.array(tok[i:i + n * (dim + 1)], dtype=float).reshape(n, dim + 1)[:, :dim]
            i += n * (dim + 1)
        elif k in WIDTH and i + 1 < len(tok) and tok[i + 1].isdigit():
            n, w = int(tok[i + 1]), WIDTH[k]
            i += 2
            if k == "Triangles":
                tris.append(np.array(tok[i:i + n * w], dtype=np.int64).reshape(n, w)[:, :3] - 1)
            elif k == "Quadrilaterals":
                Q = np.array(tok[i:i + n * w], dtype=np.int64).reshape(n, w)[:, :4] - 1
                tris += [Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]]
            i += n * w
        elif k == "End":
            break
        else:
            i += 1
    if P is None:
        raise ValueError("%s: no Vertices" % path)
    if P.shape[1] == 2:
        P = np.hstack([P, np.zeros((len(P), 1))])
    T = np.concatenate(tris) if tris else np.zeros((0, 3), np.int64)
    return P, T


# ------------------------------------------------------------------------------ sharp edges
def feature_edges(P, T, angle_deg, include_open):
    """Edges (k, 2) whose dihedral angle (between the two face normals, 0 = flat) is >= angle_deg;
    with include_open, boundary and non-manifold edges too. Normals are made consistent across
    each edge (two triangles running through it the same way are oppositely oriented); an edge
    next to a zero-area triangle has no dihedral angle and is not counted."""
    if len(T) == 0:
        return np.zeros((0, 2), np.int64)
    D = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    direction = np.where(D[:, 0] < D[:, 1], 1.0, -1.0)
    E = np.sort(D, axis=1)
    tri = np.tile(np.arange(len(T)), 3)
    N = np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]])
    norm = np.linalg.norm(N, axis=1)
    good = norm > 0
    N = N / np.where(good, norm, 1.0)[:, None]
    key = E[:, 0] * (len(P) + 1) + E[:, 1]
    order = np.argsort(key, kind="stable")
    key, E, tri, direction = key[order], E[order], tri[order], direction[order]
    _, start, cnt = np.unique(key, return_index=True, return_counts=True)
    s2 = start[cnt == 2]
    t1, t2 = tri[s2], tri[s2 + 1]
    flip = np.where(direction[s2] == direction[s2 + 1], -1.0, 1.0)
    cosang = np.clip((N[t1] * N[t2]).sum(1) * flip, -1.0, 1.0)
    sharp = (cosang <= math.cos(math.radians(angle_deg))) & good[t1] & good[t2]
    out = [E[s2][sharp]]
    if include_open:
        out.append(E[start[cnt != 2]])
    return np.concatenate(out)


def seg_dist(Q, A, B):
    ab = B - A
    t = np.clip(((Q - A) * ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-300), 0.0, 1.0)
    return np.linalg.norm(Q - (A + t[:, None] * ab), axis=1)


def sharp_kept(P0, T0, P1, T1, tol):
    """Share (%) of the input's sharp-edge length (dihedral >= SHARP_IN_DEG) whose samples at 1/4,
    1/2, 3/4 of each edge lie within tol of an output feature edge (dihedral >= SHARP_OUT_DEG,
    boundary, non-manifold). Returns (pct or None when the input has no sharp edge, input sharp
    length, the lost sample farthest from an output feature edge and its distance)."""
    se0 = feature_edges(P0, T0, SHARP_IN_DEG, include_open=False)
    if len(se0) == 0:
        return None, 0.0, None, 0.0
    A0, B0 = P0[se0[:, 0]], P0[se0[:, 1]]
    L0 = np.linalg.norm(B0 - A0, axis=1)
    Q = np.concatenate([A0 + t * (B0 - A0) for t in (0.25, 0.5, 0.75)])
    W = np.tile(L0 / 3.0, 3)
    se1 = feature_edges(P1, T1, SHARP_OUT_DEG, include_open=True)
    best = np.full(len(Q), np.inf)
    if len(se1):
        A1, B1 = P1[se1[:, 0]], P1[se1[:, 1]]
        half = 0.5 * np.linalg.norm(B1 - A1, axis=1)
        tree = cKDTree(0.5 * (A1 + B1))
        # a segment within tol of q has its midpoint within tol + its half length of q
        lists = tree.query_ball_point(Q, tol + half.max() + 1e-12)
        qi = np.concatenate([np.full(len(l), j, dtype=np.int64) for j, l in enumerate(lists)])
        ti = np.concatenate([np.asarray(l, dtype=np.int64) for l in lists])
        if len(qi):
            np.minimum.at(best, qi, seg_dist(Q[qi], A1[ti], B1[ti]))
        far = np.flatnonzero(~np.isfinite(best))
        if len(far):  # lost anyway; their exact distance, for the notes
            dm, _ = tree.query(Q[far])
            for j, q, l in zip(far, Q[far], tree.query_ball_point(Q[far], dm + half.max() + 1e-12)):
                l = np.asarray(l, dtype=np.int64)
                best[j] = seg_dist(np.repeat(q[None], len(l), 0), A1[l], B1[l]).min()
    kept = best <= tol
    pct = 100.0 * W[kept].sum() / W.sum()
    worst = None
    if not kept.all():
        j = int(np.argmax(best))
        worst = Q[j].tolist()
        return pct, float(L0.sum()), worst, float(best[j])
    return pct, float(L0.sum()), worst, 0.0


# ----------------------------------------------------------------------------------- helpers
def where_in_box(p, lo, hi):
    """A point as fractions of the bounding box (0 = min, 1 = max) along x, y, z."""
    f = (np.asarray(p) - lo) / np.maximum(hi - lo, 1e-300)
    return "(%.2f, %.2f, %.2f) of the bbox" % tuple(f)


def fmt(x, spec, none="-"):
    return none if x is None else format(x, spec)


def out_dir_default():
    return os.path.join(os.environ.get("TMPDIR", "/tmp"), "fidelity")


def binary_id(path):
    """The binary's modification time and a hash prefix (another engineer may rebuild it mid-run)."""
    try:
        import hashlib
        with open(path, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()[:12]
        return "%s, built %s UTC" % (digest, time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime(os.path.getmtime(path))))
    except OSError:
        return "missing"


def stem(name):
    return os.path.splitext(name)[0]


class Case:
    """One input: converted to Medit once, its diagonal and bounding box."""

    def __init__(self, name, src, work):
        self.name, self.src, self.work = name, src, work
        self.inp = os.path.join(work, "in.mesh")
        self.error, self.diag, self.P0, self.T0, self.lo, self.hi = "", None, None, None, None, None

    def prepare(self, anisurf):
        os.makedirs(self.work, exist_ok=True)
        if not os.path.exists(self.src):
            self.error = "missing: " + self.src
            return False
        if not wait_for(anisurf):
            self.error = "missing: " + anisurf
            return False
        r = run_measured([anisurf, "convert", self.src, self.inp], os.path.join(self.work, "convert.log"))
        if not r.ok:
            self.error = "convert " + r.status + " (" + r.detail + ")"
            return False
        try:
            info = subprocess.run([anisurf, "info", self.src, "--json"], capture_output=True, text=True,
                                  timeout=EVAL_TIMEOUT)
            d = json.loads(info.stdout)
            self.diag = float(d["bbox"]["diagonal"])
            self.lo, self.hi = np.array(d["bbox"]["min"], float), np.array(d["bbox"]["max"], float)
        except (ValueError, KeyError, subprocess.TimeoutExpired) as e:
            self.error = "info failed: %s" % e
            return False
        self.P0, self.T0 = read_mesh(self.inp)
        return True


def measure(case, run, out_mesh, surfdist, evaluator, h=None):
    """Figures of one output against its input; res["status"] is the run's, or an evaluator's failure."""
    res = {"status": run.status, "seconds": run.seconds, "rss_mb": run.rss_mb, "detail": run.detail,
           "mesh": out_mesh}
    if not run.ok:
        return res
    tag = os.path.splitext(os.path.basename(out_mesh))[0]
    sd, err = run_json([sys.executable, surfdist, case.inp, out_mesh, "--json"],
                       os.path.join(case.work, tag + ".surfdist.log"))
    if sd is None:
        res.update(status="failed", detail=err)
        return res
    res["V"], res["T"] = sd["V"], sd["T"]
    parts = {"vertex": sd["vert_max"], "edge midpoint": sd["mid_max"], "centroid": sd["cen_max"]}
    worst = max(parts, key=parts.get)
    res["dist"] = parts[worst]
    res["dist_pct"] = 100.0 * res["dist"] / case.diag
    res["dist_worst_kind"] = worst
    res["worst_vertex"], res["worst_centroid"] = sd["worst_vertex"], sd["worst_centroid"]
    res["dist_vert_max"], res["dist_mid_max"], res["dist_cen_max"] = sd["vert_max"], sd["mid_max"], sd["cen_max"]
    if h is not None:
        ev, err = run_json([sys.executable, evaluator, out_mesh, "--metric", "iso:%.17g" % h, "--json"],
                           os.path.join(case.work, tag + ".eval.log"))
        if ev is None:
            res.update(status="failed", detail=err)
            return res
        res["band_pct"], res["len_max"] = ev["len_in_range_pct"], ev["len_max"]
        try:
            P1, T1 = read_mesh(out_mesh)
        except (ValueError, OSError) as e:
            res.update(status="failed", detail="read %s: %s" % (out_mesh, e))
            return res
        pct, length, lost_at, lost_d = sharp_kept(case.P0, case.T0, P1, T1, h / 4.0)
        res["sharp_kept_pct"], res["sharp_in_length"] = pct, length
        res["sharp_lost_at"], res["sharp_lost_dist"] = lost_at, lost_d
    return res


# ------------------------------------------------------------------------------------ table 1
def verdict1(r, name):
    if r["status"] != "ok":
        return r["status"]
    bad = []
    if r["dist_pct"] > DIST_MAX_PCT:
        bad.append("dist")
    if r["band_pct"] < BAND_MIN.get(stem(name), BAND_MIN_DEFAULT):
        bad.append("band")
    if r["len_max"] > LEN_MAX:
        bad.append("long")
    if r["sharp_kept_pct"] is not None and r["sharp_kept_pct"] < 100.0:
        bad.append("sharp")
    return "pass" if not bad else "fail: " + ", ".join(bad)


def cells1(r, name):
    if r["status"] != "ok":
        t = fmt(r["seconds"], ".2f") if r["status"] == "timeout" else "-"
        return ["-", "-", t, "-", "-", "-", "-", r["status"]]
    return [str(r["V"]), str(r["T"]), "%.2f" % r["seconds"], "%.3f" % r["dist_pct"], "%.1f" % r["band_pct"],
            "%.2f" % r["len_max"], fmt(r["sharp_kept_pct"], ".2f", "no sharp"), verdict1(r, name)]


def table1(a, names, mmgs, rows, notes):
    cols = ["V", "T", "time s", "dist % diag", "% in band", "longest", "sharp kept %", "pass"]
    tools = ["anisurf"] + (["mmgs"] if mmgs else [])
    print("\n## Table 1: size diagonal/60\n")
    print("| input | h | " + " | ".join("%s %s" % (t, c) for t in tools for c in cols) + " |")
    print("|---|---|" + "---|" * (len(cols) * len(tools)))
    sys.stdout.flush()
    for name in names:
        case = Case(name, os.path.join(a.shared, "meshes", name), os.path.join(a.out, stem(name)))
        if not case.prepare(a.anisurf):
            print("| %s | %s |" % (name, case.error) + " |" * (len(cols) * len(tools) - 1))
            rows.append({"table": 1, "input": name, "status": case.error, "anisurf_binary": a.binary_ident})
            sys.stdout.flush()
            continue
        h = case.diag / 60.0
        row = {"table": 1, "input": name, "diagonal": case.diag, "h": h, "anisurf_binary": a.binary_ident}
        cells = []
        for tool in tools:
            out_mesh = os.path.join(case.work, "t1_%s.mesh" % tool)
            if tool == "anisurf":
                cmd = [a.anisurf, "adapt", case.inp, "--size", "%.17g" % h, "-o", out_mesh]
            else:
                cmd = [mmgs, case.inp, "-hsiz", "%.17g" % h, "-out", out_mesh]
            run = run_measured(cmd, os.path.join(case.work, "t1_%s.log" % tool))
            r = measure(case, run, out_mesh, a.surfdist, a.evaluator, h)
            r["command"] = " ".join(cmd)
            row[tool] = r
            cells += cells1(r, name)
            if r["status"] == "ok" and r["dist_pct"] > DIST_MAX_PCT:
                notes.append("%s, %s: distance %.3f%% of the diagonal (%.4g) at an output %s; worst vertex %s "
                             "(vertex max %.3f%%), worst centroid %s (centroid max %.3f%%, midpoint max %.3f%%)" % (
                                 name, tool, r["dist_pct"], r["dist"], r["dist_worst_kind"],
                                 ", ".join("%.4g" % x for x in r["worst_vertex"]) + " " + where_in_box(r["worst_vertex"], case.lo, case.hi),
                                 100 * r["dist_vert_max"] / case.diag,
                                 ", ".join("%.4g" % x for x in r["worst_centroid"]) + " " + where_in_box(r["worst_centroid"], case.lo, case.hi),
                                 100 * r["dist_cen_max"] / case.diag, 100 * r["dist_mid_max"] / case.diag))
            if r["status"] == "ok" and r["sharp_lost_at"] is not None:
                notes.append("%s, %s: %.2f%% of %.4g sharp length kept; the lost sample farthest from an output "
                             "feature edge (%.3g h away) at %s %s" % (
                                 name, tool, r["sharp_kept_pct"], r["sharp_in_length"], r["sharp_lost_dist"] / h,
                                 ", ".join("%.4g" % x for x in r["sharp_lost_at"]),
                                 where_in_box(r["sharp_lost_at"], case.lo, case.hi)))
            if r["status"] != "ok":
                notes.append("%s, %s: %s %s" % (name, tool, r["status"], r["detail"]))
        rows.append(row)
        print("| %s | %.4g | %s |" % (name, h, " | ".join(cells)))
        sys.stdout.flush()


# ------------------------------------------------------------------------------------ table 2
def own_metric_band(evaluator, out_mesh, work):
    """% of the output's edges in [0.71, 1.41] in the metric the tool wrote beside it (OUT.sol:
    the final metric on the output mesh, after gradation), or None without one."""
    sol = os.path.splitext(out_mesh)[0] + ".sol"
    if not os.path.exists(sol):
        return None
    tag = os.path.splitext(os.path.basename(out_mesh))[0]
    ev, _ = run_json([sys.executable, evaluator, out_mesh, "--metric", "sol", "--sol", sol, "--json"],
                     os.path.join(work, tag + ".band.log"))
    return None if ev is None else ev["len_in_range_pct"]


def table2(a, names, mmgs, rows, notes):
    cols = ["T", "time s", "dev / D", "% in band"]
    tools = ["anisurf"] + (["mmgs"] if mmgs else [])
    print("\n## Table 2: --curvature --hausd D (D relative to the diagonal)\n")
    print("| input | D | hgrad | " + " | ".join("%s %s" % (t, c) for t in tools for c in cols) + " | pass |")
    print("|---|---|---|" + "---|" * (len(cols) * len(tools) + 1))
    sys.stdout.flush()
    for name in names:
        case = Case(name, os.path.join(a.shared, "meshes", name), os.path.join(a.out, stem(name)))
        if not case.prepare(a.anisurf):
            print("| %s | %s | |" % (name, case.error) + " |" * (len(cols) * len(tools) + 1))
            rows.append({"table": 2, "input": name, "status": case.error, "anisurf_binary": a.binary_ident})
            sys.stdout.flush()
            continue
        for f in a.factors:
            D = f * case.diag
            for grad in a.gradations:
                tag = "t2_%g_%s" % (f, "grad" if grad else "nograd")
                row = {"table": 2, "input": name, "diagonal": case.diag, "D_factor": f, "D": D, "hgrad": grad,
                       "anisurf_binary": a.binary_ident}
                cells = []
                jobs, out_meshes = [], {}
                for tool in tools:
                    out_mesh = out_meshes[tool] = os.path.join(case.work, "%s_%s.mesh" % (tag, tool))
                    if tool == "anisurf":
                        cmd = [a.anisurf, "adapt", case.inp, "--curvature", "--hausd", "%.17g" % D] + \
                              ([] if grad else ["--hgrad", "-1"]) + ["-o", out_mesh]
                    else:
                        cmd = [mmgs, case.inp, "-hausd", "%.17g" % D] + \
                              ([] if grad else ["-hgrad", "-1"]) + ["-out", out_mesh]
                    jobs.append((tool, cmd, os.path.join(case.work, "%s_%s.log" % (tag, tool))))
                runs = run_alternating(jobs, a.repeat)
                for tool, cmd, _ in jobs:
                    out_mesh = out_meshes[tool]
                    r = measure(case, runs[tool], out_mesh, a.surfdist, a.evaluator)
                    r["command"] = " ".join(cmd)
                    r["times"] = getattr(runs[tool], "times", [])
                    if r["status"] == "ok":
                        r["band_pct"] = own_metric_band(a.evaluator, out_mesh, case.work)
                    if r["status"] == "ok":
                        r["dev_over_D"] = r["dist"] / D
                        cells += [str(r["T"]), "%.2f" % r["seconds"], "%.2f" % r["dev_over_D"], fmt(r["band_pct"], ".1f")]
                        if r["dev_over_D"] > HAUSD_RATIO_MAX:
                            notes.append("%s D=%g diag %s, %s: deviation %.2f D at an output %s; worst vertex %s, "
                                         "worst centroid %s" % (
                                             name, f, "hgrad 1.3" if grad else "hgrad off", tool, r["dev_over_D"],
                                             r["dist_worst_kind"],
                                             ", ".join("%.4g" % x for x in r["worst_vertex"]) + " " + where_in_box(r["worst_vertex"], case.lo, case.hi),
                                             ", ".join("%.4g" % x for x in r["worst_centroid"]) + " " + where_in_box(r["worst_centroid"], case.lo, case.hi)))
                    else:
                        cells += ["-", fmt(r["seconds"], ".2f") if r["status"] == "timeout" else "-", r["status"]]
                        notes.append("%s D=%g diag %s, %s: %s %s" % (name, f, "hgrad 1.3" if grad else "hgrad off", tool,
                                                                    r["status"], r["detail"]))
                    row[tool] = r
                an, mm = row["anisurf"], row.get("mmgs")
                if an["status"] != "ok":
                    v = an["status"]
                else:
                    bad = ["dev"] if an["dev_over_D"] > HAUSD_RATIO_MAX else []
                    if mm is not None and mm["status"] == "ok":
                        if an["T"] >= mm["T"]:
                            bad.append("more T")
                        if an["seconds"] >= mm["seconds"]:
                            bad.append("slower")
                    v = "pass" if not bad else "fail: " + ", ".join(bad)
                    if mm is None or mm["status"] != "ok":
                        v += " (no mmgs to compare)"
                row["pass"] = v
                rows.append(row)
                print("| %s | %g | %s | %s | %s |" % (name, f, "1.3" if grad else "off", " | ".join(cells), v))
                sys.stdout.flush()


# --------------------------------------------------------------------------------------- main
def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--anisurf", default=os.path.join(here, "..", "build", "app", "anisurf"))
    ap.add_argument("--mmgs", default=None, help="mmgs_O3 (default: on PATH, then /tmp/mmg-peer/mmg/build/bin)")
    ap.add_argument("--shared", default=os.path.join(here, "..", "..", "shared"))
    ap.add_argument("--out", default=out_dir_default())
    ap.add_argument("--cases", default="", help="comma-separated inputs (file names or stems) to run")
    ap.add_argument("--table", default="both", choices=["1", "2", "both"])
    ap.add_argument("--factors", default=",".join("%g" % f for f in HAUSD_FACTORS),
                    help="table 2: D / diagonal, comma-separated (default %s)" % ",".join("%g" % f for f in HAUSD_FACTORS))
    ap.add_argument("--hgrad", default="both", choices=["both", "on", "off"],
                    help="table 2: gradation 1.3 (on), none (off) or both")
    ap.add_argument("--repeat", type=int, default=3,
                    help="table 2: runs per tool and row, alternated, the median time counts (default 3)")
    ap.add_argument("--json", default="", help="also write every row as JSON to this file")
    a = ap.parse_args()
    a.factors = [float(x) for x in a.factors.split(",") if x.strip()]
    a.gradations = {"both": (True, False), "on": (True,), "off": (False,)}[a.hgrad]
    a.anisurf = os.path.abspath(a.anisurf)
    a.shared = os.path.abspath(a.shared)
    a.out = os.path.abspath(a.out)
    a.surfdist = os.path.join(a.shared, "bench", "surfdist.py")
    a.evaluator = os.path.join(a.shared, "bench", "eval.py")
    for p in (a.surfdist, a.evaluator):
        if not os.path.exists(p):
            sys.exit("fidelity.py: missing evaluator %s (see --shared)" % p)
    mmgs = a.mmgs or find_mmgs()
    if mmgs and not os.access(mmgs, os.X_OK):
        print("fidelity.py: %s is not executable: anisurf columns only" % mmgs)
        mmgs = None
    if not mmgs:
        print("fidelity.py: mmgs_O3 not found (--mmgs, PATH, /tmp/mmg-peer/mmg/build/bin): anisurf columns "
              "only; build it with ../shared/peers/build-mmg.sh")
    os.makedirs(a.out, exist_ok=True)
    sel = set(c.strip() for c in a.cases.split(",") if c.strip())

    def pick(names):
        return [n for n in names if not sel or n in sel or stem(n) in sel]

    if not wait_for(a.anisurf):
        sys.exit("fidelity.py: no anisurf binary at %s (see --anisurf)" % a.anisurf)
    # the build directory may be rebuilt meanwhile: every row runs one copy of the binary
    a.anisurf_source = a.anisurf
    ident = binary_id(a.anisurf)
    snapshot = os.path.join(a.out, "anisurf-" + ident.split(",")[0])
    shutil.copy2(a.anisurf, snapshot + ".tmp")
    os.replace(snapshot + ".tmp", snapshot)
    a.anisurf = snapshot
    a.binary_ident = ident
    print("anisurf: %s (%s), run as its copy %s\nmmgs: %s\nshared: %s\nout: %s\nstarted: %s" % (
        a.anisurf_source, ident, a.anisurf, mmgs or "-", a.shared, a.out, time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())))
    rows, notes = [], []
    if a.table in ("1", "both") and pick(TABLE1):
        table1(a, pick(TABLE1), mmgs, rows, notes)
    if a.table in ("2", "both") and pick(TABLE2):
        table2(a, pick(TABLE2), mmgs, rows, notes)
    if notes:
        print("\nNotes:")
        for n in notes:
            print("- " + n)
    print("\nfinished: %s" % time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
