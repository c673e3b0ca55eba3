"""``make validate``: the 2D grid solver against the 1D method (y-invariant sinusoid) and against
the oblique-sliding reduction; writes validation.md and figures/validation_*.png into the folder
``-o`` names (default: the current directory; ``make validate`` writes docs/).

β = 10, Γ = 0.008, ã0 = 0.01, p̃∞ ∈ {0.05, 0.15}, ζ from 1e-3 to 1e2.  The grid resolves
both a0 (≥ 8 layers) and the relaxation length vτ (≥ 8 cells): cells per wavelength
N = max(5027, 8λ/(vτ)), with a0 a whole number of cells; a second table runs N = 3000 and
4096 (a0/h = 4.77 and 6.52, not whole numbers).  The 1D reference uses the same a0.
Acceptance: ã and ẽ within 1 % (ẽ relative to ã), G1/Δγ and G2/Δγ within 2 % (relative to
max(|G|, Δγ): :data:`G_SCALE_MIN`), μ̄ within 2 %.

Usage: python -m spectralbem.validate [--quick] [-o DIR]  (or ``spectralbem validate``); the
folder DIR is created with its parents when missing.  validation.md names the command that
wrote it and, for ``--quick``, that it is a quick run.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from . import oned as s1
from .scenes import Scene, solve

ROOT = Path(__file__).resolve().parent.parent
KEYS = ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar")
TOL = {"a_tilde": 0.01, "e_tilde": 0.01, "G1_over_dgamma": 0.02, "G2_over_dgamma": 0.02,
       "mu_bar": 0.02}
BETA, GAMMA, A0 = 10.0, 0.008, 0.01
#: the release rates' differences are taken relative to max(|G|/Δγ, G_SCALE_MIN): G = Δγ −
#: δL_P/δA is a difference of two terms of order Δγ, and G1 changes sign between ζ = 4.64
#: and 5.62 at p̃∞ = 0.15 (1D: −0.045 and +0.065 Δγ), where a difference relative to |G1|
#: is undefined (at ζ = 5.0, G1 = −0.0022 Δγ: the 2D value, −0.0006 Δγ, reads 74 % off)
G_SCALE_MIN = 1.0
#: the ζ of the full sweep (16 per 5 decades) and those of ``--quick`` (5), so that every
#: point of the quick run is one of the full report's rows
ZETAS_FULL = np.logspace(-3, 2, 16)
ZETAS_QUICK = np.logspace(-3, 2, 5)


def cells_for(zeta: float) -> int:
    lam = 2 * np.pi
    # a0 = m h exactly with h ≤ a0/8 and h ≤ vτ/8 (vτ = ζ/k, k = 1)
    m = max(8, int(np.ceil(8 * A0 / zeta - 1e-9))) if np.isfinite(zeta) and zeta > 0 else 8
    return int(round(m * lam / A0))


def compare(zeta, p_tilde, direction_deg=0.0, ny=2, n=None, keys=KEYS, solver=None):
    """The seed sinusoid on the 2D grid (n cells per wavelength, default :func:`cells_for`;
    ``solver``: [solver] entries) against the 1D method at the same a0: per name of ``keys``
    (2D, 1D, relative difference; ẽ relative to ã, G1, G2 to max(|G|, Δγ): G_SCALE_MIN)."""
    n = n or cells_for(zeta * np.cos(np.radians(direction_deg)))
    t = time.perf_counter()
    ds = solve(Scene.sinusoid(zeta, BETA, GAMMA, p_tilde=p_tilde, a0_tilde=A0,
                              cells_per_wavelength=n, ny=ny, direction_deg=direction_deg,
                              solver=solver))
    t2 = time.perf_counter() - t
    a0e = A0  # the a0 asked for is the a0 used (a band of m + θ layers)
    ref = s1.solve(zeta * np.cos(np.radians(direction_deg)), BETA, GAMMA, p_tilde=p_tilde,
                   a0_tilde=a0e, adhesiveless_reference=False)
    row = {"zeta": zeta, "p_tilde": p_tilde, "N": n, "a0_eff": a0e, "time_2d": t2,
           "status": ds.status.item()}
    for k in keys:
        v2, v1 = ds[k].item(), ref[k].item()
        if k == "mu_bar":
            v2 /= np.cos(np.radians(direction_deg)) if direction_deg else 1.0
        scale = (abs(ref["a_tilde"].item()) if k == "e_tilde"
                 else max(abs(v1), G_SCALE_MIN) if k.startswith("G") else abs(v1))
        row[k] = (v2, v1, (v2 - v1) / scale)
    if direction_deg:
        row["mu_lateral"] = (ds["mu_bar_lateral"].item(), -ref["mu_bar"].item()
                             * np.sin(np.radians(direction_deg)))
    return row


def _command(argv) -> str:
    """The command line of a run from ``python -m spectralbem.validate`` (argv: its
    arguments, default sys.argv[1:])."""
    import shlex
    import sys

    args = list(sys.argv[1:] if argv is None else argv)
    return " ".join(["python -m spectralbem.validate", *([shlex.join(args)] if args else [])])


def main(argv=None, command: str | None = None):
    """Run the validation and write the report into ``-o``; ``command``: the command line
    the report names (default: ``python -m spectralbem.validate`` with ``argv``)."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="5 ζ points, one load")
    ap.add_argument("-o", "--output", type=Path, default=Path("."),
                    help="folder of the report validation.md and figures/, created with its "
                         "parents when missing (default: the current directory; make "
                         "validate writes docs/)")
    args = ap.parse_args(argv)
    command = command or _command(argv)
    if args.output.exists() and not args.output.is_dir():
        raise SystemExit(f"validate: output {str(args.output)!r} exists and is not a folder")
    try:  # before any solve
        args.output.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SystemExit(f"validate: cannot create the output folder {str(args.output)!r}: "
                         f"{exc.strerror or exc}") from None
    zetas = ZETAS_QUICK if args.quick else np.union1d(ZETAS_FULL, ZETAS_QUICK)
    loads = (0.15,) if args.quick else (0.05, 0.15)
    rows = []
    for p in loads:
        for z in zetas:
            r = compare(float(z), p)
            rows.append(r)
            worst = max(abs(r[k][2]) / TOL[k] for k in KEYS)
            print(f"p̃ {p:4.2f} ζ {z:8.3g} N {r['N']:6d} {r['status']:8s} "
                  + " ".join(f"{k[:2]} {r[k][2]:+.1e}" for k in KEYS)
                  + f"  worst/tol {worst:.2f}  {r['time_2d']:.1f}s", flush=True)
    fractional = [] if args.quick else [compare(float(z), p, n=n) for n in (3000, 4096)
                                        for p in loads for z in ZETAS_FULL[::3]]
    oblique = compare(0.3, 0.15, direction_deg=40.0)
    print("oblique 40°:", {k: f"{oblique[k][2]:+.1e}" for k in KEYS})
    jkr = [] if args.quick else jkr_sphere()
    rough = None if args.quick else rough_cycle()
    ok = write_report(rows, oblique, jkr, rough, fractional, args.output, command=command,
                      quick=args.quick)
    if not ok:
        raise SystemExit("validate: the 2D solver is outside tolerance against the 1D method "
                         f"(see {args.output / 'validation.md'})")


#: Δγ of the JKR validation: the zero-load JKR radius (9πΔγR²/(2E*))^(1/3) is 0.1 L (small
#: enough for the periodic images to move it by O((a/L)³) only, docs/derivations.md §6); at
#: 1024² it has 102 cells and the pull-off radius (1/4)^(1/3) of it 65
W_JKR = 2 * 0.1**3 / (9 * np.pi)


def jkr_cell(n: int, w: float = 2e-4):
    """The JKR scene: elastic paraboloid R = L = E* = 1 (ν = 0), work of adhesion w."""
    from .materials import Elastic
    from .spectral import Cell, SpectralOperator
    from .surfaces import paraboloid

    cell = Cell(1.0, 1.0, n, n)
    X, Y = cell.coordinates()
    r = np.hypot(X - cell.Nx // 2 * cell.hx, Y - cell.Ny // 2 * cell.hy)
    return cell, SpectralOperator(cell, Elastic(1.0, 0.0)), paraboloid(cell, 1.0), r, w


def griffith_radius(res, cell) -> float:
    """Equivalent radius of a disc-shaped contact at the Griffith edge: the mask radius plus
    the mean sub-cell offset of the outer front, which in an elastic scene is already that of
    the sharp-crack edge (docs/theory.md)."""
    a = np.sqrt(res.contact.sum() * cell.cell_area / np.pi)
    s = res.offset_out[res.tests.bands.outer_front]
    s = s[np.isfinite(s)]
    return float(a + (s.mean() if s.size else 0.0))


def area_radius(op, res, dgamma) -> float:
    """√(A/π) of the area A inside the balanced sub-cell front (spectralbem.front)."""
    from .front import front_outputs

    if res.status != "partial":
        return float("nan")
    return float(np.sqrt(front_outputs(op, res, dgamma)["area"] / np.pi))


def smoothing(sigma: float | None) -> dict:
    """solve_adhesive keywords: None → the default front smoothing (of the scene's kind,
    ≥ 0.23 of the patch's front radius); a number → that σ in units of a0 fixed (no growth
    with the patch)."""
    return {} if sigma is None else {"front_smoothing": sigma, "smoothing_per_radius": 0.0}


def pulloff_bisection(op, h, w, cell, mask, steps: int = 7, verbose: bool = False, **kw):
    """Load-control pull-off of the JKR scene by bisection on the mean pressure, unloading
    from ``mask`` (each partial state's mask starts the next step): (lo, hi) in units of the
    JKR value Pc = -3πwR/2.  The first step tries 0.9 Pc, the bracket starts at [0, 1.2 Pc];
    after 7 steps it is 0.3 % of Pc wide."""
    from . import reference as ref
    from .adhesive import solve_adhesive

    Pc = ref.jkr_pulloff(1.0, w)
    lo, hi = 0.0, 1.2 * Pc
    for k in range(steps):
        mid = 0.9 * Pc if k == 0 else 0.5 * (lo + hi)
        res = solve_adhesive(op, h, w, cell.hx, mean_pressure=mid, mask0=mask, **kw)
        if res.status == "partial":
            lo, mask = mid, res.contact
        else:
            hi = mid
        if verbose:
            print(f"  pull-off bisection {k + 1}/{steps}: P/Pc = {mid / Pc:.4f} {res.status} "
                  f"({res.iterations} outer iterations)", flush=True)
    return lo / Pc, hi / Pc


def jkr_sphere(n: int = 1024, sigma: float | None = None, w: float = W_JKR):
    """Elastic JKR sphere in a periodic cell: contact radius against JKR at zero load and at
    half the pull-off force (tensile), approached from a smaller (loading) and a larger
    (unloading) contact, and the load-control pull-off by bisection (unloading from the
    zero-load contact).  ``sigma`` None: the default front smoothing (½ a0, ≥ 0.23 of the
    patch radius); a number: that σ fixed (in units of a0, here one cell)."""
    from . import reference as ref
    from .adhesive import solve_adhesive

    cell, op, h, r, w = jkr_cell(n, w)
    kw = smoothing(sigma)
    out = []
    for P in (0.0, 0.5 * ref.jkr_pulloff(1.0, w)):
        aJ = ref.jkr_radius(P, 1.0, 1.0, w)
        for branch, start in (("loading", 0.9), ("unloading", 1.1)):
            t = time.perf_counter()
            res = solve_adhesive(op, h, w, cell.hx, mean_pressure=P, mask0=r < start * aJ,
                                 **kw)
            a = area_radius(op, res, w)
            out.append(dict(P=P, branch=branch, a_jkr=aJ, cells=aJ / cell.hx, error=a / aJ - 1,
                            radius_over_L=aJ / cell.Lx,
                            status=res.status, message=res.message,
                            time=time.perf_counter() - t))
            print(f"JKR P={P} {branch}: radius error {a / aJ - 1:+.2e} ({res.status}, "
                  f"{res.message[:60]})", flush=True)
    Pc = ref.jkr_pulloff(1.0, w)
    t = time.perf_counter()
    lo, hi = pulloff_bisection(op, h, w, cell, r < ref.jkr_radius(0.0, 1.0, 1.0, w),
                               verbose=True, **kw)
    pull = dict(lo=lo, hi=hi, Pc=Pc, cells=ref.jkr_radius(Pc, 1.0, 1.0, w) / cell.hx,
                time=time.perf_counter() - t, n=n, w=w)
    print(f"JKR pull-off between {lo:.4f} and {hi:.4f} of -3πwR/2", flush=True)
    return out, pull


def rough_cycle():
    """cases/rough_load_unload.toml at 256² (β = 10, ζ = 0.1 at the roll-off): the load path
    1e4 → 3e4 → 1e4 → 3e3 Pa with the mask as the state; statuses, outer iterations and
    area fractions (adhesion hysteresis: more contact on unloading at the same load)."""
    from .scenes import load_scene

    t = time.perf_counter()
    ds = solve(load_scene(ROOT / "cases" / "rough_load_unload.toml"))
    out = dict(p=ds.mean_pressure.values.tolist(), area=ds.area_fraction.values.tolist(),
               outer=ds.iterations.values.astype(int).tolist(),
               status=[str(s) for s in ds.status.values],
               message=[str(m) for m in ds.solver_message.values],
               time=time.perf_counter() - t)
    print("rough load/unload:", out["status"], out["area"], flush=True)
    return out


def within(rows) -> bool:
    """Every quantity of every row within its tolerance."""
    return all(abs(r[k][2]) <= TOL[k] for r in rows for k in KEYS)


def worst_line(rows) -> str:
    """The largest relative difference of each quantity over ``rows`` and the verdict."""
    worst = {k: max(abs(r[k][2]) for r in rows) for k in KEYS}
    return (", ".join(f"{k} {worst[k]:.1e}" for k in KEYS)
            + (" — **all within tolerance**." if within(rows) else " — **outside tolerance**."))


def _table(rows) -> list:
    lines = ["| p̃∞ | ζ | N/λ | a0/h | vτ/h | status | ã | ẽ (rel. ã) | G1/Δγ | G2/Δγ | μ̄ | "
             "2D s |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        h = 2 * np.pi / r["N"]
        lines.append(f"| {r['p_tilde']} | {r['zeta']:.3g} | {r['N']} | {A0 / h:.2f} | "
                     f"{r['zeta'] / h:.3g} | {r['status']} | "
                     + " | ".join(f"{r[k][2]:+.1e}" for k in KEYS) + f" | {r['time_2d']:.1f} |")
    return lines


#: the finite-thickness layer references of tests/test_layer_references.py (run by
#: `make test`, not by this command), stated in the report with their measured errors
LAYER_CHECKS = """
## Finite-thickness layers

Checked by `make test` (`tests/test_layer_references.py`; the numbers below are those tests'
measurements, not this command's): each reference is computed in its test without
`spectralbem.layers`; measured error (the asserted tolerance in brackets).

- **Eqs. (A.3)-(A.5)**: the plane-strain layer equations in (u_x, u_z, σ_xz, σ_zz) integrated
  by a matrix exponential, far face glued or free; all modes of 32 × 16, |q|d 0.06-14,
  ν = 0, 0.3, 0.5, elastic or SLS (complex modulus): 2.3e-13 (1e-10).
  `test_elastic_kernel_is_the_plane_strain_layer`,
  `test_viscoelastic_sampled_kernel_is_the_layer_with_complex_modulus`.
- **Sphere on a glued layer**: Abel reduction to a Fredholm equation with kernel ∫(S − 1)cos;
  256², radius 16 cells, d/a = 2, 1, 0.5, ν = 0.5, 0.3: Δ 2.9e-4 (1e-3), load 5.5e-4 (1.5e-3).
  `test_sphere_on_glued_layer_against_axisymmetric_fredholm`.
- **Thin glued layers**, 128²: incompressible squeeze, P = 2πER²Δ³/(3d³), d/a = 0.0125: 3.8e-3
  (1e-2; 3.3e-3 is the asymptote's own (d/a)² term); Winkler bed P = πMRΔ²/d, ν = 0.3,
  d/a = 0.025: 4e-4 (2e-3). `test_thin_glued_layer_asymptotics`.
- **(A.5) is a plate on back pressure p̄**: periodic cylinder, 1024 cells: p = p̄ in contact,
  2e-4 (1e-3); free span b³ = 3DL/(2Rp̄) (beam), extrapolated in d: 0.5 cells (1.5).
  `test_pressure_layer_is_a_plate_on_back_pressure`.
- **Sliding full contact**, μ = kΛ²|Im(1/Ĉ(k))|/(2p̄), both kinds: sampled kernel 1e-12 (1e-9);
  cell-averaged 4e-5 at 256 cells, second order.
  `test_full_contact_friction_on_viscoelastic_layers`.
"""


def write_report(rows, oblique, jkr=(), rough=None, fractional=(), out: Path = Path("."),
                 command: str = "python -m spectralbem.validate", quick: bool = False):
    """Write ``out``/validation.md and ``out``/figures/validation_sinusoid.png; ``command``:
    the command line the report names, ``quick``: a ``--quick`` run (said in the report).
    Returns whether every compared point is within tolerance."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figdir = out / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    names = {"a_tilde": "ã", "G1_over_dgamma": "G1/Δγ", "G2_over_dgamma": "G2/Δγ",
             "mu_bar": "μ̄"}
    styles = {p: ("-", "--", ":", "-.")[i % 4]
              for i, p in enumerate(sorted({r["p_tilde"] for r in rows}))}
    for p, ls in styles.items():
        rr = sorted((r for r in rows if r["p_tilde"] == p), key=lambda r: r["zeta"])
        z = [r["zeta"] for r in rr]
        for j, (k, a) in enumerate((("a_tilde", ax[0]), ("G1_over_dgamma", ax[1]),
                                    ("G2_over_dgamma", ax[1]))):
            c = f"C{j}"  # 1D: open circles joined; 2D grid: dots on them
            a.semilogx(z, [r[k][1] for r in rr], ls=ls, color=c, marker="o", mfc="none",
                       ms=6, lw=0.8, label=f"{names[k]} 1D, p̃∞ = {p:g}")
            a.semilogx(z, [r[k][0] for r in rr], "o", color=c, ms=2.5,
                       label=f"{names[k]} 2D, p̃∞ = {p:g}")
        for j, k in enumerate(("a_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar")):
            ax[2].semilogx(z, [abs(r[k][2]) for r in rr], f"C{j}", ls=ls, marker="o", ms=3,
                           label=f"{names[k]}, p̃∞ = {p:g}")
    ax[0].set(xlabel="ζ", ylabel="ã = k a (contact half-width)",
              title="contact size: 1D method (open) and 2D grid (dots)")
    ax[1].set_yscale("symlog", linthresh=0.1)  # G1 changes sign near ζ = 5
    ax[1].axhline(1.0, color="0.6", lw=0.6)
    ax[1].set(xlabel="ζ", ylabel="G/Δγ (symlog)",
              title="release rates: 1D method (open) and 2D grid (dots)")
    ax[2].set_yscale("log")
    ax[2].axhline(0.01, color="0.5", ls=":")
    ax[2].axhline(0.02, color="0.5", ls="--")
    ax[2].set(xlabel="ζ", ylabel="|2D − 1D| / 1D (G: / max(|G|, Δγ))",
              title="relative difference (dotted 1 %, dashed 2 %)")
    for a in ax:
        a.legend(fontsize=6)
    fig.savefig(figdir / "validation_sinusoid.png", dpi=110)
    plt.close(fig)
    lines = _table(rows)
    kind = (f"A quick run (`--quick`): {len(rows)} points at p̃∞ = "
            f"{', '.join(f'{p:g}' for p in sorted({r['p_tilde'] for r in rows}))} and the "
            "oblique case only, without the fractional-a0 table, the JKR sphere and the rough "
            "cycle; the full report is `make validate` "
            "(`python -m spectralbem.validate -o docs`)." if quick else "The full run.")
    text = f"""# Validation of the 2D solver{' (quick run)' if quick else ''}

Generated by `{command}` on {time.strftime('%Y-%m-%d')}. {kind}

A y-invariant sinusoid on an N × 2 grid (the 2D operator, masked Krylov solves and
front-layer criterion) against the 1D method of `spectralbem.sinusoid1d` at the same a0.
β = 10, Γ = 0.008.
Relative differences (ẽ relative to ã; G1/Δγ and G2/Δγ relative to max(|G|, Δγ): G1 changes
sign near ζ = 5 at p̃∞ = 0.15, where a difference relative to |G1| is undefined); acceptance:
ã, ẽ 1 %, G1, G2 2 %, μ̄ 2 %.

Worst over the sweep: """ + worst_line(rows) + """

![validation](figures/validation_sinusoid.png)

""" + "\n".join(lines) + ("""

### a0 not a whole number of cells

The same comparison at N = 3000 and 4096 cells per wavelength (a0/h = 4.77 and 6.52: the
band is the interpolation of the works of ⌊a0/h⌋ and ⌈a0/h⌉ layers), with the default kernel
(its delayed part averaged over the cells) also where vτ spans less than a cell (ζ = 1e-3:
vτ/h = 0.48 and 0.65); the sampled kernel (`solver.delayed_kernel = "sampled"`) puts μ̄ 7 %
off there (docs/performance.md, "Resolving the relaxation length").

Worst over these points: """ + worst_line(fractional) + """

""" + "\n".join(_table(fractional)) if fractional else "") + """

## Oblique sliding

Sliding at 40° to the wave vector at ζ = 0.3 equals the 1D problem at ζ cos 40° (the kernel
depends on v through q·v only); μ̄ along v is divided by cos 40°: """ + ", ".join(
        f"{k} {oblique[k][2]:+.1e}" for k in KEYS) + f"""; lateral μ̄ {oblique['mu_lateral'][0]:.5f}
against −μ̄₁D sin 40° = {oblique['mu_lateral'][1]:.5f}.
"""
    if jkr:
        jkr, pull = jkr
        text += f"""
## JKR sphere

Elastic paraboloid R = L = E* = 1 (ν = 0), Δγ = {pull['w']:.4g} (zero-load JKR radius
0.1 L), {pull['n']}² cell, a0 = one cell, the default front smoothing (σ = max(½ a0,
0.23 r), r = 2A/P the patch's front radius: 15-24 cells here). The radius is √(A/π) of the
area A inside the balanced sub-cell front (the dataset's `area_fraction`; in this elastic
scene the sharp-crack edge). Acceptance: radius within 1 % at ≥ 50 cells per radius
(contact radius ≤ 0.1 L), on loading and unloading; pull-off within 2 %.

| P | branch | JKR radius (cells) | radius / L | radius error | status | note | s |
|---|---|---|---|---|---|---|---|
""" + "\n".join(f"| {j['P']:.3g} | {j['branch']} | {j['cells']:.1f} | {j['radius_over_L']:.3f} | "
                 f"{j['error']:+.2e} | {j['status']} | {j['message'][:70]} | {j['time']:.0f} |"
                 for j in jkr) + f"""

Load-control pull-off (bisection from the zero-load contact, 7 solves, {pull['time']:.0f} s):
between {pull['lo']:.4f} and {pull['hi']:.4f} of the JKR value -3πΔγR/2; the JKR radius at
pull-off is {pull['cells']:.0f} cells.
"""
    if rough is not None:
        cyc = any(st != "partial" for st in rough["status"])
        text += f"""
## Rough load/unload cycle

`cases/rough_load_unload.toml` (self-affine, 256², β = 10, ζ = 0.1 at the roll-off, a0 = 2
cells, default front smoothing), the mask carried along the mean-pressure path,
{rough['time']:.0f} s. Acceptance: every step converged (`partial`: every resolved front
cell balanced) and adhesion hysteresis. {'Some step did not converge.' if cyc else
'Every step converged.'} The grid refinement of this kind of scene is in
docs/rough_convergence.md.

| p̄ (Pa) | status | outer iterations | area fraction | message |
|---|---|---|---|---|
""" + "\n".join(f"| {p:g} | {s} | {o} | {a:.4f} | {m[:80]} |" for p, s, o, a, m in
                 zip(rough["p"], rough["status"], rough["outer"], rough["area"],
                     rough["message"], strict=True)) + f"""

Hysteresis: at {rough['p'][0]:g} Pa the contact covers {rough['area'][0]:.4f} of the cell on
loading and {rough['area'][2]:.4f} on unloading ({100 * (rough['area'][2] / rough['area'][0]
                                                      - 1):+.0f} %).
"""
    (out / "validation.md").write_text(text + LAYER_CHECKS)
    return within(rows) and within(fractional)


if __name__ == "__main__":
    main()
