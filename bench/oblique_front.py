"""A straight viscoelastic front at 45° to the grid against the 1D method: the seed sinusoid
h = cos((x + y)/√2) on a (2π√2)² periodic cell (the seed's units: wavelength 2π, E* = 1,
p* = 1/2), sliding along its wave vector, β = 10, Γ = 0.008, p̃∞ = 0.15, with a0 and ζ
such that vτ = 1.28 a0 (ζ = 1.28 ã0), at a0 = 2 and 4 cells along the axes.  The front is
straight, so the 1D method at the same ζ, β, Γ, p̃, ã0 is its exact answer; its digital
staircase is what a curved front has on its oblique parts.  Writes the table between
<!-- bench:oblique_front --> markers in docs/performance.md and bench/oblique_front.json.

Usage: python bench/oblique_front.py [--a0 0.05] [--cells 2 4] [--slope 1] [--out F]
``--slope q`` turns the front's normal to (1, q) (71.6° for 3) on a q Ly × Ly cell (0: the
y-invariant front, on an N × 2 grid); a run
with ``--out`` elsewhere prints its table instead of writing docs/performance.md's.
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

import spectralbem.adhesive as ad  # noqa: E402
from spectralbem import oned  # noqa: E402
from spectralbem.front import front_outputs  # noqa: E402
from spectralbem.oned.branches import dimensionless_material  # noqa: E402
from spectralbem.spectral import Cell, SpectralOperator  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

BETA, GAMMA, P_TILDE = 10.0, 0.008, 0.15
OUT = Path(__file__).with_name("oblique_front.json")
KEYS = (("a_tilde", "ã"), ("G1_over_dgamma", "G1/Δγ"), ("G2_over_dgamma", "G2/Δγ"))


def run(a0: float, cells: int, ref, slope: int = 1) -> dict:
    """One 2D state: the front's normal along (1, ``slope``) (45° for 1), on a cell of
    ``slope`` Ly × Ly with one wavelength along each side (|k| = 1) and square cells, a0 =
    ``cells`` cells; ``slope`` 0: the y-invariant front on an N × 2 grid."""
    zeta = 1.28 * a0
    mat, v = dimensionless_material(zeta, BETA)
    if slope == 0:
        n = 2
        nx = int(round(2 * np.pi * cells / a0))
        cell = Cell(2 * np.pi, 2 * np.pi * n / nx, nx, n)
        k = np.array([1.0, 0.0])
    else:
        Ly = 2 * np.pi * np.hypot(1.0, 1.0 / slope)
        n = int(round(Ly * cells / a0))
        cell = Cell(slope * Ly, Ly, slope * n, n)
        k = np.array([2 * np.pi / cell.Lx, 2 * np.pi / Ly])  # |k| = 1
    X, Y = cell.coordinates()
    op = SpectralOperator(cell, mat, velocity=tuple(v * k))
    dg = np.pi * GAMMA
    t = time.process_time()
    r = ad.solve_adhesive(op, np.cos(k[0] * X + k[1] * Y), dg, a0,
                          mean_pressure=0.5 * P_TILDE)
    cpu = time.process_time() - t
    fo = front_outputs(op, r, dg)
    got = {"a_tilde": np.pi * fo["area_fraction"], "G1_over_dgamma": fo["G1"] / dg,
           "G2_over_dgamma": fo["G2"] / dg}
    row = dict(a0_tilde=a0, zeta=zeta, cells=cells, N=n, Nx=cell.Nx, slope=slope,
               status=r.status, iterations=r.iterations, cpu=cpu)
    for k, _ in KEYS:
        row[k] = (got[k], float(ref[k]), got[k] / float(ref[k]) - 1)
    return row


def markdown(rows) -> str:
    head = ("| ã0 | ζ | a0/h | grid | status | "
            + " | ".join(f"{lab} (2D, 1D, rel.)" for _, lab in KEYS)
            + " | outer | CPU s |\n|" + "---|" * (7 + len(KEYS)))
    lines = [f"| {r['a0_tilde']:g} | {r['zeta']:.3g} | {r['cells']} | "
             f"{r.get('Nx', r['N'])}×{r['N']} | "
             f"{r['status']} | "
             + " | ".join(f"{r[k][0]:.4f}, {r[k][1]:.4f}, {100 * r[k][2]:+.2f} %"
                          for k, _ in KEYS)
             + f" | {r['iterations']} | {r['cpu']:.0f} |" for r in rows]
    return head + "\n" + "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a0", type=float, default=0.05, help="ã0 = k a0 (default 0.05)")
    ap.add_argument("--cells", type=int, nargs="+", default=[2, 4],
                    help="a0 in cells along the axes (default 2 4)")
    ap.add_argument("--slope", type=int, default=1,
                    help="the front's normal along (1, slope) (default 1: 45°; 0: along x)")
    ap.add_argument("--out", type=Path, default=OUT,
                    help="JSON of the rows (docs/performance.md's table only from the default)")
    a = ap.parse_args(argv)
    ref = oned.solve(1.28 * a.a0, BETA, GAMMA, p_tilde=P_TILDE, a0_tilde=a.a0,
                     adhesiveless_reference=False)
    rows = []
    for c in a.cells:
        rows.append(run(a.a0, c, ref, a.slope))
        print(json.dumps(rows[-1]), flush=True)
        a.out.write_text(json.dumps(rows, indent=1))  # every finished size is kept
    if a.out.resolve() != OUT.resolve():
        print(markdown(rows))
        return
    write_section("oblique_front", f"Measured {time.strftime('%Y-%m-%d')} with "
                  f"`python bench/oblique_front.py --a0 {a.a0:g} --cells "
                  f"{' '.join(map(str, a.cells))}"
                  + (f" --slope {a.slope}" if a.slope != 1 else "")
                  + "` (one thread):\n\n" + markdown(rows))


if __name__ == "__main__":
    main()
