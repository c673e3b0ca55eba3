"""Benchmark of the 2D adhesive viscoelastic sphere at 512² and one load.

Elastic-unit scene: L = R = E0 = 1 (ν = 0), β = E∞/E0 = 10, τ = 1, sliding speed v = 0.1 a_J
so that ζ = vτ/a = 0.1 on the JKR zero-load radius a_J = 0.1 L, Δγ chosen for that radius
(Δγ = a_J³ (4/3)/(6π R²)), a0 = one cell, zero mean pressure.  Reports wall time, outer
iterations, masked solves per outer iteration and the time split (masked solves, operator
applications outside them, the rest); writes the table between the markers
<!-- bench:sphere --> in docs/performance.md.

Usage: python bench/sphere.py [N [SIGMA ...]]   (default: 512 default; SIGMA = "default"
for the library's front smoothing, or a number of cells for a fixed σ)
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import spectralbem.adhesive as ad  # noqa: E402
import spectralbem.criterion as cr  # noqa: E402
from spectralbem import reference as ref  # noqa: E402
from spectralbem.materials import StandardLinearSolid  # noqa: E402
from spectralbem.spectral import Cell, SpectralOperator  # noqa: E402
from spectralbem.surfaces import paraboloid  # noqa: E402
from spectralbem.validate import smoothing  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402


def timed(module, name, bucket):
    f = getattr(module, name)

    def wrapper(*a, **k):
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            bucket[name] = bucket.get(name, 0.0) + time.perf_counter() - t
            bucket[name + "_n"] = bucket.get(name + "_n", 0) + 1

    setattr(module, name, wrapper)


A_J = 0.1  # JKR zero-load radius (units of L), the start disc


def sphere_scene(n: int):
    """(cell, operator, heights, Δγ, start mask) of the benchmark scene at n²."""
    w = A_J**3 * (4.0 / 3.0) / (6 * np.pi)
    cell = Cell(1.0, 1.0, n, n)
    op = SpectralOperator(cell, StandardLinearSolid(1.0, 10.0, 1.0, 0.0),
                          velocity=(0.1 * A_J, 0.0))
    X, Y = cell.coordinates()
    mask0 = np.hypot(X - n // 2 * cell.hx, Y - n // 2 * cell.hy) < A_J
    return cell, op, paraboloid(cell, 1.0), w, mask0


def run(n: int = 512, sigma: float | None = None):
    """``sigma`` None: the library's default smoothing (σ = 1.5 a0, raised to 0.23 of the
    patch radius); a number: that σ fixed (in units of a0, here one cell)."""
    cell, op, h, w, mask0 = sphere_scene(n)
    bucket = {}
    timed(ad, "solve_masked", bucket)
    timed(cr, "solve_masked", bucket)
    kw = smoothing(sigma)
    t0 = time.perf_counter()
    res = ad.solve_adhesive(op, h, w, cell.hx, mean_pressure=0.0, mask0=mask0, **kw)
    wall = time.perf_counter() - t0
    solves = res.solves
    t_solve = bucket.get("solve_masked", 0.0)
    a = np.sqrt(res.contact.sum() * cell.cell_area / np.pi)
    row = dict(N=n, sigma=sigma, wall=wall, status=res.status, outer=res.iterations,
               solves=solves,
               per_outer=solves / max(res.iterations, 1), t_solve=t_solve,
               t_rest=wall - t_solve, radius_cells=a / cell.hx,
               radius_jkr_E0=ref.jkr_radius(0.0, 1.0, 1.0, w) / cell.hx, message=res.message)
    return row


def sig_label(sigma):
    return "default (1.5 a0, ≥ 0.23 r)" if sigma is None else f"{sigma:g} fixed"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int, nargs="?", default=512, help="grid size N (default 512)")
    ap.add_argument("sigma", nargs="*", help='"default" or a fixed σ in cells')
    args = ap.parse_args(argv)
    n = args.n
    sigmas = [None if v == "default" else float(v) for v in args.sigma] or [None]
    rows = []
    for sg in sigmas:
        row = run(n, sg)
        print(row, flush=True)
        rows.append(row)
    table = (
        "| N² | σ (cells) | wall s | status | outer iterations | masked solves | solves/outer | "
        "time in masked solves s | rest s | contact radius (cells) |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n")
    for row in rows:
        table += (
            f"| {row['N']}² | {sig_label(row['sigma'])} | {row['wall']:.1f} | {row['status']} | "
            f"{row['outer']} | {row['solves']} | {row['per_outer']:.1f} | {row['t_solve']:.1f} | "
            f"{row['t_rest']:.1f} | {row['radius_cells']:.1f} (JKR with E0: "
            f"{row['radius_jkr_E0']:.1f}) |\n")
    table += "\n" + "\n".join(f"σ {sig_label(r['sigma'])}: {r['message'][:150]}"
                               for r in rows) + "\n"
    write_section("sphere", table)


if __name__ == "__main__":
    main()
