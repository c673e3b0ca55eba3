"""Issue 6's sweep target: a 25-point ζ sweep of the y-invariant sinusoid on the 4096 × 8 grid
(β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01, ζ = 1e-3…1e2 log-spaced) with the package's dask
sweep on all cores of this machine (2 workers).  Target: under 10 minutes.

Writes the <!-- bench:sweep2d --> section of docs/performance.md.
Usage: python bench/sweep2d.py [--workers 2]
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

from spectralbem.criterion import layers  # noqa: E402
from spectralbem.sweep import run_sweep  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    zetas = np.geomspace(1e-3, 1e2, 25)
    tmp = Path(tempfile.mkdtemp(prefix="sb_sweep2d_"))
    try:
        t = time.perf_counter()
        path = run_sweep(ROOT / "cases" / "seed_sinusoid_2d.toml", [("zeta", zetas)],
                         tmp / "sweep.nc", workers=args.workers, progress=False,
                         overrides={"sinusoid.cells_per_wavelength": 4096, "sinusoid.ny": 8})
        wall = time.perf_counter() - t
        ds = xr.load_dataset(path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    status = [str(s) for s in np.asarray(ds["status"].values).ravel()]
    counts = {s: status.count(s) for s in sorted(set(status))}
    m = layers(0.01, 2 * np.pi / 4096, 2 * np.pi / 4096)
    text = (f"Measured {time.strftime('%Y-%m-%d')} with `python bench/sweep2d.py` "
            f"({args.workers} dask workers, one thread each): 25 ζ points from 1e-3 to 1e2 of "
            f"`cases/seed_sinusoid_2d.toml` at 4096 × 8 cells (ã0 = 0.01: a0 = {m} cells) in "
            f"**{wall:.0f} s** ({wall / 60:.1f} min; target 10 min); statuses: "
            + ", ".join(f"{k} {v}" for k, v in counts.items()) + ".")
    print(text)
    write_section("sweep2d", text)


if __name__ == "__main__":
    main()
