"""How many cells the relaxation length vτ needs: the 2D adhesive solver against the 1D method.

The y-invariant sinusoid (β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = k a0 = 0.01, N × 2 grid) is
solved at ζ = k v τ = 0.02, 0.005 and 0.001 (a0 = vτ/2, 2 vτ and 10 vτ) on grids of N cells
per wavelength, so that vτ/h = ζ N / 2π and a0/h = 0.01 N / 2π vary separately; each state is
compared with the seed's 1D method at the same a0 (errors in ã, G1, G2, μ̄ and the adhesive
friction μ̄_a, which is proportional to G1 − G2).  Writes bench/relaxation_length.json,
docs/figures/relaxation_length.png and the table of docs/performance.md ("Resolving the
relaxation length").  Every finished point is kept in the JSON as it is measured.

Usage: python bench/relaxation_length.py [--report-only]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import itertools  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from spectralbem.keys import DELAYED  # noqa: E402
from spectralbem.validate import A0, compare  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import write_section  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "bench" / "relaxation_length.json"
P_TILDE = 0.15
KEYS = ("a_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar", "mu_bar_adhesive")
#: ζ → cells per wavelength (a0 at least one cell: N ≥ 629)
PLAN = {0.02: (629, 942, 1257, 2513, 5027),
        0.005: (629, 1257, 2513, 3770, 5027, 7540, 10053),
        0.001: (3000, 5027, 10053, 20106, 31416)}


def point(zeta: float, n: int, delayed: str = "sampled") -> dict:
    # the 2D state against the 1D method
    r = compare(zeta, P_TILDE, n=n, keys=KEYS, solver={"delayed_kernel": delayed})
    return {"zeta": zeta, "N": n, "delayed_kernel": delayed,
            "vtau_over_h": zeta * n / (2 * np.pi),
            "a0_over_h": A0 * n / (2 * np.pi), "status": r["status"],
            "seconds": r["time_2d"], **{k: list(r[k]) for k in KEYS}}


def _kind(r: dict) -> str:
    return r.get("delayed_kernel", "sampled")


def report(rows: list) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), constrained_layout=True)
    for (z, col), (dk, style) in itertools.product(
            zip(PLAN, ("C0", "C1", "C2"), strict=True), (("sampled", "o-"), ("cell", "s--"))):
        rr = sorted((r for r in rows if r["zeta"] == z and _kind(r) == dk),
                    key=lambda r: r["N"])
        if not rr:
            continue
        x = np.array([r["vtau_over_h"] for r in rr])
        for ax, k in zip(axes, ("mu_bar_adhesive", "G2_over_dgamma"), strict=True):
            e = np.array([max(abs(r[k][2]), 1e-5) for r in rr])
            ax.loglog(x, e, style, color=col,
                      label=f"ζ = {z:g} (a0 = {A0 / z:g} vτ), {dk}")
    for ax, name in zip(axes, ("μ̄_a (adhesive friction)", "G2/Δγ (trailing edge)"),
                        strict=True):
        for lev in (0.05, 0.02):
            ax.axhline(lev, color="0.6", ls=":")
        ax.set_xlabel("cells per relaxation length, vτ/h")
        ax.set_ylabel(f"|relative error| of {name}")
        ax.legend(fontsize=8)
    fig.suptitle("2D solver against the 1D method: y-invariant sinusoid, β = 10, p̃∞ = 0.15, "
                 "ã0 = 0.01 (dotted: 5 % and 2 %; dashed: delayed kernel averaged over the "
                 "cells)", fontsize=9)
    fig.savefig(ROOT / "docs" / "figures" / "relaxation_length.png", dpi=120)
    lines = ["| ζ | N | vτ/h | a0/h | delayed kernel | status | ã | G1 | G2 | μ̄ | μ̄_a | s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: (-r["zeta"], r["N"], _kind(r) == "cell")):
        lines.append(f"| {r['zeta']:g} | {r['N']} | {r['vtau_over_h']:.2f} | "
                     f"{r['a0_over_h']:.2f} | {_kind(r)} | {r['status']} | "
                     + " | ".join(f"{100 * r[k][2]:+.2f} %" for k in KEYS)
                     + f" | {r['seconds']:.1f} |")
    write_section("relaxation_length", f"Measured {time.strftime('%Y-%m-%d')} with `python "
                  "bench/relaxation_length.py` (one thread, wall seconds of the 2D solve; "
                  "signed errors (2D − 1D)/|1D|; [figure](figures/relaxation_length.png)):"
                  "\n\n" + "\n".join(lines))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--report-only", action="store_true",
                    help="redraw the figure and table from bench/relaxation_length.json")
    ap.add_argument("--delayed-kernel", nargs="+", default=list(DELAYED), choices=DELAYED,
                    help="solver.delayed_kernel values to run (rows of the others are kept)")
    args = ap.parse_args(argv)
    if args.report_only:
        report(json.loads(OUT.read_text()))
        return
    rows = [r for r in (json.loads(OUT.read_text()) if OUT.exists() else [])
            if _kind(r) not in args.delayed_kernel]
    for dk, (z, ns) in itertools.product(args.delayed_kernel, PLAN.items()):
        for n in ns:
            r = point(z, n, dk)
            rows.append(r)
            OUT.write_text(json.dumps(rows, indent=1))  # every finished point is kept
            print(f"{dk:7s} ζ {z:g} N {n:6d} vτ/h {r['vtau_over_h']:5.2f} {r['status']:13s} "
                  + " ".join(f"{k[:5]} {100 * r[k][2]:+6.2f}%" for k in KEYS)
                  + f"  {r['seconds']:.1f} s", flush=True)
    report(rows)


if __name__ == "__main__":
    main()
