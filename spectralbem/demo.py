"""Default scene for ``make demo``: a rubber block (standard linear solid) sliding on a
self-affine rough surface; writes ``demo.nc`` and ``demo.png``.

Run ``python -m spectralbem.demo --out DIR``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from . import __version__, fft
from .contact import solve_contact
from .io import contact_dataset, write_dataset
from .materials import StandardLinearSolid
from .plotting import plot_contact
from .spectral import Cell, SpectralOperator
from .surfaces import self_affine

SCENE = {
    "cell": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 128, "Ny": 128},
    "material": {"kind": "sls", "E0": 2e6, "Einf": 2e7, "tau": 1e-2, "nu": 0.5},
    "surface": {"kind": "self_affine", "hurst": 0.8, "rolloff_wavelength": 2.5e-4,
                "cutoff_cells": 8, "rms_slope": 0.1, "seed": 1},
    "velocity": [4e-3, 0.0],
    "mean_pressure": 0.004 * 2e6 / 0.75,
}


def run(out: Path) -> Path:
    s = SCENE
    cell = Cell(**s["cell"])
    m = s["material"]
    mat = StandardLinearSolid(m["E0"], m["Einf"], m["tau"], m["nu"])
    sf = s["surface"]
    h = self_affine(cell, sf["hurst"], rolloff=2 * np.pi / sf["rolloff_wavelength"],
                    cutoff=2 * np.pi / (sf["cutoff_cells"] * cell.hx), rms_slope=sf["rms_slope"],
                    seed=sf["seed"])
    op = SpectralOperator(cell, mat, velocity=s["velocity"])
    t0 = time.perf_counter()
    res = solve_contact(op, h, mean_pressure=s["mean_pressure"])
    dt = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    ds = contact_dataset(res, cell, h, scene=s)
    ds.attrs["wall_time_s"] = dt
    nc = write_dataset(ds, out / "demo.nc")
    plot_contact(ds, out / "demo.png")
    print(f"spectralbem {__version__} ({fft.backend()} FFT): {cell.Nx}x{cell.Ny} viscoelastic "
          f"sliding contact in {dt:.2f} s, {res.message}; area fraction "
          f"{res.area_fraction:.4f}, mu = {res.mu:.4f}")
    print(f"wrote {nc} and {out / 'demo.png'}")
    if not res.converged:
        raise SystemExit(f"demo solve did not converge: {res.message}")
    return nc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="demo_out", help="output folder (default demo_out)")
    args = ap.parse_args(argv)
    run(Path(args.out))


if __name__ == "__main__":
    main()
