"""The accuracy-cost map: error against wall time of the 2D adhesive solver.

Two scenes with independent references:

* the y-invariant sinusoid (β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01, ζ = 0.1 and 1) against
  the seed's 1D method at the same effective a0 (errors in ã, ẽ relative to ã, G1, G2, μ̄);
  varied: a0/h = m (cells per wavelength N = m·λ/a0) and the Krylov tolerance;
* the elastic JKR sphere (R = L = E* = 1, zero-load JKR radius 0.1 L) against JKR: the
  Griffith radius at zero load and the load-control pull-off (bisection, 7 solves); varied:
  grid N² (cells per radius), the front smoothing σ (default, or fixed 3/6/12 cells) and
  the Krylov tolerance.

and the front criterion: exact layer tests (every front layer tested by a masked solve),
the zero-solve predictor alone (docs/theory.md) ('predictor': the exact tests only
evaluate the outputs of its final mask) or the predictor then exact tests ('hybrid').
One thread, wall seconds of the solve (operator construction and FFT planning excluded).
Writes bench/accuracy.json, docs/figures/accuracy_cost.png and the accuracy table of
docs/performance.md.  Usage: python bench/accuracy.py [--quick] [--criteria-only] [--report-only]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from spectralbem import fft  # noqa: E402
from spectralbem import reference as ref  # noqa: E402
from spectralbem import sinusoid1d as s1  # noqa: E402
from spectralbem.adhesive import solve_adhesive  # noqa: E402
from spectralbem.scenes import Scene, solve  # noqa: E402
from spectralbem.validate import (  # noqa: E402
    W_JKR,
    griffith_radius,
    jkr_cell,
    pulloff_bisection,
    smoothing,
)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
BETA, GAMMA, A0, P_TILDE = 10.0, 0.008, 0.01, 0.15
SIN_KEYS = ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar")


def sinusoid_point(zeta: float, m: int, tol: float, criterion: str = "exact") -> dict:
    n = int(np.ceil(m * 2 * np.pi / A0))  # h ≤ a0/m
    scene = Scene.sinusoid(zeta, BETA, GAMMA, p_tilde=P_TILDE, a0_tilde=A0,
                           cells_per_wavelength=n, ny=2)
    scene = dataclasses.replace(scene, solver={**scene.solver, "tol": tol,
                                               "criterion": criterion})
    fft.plan(scene.cell.shape)  # FFT planning is not part of the solve
    t = time.perf_counter()
    ds = solve(scene)
    wall = time.perf_counter() - t
    r1 = s1.solve(zeta, BETA, GAMMA, p_tilde=P_TILDE, a0_tilde=A0,
                  adhesiveless_reference=False)
    err = {}
    for k in SIN_KEYS:
        v2, v1 = ds[k].item(), r1[k].item()
        scale = abs(r1["a_tilde"].item()) if k == "e_tilde" else abs(v1)
        err[k] = abs(v2 - v1) / scale
    return {"case": "sinusoid", "zeta": zeta, "a0_over_h": m, "N": n, "tol": tol,
            "criterion": criterion, "status": ds.status.item(), "seconds": wall, "errors": err,
            "error": max(err.values())}


def jkr_point(n: int, sigma: float | None, tol: float, pulloff: bool = True,
              criterion: str = "exact") -> dict:
    """``sigma`` None: the default front smoothing (½ a0 in this elastic scene, ≥ 0.23 of
    the patch radius); a number: that σ fixed (in units of a0, here one cell)."""
    cell, op, h, r, w = jkr_cell(n, W_JKR)
    aJ = ref.jkr_radius(0.0, 1.0, 1.0, w)
    op.apply(h)  # plans the transforms
    kw = {**smoothing(sigma), "rtol": tol, "criterion": criterion}
    t = time.perf_counter()
    res = solve_adhesive(op, h, w, cell.hx, mean_pressure=0.0, mask0=r < 0.9 * aJ, **kw)
    err = {"radius": abs(griffith_radius(res, cell) / aJ - 1)}
    if pulloff:
        # the bracket (0.3 % of Pc after 7 steps) is part of the error; the midpoint is the
        # estimate
        lo, hi = pulloff_bisection(op, h, w, cell, res.contact, **kw)
        err["pulloff"] = abs(0.5 * (lo + hi) - 1)
    return {"case": "jkr", "N": n, "cells_per_radius": aJ / cell.hx, "sigma": sigma,
            "tol": tol, "criterion": criterion, "status": res.status,
            "seconds": time.perf_counter() - t,
            "errors": err, "error": max(err.values())}


def pareto(rows):
    """Indices of the rows not dominated in (seconds, error)."""
    keep = []
    for i, r in enumerate(rows):
        if not any((o["seconds"] <= r["seconds"] and o["error"] < r["error"])
                   or (o["seconds"] < r["seconds"] and o["error"] <= r["error"])
                   for j, o in enumerate(rows) if j != i):
            keep.append(i)
    return keep


def label(r):
    crit = r.get("criterion", "exact")
    crit = "" if crit == "exact" else f" {crit}"
    if r["case"] == "sinusoid":
        return f"ζ={r['zeta']:g} a0/h={r['a0_over_h']} tol={r['tol']:.0e}{crit}"
    sig = "default" if r["sigma"] is None else f"{r['sigma']:g} fixed"
    return f"{r['N']}² σ={sig} tol={r['tol']:.0e}{crit}"


def report(rows):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
    lines = ["| case | setting | status | wall s | max error | errors |",
             "|---|---|---|---|---|---|"]
    for case, mk in (("sinusoid", "o"), ("jkr", "s")):
        rr = [r for r in rows if r["case"] == case]
        if not rr:
            continue
        front = set(pareto(rr))
        t = np.array([r["seconds"] for r in rr])
        e = np.array([max(r["error"], 1e-7) for r in rr])
        name = ("y-invariant sinusoid vs 1D method (one load point)" if case == "sinusoid"
                else "JKR sphere (radius + 7 pull-off solves)")
        ax.loglog(t, e, mk, mfc="none", color="C0" if case == "sinusoid" else "C1",
                  label=f"{name}: all settings")
        alt = [i for i, r in enumerate(rr) if r.get("criterion", "exact") != "exact"]
        if alt:
            ax.loglog(t[alt], e[alt], "x", color="C0" if case == "sinusoid" else "C1",
                      label=f"{case}: predictor or hybrid criterion")
        idx = sorted(front, key=lambda i: t[i])
        ax.loglog(t[idx], e[idx], mk + "-", color="C0" if case == "sinusoid" else "C1",
                  label="Pareto front")
        for i in idx:
            ax.annotate(label(rr[i]), (t[i], e[i]), fontsize=6, xytext=(3, 3),
                        textcoords="offset points")
        for i, r in enumerate(rr):
            lines.append(f"| {case} | {label(r)} | {r['status']} | {r['seconds']:.2f} | "
                         f"{r['error']:.1e}{' (Pareto)' if i in front else ''} | "
                         + ", ".join(f"{k} {v:.1e}" for k, v in r["errors"].items()) + " |")
    for lev in (0.01, 0.001):
        ax.axhline(lev, color="0.6", ls=":")
    ax.set_xlabel("wall time of the solve (s, one thread)")
    ax.set_ylabel("largest relative error of the observables")
    ax.set_title("accuracy against cost: 2D adhesive solver")
    ax.legend(fontsize=7)
    fig.savefig(ROOT / "docs" / "figures" / "accuracy_cost.png", dpi=120)
    guide = []
    for case in ("sinusoid", "jkr"):
        # a setting (the sinusoid's a0/h and tolerance; the sphere's grid, σ, tolerance)
        # meets a level when every measured scene with it does (both ζ for the sinusoid)
        settings = {}
        for r in rows:
            if r["case"] == case:
                key = label(r).split(" ", 1)[1] if case == "sinusoid" else label(r)
                settings.setdefault(key, []).append(r)
        for lev in (0.01, 0.001):
            ok = [(max(r["seconds"] for r in rr), k) for k, rr in settings.items()
                  if all(r["status"] == "partial" and r["error"] <= lev for r in rr)]
            best = min(ok) if ok else None
            guide.append(f"- {case}, {100 * lev:g} %: " + (
                f"{best[1]} ({best[0]:.1f} s, the slowest measured case)" if best else
                "not reached by any setting measured"))
    text = (f"Measured {time.strftime('%Y-%m-%d')} with `python bench/accuracy.py` (one "
            "thread; [figure](figures/accuracy_cost.png)). The cheapest measured setting "
            "per accuracy level:\n\n" + "\n".join(guide) + "\n\n" + "\n".join(lines))
    write_section("accuracy", text)
    return guide


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="a few points only")
    ap.add_argument("--report-only", action="store_true",
                    help="redraw the figure and table from bench/accuracy.json")
    ap.add_argument("--criteria-only", action="store_true",
                    help="only the predictor and hybrid points, added to the exact-criterion "
                         "rows of bench/accuracy.json")
    args = ap.parse_args(argv)
    out = ROOT / "bench" / "accuracy.json"
    if args.report_only:
        for g in report(json.loads(out.read_text())):
            print(g)
        return
    rows, plan = [], []
    if args.criteria_only:  # keep the exact-criterion rows, redo the others
        rows = [r for r in json.loads(out.read_text()) if r.get("criterion", "exact") == "exact"]
    else:
        for z in ((0.1,) if args.quick else (0.1, 1.0)):
            for m in ((1, 4) if args.quick else (1, 2, 4, 8)):
                plan.append(("sin", z, m, 1e-10))
            for tol in ((1e-6,) if args.quick else (1e-4, 1e-6, 1e-8)):
                plan.append(("sin", z, 4, tol))
        for n in ((128,) if args.quick else (128, 256, 512)):
            plan.append(("jkr", n, None, 1e-10, True))
        if not args.quick:
            for sigma in (3.0, 6.0, 12.0):
                plan.append(("jkr", 512, sigma, 1e-10, True))
            for tol in (1e-6, 1e-8):
                plan.append(("jkr", 256, None, tol, True))
    for crit in ("predictor", "hybrid"):
        for z in ((0.1,) if args.quick else (0.1, 1.0)):
            for m in ((4,) if args.quick else (2, 4, 8)):
                plan.append(("sin", z, m, 1e-10, crit))
        for n in ((128,) if args.quick else (256, 512)):
            plan.append(("jkr", n, None, 1e-10, True, crit))
    for item in plan:
        r = sinusoid_point(*item[1:]) if item[0] == "sin" else jkr_point(*item[1:])
        rows.append(r)
        out.write_text(json.dumps(rows, indent=1))  # every finished point is kept
        print(f"{label(r):48s} {r['status']:13s} {r['seconds']:7.2f} s  max error "
              f"{r['error']:.2e}", flush=True)
    for g in report(rows):
        print(g)


if __name__ == "__main__":
    main()
