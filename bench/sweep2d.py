"""Issue 6's sweep target: a 25-point ζ sweep of the y-invariant sinusoid on the 4096 × 8 grid
(β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01, ζ = 1e-3…1e2 log-spaced) with the package's dask
sweep on all cores of this machine (2 workers).  Target: under 10 minutes.

Writes the <!-- bench:sweep2d --> section of docs/performance.md.

``--rough N``: the fast-solves issue's sweep instead: 25 sliding speeds (ζ = 1e-3 … 1e2 at
the roll-off, log-spaced) of the adhesive viscoelastic rough scene
``cases/rough_convergence.toml`` at N² (default 512) and p̄ = 1e4 Pa, on the same local
cluster; target 30 minutes at 512².  Writes the <!-- bench:sweep_rough --> section.

Usage: python bench/sweep2d.py [--workers 2] [--rough [N]]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from spectralbem.sweep import run_sweep  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def timed_sweep(case: str, over: list, workers: int, overrides: dict):
    """Run the sweep of ``cases/<case>`` in a temporary folder: (wall seconds, dataset,
    status per point, count per status)."""
    tmp = Path(tempfile.mkdtemp(prefix="sb_sweep_bench_"))
    try:
        t = time.perf_counter()
        path = run_sweep(ROOT / "cases" / case, over, tmp / "sweep.nc", workers=workers,
                         progress=False, overrides=overrides)
        wall = time.perf_counter() - t
        ds = xr.load_dataset(path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    status = [str(s) for s in np.asarray(ds["status"].values).ravel()]
    return wall, ds, status, {s: status.count(s) for s in sorted(set(status))}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rough", type=int, nargs="?", const=512, default=None)
    args = ap.parse_args(argv)
    if args.rough:
        return rough_sweep(args.rough, args.workers)
    zetas = np.geomspace(1e-3, 1e2, 25)
    wall, _ds, _status, counts = timed_sweep(
        "seed_sinusoid_2d.toml", [("zeta", zetas)], args.workers,
        {"sinusoid.cells_per_wavelength": 4096, "sinusoid.ny": 8})
    m = f"{0.01 / (2 * np.pi / 4096):.2f}"  # ã0 = k a0 with k = 2π/λ: a0/h = ã0 · 4096/(2π)
    text = (f"Measured {time.strftime('%Y-%m-%d')} with `python bench/sweep2d.py` "
            f"({args.workers} dask workers, one thread each): 25 ζ points from 1e-3 to 1e2 of "
            f"`cases/seed_sinusoid_2d.toml` at 4096 × 8 cells (ã0 = 0.01: a0 = {m} cells) in "
            f"**{wall:.0f} s** ({wall / 60:.1f} min; target 10 min); statuses: "
            + ", ".join(f"{k} {v}" for k, v in counts.items()) + ".")
    print(text)
    write_section("sweep2d", text)


def rough_sweep(n: int, workers: int) -> None:
    zetas = np.geomspace(1e-3, 1e2, 25)
    speeds = zetas * (3.98e-4 / 0.1)  # the case's speed gives ζ = 0.1 at the roll-off
    wall, ds, status, counts = timed_sweep(
        "rough_convergence.toml", [("motion.speed", speeds)], workers,
        {"grid.Nx": n, "grid.Ny": n, "control.mean_pressure": 1e4})
    mu = np.asarray(ds["mu"].values).ravel()
    k = int(np.nanargmax(np.where(np.array(status) == "partial", mu, np.nan))) \
        if "partial" in counts else None
    peak = (f"; μ peaks at {mu[k]:.3f} at ζ = {zetas[k]:.2g}" if k is not None else "")
    failed = [f"{z:.2g}" for z, st in zip(zetas, status, strict=True) if st != "partial"]
    if failed:
        peak += f"; not partial at ζ = {', '.join(failed)}"
    text = (f"Measured {time.strftime('%Y-%m-%d')} with `python bench/sweep2d.py --rough {n}` "
            f"({workers} dask workers, one thread each): 25 sliding speeds (ζ = 1e-3 … 1e2 at "
            f"the roll-off) of the adhesive SLS rough scene `cases/rough_convergence.toml` at "
            f"{n}², p̄ = 1e4 Pa, in **{wall:.0f} s** ({wall / 60:.1f} min; target 30 min at "
            "512²); statuses: " + ", ".join(f"{k} {v}" for k, v in counts.items()) + peak + ".")
    print(text)
    write_section("sweep_rough", text)


if __name__ == "__main__":
    main()
