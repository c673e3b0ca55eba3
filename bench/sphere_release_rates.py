"""Grid refinement of the release rates on a curved viscoelastic front: the sliding sphere of
bench/sphere.py (L = R = E0 = 1, β = 10, τ = 1, v = 0.1 a_J, zero mean pressure) with the
advance width a0 fixed in length (2 cells of the 256² grid, 0.0078 L) while N grows, so
that a0/h and vτ/h grow with N (2, 4, 8 and 2.6, 5.1, 10.2 at 256², 512², 1024²).  The
continuum problem is the same at every N: area, G1, G2 and the release rate along the front
(means over 30° sectors of the outer front cells' G, the angle measured from the sliding
direction) should stop moving.  Writes the table between <!-- bench:sphere_release_rates -->
markers in docs/performance.md and bench/sphere_release_rates.json.

Usage: python bench/sphere_release_rates.py [--sizes N ...] [--delayed-kernel cell|sampled]
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
from spectralbem.front import front_outputs  # noqa: E402
from spectralbem.keys import DELAYED, DELAYED_DEFAULT  # noqa: E402
from spectralbem.spectral import SpectralOperator  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402
from sphere import A_J, sphere_scene  # noqa: E402

A0 = 2.0 / 256  # the advance width (units of L), fixed
SECTORS = np.arange(-180, 181, 30)


def run(n: int, delayed: str) -> dict:
    cell, op, h, w, mask0 = sphere_scene(n)
    op = SpectralOperator(op.cell, op.material, op.layer, op.velocity, delayed=delayed)
    t = time.process_time()
    r = ad.solve_adhesive(op, h, w, A0, mean_pressure=0.0, mask0=mask0)
    cpu = time.process_time() - t
    fo = front_outputs(op, r, w)
    G = fo["G_map"]
    X, Y = cell.coordinates()
    c = n // 2 * cell.hx
    theta = np.degrees(np.arctan2(Y - c, X - c))
    ok = np.isfinite(G)
    prof = [float(np.mean(G[sel])) if (sel := ok & (theta >= lo) & (theta < hi)).any()
            else float("nan") for lo, hi in zip(SECTORS[:-1], SECTORS[1:], strict=True)]
    # the scene is symmetric about the sliding axis: G(θ) = G(−θ) in the continuum
    asym = max(abs(prof[k] - prof[-1 - k]) for k in range(len(prof) // 2))
    return dict(N=n, delayed_kernel=delayed, a0_cells=A0 * n, vtau_cells=0.1 * A_J * n,
                status=r.status, area=fo["area_fraction"], G1=fo["G1"] / w, G2=fo["G2"] / w,
                sectors=prof, asymmetry=asym, iterations=r.iterations, cpu=cpu)


def markdown(rows) -> str:
    head = ("| kernel | N² | a0/h | vτ/h | status | area | G1/Δγ | G2/Δγ | G/Δγ by sector, "
            "from −180° (trailing) to +180°, 30° each | largest G(θ) − G(−θ) | outer | CPU s |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|")
    lines = [f"| {r['delayed_kernel']} | {r['N']}² | {r['a0_cells']:.0f} | {r['vtau_cells']:.1f} | "
             f"{r['status']} | {r['area']:.5f} | {r['G1']:.3f} | {r['G2']:.3f} | "
             + " ".join(f"{g:.2f}" for g in r["sectors"])
             + f" | {r['asymmetry']:.2f} | {r['iterations']} | {r['cpu']:.0f} |" for r in rows]
    return head + "\n" + "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024])
    ap.add_argument("--delayed-kernel", nargs="+", default=[DELAYED_DEFAULT], choices=DELAYED)
    a = ap.parse_args(argv)
    out = Path(__file__).with_name("sphere_release_rates.json")
    rows = []
    for dk in a.delayed_kernel:
        for n in a.sizes:
            rows.append(run(n, dk))
            print(json.dumps(rows[-1]), flush=True)
            out.write_text(json.dumps(rows, indent=1))  # every finished size is kept
    write_section("sphere_release_rates", f"Measured {time.strftime('%Y-%m-%d')} with "
                  f"`python bench/sphere_release_rates.py --sizes {' '.join(map(str, a.sizes))}"
                  f" --delayed-kernel {' '.join(a.delayed_kernel)}` (one thread):\n\n"
                  + markdown(rows))


if __name__ == "__main__":
    main()
