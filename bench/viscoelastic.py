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

``--robustness``: the default solver (``solve_contact``, with its fallback) against the
active set over β ∈ {1, 10, 100, 1e4} × ζ ∈ {1e-3, 0.1, 1, 10, 1e3} × load/penetration
control × half-space / glued layer / layer under pressure (thickness 0.05 L) on the 128²
surface (section ``visco_robust``, bench/viscoelastic_robustness.json; ~20 min).
``--starts``: FFT pairs of the whole Newton solve from three starts (PK on |Ĉ|, on Re Ĉ, on
the relaxed E0) over the 60 cases of tests/test_newton.py's 64² surface (β 10-1e4, ζ
1e-3-1e3, half-space and glued layer, both controls) and the table's surface at 1024²
(section ``visco_starts``, bench/viscoelastic_starts.json).

``--adhesive``: the adhesive state of cases/rough_convergence.toml (the physical surface,
Δγ = 0.01 J/m², a0 = 7.8 µm, p̄ = 1e4 Pa, loading), elastic and SLS, against the
adhesiveless solve of the same scene (adhesion removed), at 128², 256², 512², in CPU seconds
and in FFT pairs (the datasets' ``fft_transforms``: a ratio that the machine's load does not
move) (section ``adhesive_cost``, bench/viscoelastic_adhesive.json), and the figure
docs/figures/solve_cost.png: CPU seconds and peak memory against N² for the elastic PK, the
viscoelastic adhesiveless and the adhesive solves (``--figure`` redraws it from the JSON).

``--large``: the SLS adhesive state of the same case at 1024² and 2048² with ``--threads``
FFT threads (default 2, the machine's cores), in wall seconds, from the adhesiveless start
(the default) and from the coarse-grid start (``solver.coarse_start``), against its
adhesiveless solve timed alike (section ``adhesive_large``, bench/viscoelastic_large.json);
``--large-starts`` picks the starts, ``--front-tol`` sets ``solver.front_tol`` (cells),
``--band-tol`` ``solver.band_tol``, and a run replaces only the rows of its own sizes, starts
and tolerances.

Usage: python bench/viscoelastic.py [--sizes 256 512 1024 2048] [--runs 3]
       python bench/viscoelastic.py --robustness | --starts | --adhesive [--sizes 128 256 512]
       python bench/viscoelastic.py --large [--sizes 1024 2048] [--threads 2]
           [--large-starts adhesiveless coarse] [--front-tol F] [--band-tol B]
       python bench/viscoelastic.py --figure
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import itertools  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import tracemalloc  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from spectralbem import __version__, newton  # noqa: E402
from spectralbem.contact import active_set, polonsky_keer, solve_contact  # noqa: E402
from spectralbem.keys import FRONT_TOL  # noqa: E402
from spectralbem.layers import GluedLayer, HalfSpace, PressureLayer  # noqa: E402
from spectralbem.materials import Elastic, StandardLinearSolid  # noqa: E402
from spectralbem.spectral import SpectralOperator  # noqa: E402
from spectralbem.state import Solution  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run import fft_pair_seconds, surface, write_section  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
PBAR = 0.01
ZETA = 0.1
TOL = 1e-10


def operators(n, runs=1):
    """The surface, the viscoelastic and elastic operators, and the CPU seconds of building
    each one's kernel (fastest of ``runs``; the transforms are planned apart)."""
    cell, h = surface(n)
    v = ZETA * (cell.Lx / 4) / (2 * np.pi)  # ζ = 2π v τ / λ_r, λ_r = L/4, τ = 1
    t_v, visco = timed(lambda: SpectralOperator(cell, StandardLinearSolid(1.0, 10.0, 1.0, 0.5),
                                                velocity=(v, 0.0)), runs)
    t_e, elastic = timed(lambda: SpectralOperator(cell, Elastic(1.0, 0.5)), runs)
    visco.apply(h)  # plans the transforms (shared plan per shape)
    return h, visco, elastic, (t_v, t_e)


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
        s = polonsky_keer(visco.relaxed_part(), h, mean_pressure=PBAR, tol=newton.START_TOL)
        r = newton.newton_contact(visco, h, mean_pressure=PBAR, tol=TOL, mask0=s.contact,
                                  p0=s.pressure)
        return r._replace(fft_pairs=r.fft_pairs + s.fft_pairs)

    def splitting(maxit=60):
        """PK on C^E with the odd part lagged: p ← PK_E(h − C^O p)."""
        even = visco.even_part()
        p = np.zeros(h.shape)
        pairs = sweeps = 0
        ok = False
        while sweeps < maxit:
            sweeps += 1
            r = polonsky_keer(even, h - visco.apply_odd(p), mean_pressure=PBAR, tol=TOL, p0=p)
            pairs += r.fft_pairs + 1
            change = np.linalg.norm(r.pressure - p) / np.linalg.norm(r.pressure)
            p = r.pressure
            if change < 1e-8:
                ok = True
                break
        return Solution(p, None, r.penetration, p > 0, sweeps, ok, f"change {change:.1e}",
                        sweeps, pairs)

    return {
        "active set": lambda: active_set(visco, h, mean_pressure=PBAR, tol=TOL),
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
    k = runs if n <= 1024 else 1
    h, visco, elastic, (build, build_el) = operators(n, k)
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
                   kernel_seconds=build, elastic_kernel_seconds=build_el,
                   ratio_with_kernels=(t + build) / (t_el + build_el),
                   elastic_iterations=r_el.iterations, elastic_pairs=r_el.fft_pairs,
                   pair_ms=1e3 * pair, converged=bool(r.converged), products=int(r.iterations),
                   outer=int(r.outer_iterations), pairs=float(r.fft_pairs),
                   area=float(np.mean(r.contact)))
        if ref is not None and name != "active set":
            row["set_diff"] = int(np.count_nonzero(ref.contact != r.contact))
            row["p_rel"] = float(np.linalg.norm(ref.pressure - r.pressure)
                                 / np.linalg.norm(ref.pressure))
        if name == "newton" and n <= 1024:
            row["peak_arrays"] = peak_arrays(cands[name], n)
        rows.append(row)
        print(json.dumps(row), flush=True)
    return rows


def markdown(rows) -> str:
    head = ("| N² | method | s | elastic PK (s) | ratio | kernel build (s): viscoelastic / "
            "elastic | ratio with the builds | FFT pairs | pairs / elastic's | "
            "products | outer | area | set diff / p rel. vs active set | peak (N² arrays) |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    lines = []
    for r in rows:
        pairs = "—" if not np.isfinite(r["pairs"]) else f"{r['pairs']:.0f}"
        rel = "—" if not np.isfinite(r["pairs"]) else f"{r['pairs'] / r['elastic_pairs']:.2f}"
        cmp_ = (f"{r['set_diff']} / {r['p_rel']:.1e}" if "set_diff" in r else "—")
        peak = f"{r['peak_arrays']:.1f}" if "peak_arrays" in r else "—"
        ok = "" if r["converged"] else " (not converged)"
        lines.append(f"| {r['N']}² | {r['method']}{ok} | {r['seconds']:.3f} | "
                     f"{r['elastic_seconds']:.3f} | **{r['ratio']:.2f}×** | "
                     f"{r['kernel_seconds']:.3f} / {r['elastic_kernel_seconds']:.4f} | "
                     f"{r['ratio_with_kernels']:.2f}× | {pairs} | {rel} | "
                     f"{r['products']} | {r['outer']} | {r['area']:.4f} | {cmp_} | {peak} |")
    return head + "\n" + "\n".join(lines)


LAYERS = {"half": lambda: HalfSpace(), "glued": lambda: GluedLayer(0.05),
          "pressure": lambda: PressureLayer(0.05)}


def robustness(n=128):
    cell, h = surface(n)
    rows = []
    for beta, zeta, kind, lay in itertools.product((1.0, 10.0, 100.0, 1e4),
                                                    (1e-3, 0.1, 1.0, 10.0, 1e3),
                                                    ("load", "penetration"), LAYERS):
        mat = (Elastic(1.0, 0.5) if beta == 1.0 else StandardLinearSolid(1.0, beta, 1.0, 0.5))
        v = zeta * (cell.Lx / 4) / (2 * np.pi)
        op = SpectralOperator(cell, mat, LAYERS[lay](), (v, 0.0))
        kw = ({"mean_pressure": 0.004} if kind == "load"
              else {"penetration": 0.3 * float(h.max() - h.mean())})
        t = time.process_time()
        ref = active_set(op, h, tol=TOL, **kw)
        t_ref = time.process_time() - t
        t = time.process_time()
        res = solve_contact(op, h, tol=TOL, **kw)
        t_new = time.process_time() - t
        row = dict(beta=beta, zeta=zeta, control=kind, layer=lay,
                   area=float(ref.contact.mean()), active_converged=bool(ref.converged),
                   active_seconds=t_ref, active_products=int(ref.iterations),
                   converged=bool(res.converged),
                   method=res.method, seconds=t_new,
                   pairs=float(res.diagnostics.get("fft_pairs", np.nan)),
                   set_diff=int(np.count_nonzero(ref.contact != res.contact)),
                   p_rel=float(np.linalg.norm(ref.pressure - res.pressure)
                               / max(np.linalg.norm(ref.pressure), 1e-300)))
        rows.append(row)
        print(json.dumps(row), flush=True)
    return rows


def robustness_markdown(rows) -> str:
    both = [r for r in rows if r["active_converged"] and r["converged"]]
    agree = [r for r in both if r["set_diff"] == 0 and r["p_rel"] < 1e-8]
    only_new = [r for r in rows if r["converged"] and not r["active_converged"]]
    neither = [r for r in rows if not r["converged"] and not r["active_converged"]]
    only_ref = [r for r in rows if r["active_converged"] and not r["converged"]]
    fell = [r for r in rows if r["method"] == "active-set"]
    speed = [r["active_seconds"] / max(r["seconds"], 1e-9) for r in both]

    def cases(rs):
        return ", ".join(f"β {r['beta']:g} ζ {r['zeta']:g} {r['control']} {r['layer']}"
                         for r in rs) or "none"

    return (f"{len(rows)} cases: both converged in {len(both)}, of which {len(agree)} with "
            f"the same contact set and pressures within 1e-8 (largest difference "
            f"{max((r['p_rel'] for r in both), default=0):.1e}); the default solver "
            f"{np.median(speed):.1f}× faster in the median (CPU s, range "
            f"{min(speed, default=0):.1f}-{max(speed, default=0):.1f}×). Converged by the "
            f"default solver only: {cases(only_new)}. By the active set only: "
            f"{cases(only_ref)}. By neither: {cases(neither)}. The Newton steps fell back to "
            f"the active set in: {cases(fell)}.")


def starts():
    sys.path.insert(0, str(ROOT / "tests"))
    import test_newton as tn

    def variants(op):
        return {"|Ĉ|": op.magnitude_part(), "Re Ĉ": op.even_part(),
                "E0": op.relaxed_part()}

    rows = []
    cases = [(b, z, lay, kind) for b in (10.0, 100.0, 1e4) for z in (1e-3, 0.1, 1.0, 10.0, 1e3)
             for lay in ("half", "glued") for kind in ("load", "penetration")]
    for b, z, lay, kind in cases:
        op, h = tn.operator(b, z, lay)
        rows.append(_start_row(dict(N=64, beta=b, zeta=z, layer=lay, control=kind), op, h,
                               tn.control(kind, h), variants(op)))
    h, visco, _el, _build = operators(1024)
    rows.append(_start_row(dict(N=1024, beta=10.0, zeta=ZETA, layer="half", control="load"),
                           visco, h, {"mean_pressure": PBAR}, variants(visco)))
    return rows


def _start_row(row, op, h, kw, variants):
    for name, sym in variants.items():
        s = polonsky_keer(sym, h, tol=newton.START_TOL, maxiter=newton.START_MAXITER, **kw)
        r = newton.newton_contact(op, h, tol=TOL, mask0=s.contact, p0=s.pressure, **kw)
        row[name] = dict(pairs=s.fft_pairs + r.fft_pairs, converged=bool(r.converged),
                         start_area=float(np.mean(s.contact)), area=float(np.mean(r.contact)))
    print(json.dumps(row), flush=True)
    return row


def starts_markdown(rows) -> str:
    names = ("|Ĉ|", "Re Ĉ", "E0")
    grid = [r for r in rows if r["N"] == 64]
    ok = [r for r in grid if all(r[m]["converged"] for m in names)]
    lines = ["| start | FFT pairs, sum over the cases all three converge | cases not converged |"
             " 1024² table case: pairs (start area / final) |", "|---|---|---|---|"]
    big = [r for r in rows if r["N"] == 1024]
    for m in names:
        b = big[0][m] if big else None
        label = m.replace("|", "\\|")  # a table cell
        lines.append(f"| {label} | {sum(r[m]['pairs'] for r in ok):.0f} ({len(ok)} cases) | "
                     f"{sum(not r[m]['converged'] for r in grid)} of {len(grid)} | "
                     + (f"{b['pairs']:.0f} ({b['start_area']:.3f} / {b['area']:.3f})"
                        if b else "—") + " |")
    return "\n".join(lines)


ROUGH_CASE = ROOT / "cases" / "rough_convergence.toml"


def _rough_case(material: str):
    """(adhesive, adhesiveless) raw scenes of cases/rough_convergence.toml loaded at 1e4 Pa,
    with its SLS or an elastic slab of E0."""
    from spectralbem.scenes import read_scene_file

    raw = read_scene_file(ROUGH_CASE)
    raw["control"] = {"mean_pressure": 1e4}
    if material == "elastic":
        raw["material"] = {"kind": "elastic", "E": 1e6, "nu": 0.5}
    return raw, {k: v for k, v in raw.items() if k != "adhesion"}


def _pairs(ds) -> int:
    """The FFT pairs of a solve (its inverse transforms, the dataset's diagnostics): one
    operator application each, whatever the machine's speed."""
    return int(json.loads(ds.attrs["solver_diagnostics"])["fft_transforms"]["inverse"])


def adhesive_rows(sizes):
    from spectralbem.scenes import load_scene, solve

    case = ROUGH_CASE
    rows = []
    for n in sizes:
        for material in ("elastic", "sls"):
            raw, free = _rough_case(material)
            ov = {"grid.Nx": n, "grid.Ny": n}
            times = {}
            solve(load_scene(free, overrides=ov, base_dir=case.parent))  # plans, compiles
            for name, r, extra in (("adhesiveless", free, {}), ("adhesive", raw, {}),
                                   ("coarse", raw, {"solver.coarse_start": True})):
                scene = load_scene(r, overrides={**ov, **extra}, base_dir=case.parent)
                t = time.process_time()
                ds = solve(scene)
                times[name] = (time.process_time() - t, ds)
            ds = times["adhesive"][1]
            pairs = {k: _pairs(v[1]) for k, v in times.items()}
            row = dict(N=n, material=material, adhesive_seconds=times["adhesive"][0],
                       adhesive_pairs=pairs["adhesive"],
                       adhesiveless_pairs=pairs["adhesiveless"],
                       pair_ratio=pairs["adhesive"] / pairs["adhesiveless"],
                       coarse_pairs=pairs["coarse"],
                       adhesiveless_seconds=times["adhesiveless"][0],
                       ratio=times["adhesive"][0] / times["adhesiveless"][0],
                       status=str(ds["status"].values), outer=int(ds["iterations"]),
                       area=float(ds["area_fraction"]),
                       area_adhesiveless=float(times["adhesiveless"][1]["area_fraction"]))
            # the peak of the adhesive solve's numpy allocations, in a run of its own after
            # the timed ones (compiled kernels and the grid's FFT plan exist by then)
            tracemalloc.start()
            solve(load_scene(raw, overrides=ov, base_dir=case.parent))
            row["peak_arrays"] = tracemalloc.get_traced_memory()[1] / (8.0 * n * n)
            tracemalloc.stop()
            dc = times["coarse"][1]
            row.update(coarse_seconds=times["coarse"][0],
                       coarse_ratio=times["coarse"][0] / times["adhesiveless"][0],
                       coarse_status=str(dc["status"].values), coarse_outer=int(dc["iterations"]),
                       coarse_area=float(dc["area_fraction"]))
            rows.append(row)
            print(json.dumps(row), flush=True)
    return rows


LARGE_STARTS = ("adhesiveless", "coarse")


def large_rows(sizes, threads, out: Path, starts=LARGE_STARTS, front_tol=None,
               band_tol=None):
    """The viscoelastic adhesive loading state of cases/rough_convergence.toml (1e4 Pa) at
    the large grids with ``threads`` FFT threads, wall seconds, against its adhesiveless
    solve timed alike (the targets: 1024² in 2 min, 2048² in 15 min on 2 cores), from each
    of ``starts``: the adhesiveless solve (the default) and the coarse-grid start
    (``solver.coarse_start``), at ``front_tol`` cells and the band tests' ``band_tol``
    (None: the defaults).  Each finished row is merged into ``out`` at once, replacing the
    row of the same N, start, front_tol and band_tol of an earlier run; returns all the rows
    of ``out``."""
    from spectralbem.scenes import load_scene, solve

    case = ROUGH_CASE
    rows = json.loads(out.read_text()) if out.exists() else []
    for n in sizes:
        raw, free = _rough_case("sls")
        ov = {"grid.Nx": n, "grid.Ny": n, "solver.threads": threads}
        solve(load_scene(free, overrides=ov, base_dir=case.parent))  # plans, compiles
        w = time.perf_counter()
        free_pairs = _pairs(solve(load_scene(free, overrides=ov, base_dir=case.parent)))
        free_wall = time.perf_counter() - w
        for start in starts:
            extra = {"solver.coarse_start": start == "coarse"}
            if front_tol is not None:
                extra["solver.front_tol"] = front_tol
            if band_tol is not None:
                extra["solver.band_tol"] = band_tol
            scene = load_scene(raw, overrides={**ov, **extra}, base_dir=case.parent)
            w, c = time.perf_counter(), time.process_time()
            ds = solve(scene)
            wall, cpu = time.perf_counter() - w, time.process_time() - c
            row = dict(N=n, threads=threads, start=start, adhesive_wall=wall,
                       adhesive_cpu=cpu, adhesiveless_wall=free_wall, ratio=wall / free_wall,
                       status=str(ds["status"].values), outer=int(ds["iterations"]),
                       area=float(ds["area_fraction"]), mu=float(ds["mu"]),
                       mu_adhesive=float(ds["mu_adhesive"]), G1=float(ds["G1"]),
                       G2=float(ds["G2"]), dgamma=float(raw["adhesion"]["dgamma"]),
                       adhesive_pairs=_pairs(ds), adhesiveless_pairs=free_pairs,
                       front_tol=front_tol, band_tol=band_tol,
                       date=time.strftime("%Y-%m-%d"))
            rows = [r for r in rows if _large_key(r) != _large_key(row)] + [row]
            rows.sort(key=_large_key)
            out.write_text(json.dumps(rows, indent=1))
            print(json.dumps(row), flush=True)
    return rows


def _large_key(r: dict) -> tuple:
    """A large row's identity: N, front_tol, band_tol (None, the default, first), start."""
    ft, bt = r.get("front_tol"), r.get("band_tol")
    return (r["N"], -1.0 if ft is None else ft, -1.0 if bt is None else bt,
            LARGE_STARTS.index(r["start"]))


def _default_band_tol() -> float:
    """The band tests' tolerance of a scene that sets neither solver.tol nor band_tol."""
    from spectralbem.criterion import loose_band_rtol
    from spectralbem.schema import SECTIONS

    return loose_band_rtol(SECTIONS["solver"]["tol"].default)


def large_markdown(rows) -> str:
    lines = ["| N² | FFT threads | start | front_tol (cells) | band_tol | adhesive state "
             "(wall s) | its CPU "
             "s | adhesiveless (wall s) | ratio | FFT pairs (adhesive / adhesiveless) | status | "
             "front iterations | area | μ | μ_a | G1/Δγ | G2/Δγ | target | measured |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    target = {1024: 120.0, 2048: 900.0}
    for r in rows:
        t = target.get(r["N"])
        verdict = ("—" if t is None else
                   f"{t / 60:.0f} min: {'met' if r['adhesive_wall'] <= t else '**not met**'}")
        dg = r["dgamma"]
        start = {"coarse": "coarse grid"}.get(r["start"], r["start"])
        ft = (f"{FRONT_TOL:g} (default)" if r.get("front_tol") is None
              else f"{r['front_tol']:g}")
        bt = (f"{_default_band_tol():g} (default)" if r.get("band_tol") is None
              else f"{r['band_tol']:g}")
        lines.append(f"| {r['N']}² | {r['threads']} | {start} | {ft} | {bt} | "
                     f"{r['adhesive_wall']:.0f} | "
                     f"{r['adhesive_cpu']:.0f} | {r['adhesiveless_wall']:.2f} | "
                     f"**{r['ratio']:.0f}×** | "
                     + (f"{r['adhesive_pairs']} / {r['adhesiveless_pairs']} | "
                        if "adhesive_pairs" in r else "— | ")
                     + f"{r['status']} | {r['outer']} | {r['area']:.4f} | "
                     f"{r['mu']:.5f} | {r['mu_adhesive']:.3g} | {r['G1'] / dg:.3f} | "
                     f"{r['G2'] / dg:.3f} | {verdict} | {r['date']} |")
    return "\n".join(lines)


def adhesive_markdown(rows) -> str:
    lines = ["| N² | material | adhesive state (s) | adhesiveless (s) | ratio | FFT pairs "
             "(adhesive / adhesiveless) | ratio in pairs | status | front iterations | area "
             "(adhesive / adhesiveless) | with coarse start (s) | ratio | FFT pairs | status | "
             "fine front iterations | area | peak (N² arrays) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        def pairs(key, _r=r):  # rows recorded before the datasets counted transforms: —
            return f"{_r[key]}" if key in _r else "—"
        pr = f"**{r['pair_ratio']:.0f}×**" if "pair_ratio" in r else "—"
        lines.append(f"| {r['N']}² | {r['material']} | {r['adhesive_seconds']:.2f} | "
                     f"{r['adhesiveless_seconds']:.3f} | **{r['ratio']:.0f}×** | "
                     f"{pairs('adhesive_pairs')} / {pairs('adhesiveless_pairs')} | {pr} | "
                     f"{r['status']} | "
                     f"{r['outer']} | {r['area']:.4f} / {r['area_adhesiveless']:.4f} | "
                     f"{r['coarse_seconds']:.2f} | **{r['coarse_ratio']:.0f}×** | "
                     f"{pairs('coarse_pairs')} | "
                     f"{r['coarse_status']} | {r['coarse_outer']} | {r['coarse_area']:.4f} | "
                     f"{r.get('peak_arrays', float('nan')):.1f} |")
    return "\n".join(lines)


def cost_figure(adhesive, table):
    """CPU seconds (left) and peak memory (right) against N² (log-log): the elastic PK, the
    viscoelastic adhesiveless and the adhesive solves of the tables."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, am) = plt.subplots(1, 2, figsize=(11.0, 4.4), constrained_layout=True)
    newton_rows = [r for r in table if r["method"] == "newton"]
    series = [
        ("elastic PK (Tamaas-table surface)", newton_rows, "elastic_seconds", "k", "o"),
        ("viscoelastic, semismooth Newton (same)", newton_rows, "seconds", "C0", "s"),
    ]
    memory = [("viscoelastic, semismooth Newton", newton_rows, "C0", "s")]
    for mat, colour in (("elastic", "C2"), ("sls", "C3")):
        rs = [r for r in adhesive if r["material"] == mat]
        series.append((f"adhesive state, {mat} (rough_convergence)", rs, "adhesive_seconds",
                       colour, "^"))
        series.append((f"the same with the coarse start, {mat}", rs, "coarse_seconds", colour,
                       "x"))
        series.append((f"its adhesiveless solve, {mat}", rs, "adhesiveless_seconds", colour, "v"))
        memory.append((f"adhesive state, {mat}", rs, colour, "^"))
    for label, rs, key, colour, marker in series:
        if rs:
            n2 = [r["N"] ** 2 for r in rs]
            ax.loglog(n2, [r[key] for r in rs], marker=marker, color=colour, label=label,
                      ls={"v": "--", "x": ":"}.get(marker, "-"))
    n2_all = []
    for label, rs, colour, marker in memory:
        rs = [r for r in rs if r.get("peak_arrays")]
        if rs:
            n2 = [r["N"] ** 2 for r in rs]
            n2_all += n2
            am.loglog(n2, [r["peak_arrays"] * 8e-6 * r["N"] ** 2 for r in rs], marker=marker,
                      color=colour, label=f"{label} (numpy peak)")
    if n2_all:
        lim = np.array([min(n2_all), max(n2_all)], float)
        am.loglog(lim, 25 * 8e-6 * lim, "k--", lw=1, label="target: 25 N² float64 arrays")
    ax.set_xlabel("grid cells N²")
    ax.set_ylabel("CPU seconds (one thread)")
    ax.set_title("Cost of a solve against the grid size")
    am.set_xlabel("grid cells N²")
    am.set_ylabel("peak numpy allocations (MB)")
    am.set_title("Memory of a solve against the grid size")
    for a_ in (ax, am):
        a_.grid(True, which="both", alpha=0.3)
        a_.legend(fontsize=7)
    out = ROOT / "docs" / "figures" / "solve_cost.png"
    out.parent.mkdir(exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024, 2048])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "bench" / "viscoelastic.json"))
    ap.add_argument("--robustness", action="store_true")
    ap.add_argument("--starts", action="store_true")
    ap.add_argument("--adhesive", action="store_true")
    ap.add_argument("--large", action="store_true",
                    help="the viscoelastic adhesive state at 1024² and 2048² (or --sizes) "
                         "with --threads FFT threads, wall seconds")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--large-starts", nargs="+", choices=LARGE_STARTS, default=LARGE_STARTS,
                    help="--large: the starts to time (default both)")
    ap.add_argument("--front-tol", type=float, default=None,
                    help="--large: solver.front_tol in cells (default: the solver's, 0.5)")
    ap.add_argument("--band-tol", type=float, default=None,
                    help="--large: solver.band_tol (default: the solver's, "
                         f"{_default_band_tol():g})")
    ap.add_argument("--figure", action="store_true",
                    help="only redraw docs/figures/solve_cost.png from the JSON files")
    a = ap.parse_args(argv)
    if a.figure:
        cost_figure(json.loads((ROOT / "bench" / "viscoelastic_adhesive.json").read_text()),
                    json.loads(Path(a.out).read_text()))
        return
    stamp = f"Measured {time.strftime('%Y-%m-%d')} with `python bench/viscoelastic.py "
    if a.robustness:
        rows = robustness()
        (ROOT / "bench" / "viscoelastic_robustness.json").write_text(json.dumps(rows, indent=1))
        write_section("visco_robust", stamp + "--robustness` (128², tolerance 1e-10): "
                      + robustness_markdown(rows))
        return
    if a.adhesive:
        sizes = a.sizes if a.sizes != ap.get_default("sizes") else [128, 256, 512]
        rows = adhesive_rows(sizes)
        (ROOT / "bench" / "viscoelastic_adhesive.json").write_text(json.dumps(rows, indent=1))
        write_section("adhesive_cost", stamp + f"--adhesive --sizes {' '.join(map(str, sizes))}"
                      "` (CPU seconds, one thread):\n\n" + adhesive_markdown(rows))
        table = json.loads(Path(a.out).read_text()) if Path(a.out).exists() else []
        cost_figure(rows, table)
        return
    if a.large:
        sizes = a.sizes if a.sizes != ap.get_default("sizes") else [1024, 2048]
        rows = large_rows(sizes, a.threads, ROOT / "bench" / "viscoelastic_large.json",
                          tuple(a.large_starts), a.front_tol, a.band_tol)
        write_section("adhesive_large", "Measured with `python bench/viscoelastic.py --large "
                      "[--sizes 1024 2048] [--large-starts adhesiveless coarse] [--front-tol "
                      "F] [--band-tol B] --threads 2` (wall seconds, FFT threads as in the "
                      f"row, {os.cpu_count()} cores; a run replaces the rows of its sizes, "
                      "starts, front_tol and band_tol and keeps the others, each row with its "
                      "date):\n\n"
                      + large_markdown(rows))
        return
    if a.starts:
        rows = starts()
        (ROOT / "bench" / "viscoelastic_starts.json").write_text(json.dumps(rows, indent=1))
        write_section("visco_starts", stamp + "--starts`:\n\n" + starts_markdown(rows))
        return
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
