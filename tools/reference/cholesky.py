#!/usr/bin/env python3
"""The numpy/scipy peer of DESIGN.md: the same systems as `brdfpaint bench --tables`,
pre-factored by Cholesky, timed side by side with brdfpaint in one run.

prepare: A and R from their compressed rows, G = A^T A + R^T R + floor I (eq. 3.4 with the
smoothing rows), dense Cholesky (scipy.linalg.cho_factor, LAPACK).
solve:   log(f + a), b = A^T log(f + a) for R, G, B at once, cho_solve, exp: one refit,
the work `brdfpaint bench` times as solve_s.

Building A from the samples' stencils is left out of the reference's prepare (brdfpaint's
includes it), so the ratios are conservative.

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

import numpy as np
import scipy.linalg
import scipy.sparse


def median_time(f, min_runs, budget_s):
    """Median of repeated timings: at least min_runs, more until budget_s has passed."""
    times, start = [], time.perf_counter()
    while len(times) < min_runs or (time.perf_counter() - start < budget_s and len(times) < 1000):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def load(folder, stem, part):
    return np.load(os.path.join(folder, f"{stem}.{part}.npy"))


def reference_case(folder, case):
    stem, n = case["stem"], case["unknowns"]
    parts = {p: load(folder, stem, p) for p in
             ("a_indptr", "a_indices", "a_data", "r_indptr", "r_indices", "r_data", "values")}
    rows = len(parts["a_indptr"]) - 1
    reg_rows = len(parts["r_indptr"]) - 1
    state = {}

    def prepare():
        a = scipy.sparse.csr_matrix((parts["a_data"], parts["a_indices"], parts["a_indptr"]), shape=(rows, n))
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
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return {c["case"]: c for c in json.loads(out)}


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
