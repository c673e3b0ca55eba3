"""Mesh convergence of the 1D method at fixed a0 (table for docs/oned.md).

For β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01 and several ζ: ã, ẽ, G1/Δγ, G2/Δγ, μ̄ at the
default Chebyshev modes M and kernel nodes Q, and with both raised to 1.5× and 2×, with the
largest relative change (ẽ relative to max(|ẽ|, 0.01 ã)) over these and the adhesiveless
ã, ẽ, μ̄ that ``solve`` reports at the same load.
Usage: python cases/oned_convergence.py  (prints a Markdown table)
"""

import time

import numpy as np

from spectralbem import sinusoid1d as s1

KEYS = ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar",
        "a_tilde_adhesiveless", "e_tilde_adhesiveless", "mu_bar_adhesiveless")


def main():
    print("| ζ | M, Q (default) | ã | ẽ | G1/Δγ | G2/Δγ | μ̄ | max rel. difference from "
          "(2M, 2Q): of (M, Q), of (1.5M, 1.5Q) | s per point |")
    print("|---|---|---|---|---|---|---|---|---|")
    for zeta in (1e-3, 2e-3, 3e-3, 5e-3, 1e-2, 0.1, 1.0, 10.0, 100.0):
        pr = s1.dimensionless_problem(zeta, 10.0, 0.008, 0.01)
        M, Q = pr.M, pr.Q
        rows = []
        for f in (1.0, 1.5, 2.0):
            t = time.perf_counter()
            ds = s1.solve(zeta, 10.0, 0.008, p_tilde=0.15, a0_tilde=0.01, modes=int(f * M),
                          quad=int(f * Q))
            rows.append([ds[k].item() for k in KEYS] + [time.perf_counter() - t])
        r = np.array(rows)
        n = len(KEYS)
        ref = r[2, :n]
        # ẽ relative to ã when small (both states)
        scale = np.maximum(np.abs(ref), 1e-2 * np.abs(r[2, [0, 0, 0, 0, 0, 5, 5, 5]]))
        change = np.max(np.abs(r[:2, :n] - ref) / scale, axis=1)
        print(f"| {zeta:g} | {M}, {Q} | {r[0, 0]:.6f} | {r[0, 1]:.6f} | {r[0, 2]:.5f} | "
              f"{r[0, 3]:.5f} | {r[0, 4]:.5f} | {change[0]:.1e}, {change[1]:.1e} | "
              f"{r[0, n]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
