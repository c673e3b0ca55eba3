"""Benchmark of the scaling with the grid size N² (64² to 2048²).

* Elastic adhesiveless rough contact (the surface of bench/run.py, p = 0.004 E*, tol 1e-10):
  time per iteration, iterations, FFT pairs per iteration and the time of one planned FFTW
  pair, against N.  Time per iteration should follow N² log N.
* Viscoelastic adhesive sphere (the scene of bench/sphere.py: β = 10, ζ = 0.1, contact radius
  0.1 L, a0 = one cell, zero load; σ scaled with the radius, 6 a0 = 6 cells at 256²) up to 512²:
  peak memory of the solve (numpy allocations traced by tracemalloc, which numpy reports to)
  in units of one N² float64 array; target ≤ 25.

Writes docs/figures/scaling.png, the table between <!-- bench:scaling --> markers in
docs/performance.md and bench/scaling.json.
Usage: python bench/scaling.py [--max N]   (default 2048; about five minutes)
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import tracemalloc  # noqa: E402
from pathlib import Path  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spectralbem.adhesive as ad  # noqa: E402
from spectralbem.contact import polonsky_keer  # noqa: E402
from spectralbem.materials import Elastic  # noqa: E402
from spectralbem.spectral import SpectralOperator  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import OUR_TOL, fft_pair_seconds, surface, write_section  # noqa: E402
from sphere import sphere_scene  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def elastic_row(n: int) -> dict:
    cell, h = surface(n)
    op = SpectralOperator(cell, Elastic(1.0, 0.0))
    polonsky_keer(op, h, mean_pressure=0.004, tol=OUR_TOL, maxiter=5)  # plans, caches
    t = time.perf_counter()
    r = polonsky_keer(op, h, mean_pressure=0.004, tol=OUR_TOL)
    its, conv, pairs = r.iterations, r.converged, r.fft_pairs
    wall = time.perf_counter() - t
    pair = fft_pair_seconds(n)
    return {"case": "elastic_rough", "N": n, "seconds": wall, "iterations": its,
            "converged": bool(conv), "s_per_iteration": wall / its,
            "fft_pairs_per_iteration": pairs / its, "fft_pair_s": pair}


def adhesive_row(n: int) -> dict:
    cell, op, h, w, mask0 = sphere_scene(n)
    sigma = 6.0 * n / 256  # in units of a0 = one cell: the same length against the radius
    tracemalloc.start()
    t = time.perf_counter()
    res = ad.solve_adhesive(op, h, w, cell.hx, mean_pressure=0.0, mask0=mask0,
                            front_smoothing=sigma, smoothing_per_radius=0.0)
    wall = time.perf_counter() - t
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return {"case": "visco_adhesive_sphere", "N": n, "seconds": wall, "status": res.status,
            "outer_iterations": res.iterations, "sigma": sigma,
            "peak_bytes": peak, "peak_arrays": peak / (8.0 * n * n)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--max", type=int, default=2048)
    args = ap.parse_args(argv)
    sizes = [n for n in (64, 128, 256, 512, 1024, 2048) if n <= args.max]
    rows = []
    for n in sizes:
        rows.append(elastic_row(n))
        print(rows[-1], flush=True)
    for n in [n for n in sizes if n <= 512]:
        rows.append(adhesive_row(n))
        print(rows[-1], flush=True)
    (ROOT / "bench" / "scaling.json").write_text(json.dumps(rows, indent=1))
    el = [r for r in rows if r["case"] == "elastic_rough"]
    av = [r for r in rows if r["case"] != "elastic_rough"]
    N = np.array([r["N"] for r in el], float)
    fig, ax = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
    tpi = np.array([r["s_per_iteration"] for r in el])
    ax[0].loglog(N**2, tpi, "o-", label="time per iteration")
    ax[0].loglog(N**2, [r["fft_pair_s"] for r in el], "s--", label="one FFTW pair")
    ref = N**2 * np.log(N**2)
    ax[0].loglog(N**2, tpi[-1] * ref / ref[-1], "k:", label="∝ N² log N²")
    ax[0].set_xlabel("grid cells N²")
    ax[0].set_ylabel("s")
    ax[0].legend(fontsize=8)
    ax[1].semilogx(N**2, [r["iterations"] for r in el], "o-")
    ax[1].set_xlabel("grid cells N²")
    ax[1].set_ylabel("PK iterations (tol 1e-10)")
    if av:
        ax[2].semilogx([r["N"] ** 2 for r in av], [r["peak_arrays"] for r in av], "o-")
        ax[2].axhline(25, color="C3", ls="--", label="target 25")
        ax[2].set_xlabel("grid cells N²")
        ax[2].set_ylabel("peak memory / (8 N² bytes)")
        ax[2].legend(fontsize=8)
    ax[0].set_title("elastic rough contact")
    ax[2].set_title("viscoelastic adhesive sphere")
    fig.savefig(ROOT / "docs" / "figures" / "scaling.png", dpi=110)
    lines = [f"Measured {time.strftime('%Y-%m-%d')} with `python bench/scaling.py` (one thread):",
             "", "| case | N² | s | iterations | s / iteration | FFT pairs / it | 1 pair (ms) |"
             " peak memory (N² arrays) |", "|---|---|---|---|---|---|---|---|"]
    for r in el:
        lines.append(f"| elastic rough | {r['N']}² | {r['seconds']:.3f} | {r['iterations']} | "
                     f"{1e3 * r['s_per_iteration']:.2f} ms | {r['fft_pairs_per_iteration']:.2f} "
                     f"| {1e3 * r['fft_pair_s']:.2f} | — |")
    for r in av:
        lines.append(f"| visco adhesive sphere (σ = {r['sigma']:g}) | {r['N']}² | "
                     f"{r['seconds']:.1f} | {r['outer_iterations']} outer | — | — | — | "
                     f"{r['peak_arrays']:.1f} |")
    text = "\n".join(lines)
    write_section("scaling", text)
    print(text)


if __name__ == "__main__":
    main()
