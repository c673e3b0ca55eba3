"""Benchmark of the viscoelastic adhesiveless rough solve against the elastic PK solve of the
same surface and load (issue: fast viscoelastic and adhesive solves, target ≤ 3×).

Surface: the self-affine surface of bench/run.py (L = 1, Hurst 0.8, rms slope 0.1, roll-off
L/4, cut-off 8 cells), E0 = 1, ν = 0.5, p̄ = 0.01 E0 (the issue's 1e4 Pa on 1 MPa); sliding
standard linear solid β = 10, τ = 1, ζ = 2π v τ / λ_r = 0.1 at the roll-off.  Reference: PK on
the elastic slab E = E0, timed in the same run.  CPU seconds of the solve (planning and
kernels built outside), fastest of k runs, one thread.  At N ≤ 512 the candidates too:

* ``splitting`` — PK on the even part C^E with the odd part lagged, p ← PK_E(h − C^O p),
  until p changes by < 1e-8 (60 sweeps at most);
* ``active set`` — exact masked solves (scipy BiCGSTAB/GMRES, two per step under load
  control), elastic E0 start: the method before this benchmark;
* ``newton, exact`` — the semismooth Newton steps with every solve to 1e-10;
* ``newton, E0 start`` — the default but started from PK on the relaxed elastic kernel;
* ``newton`` — the default (even-part start, inexact solves, one projected solve per step).

Also the peak memory of the default solve (numpy allocations, tracemalloc) in N² float64
arrays.  Writes the table between <!-- bench:visco_rough --> markers in docs/performance.md
and the rows to bench/viscoelastic.json.

Usage: python bench/viscoelastic.py [--sizes 256 512 1024 2048] [--runs 3]
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

import numpy as np  # noqa: E402

from spectralbem import __version__, newton  # noqa: E402
from spectralbem.contact import active_set, polonsky_keer  # noqa: E402
from spectralbem.materials import Elastic, StandardLinearSolid  # noqa: E402
from spectralbem.spectral import SpectralOperator  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import fft_pair_seconds, surface, write_section  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
PBAR = 0.01
ZETA = 0.1
TOL = 1e-10


def operators(n):
    cell, h = surface(n)
    v = ZETA * (cell.Lx / 4) / (2 * np.pi)  # ζ = 2π v τ / λ_r, λ_r = L/4, τ = 1
    visco = SpectralOperator(cell, StandardLinearSolid(1.0, 10.0, 1.0, 0.5), velocity=(v, 0.0))
    elastic = SpectralOperator(cell, Elastic(1.0, 0.5))
    visco.apply(h)  # plans the transforms (shared plan per shape)
    return h, visco, elastic


def timed(fn, runs):
    best = None
    for _ in range(max(1, runs)):
        t = time.process_time()
        out = fn()
        dt = time.process_time() - t
        if best is None or dt < best[0]:
            best = (dt, out)
    return best


def candidates(h, visco):
    def relaxed_start():
        op = SpectralOperator(visco.cell, Elastic(1.0, 0.5))
        p, *_rest, pairs = polonsky_keer(op, h, mean_pressure=PBAR, tol=newton.START_TOL)
        r = newton.newton_contact(visco, h, mean_pressure=PBAR, tol=TOL, mask0=p > 0, p0=p)
        return r[:8] + (r[8] + pairs,)

    def splitting(maxit=60):
        """PK on C^E with the odd part lagged: p ← PK_E(h − C^O p)."""
        even = visco.even_part()
        p = np.zeros(h.shape)
        pairs = sweeps = 0
        ok = False
        while sweeps < maxit:
            sweeps += 1
            r = polonsky_keer(even, h - visco.apply_odd(p), mean_pressure=PBAR, tol=TOL, p0=p)
            pairs += r[6] + 1
            change = np.linalg.norm(r[0] - p) / np.linalg.norm(r[0])
            p = r[0]
            if change < 1e-8:
                ok = True
                break
        return p, None, r[2], p > 0, sweeps, ok, f"change {change:.1e}", sweeps, pairs

    return {
        "active set": lambda: active_set(visco, h, mean_pressure=PBAR, tol=TOL) + (np.nan,),
        "splitting": splitting,
        "newton, exact": lambda: newton.newton_contact(visco, h, mean_pressure=PBAR, tol=TOL,
                                                       loose=TOL),
        "newton, E0 start": relaxed_start,
        "newton": lambda: newton.newton_contact(visco, h, mean_pressure=PBAR, tol=TOL),
    }


def peak_arrays(fn, n) -> float:
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / (8.0 * n * n)


def run_size(n, runs):
    h, visco, elastic = operators(n)
    k = runs if n <= 1024 else 1
    pair = fft_pair_seconds(n)
    t_el, r_el = timed(lambda: polonsky_keer(elastic, h, mean_pressure=PBAR, tol=TOL), k)
    rows = []
    cands = candidates(h, visco)
    names = [m for m in cands if n <= 256 or (n <= 512 and m != "splitting") or m == "newton"]
    ref = None
    for name in names:
        t, r = timed(cands[name], 1 if name in ("active set", "splitting") else k)
        if name == "active set":
            ref = r
        row = dict(N=n, method=name, seconds=t, elastic_seconds=t_el, ratio=t / t_el,
                   elastic_iterations=r_el[3], elastic_pairs=r_el[6], pair_ms=1e3 * pair,
                   converged=bool(r[5]), products=int(r[4]), outer=int(r[7]),
                   pairs=float(r[8]), area=float(np.mean(r[3])))
        if ref is not None and name != "active set":
            row["set_diff"] = int(np.count_nonzero(ref[3] != r[3]))
            row["p_rel"] = float(np.linalg.norm(ref[0] - r[0]) / np.linalg.norm(ref[0]))
        if name == "newton" and n <= 1024:
            row["peak_arrays"] = peak_arrays(cands[name], n)
        rows.append(row)
        print(json.dumps(row), flush=True)
    return rows


def markdown(rows) -> str:
    head = ("| N² | method | s | elastic PK (s) | ratio | FFT pairs | pairs / elastic's | "
            "products | outer | area | set diff / p rel. vs active set | peak (N² arrays) |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|")
    lines = []
    for r in rows:
        pairs = "—" if not np.isfinite(r["pairs"]) else f"{r['pairs']:.0f}"
        rel = "—" if not np.isfinite(r["pairs"]) else f"{r['pairs'] / r['elastic_pairs']:.2f}"
        cmp_ = (f"{r['set_diff']} / {r['p_rel']:.1e}" if "set_diff" in r else "—")
        peak = f"{r['peak_arrays']:.1f}" if "peak_arrays" in r else "—"
        ok = "" if r["converged"] else " (not converged)"
        lines.append(f"| {r['N']}² | {r['method']}{ok} | {r['seconds']:.3f} | "
                     f"{r['elastic_seconds']:.3f} | **{r['ratio']:.2f}×** | {pairs} | {rel} | "
                     f"{r['products']} | {r['outer']} | {r['area']:.4f} | {cmp_} | {peak} |")
    return head + "\n" + "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024, 2048])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "bench" / "viscoelastic.json"))
    a = ap.parse_args(argv)
    rows = []
    for n in a.sizes:
        rows += run_size(n, a.runs)
        Path(a.out).write_text(json.dumps(rows, indent=1))  # every finished size is kept
    meta = (f"Measured {time.strftime('%Y-%m-%d')} with `python bench/viscoelastic.py "
            f"--sizes {' '.join(map(str, a.sizes))}` (spectralbem {__version__}, one thread, "
            f"CPU seconds, fastest of {a.runs} up to 1024², one run of the active set and at "
            "2048²; the elastic PK reference timed alike in the same run):")
    write_section("visco_rough", meta + "\n\n" + markdown(rows))


if __name__ == "__main__":
    main()
