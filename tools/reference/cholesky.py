#!/usr/bin/env python3
"""The numpy/scipy peer of DESIGN.md: the same systems as `brdfpaint bench --tables`,
pre-factored by Cholesky, timed side by side with brdfpaint in one run.

prepare: A from the samples' directions (each factor's table coordinate and its linear or
bilinear stencil, vectorized: `design` below), G = A^T A + R^T R + floor I (eq. 3.4 with
the smoothing rows R, read as brdfpaint wrote them), dense Cholesky (scipy.linalg.cho_factor,
LAPACK): the work brdfpaint times as prepare_s.
solve:   log(f + a), b = A^T log(f + a) for R, G, B at once, cho_solve, exp: one refit,
the work `brdfpaint bench` times as solve_s.

Before timing, the A built here is checked against the A brdfpaint wrote (same entries to
1e-9), so both sides solve the same system.

Usage: tools/reference/cholesky.py [--brdfpaint target/release/brdfpaint] [--rounds 2]
Prints a Markdown table: per case, the reference's and brdfpaint's medians and the ratios
(reference / brdfpaint; the smallest over the rounds).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
    import scipy.linalg
    import scipy.sparse
except ImportError as e:
    raise SystemExit(f"error: the reference needs numpy and scipy ({e}); "
                     "sudo apt install python3-numpy python3-scipy, or pip install numpy scipy in a venv")


def median_time(f, min_runs, budget_s):
    """Median of repeated timings: at least min_runs, more until budget_s has passed."""
    times, start = [], time.perf_counter()
    while len(times) < min_runs or (time.perf_counter() - start < budget_s and len(times) < 1000):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def theta_to_rho(c, s):
    """tan(theta/2) above the horizon, 2 - tan((pi - theta)/2) below (the extended radius)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(c >= 0, s / (1 + c), 2 - s / (1 - c))


def coordinate(spec, l, v, uv):
    """Table coordinates (N x 2) of one factor, as brdfpaint's factor::system::coordinate."""
    kind = spec["input"]
    if kind == "uv":
        return np.clip(uv, 0, 1)
    if kind == "light":
        d = l
    elif kind == "view":
        d = v
    elif kind == "half":
        h = l + v
        n = np.linalg.norm(h, axis=1, keepdims=True)
        d = np.where(n > 1e-12, h / np.where(n > 1e-12, n, 1), [0, 0, 1])
    else:
        raise SystemExit(f"factor input {kind} is not in the reference")
    s = np.hypot(d[:, 0], d[:, 1])
    z = d[:, 2]
    hemi = spec["domain"] == "hemisphere"
    if spec["param"] == "radius":
        t = np.where(z <= 0, 1.0, np.minimum(s / (1 + np.maximum(z, 0)), 1.0)) if hemi else theta_to_rho(z, s) * 0.5
        warp = spec.get("warp", 1.0)
        if warp != 1.0:
            t = np.clip(t, 0, 1) ** (1 / warp)
        return np.stack([t, np.zeros_like(t)], axis=1)
    if spec["param"] == "parabolic":
        safe = np.where(s > 1e-12, s, 1)
        az = np.where((s > 1e-12)[:, None], d[:, :2] / safe[:, None], [1, 0])
        if hemi:
            r, scale = np.minimum(theta_to_rho(np.maximum(z, 0), np.where(z <= 0, 1.0, s)), 1.0), 1.0
        else:
            r, scale = theta_to_rho(z, s), 0.5
        return (az * (r * scale)[:, None] + 1) * 0.5
    raise SystemExit(f"parameterization {spec['param']} is not in the reference")


def cell(t, m):
    x = np.clip(t, 0, 1) * (m - 1)
    i = np.minimum(np.floor(x), m - 2)
    return i.astype(np.int64), x - i


def design(case, queries):
    """The sample matrix A (CSR): per factor, the stencil of each sample's coordinate."""
    l, v, uv = queries[:, 0:3], queries[:, 3:6], queries[:, 6:8]
    rows, cols, vals, offset = [], [], [], 0
    sample = np.arange(len(queries))
    for spec in case["factors"]:
        m = spec["res"]
        t = coordinate(spec, l, v, uv)
        i, fx = cell(t[:, 0], m)
        if spec["param"] == "radius":
            idx, w = [i, i + 1], [1 - fx, fx]
            size = m
        else:
            j, fy = cell(t[:, 1], m)
            idx = [j * m + i, j * m + i + 1, (j + 1) * m + i, (j + 1) * m + i + 1]
            w = [(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy]
            size = m * m
        for k, wk in zip(idx, w):
            rows.append(sample)
            cols.append(offset + k)
            vals.append(wk)
        offset += size
    a = scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                shape=(len(queries), offset))
    a.eliminate_zeros()
    return a


def load(folder, stem, part):
    return np.load(os.path.join(folder, f"{stem}.{part}.npy"))


def reference_case(folder, case):
    stem, n = case["stem"], case["unknowns"]
    parts = {p: load(folder, stem, p) for p in
             ("a_indptr", "a_indices", "a_data", "r_indptr", "r_indices", "r_data", "values", "queries")}
    rows = len(parts["a_indptr"]) - 1
    reg_rows = len(parts["r_indptr"]) - 1
    state = {}
    written = scipy.sparse.csr_matrix((parts["a_data"], parts["a_indices"], parts["a_indptr"]), shape=(rows, n))
    mine = design(case, parts["queries"])
    gap = abs(mine - written).max() if mine.shape == written.shape else float("inf")
    if gap > 1e-9:
        raise SystemExit(f"{case['case']}: the reference's A differs from brdfpaint's by {gap}")

    def prepare():
        a = design(case, parts["queries"])
        r = scipy.sparse.csr_matrix((parts["r_data"], parts["r_indices"], parts["r_indptr"]), shape=(reg_rows, n))
        at = a.T.tocsr()
        g = (at @ a + r.T @ r).toarray()
        g[np.diag_indices(n)] += case["floor"]
        state["at"], state["chol"] = at, scipy.linalg.cho_factor(g, lower=True, check_finite=False)

    values, offset = parts["values"], case["offset"]

    def solve():
        b = state["at"] @ np.log(values + offset)
        y = scipy.linalg.cho_solve(state["chol"], b, check_finite=False)
        return np.exp(y)

    prepare_s = median_time(prepare, 3, 0.0)
    solve_s = median_time(solve, 5, 0.5)
    return prepare_s, solve_s


def ours(binary, folder=None):
    cmd = [binary, "bench", "--tables", "--json"] + (["--systems", folder] if folder else [])
    try:
        run = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as e:
        raise SystemExit(f"error: cannot run {binary} ({e.strerror}); build it with `cargo build --release` "
                         "or name it with --brdfpaint")
    if run.returncode != 0:
        raise SystemExit(f"error: {' '.join(cmd)} failed: {run.stderr.strip()}")
    return {c["case"]: c for c in json.loads(run.stdout)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--brdfpaint", default="target/release/brdfpaint")
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = os.path.join(tmp, "systems")
        rounds = []
        for k in range(args.rounds):
            mine = ours(args.brdfpaint, folder if k == 0 else None)
            cases = json.load(open(os.path.join(folder, "cases.json")))
            peer = {c["case"]: reference_case(folder, c) for c in cases}
            rounds.append((mine, peer))
            print(f"round {k + 1} of {args.rounds} done", file=sys.stderr)
    print(f"numpy {np.__version__}, scipy {scipy.__version__}; {args.rounds} rounds, "
          "each brdfpaint then the reference; ratio = reference / brdfpaint, the smallest over the rounds")
    print()
    print("| case | unknowns | reference prepare ms | brdfpaint prepare ms | prepare ratio "
          "| reference solve ms | brdfpaint solve ms | solve ratio |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    worst = [float("inf"), float("inf")]
    for c in cases:
        name = c["case"]
        rp = [p[name][0] for _, p in rounds]
        rs = [p[name][1] for _, p in rounds]
        op = [m[name]["prepare_s"] for m, _ in rounds]
        os_ = [m[name]["solve_s"] for m, _ in rounds]
        ratio_p = min(a / b for a, b in zip(rp, op))
        ratio_s = min(a / b for a, b in zip(rs, os_))
        worst = [min(worst[0], ratio_p), min(worst[1], ratio_s)]
        print(f"| {name} | {c['unknowns']} | {statistics.median(rp) * 1e3:.2f} | {statistics.median(op) * 1e3:.2f} "
              f"| {ratio_p:.1f}× | {statistics.median(rs) * 1e3:.3f} | {statistics.median(os_) * 1e3:.3f} | {ratio_s:.1f}× |")
    print()
    print(f"smallest ratio: prepare {worst[0]:.1f}×, solve {worst[1]:.1f}×")


if __name__ == "__main__":
    main()
