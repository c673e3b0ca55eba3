"""Regenerate the seed paper's Figs. 3, 5, 6, 7, 8, 9, 11, 12 and 13 with the 1D method.

Run by ``make figures``; writes PNGs to docs/figures/ (and the curve data to
docs/figures/oned_curves.nc).  Every figure states the advance width a0 (k a0 = ã0) of the
edge energy balance; the seed does not state its own, so the curves
are comparable to the paper's qualitatively.  Curves run in parallel (one process per core).

Usage: python cases/figures_1d.py [--quick] [--only 3 6 ...]
"""

from __future__ import annotations

import argparse
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from spectralbem import sinusoid1d as s1  # noqa: E402

OUT = Path(__file__).resolve().parent.parent / "docs" / "figures"
BETA, GAMMA, A0 = 10.0, 0.008, 0.01


def zeta_grid(quick):
    return np.logspace(-3, 2, 11 if quick else 26)


def curve(args):
    """One ζ sweep (continuation) -> dict of arrays."""
    zetas, beta, Gamma, a0, control, value = args
    kw = {control: value}
    ds = s1.sweep(zetas, beta, Gamma, a0_tilde=a0, **kw)
    return {v: ds[v].values for v in ds.data_vars if v != "status"} | {"zeta": zetas}


def run_curves(jobs):
    with ProcessPoolExecutor(max_workers=min(len(jobs), os.cpu_count() or 1)) as ex:
        return list(ex.map(curve, jobs))


def stamp(fig, text):
    """The figure's parameters (a0 among them) as a small title, clear of the axis labels."""
    fig.suptitle(text, fontsize=9, color="0.35")


def fig3(quick):
    z = zeta_grid(quick)
    loads, deltas = (0.05, 0.15, 0.3), (0.2, 0.5, 0.8)
    res = run_curves([(z, BETA, GAMMA, A0, "p_tilde", p) for p in loads]
                     + [(z, BETA, GAMMA, A0, "delta_tilde", d) for d in deltas])
    fig, ax = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True, sharex=True)
    for i, p in enumerate(loads):
        r = res[i]
        ax[0, 0].semilogx(z, r["a_tilde"], f"C{i}-", label=f"p̃∞ = {p}")
        ax[0, 0].semilogx(z, r["a_tilde_adhesiveless"], f"C{i}--")
        ax[1, 0].semilogx(z, r["e_tilde"], f"C{i}-")
        ax[1, 0].semilogx(z, r["e_tilde_adhesiveless"], f"C{i}--")
    for i, d in enumerate(deltas):
        r = res[len(loads) + i]
        ax[0, 1].semilogx(z, r["a_tilde"], f"C{i}-", label=f"Δ̃ = {d}")
        ax[1, 1].semilogx(z, r["e_tilde"], f"C{i}-")
    ax[0, 0].set_ylabel("ã")
    ax[1, 0].set_ylabel("ẽ")
    for a in ax[1]:
        a.set_xlabel("ζ")
    ax[0, 0].legend()
    ax[0, 1].legend()
    ax[0, 0].set_title("(a) load control (dashed: adhesiveless)")
    ax[0, 1].set_title("(b) displacement control")
    stamp(fig, f"Fig. 3 — β = {BETA:g}, Γ = {GAMMA}, ã0 = k a0 = {A0}")
    fig.savefig(OUT / "fig03_contact_size.png", dpi=110)
    return res


def fig5(quick):
    z = zeta_grid(quick)
    gammas = (0.002, 0.008, 0.016)
    res = run_curves([(z, BETA, g, A0, "p_tilde", 0.15) for g in gammas])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, g in enumerate(gammas):
        ax[0].semilogx(z, res[i]["a_tilde"], f"C{i}-", label=f"Γ = {g}")
        ax[1].semilogx(z, res[i]["e_tilde"], f"C{i}-")
    ax[0].semilogx(z, res[0]["a_tilde_adhesiveless"], "k--", label="adhesiveless")
    ax[0].set_ylabel("ã")
    ax[1].set_ylabel("ẽ")
    for a in ax:
        a.set_xlabel("ζ")
    ax[0].legend()
    stamp(fig, f"Fig. 5 — p̃∞ = 0.15, β = {BETA:g}, ã0 = {A0}")
    fig.savefig(OUT / "fig05_gamma.png", dpi=110)


def fig6(quick):
    z = zeta_grid(quick)
    loads = (-0.02, 0.05, 0.15)  # (0.3 snaps into full contact at intermediate ζ)
    res = run_curves([(z, BETA, GAMMA, A0, "p_tilde", p) for p in loads])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, p in enumerate(loads):
        ax[0].semilogx(z, res[i]["G1_over_dgamma"], f"C{i}-", label=f"p̃∞ = {p}")
        ax[1].semilogx(z, res[i]["G2_over_dgamma"], f"C{i}-")
    ax[0].set_ylabel("G1/Δγ (trailing, opening)")
    ax[1].set_ylabel("G2/Δγ (leading, closing)")
    for a in ax:
        a.set_xlabel("ζ")
        a.axhline(1.0, color="0.6", lw=0.8)
    ax[0].legend()
    stamp(fig, f"Fig. 6 — β = {BETA:g}, Γ = {GAMMA}, ã0 = {A0}")
    fig.savefig(OUT / "fig06_release_rates.png", dpi=110)


def fig7(quick):
    z = zeta_grid(quick)
    betas = (3.0, 10.0, 30.0, 100.0)
    res = run_curves([(z, b, GAMMA, A0, "p_tilde", -0.02) for b in betas])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, b in enumerate(betas):
        ax[0].loglog(z, res[i]["G1_over_dgamma"], f"C{i}-", label=f"β = {b:g}")
        ax[0].axhline(b, color=f"C{i}", lw=0.6, ls=":")
        ax[1].loglog(z, res[i]["G2_over_dgamma"], f"C{i}-")
        ax[1].axhline(1 / b, color=f"C{i}", lw=0.6, ls=":")
    ax[0].set_ylabel("G1/Δγ")
    ax[1].set_ylabel("G2/Δγ")
    for a in ax:
        a.set_xlabel("ζ")
    ax[0].legend()
    stamp(fig, f"Fig. 7 — p̃∞ = -0.02, Γ = {GAMMA}, ã0 = {A0} (dotted: β and 1/β)")
    fig.savefig(OUT / "fig07_beta.png", dpi=110)


def fig8(quick):
    """λ from 10 μm to 1.2 mm at fixed Λ, E0, Δγ: Γ ∝ λ; a fixed physical a0 gives ã0 ∝ 1/λ.
    a0 is set so that ã0 = 0.01 at Γ = 0.008 (λ = 0.8 mm): a0 = 1.27 μm."""
    lams = np.array([10e-6, 100e-6, 400e-6, 1.2e-3])
    gammas = 1e-4 * lams / 10e-6
    a0 = A0 * 0.8e-3 / (2 * np.pi)
    z = zeta_grid(quick)
    res = run_curves([(z, BETA, g, 2 * np.pi * a0 / lam, "p_tilde", 0.0)
                      for g, lam in zip(gammas, lams, strict=True)])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, lam in enumerate(lams):
        vt = z * lam / (2 * np.pi)
        lab = f"λ = {lam * 1e6:g} μm, Γ = {gammas[i]:.2g}"
        ax[0].loglog(vt, res[i]["G1_over_dgamma"], f"C{i}-", label=lab)
        ax[1].loglog(vt, res[i]["G2_over_dgamma"], f"C{i}-")
    for a in ax:
        a.set_xlabel("v τ (m)")
    ax[0].axhline(BETA, color="0.6", ls=":")
    ax[1].axhline(1 / BETA, color="0.6", ls=":")
    ax[0].set_ylabel("G1/Δγ")
    ax[1].set_ylabel("G2/Δγ")
    ax[0].legend(fontsize=8)
    stamp(fig, f"Fig. 8 — p̃∞ = 0 (a contact exists for every Γ), β = {BETA:g}, "
               f"fixed a0 = {a0 * 1e6:.2f} μm")
    fig.savefig(OUT / "fig08_wavelength.png", dpi=110)


def fig9_11(quick):
    z = zeta_grid(quick)
    gammas = (0.0, 0.004, 0.008, 0.016)
    loads, deltas = (0.05, 0.15, 0.3), (0.2, 0.5, 0.8)
    res = run_curves([(z, BETA, g, A0, "p_tilde", 0.15) for g in gammas]
                     + [(z, BETA, GAMMA, A0, "p_tilde", p) for p in loads]
                     + [(z, BETA, GAMMA, A0, "delta_tilde", d) for d in deltas])
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    for i, g in enumerate(gammas):
        ax.loglog(z, res[i]["mu_bar"], f"C{i}-", label=f"μ̄, Γ = {g}")
        if g > 0:
            ax.loglog(z, np.abs(res[i]["mu_bar_adhesive"]), f"C{i}--", lw=0.9)
    ax.set_xlabel("ζ")
    ax.set_ylabel("μ̄ = μ/Λ̃ (dashed: |μ̄_a|)")
    ax.legend(fontsize=8)
    stamp(fig, f"Fig. 9 — p̃∞ = 0.15, β = {BETA:g}, ã0 = {A0}")
    fig.savefig(OUT / "fig09_friction_gamma.png", dpi=110)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, p in enumerate(loads):
        r = res[len(gammas) + i]
        ax[0].loglog(z, r["mu_bar"], f"C{i}-", label=f"p̃∞ = {p}")
        ax[0].loglog(z, r["mu_bar_adhesiveless"], f"C{i}--", lw=0.9)
    for i, d in enumerate(deltas):
        r = res[len(gammas) + len(loads) + i]
        ax[1].loglog(z, r["mu_bar"], f"C{i}-", label=f"Δ̃ = {d}")
    for a in ax:
        a.set_xlabel("ζ")
        a.set_ylabel("μ̄")
        a.legend(fontsize=8)
    ax[0].set_title("(a) load control (dashed: adhesiveless)")
    ax[1].set_title("(b) displacement control")
    stamp(fig, f"Fig. 11 — β = {BETA:g}, Γ = {GAMMA}, ã0 = {A0}")
    fig.savefig(OUT / "fig11_friction_load.png", dpi=110)


def special(args):
    zeta, Gamma = args
    sp = s1.special_points(zeta, BETA, Gamma, a0_tilde=A0, n=24, cheb=12)
    out = {k: float(sp[k]) for k in ("p_min", "delta_min", "p_dmin", "T", "p_max")}
    return out | {"branch": {k: np.asarray(v).tolist() for k, v in sp["branch"].items()}}


SPECIAL_CACHE = OUT / "special_points.json"  # (ζ, Γ) -> special points and branch


def special_points_for(jobs):
    """Special points for each (ζ, Γ), computed in parallel where not yet in the cache file
    (re-plotting Figs. 12-13 costs nothing; delete the file to recompute)."""
    import json

    cache = json.loads(SPECIAL_CACHE.read_text()) if SPECIAL_CACHE.exists() else {}
    key = [f"{z:.6g},{g:g}" for z, g in jobs]
    todo = [j for j, k in zip(jobs, key, strict=True) if k not in cache]
    if todo:
        with ProcessPoolExecutor(max_workers=os.cpu_count() or 1) as ex:
            for j, r in zip(todo, ex.map(special, todo), strict=True):
                cache[f"{j[0]:.6g},{j[1]:g}"] = r
        SPECIAL_CACHE.write_text(json.dumps(cache))
    return [cache[k] for k in key]


def fig12(quick):
    zs = np.logspace(-3, 2, 6 if quick else 11)
    gammas = (0.004, 0.008, 0.016)
    res = special_points_for([(z, g) for g in gammas for z in zs])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, g in enumerate(gammas):
        rr = res[i * zs.size:(i + 1) * zs.size]
        ax[0].semilogx(zs, [r["T"] for r in rr], f"C{i}-o", ms=3, label=f"Γ = {g}")
        ax[1].plot([abs(r["p_dmin"]) for r in rr], [abs(r["delta_min"]) for r in rr],
                   f"C{i}-o", ms=3, label=f"Γ = {g} (iso-Γ)")
    for j in range(zs.size):  # iso-ζ lines
        ax[1].plot([abs(res[i * zs.size + j]["p_dmin"]) for i in range(len(gammas))],
                   [abs(res[i * zs.size + j]["delta_min"]) for i in range(len(gammas))],
                   "k:", lw=0.7)
    ax[0].set_xlabel("ζ")
    ax[0].set_ylabel("T̃ (Eq. 24)")
    ax[1].set_xlabel("|p̃_out| (fixed-Δ pull-off)")
    ax[1].set_ylabel("|Δ̃_out|")
    ax[0].legend(fontsize=8)
    ax[1].legend(fontsize=8)
    stamp(fig, f"Fig. 12 — β = {BETA:g}, ã0 = {A0} (dotted: iso-ζ)")
    fig.savefig(OUT / "fig12_toughness.png", dpi=110)


def fig13(quick):
    """p̃∞ against Δ̃ along the equilibrium branch, one curve per ζ: (a) ζ ≤ 1 on linear axes,
    where the snap-in load (○) falls with ζ; (b) all ζ, symmetric-log load axis."""
    zs = np.logspace(-3, 2, 6 if quick else 11)
    res = special_points_for([(z, GAMMA) for z in zs])
    colours = plt.cm.viridis(np.linspace(0, 0.95, zs.size))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    for j, z in enumerate(zs):
        br, r = res[j]["branch"], res[j]
        for k, a in enumerate(ax):
            if k == 0 and z > 1.0:
                continue
            a.plot(br["delta_tilde"], br["p_tilde"], "-", color=colours[j],
                   label=f"ζ = {z:.2g}" if k == 1 or z <= 1.0 else None)
            i = int(np.argmax(br["p_tilde"]))
            if np.isfinite(r["p_max"]):
                a.plot(br["delta_tilde"][i], r["p_max"], "o", color=colours[j], ms=4)
    ax[1].set_yscale("symlog", linthresh=0.1)
    for a in ax:
        a.axhline(0.0, color="0.6", lw=0.6)
        a.set_xlabel("Δ̃")
        a.set_ylabel("p̃∞")
        a.legend(fontsize=7, ncol=2)
    ax[0].set_title("(a) ζ ≤ 1 (○: snap-in to full contact)")
    ax[1].set_title("(b) all ζ")
    stamp(fig, f"Fig. 13 — β = {BETA:g}, Γ = {GAMMA}, ã0 = {A0}")
    fig.savefig(OUT / "fig13_load_penetration.png", dpi=110)


FIGS = {3: fig3, 5: fig5, 6: fig6, 7: fig7, 8: fig8, 9: fig9_11, 11: fig9_11, 12: fig12,
        13: fig13}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="coarse ζ grids (for checks)")
    ap.add_argument("--only", type=int, nargs="+", help="figure numbers")
    args = ap.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    done = set()
    for num in args.only or sorted(FIGS):
        fn = FIGS[num]
        if fn in done:
            continue
        done.add(fn)
        t = time.time()
        fn(args.quick)
        print(f"{fn.__name__}: {time.time() - t:.0f} s", flush=True)


if __name__ == "__main__":
    main()
