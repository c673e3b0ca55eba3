"""Mesh convergence of the 1D method at fixed a0 (table for docs/oned.md).

For β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01 and several ζ: ã, ẽ, G1/Δγ, G2/Δγ at the
default number of Chebyshev modes M and at 1.5 M and 2 M, with the largest relative change.
Usage: python cases/oned_convergence.py  (prints a Markdown table)
"""

import time

import numpy as np

from spectralbem import sinusoid1d as s1

KEYS = ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma")


def main():
    print("| ζ | M (default) | ã | ẽ | G1/Δγ | G2/Δγ | max rel. change to 1.5M, 2M | "
          "s per point |")
    print("|---|---|---|---|---|---|---|---|")
    for zeta in (1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0):
        M = s1.dimensionless_problem(zeta, 10.0, 0.008, 0.01).M
        rows = []
        for m in (M, int(1.5 * M), 2 * M):
            t = time.perf_counter()
            ds = s1.solve(zeta, 10.0, 0.008, p_tilde=0.15, a0_tilde=0.01, modes=m,
                          adhesiveless_reference=False)
            rows.append([ds[k].item() for k in KEYS] + [time.perf_counter() - t])
        r = np.array(rows)
        ref = r[2, :4]
        scale = np.maximum(np.abs(ref), 1e-2 * np.abs(r[2, 0]))  # ẽ relative to ã when small
        change = np.max(np.abs(r[:2, :4] - ref) / scale, axis=1)
        print(f"| {zeta:g} | {M} | {r[0, 0]:.6f} | {r[0, 1]:.6f} | {r[0, 2]:.5f} | "
              f"{r[0, 3]:.5f} | {change[0]:.1e}, {change[1]:.1e} | {r[0, 4]:.2f} |")


if __name__ == "__main__":
    main()
