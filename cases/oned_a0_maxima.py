"""Where the toughness and the adhesive strength peak in ζ, against the advance width a0
(the seed's claim on the maxima against a0; table for docs/oned.md).

β = 10, Γ = 0.008: T̃ (Eq. 24) and |p̃_out| (the fixed-Δ pull-off) from
``sinusoid1d.special_points`` (n = 16, cheb = 8) for ã0 = 1e-2 … 1e-5 and the strict limit
ã0 = 0 (glassy tip), on a ζ grid; the largest value of each row is in bold.
Usage: python cases/oned_a0_maxima.py  (prints two Markdown tables, about 3 min)
"""

import numpy as np

from spectralbem import sinusoid1d as s1

ZETAS = (0.0, 1e-3, 1e-2, 3e-2, 5e-2, 0.1, 0.3, 1.0, 10.0)
A0S = (1e-2, 1e-3, 1e-4, 1e-5, 0.0)


def row(values):
    i = int(np.nanargmax(values))
    return " | ".join(f"**{v:.4f}**" if j == i else f"{v:.4f}" for j, v in enumerate(values))


def main():
    head = "| ã0 | " + " | ".join(f"ζ = {z:g}" for z in ZETAS) + " |"
    rule = "|---" * (len(ZETAS) + 1) + "|"
    tables = {"T̃ (Eq. 24)": [], "|p̃_out| (fixed Δ)": []}
    for a0 in A0S:
        sp = [s1.special_points(z, 10.0, 0.008, a0_tilde=a0, n=16, cheb=8) for z in ZETAS]
        tables["T̃ (Eq. 24)"].append((a0, [p["T"] for p in sp]))
        tables["|p̃_out| (fixed Δ)"].append((a0, [abs(p["p_dmin"]) for p in sp]))
        print(f"ã0 = {a0:g} done", flush=True)
    for name, rows in tables.items():
        print(f"\n{name}\n\n{head}\n{rule}")
        for a0, vals in rows:
            print(f"| {a0:g} | {row(vals)} |")


if __name__ == "__main__":
    main()
