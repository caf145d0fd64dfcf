#!/usr/bin/env python3
"""mocapseg's methods beside other segmentation libraries, on the labelled takes of the shared data.

For each labelled take (CMU 86_01 with the Barbič/Zhou labels, mocap6 13_29, 13_30, 13_31, 14_14 with
the Fox/Hughes labels -- the takes and truth CSVs of examples/eval_data.rs) this script

* gets the 15 end-effector features per 30 Hz frame from mocapseg itself (`mocapseg features`, the
  features SSSM starts from: hands, feet, head relative to the hips, facing-aligned, inches of the
  reference body);
* runs ClaSP (claspy), FLUSS (stumpy: multidimensional matrix profile + fluss), ruptures KernelCPD
  and PELT on those features, with the parameters documented in bench/peers/README.md -- library
  defaults or rules that never look at the labels; rows marked (o) are *told the true number of
  segments*, which a user does not know, and are there only as an upper reference;
* writes each result as mocapseg's segmentation JSON (boundaries mapped from 30 Hz frames to the
  file's own frames) and scores it with `mocapseg eval`, so the metrics are mocapseg's own;
* runs every registered mocapseg method (`mocapseg segment --method M`) on the same takes and
  scores it the same way;
* times everything (wall clock per take, median of --runs runs; a peer's numba compilation is done
  on a warm-up call before timing and reported apart), and prints one table: F1@0.5 s, F1@1 s,
  covering (means over the takes), total time and its ratio to SSSM's.

    bench/peers/.venv/bin/python bench/peers/run.py --data ../shared/data --cli target/release/mocapseg --out target/bench/peers
"""

import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

# (trial, BVH path under the data folder, truth CSV under the data folder) -- as examples/common/mod.rs.
TAKES = [
    ("86_01", "cmu/86/86_01.bvh", "labels/cmu86_zhou_gt.csv"),
    ("13_29", "cmu/mocap6/13_29.bvh", "labels/mocap6_gt.csv"),
    ("13_30", "cmu/mocap6/13_30.bvh", "labels/mocap6_gt.csv"),
    ("13_31", "cmu/mocap6/13_31.bvh", "labels/mocap6_gt.csv"),
    ("14_14", "cmu/mocap6/14_14.bvh", "labels/mocap6_gt.csv"),
]
FPS = 30.0  # the working rate of the features (SSSM's)
FLUSS_CAC_LIMIT = 0.5  # a regime change where the corrected arc curve is below half its no-change value


def sh(cmd, **kw):
    out = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))}: exit {out.returncode}: {out.stderr.strip()}")
    return out


def read_features(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert header[:2] == ["frame", "source_frame"] and len(header) == 17, header
    source = np.array([float(r[1]) for r in body])
    x = np.array([[float(v) for v in r[2:]] for r in body], dtype=np.float64)
    return x, source


def true_segments(truth_csv, trial):
    with open(truth_csv, newline="") as f:
        return sum(1 for r in csv.DictReader(f) if r["trial"] == trial)


def segmentation_json(info, method, params, cps_working, source_frames):
    """Change points (30 Hz frame indices where a new segment starts) -> mocapseg's segmentation JSON
    at the file's own frames (0-based, inclusive ends)."""
    frames = info["frames"]
    starts = sorted({int(round(source_frames[c])) for c in cps_working if 0 < c < len(source_frames)})
    starts = [s for s in starts if 0 < s < frames]
    bounds = [0] + starts + [frames]
    segments = [
        {"start": a, "end": b - 1, "label": f"{method}{k}", "level": "action", "cluster": k, "score": None}
        for k, (a, b) in enumerate(zip(bounds, bounds[1:]))
    ]
    return {"file": info["file"], "fps": info["fps"], "frames": frames, "method": method, "params": params,
            "segments": segments}


def timed(fn, runs):
    """Median wall clock of `runs` calls (one call only when the first takes over 2 s), and the last result."""
    times, result = [], None
    for i in range(max(1, runs)):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
        if i == 0 and times[0] > 2.0:
            break
    return statistics.median(times), result


# --- the peers: each takes the (n, 15) features and the true count (used only by the (o) rows) and
# returns (change points in working frames, the parameters it ran with) --------------------------

def clasp(x, k_true, told):
    from claspy.segmentation import BinaryClaSPSegmentation
    if told:
        seg = BinaryClaSPSegmentation(n_segments=k_true, validation=None)
    else:
        seg = BinaryClaSPSegmentation()  # every default: n_segments "learn", window "suss", significance test
    cps = seg.fit(x).predict()
    params = {"window_size": int(seg.window_size), "n_segments": k_true if told else "learn",
              "validation": None if told else "significance_test"}
    return [int(c) for c in cps], params


def clasp_window(x):
    """claspy's own window-size suggestion for a multivariate series (what BinaryClaSPSegmentation.fit
    does: per dimension max(3, suss // 2), the smallest over the dimensions)."""
    from claspy.window_size import suss
    return int(min(max(3, suss(x[:, d]) // 2) for d in range(x.shape[1])))


def fluss(x, k_true, told):
    import stumpy
    L = clasp_window(x)
    _, I = stumpy.mstump(np.ascontiguousarray(x.T), m=L)
    index = I[-1]  # the matrix profile index over all 15 dimensions
    if told:
        _, locs = stumpy.fluss(index, L=L, n_regimes=k_true, excl_factor=5)
        return sorted(int(c) for c in locs), {"L": L, "n_regimes": k_true, "excl_factor": 5}
    cac, _ = stumpy.fluss(index, L=L, n_regimes=2, excl_factor=5)
    # stumpy's regime extraction (REA: the lowest CAC, then exclude ±5 L around it) run until the
    # lowest remaining CAC is at or above the limit, instead of for a given count
    cac, locs = cac.copy(), []
    while True:
        i = int(np.argmin(cac))
        if not cac[i] < FLUSS_CAC_LIMIT:
            break
        locs.append(i)
        cac[max(0, i - 5 * L):min(len(cac), i + 5 * L)] = 1.0
    return sorted(locs), {"L": L, "excl_factor": 5, "cac_limit": FLUSS_CAC_LIMIT}


def kernel_cpd(x, k_true, told):
    import ruptures as rpt
    algo = rpt.KernelCPD(kernel="rbf").fit(x)  # rbf with the median heuristic, min_size 2, jump 1
    n = x.shape[0]
    if told:
        bkps = algo.predict(n_bkps=k_true - 1)
        params = {"kernel": "rbf", "n_bkps": k_true - 1}
    else:
        bkps = algo.predict(pen=math.log(n))
        params = {"kernel": "rbf", "pen": math.log(n)}
    return [int(b) for b in bkps if b < n], params


def pelt(x, k_true, told):
    import ruptures as rpt
    n, d = x.shape
    z = (x - x.mean(axis=0)) / np.where(x.std(axis=0) > 0, x.std(axis=0), 1.0)
    pen = d * math.log(n)  # BIC of a mean change, sigma = 1 after standardising (ruptures' user guide: log(n)·d·σ²)
    bkps = rpt.Pelt(model="l2").fit(z).predict(pen=pen)  # min_size 2, jump 5 (defaults)
    return [int(b) for b in bkps if b < n], {"model": "l2", "standardised": True, "pen": pen}


PEERS = [
    ("ClaSP (claspy {claspy})", "clasp", clasp, False),
    ("FLUSS, CAC < 0.5 (stumpy {stumpy})", "fluss", fluss, False),
    ("KernelCPD rbf, pen log n (ruptures {ruptures})", "kernelcpd", kernel_cpd, False),
    ("PELT l2, BIC pen (ruptures {ruptures})", "pelt", pelt, False),
    ("ClaSP (o)", "clasp-o", clasp, True),
    ("FLUSS (o)", "fluss-o", fluss, True),
    ("KernelCPD rbf (o)", "kernelcpd-o", kernel_cpd, True),
]


def version(module):
    try:
        from importlib.metadata import version as v
        return v(module)
    except Exception:  # noqa: BLE001 - a missing package is reported where it is used
        return "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default="../shared/data", type=Path)
    ap.add_argument("--cli", default="target/release/mocapseg", type=Path)
    ap.add_argument("--out", default="target/bench/peers", type=Path)
    ap.add_argument("--runs", default=3, type=int, help="timed runs per take (median); 1 when a run takes > 2 s")
    ap.add_argument("--methods", default=None, help="mocapseg methods (comma-separated; default every registered one)")
    a = ap.parse_args()

    if not (a.data / "labels").is_dir():
        print(f"peers: {a.data} is absent (no labels/): nothing to compare on", file=sys.stderr)
        return 1
    cli = str(a.cli)
    a.out.mkdir(parents=True, exist_ok=True)
    methods = a.methods.split(",") if a.methods else [m["info"]["name"] for m in json.loads(sh([cli, "methods", "--json"]).stdout)]

    # which peers can run here at all
    peers, missing = [], []
    for label, key, fn, told in PEERS:
        mod = {"clasp": "claspy", "fluss": "stumpy", "kernelcpd": "ruptures", "pelt": "ruptures"}[key.split("-")[0]]
        try:
            __import__(mod)
            peers.append((label.format(claspy=version("claspy"), stumpy=version("stumpy"), ruptures=version("ruptures")),
                          key, fn, told))
        except ImportError as e:
            missing.append(f"{label.split(' (')[0]}: {mod} does not import here ({e})")
    for m in missing:
        print(f"peers: NOT RUN: {m}")

    takes = [(t, a.data / b, a.data / c) for t, b, c in TAKES if (a.data / b).exists()]
    rows = {}  # key -> {"label", "scores": [(f05, f1, cov)], "time": [s], "boundaries": [n, as scored]}
    jit = {}
    true_boundaries = {}

    empty = []  # (method, trial) that found no segment at all

    def record(key, label, trial, seg, seconds, truth):
        if not seg["segments"]:
            # nothing found: `mocapseg eval` refuses an empty segmentation; score it as what it says,
            # no boundary (the whole take one segment)
            empty.append((key, trial))
            seg = dict(seg, segments=[{"start": 0, "end": seg["frames"] - 1, "label": "none", "level": "action",
                                       "cluster": 0, "score": None}])
        path = a.out / f"{trial}.{key}.json"
        path.write_text(json.dumps(seg))
        s = json.loads(sh([cli, "eval", str(path), "--truth", str(truth), "--trial", trial]).stdout)
        true_boundaries[trial] = s["true_boundaries"]
        f = {b["tolerance_s"]: b["f1"] for b in s["boundaries"]}
        r = rows.setdefault(key, {"label": label, "scores": [], "time": [], "boundaries": []})
        r["scores"].append((f[0.5], f[1.0], s["covering"]))
        r["time"].append(seconds)
        r["boundaries"].append(s["predicted_boundaries"])

    for trial, bvh, truth in takes:
        info = json.loads(sh([cli, "info", str(bvh)]).stdout)
        fpath = a.out / f"{trial}.features.csv"
        sh([cli, "features", str(bvh), "--fps", str(FPS), "-o", str(fpath)])
        x, source = read_features(fpath)
        k_true = true_segments(truth, trial)
        print(f"peers: {trial}: {info['frames']} frames at {info['fps']:.0f} fps -> {x.shape[0]} x {x.shape[1]} features; "
              f"{k_true} true segments (told only to the (o) rows)", flush=True)

        # mocapseg's methods, as a user runs them: the command line on the BVH, wall clock
        for m in methods:
            out = a.out / f"{trial}.{m}.json"

            def run_cli(m=m, out=out):
                with open(out, "w") as f:
                    r = subprocess.run([cli, "segment", "--method", m, str(bvh)], stdout=f, stderr=subprocess.PIPE, text=True)
                if r.returncode != 0:
                    raise RuntimeError(f"mocapseg segment --method {m} {bvh}: {r.stderr.strip()}")
            seconds, _ = timed(run_cli, a.runs)
            seg = json.loads(out.read_text())
            record(m, f"mocapseg {m}", trial, seg, seconds, truth)

        for label, key, fn, told in peers:
            if key not in jit:  # numba compiles on the first call: do it on this take, untimed
                t0 = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    fn(x, k_true, told)
                jit[key] = time.perf_counter() - t0
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                seconds, (cps, params) = timed(lambda: fn(x, k_true, told), a.runs)
            seg = segmentation_json(info, key, params, cps, source)
            record(key, label, trial, seg, seconds, truth)

    # the table
    base = sum(rows["sssm"]["time"]) if "sssm" in rows else None
    n_true = sum(true_boundaries.values())
    lines = [
        f"| method | boundaries found / true ({len(takes)} takes) | F1@0.5s | F1@1s | covering | time, {len(takes)} takes | time / SSSM |",
        "|---|---|---|---|---|---|---|",
    ]
    for key, r in rows.items():
        f05, f1, cov = (statistics.mean(s[i] for s in r["scores"]) for i in range(3))
        t = sum(r["time"])
        ratio = f"{t / base:.2f}×" if base else "–"
        lines.append(f"| {r['label']} | {sum(r['boundaries'])} / {n_true} | {f05:.2f} | {f1:.2f} | {cov:.2f} | {t:.2f} s | {ratio} |")
    notes = [
        "",
        f"Takes: {', '.join(t for t, _, _ in takes)} (truth: labels/cmu86_zhou_gt.csv, labels/mocap6_gt.csv; 1-based AMC frames, "
        "no T-pose row). Scores: `mocapseg eval` (action level; boundaries as it counts them), means over the takes. Time: wall clock per take, median of "
        f"{a.runs} runs, summed; mocapseg rows = the whole `mocapseg segment` process on the 120 Hz BVH (start, parse, "
        "features, method, JSON); peer rows = the library call on the 30 Hz features (`mocapseg features` not counted, "
        "numba compilation done on a warm-up call and not counted: "
        + ", ".join(f"{k} {v:.1f} s" for k, v in jit.items()) + "). (o) = told the true number of segments. "
        "knn and dtfcn run their default shipped model `exercises`, trained on the four mocap6 takes' labels: "
        "in-sample there.",
    ]
    for key, trial in empty:
        notes.append(f"{key} found no segment on {trial}: scored as one segment (no boundary).")
    for m in missing:
        notes.append(f"Not run: {m}.")
    table = "\n".join(lines + notes)
    (a.out / "peers.md").write_text(table + "\n")
    print()
    print("## peers: mocapseg's methods and other libraries on the same takes and features")
    print()
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
