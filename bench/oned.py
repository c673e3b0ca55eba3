"""``make bench``: the 1D method's speed (issue: the seed's 1D method).

β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01 at the default modes M and kernel nodes Q (which meet
the 1e-4 mesh convergence of docs/oned.md, ``python cases/oned_convergence.py``): wall seconds
of one point from a cold start (the elastic guess), with and without the adhesiveless
reference state that ``solve`` adds by default — the fastest of ``--repeats`` runs, one
thread — and the 40-point ζ sweep from 1e-3 to 1e2 with continuation (``sinusoid1d.sweep``,
one process).  Targets: one point under 1 s, the sweep under 60 s.

Writes bench/oned.json and the <!-- bench:oned --> table of docs/performance.md.
Usage: python bench/oned.py [--repeats 3]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

from spectralbem import sinusoid1d as s1  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
ZETAS = (1e-3, 2e-3, 3e-3, 5e-3, 1e-2, 0.1, 1.0, 10.0, 100.0)
ARGS = dict(beta=10.0, Gamma=0.008, p_tilde=0.15, a0_tilde=0.01)


def timed(k, **kw):
    best, ds = np.inf, None
    for _ in range(k):
        t = time.perf_counter()
        ds = s1.solve(**kw)
        best = min(best, time.perf_counter() - t)
    return best, ds


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    s1.solve(0.1, **ARGS)  # compile/load the numba loops outside the timings
    rows = []
    for zeta in ZETAS:
        t_ref, ds = timed(args.repeats, zeta=zeta, **ARGS)
        t_adh, _ = timed(args.repeats, zeta=zeta, adhesiveless_reference=False, **ARGS)
        rows.append(dict(zeta=zeta, M=int(ds.attrs["modes"]), Q=int(ds.attrs["quad"]),
                         seconds=t_ref, seconds_adhesive_only=t_adh,
                         status=str(ds["status"].item()), a_tilde=float(ds["a_tilde"])))
        print(json.dumps(rows[-1]), flush=True)
    t = time.perf_counter()
    sw = s1.sweep(np.logspace(-3, 2, 40), 10.0, 0.008, p_tilde=0.15, a0_tilde=0.01)
    sweep_s = time.perf_counter() - t
    n_partial = int(np.sum(sw["status"].values == "partial"))
    print(f"40-point sweep: {sweep_s:.1f} s, {n_partial} partial", flush=True)
    out = dict(points=rows, sweep_seconds=sweep_s, sweep_partial=n_partial)
    (ROOT / "bench" / "oned.json").write_text(json.dumps(out, indent=1))
    lines = [f"Measured {time.strftime('%Y-%m-%d')} with `python bench/oned.py` (part of "
             f"`make bench`), one thread, fastest of {args.repeats} cold-start runs.", "",
             "| ζ | M | Q | s per point (with adhesiveless reference) | s (adhesive only) |"
             " status |", "|---|---|---|---|---|---|"]
    lines += [f"| {r['zeta']:g} | {r['M']} | {r['Q']} | {r['seconds']:.2f} | "
              f"{r['seconds_adhesive_only']:.2f} | {r['status']} |" for r in rows]
    lines += ["", f"40-point ζ sweep 1e-3…1e2 with continuation (and the reference): "
                  f"{sweep_s:.1f} s, {n_partial}/40 partial."]
    write_section("oned", "\n".join(lines))


if __name__ == "__main__":
    main()
