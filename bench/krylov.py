"""Benchmark of the non-symmetric masked solves against β and ζ.

One masked solve (seed Eq. (15) on a fixed contact mask: the pressure that imposes the
indenter's profile) for a steady-sliding standard linear solid, E0 = 1, E∞ = β, τ = 1, on two
masks of a 256² cell of side L = 1:

* ``disc``: the disc of radius a = 0.1 L (the sphere scene), ζ = vτ/a;
* ``rough``: the contact set of the elastic self-affine rough surface of bench/run.py at
  p = 0.004 E* (many small patches), ζ = vτ/ℓ with ℓ = L/32 (the short cut-off wavelength 8h).

For each (β, ζ) it reports matrix-vector products (each one planned FFT pair) to the relative
residual 1e-10, with and without the Fourier preconditioner M = P F⁻¹[1/Ĉ] F P, for BiCGSTAB
(two products per iteration) and for GMRES (restart 60, unrestarted below 500 cells).  A solve
that does not meet the tolerance within the guard (20√n + 500 products) is marked "—".

Writes the table between <!-- bench:krylov --> markers in docs/performance.md and the rows to
bench/krylov.json.  Usage: python bench/krylov.py [N]   (default 256; about two minutes)
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from spectralbem.contact import polonsky_keer  # noqa: E402
from spectralbem.masked import solve_masked  # noqa: E402
from spectralbem.materials import Elastic, StandardLinearSolid  # noqa: E402
from spectralbem.spectral import SpectralOperator  # noqa: E402
from spectralbem.surfaces import paraboloid  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import surface, write_section  # noqa: E402  (surface: as in the Tamaas comparison)

ROOT = Path(__file__).resolve().parent.parent
BETAS = (1.0, 10.0, 100.0, 1e3, 1e4)
ZETAS = (0.01, 0.1, 1.0, 10.0)
VARIANTS = (("bicgstab", True), ("bicgstab", False), ("gmres", True), ("gmres", False))


def masks(n: int):
    cell, h_rough = surface(n)
    X, Y = cell.coordinates()
    disc = np.hypot(X - n // 2 * cell.hx, Y - n // 2 * cell.hy) < 0.1
    h_disc = paraboloid(cell, 1.0)
    op = SpectralOperator(cell, Elastic(1.0, 0.0))
    p = polonsky_keer(op, h_rough, mean_pressure=0.004 * 1.0, tol=1e-8).pressure
    return cell, {"disc": (disc, h_disc, 0.1), "rough": (p > 0, h_rough, 1.0 / 32)}


def run(n: int = 256):
    cell, cases = masks(n)
    rows = []
    for name, (mask, h, length) in cases.items():
        for beta in BETAS:
            for zeta in ZETAS if beta > 1 else (0.0,):
                mat = (StandardLinearSolid(1.0, beta, 1.0, 0.0) if beta > 1
                       else Elastic(1.0, 0.0))
                op = SpectralOperator(cell, mat, velocity=(zeta * length, 0.0))
                row = {"mask": name, "cells": int(mask.sum()), "beta": beta, "zeta": zeta}
                for method, pre in VARIANTS:
                    t = time.perf_counter()
                    r = solve_masked(op, mask, h, rtol=1e-10, method=method, precondition=pre)
                    key = f"{method}{'+M' if pre else ''}"
                    row[key] = r.iterations if r.converged else None
                    row[key + "_s"] = time.perf_counter() - t
                rows.append(row)
                print(row, flush=True)
    return rows


def table(rows) -> str:
    keys = [f"{m}{'+M' if p else ''}" for m, p in VARIANTS]
    out = ["| mask (cells) | β | ζ | " + " | ".join(keys) + " |",
           "|---|---|---|" + "---|" * len(keys)]
    for r in rows:
        cells = [f"{r[k]} ({1e3 * r[k + '_s']:.0f} ms)" if r[k] is not None else "—"
                 for k in keys]
        out.append(f"| {r['mask']} ({r['cells']}) | {r['beta']:g} | {r['zeta']:g} | "
                   + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int, nargs="?", default=256, help="grid size N (default 256)")
    n = ap.parse_args(argv).n
    rows = run(n)
    text = (f"Measured {time.strftime('%Y-%m-%d')} with `python bench/krylov.py {n}` ({n}², "
            "matrix-vector products to relative residual 1e-10 and, in brackets, wall time; "
            "β = 1 is the elastic case, where the symmetric system is solved as given):\n\n"
            + table(rows))
    (ROOT / "bench" / "krylov.json").write_text(json.dumps(rows, indent=1))
    write_section("krylov", text)
    print(text)


if __name__ == "__main__":
    main()
