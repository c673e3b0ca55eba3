"""The restart rule of the Polonsky–Keer solver: PK's own (β = 0 after cells join,
``restart="join"``) against ours (β kept, restarted only when t is not a descent direction,
``restart="descent"``, the default) — iterations and agreement of the solutions.

Cases: self-affine surfaces (Hurst 0.3 and 0.8, two seeds, 256² and 512², rms slope 0.1,
roll-off L/4, cut-off 8 cells) under load control from p̄ = 4e-4 to 0.1 E* and under
penetration control; a sphere, a sinusoid, a bi-sinusoid; layers glued to a rigid plate; a
layer under uniform pressure (A.5), which neither rule solves (see docs/performance.md).
Both rules at tol 1e-10; "Δp" is their relative L2 difference, "set diff" the number of cells
in one contact set and not the other.

Writes the table of docs/performance.md (section pk_restart).
Usage: python bench/pk_restart.py
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

from spectralbem import layers, surfaces  # noqa: E402
from spectralbem.contact import polonsky_keer  # noqa: E402
from spectralbem.materials import Elastic  # noqa: E402
from spectralbem.spectral import Cell, SpectralOperator  # noqa: E402


def cases():
    for n in (256, 512):
        cell = Cell(1.0, 1.0, n, n)
        for hurst in (0.3, 0.8):
            for seed in (1, 2):
                h = surfaces.self_affine(cell, hurst, rolloff=2 * np.pi * 4,
                                         cutoff=2 * np.pi / (8 * cell.hx), rms_slope=0.1,
                                         seed=seed)
                name = f"rough {n}² H={hurst} seed {seed}"
                for p in (4e-4, 4e-3, 4e-2, 1e-1):
                    yield f"{name}, p̄ = {p:g}", cell, None, h, dict(mean_pressure=p)
                # Δ below the gauge limit max h − mean h (≈ 0.0049-0.0063 here)
                yield f"{name}, Δ = 0.002", cell, None, h, dict(penetration=0.002)
    cell = Cell(1.0, 1.0, 512, 512)
    for p in (1e-5, 1e-4, 1e-3):
        yield f"sphere R = 5, 512², p̄ = {p:g}", cell, None, surfaces.paraboloid(cell, 5.0), \
            dict(mean_pressure=p)
    line = Cell(1.0, 1.0 / 64, 512, 8)
    for p in (1e-3, 5e-3, 1e-2):
        yield f"sinusoid 512×8, p̄ = {p:g}", line, None, surfaces.sinusoid(line, 0.01), \
            dict(mean_pressure=p)
    sq = Cell(1.0, 1.0, 256, 256)
    for p in (1e-3, 1e-2):
        yield f"bi-sinusoid 256², p̄ = {p:g}", sq, None, surfaces.bisinusoid(sq, 0.01), \
            dict(mean_pressure=p)
    h = surfaces.self_affine(sq, 0.8, rolloff=2 * np.pi * 4, cutoff=2 * np.pi / (8 * sq.hx),
                             rms_slope=0.1, seed=3)
    for lay in (layers.GluedLayer(0.01), layers.GluedLayer(1e-4)):
        for p in (4e-3, 4e-2):
            yield f"rough 256² on a glued layer d = {lay.d:g}, p̄ = {p:g}", sq, lay, h, \
                dict(mean_pressure=p)
    yield "rough 256² on a layer under pressure (A.5) d = 0.01, p̄ = 0.004", sq, \
        layers.PressureLayer(0.01), h, dict(mean_pressure=4e-3, maxiter=3000)


def main(argv=None):
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter
                            ).parse_args(argv)
    rows, ops = [], {}
    totals = {"join": 0, "descent": 0}
    for name, cell, layer, h, control in cases():
        key = (cell.shape, cell.Ly, layer)
        if key not in ops:
            ops[key] = SpectralOperator(cell, Elastic(1.0, 0.3), layer)
        res = {}
        for rule in ("join", "descent"):
            t0 = time.process_time()
            r = polonsky_keer(ops[key], h, tol=1e-10, restart=rule, **control)
            res[rule] = (r.pressure, r.iterations, r.converged, time.process_time() - t0)
        (pj, ij, cj, tj), (pd, id_, cd, td) = res["join"], res["descent"]
        if cj and cd:
            totals["join"] += ij
            totals["descent"] += id_
        diff = int(np.sum((pj > 0) != (pd > 0)))
        dp = float(np.linalg.norm(pj - pd) / max(np.linalg.norm(pj), 1e-300))
        status = "" if cj and cd else " (not converged)"
        rows.append(f"| {name}{status} | {float(np.mean(pd > 0)):.3f} | {ij} | {id_} | "
                    f"{id_ / ij:.2f} | {tj:.2f} / {td:.2f} | {diff} | {dp:.1e} |")
        print(rows[-1], flush=True)
    table = "\n".join([
        "| case | contact fraction | iterations, PK's rule | iterations, ours | ratio |"
        " CPU s (PK / ours) | set diff | Δp |",
        "|---|---|---|---|---|---|---|---|", *rows])
    summary = (f"All converged cases: {totals['join']} iterations with PK's rule, "
               f"{totals['descent']} with ours "
               f"({1 - totals['descent'] / totals['join']:.0%} fewer).")
    print(summary)
    write_section("pk_restart", f"Measured {time.strftime('%Y-%m-%d')} with "
                  f"`python bench/pk_restart.py` (one thread, tol 1e-10, single runs: the "
                  f"times are ±20 %).\n\n{table}\n\n{summary}")


if __name__ == "__main__":
    main()
