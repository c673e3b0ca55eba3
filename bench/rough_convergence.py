"""Grid refinement of adhesive contact on one physical rough surface (docs/rough_convergence.md).

The surface of ``cases/rough_convergence.toml`` (L = 1 mm, H = 0.8, roll-off 250 µm, cut-off
62.5 µm, rms slope 0.1, seed 3: the same Fourier coefficients at every N), elastic
(E = 1 MPa) or standard linear solid (E0 = 1 MPa, β = 10, τ = 10 ms, ζ = 0.1 at the roll-off),
ν = 0.5, Δγ = 0.01 J/m², a0 fixed in metres, along the load path 1e4 → 3e4 → 1e4 Pa
(loading, then unloading to the first load; ``--path stepped`` goes there and back in steps
of 5 kPa, each state from the last).  For each N: area fraction (sub-cell front),
mean gap, μ, μ_a, G1, G2, the hysteresis (unloading/loading area at 1e4 Pa − 1), statuses,
balanced fractions and CPU time; then the observed order and a Richardson estimate of the
error of each N from the three finest grids.

Usage: python bench/rough_convergence.py [--sizes 128 256 512] [--materials elastic sls]
           [--a0 7.8125e-6] [--sigma 1.5] [--front-tol 1.0] [--coarse-start] [--loading-only]
           [--extrapolate-a0] [--path direct|stepped]
           [--out bench/rough_convergence.json] [--report]
       python bench/rough_convergence.py --scan
       python bench/rough_convergence.py --import RUN.nc --materials sls --path stepped
``--report`` only rewrites docs/rough_convergence.md from the JSON; ``--scan`` runs the
elastic loading state against a0 and σ (SCAN; JSON rough_convergence_lengths.json).  σ, the
front smoothing, is given in units of a0 (``solver.front_smoothing``); ``--front-tol`` sets the
tolerance of the balance in position (cells, ``solver.front_tol``; default 0.5): each value its
own table.  ``--import`` takes the dataset of ``spectralbem run cases/rough_convergence.toml
--set grid.Nx=N --set grid.Ny=N --set "control.mean_pressure=[…the path's loads…]"`` (a path
too long for one sitting: the run keeps its finished steps when stopped) as that N's row.
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from spectralbem.criterion import default_smoothing  # noqa: E402
from spectralbem.keys import DELAYED, DELAYED_DEFAULT  # noqa: E402
from spectralbem.refinement import richardson  # noqa: E402
from spectralbem.scenes import load_scene, read_scene_file, solve  # noqa: E402
from spectralbem.solving import _spec_as_solved  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CASE = ROOT / "cases" / "rough_convergence.toml"
#: the case's a0 (m): 1, 2, 4, 8 cells at 128², 256², 512², 1024²
A0 = 7.8125e-6
#: the side L of the case's square cell (m): a0 in cells and areas per front length from it
SIDE = float(read_scene_file(CASE)["grid"]["Lx"])
KEYS = ("area_fraction", "mean_gap", "mu", "mu_adhesive", "G1", "G2")
#: the solver's rules a row records (:func:`current`): the release rates' definition
#: (δL_P/δA a ratio of sums along the front, docs/theory.md, "Release rates along the
#: front"), the band (the strip the front sweeps when it advances a0 along its normal,
#: "The band is a0 wide at every orientation") and the brackets of 2-cycles (the secant
#: through both masks' offsets, bisected where one offset lies beyond the band: a snap;
#: spectralbem.brackets, "Convergence").  When one of them changes, its constant changes
#: with it and the rows of the rule before leave the JSON (they cannot be rerun)
RATES = "ratio_of_sums"
BANDS = "advance"
BRACKETS = "bisect"


#: the load paths (Pa): the direct steps of the case file, and the quasi-static path through
#: steps of 5 kPa both ways (``--path stepped``); both hold the three states the tables
#: compare (:func:`_ref`)
PATHS = {"direct": (1e4, 3e4, 1e4),
         "stepped": (1e4, 1.5e4, 2e4, 2.5e4, 3e4, 2.5e4, 2e4, 1.5e4, 1e4)}


def _ref(r: dict) -> tuple:
    """The indices in a run's steps of the states the tables compare: loading at the first
    load, the top load, unloading back to the last (the first only for a loading-only run)."""
    p = [st["mean_pressure"] for st in r["steps"]]
    if len(p) < 3:
        return tuple(range(len(p)))
    return (0, int(np.argmax(p)), len(p) - 1)


def _state(r: dict, k: int) -> dict:
    """The k-th compared state of a run (0: load 1e4, 1: load 3e4, 2: unload 1e4)."""
    return r["steps"][_ref(r)[k]]


def _pa(p: float) -> str:
    """A load in the tables' notation, to two digits (1e4, 1.5e4: the reached mean pressure
    of a state is the asked one to the solver's tolerance)."""
    e = int(np.floor(np.log10(p)))
    m = round(p / 10**e, 1)
    if m >= 10:
        m, e = m / 10, e + 1
    return f"{m:g}e{e}"


def _step_name(r: dict, j: int) -> str:
    """The name of a run's j-th step: "load" up to the top load, "unload" after it."""
    ref = _ref(r)
    top = ref[1] if len(ref) > 1 else len(r["steps"])
    return ("load " if j <= top else "unload ") + _pa(r["steps"][j]["mean_pressure"])


def current(r: dict) -> bool:
    """A row solved by the solver's present rules (:data:`RATES`, :data:`BANDS`,
    :data:`BRACKETS`): the only rows the JSON keeps and the page shows (a row of a rule since
    replaced cannot be rerun)."""
    return (r.get("bands", "width") == BANDS and r.get("brackets", "clip") == BRACKETS
            and (r["material"] == "elastic" or r.get("release_rates") == RATES))
MATERIALS = {
    "elastic": {"kind": "elastic", "E": 1e6, "nu": 0.5},  # resting slab: no motion needed
    "sls": None,  # the case file's
}


def _solve(n: int, material: str, a0: float, sigma: float | None, loads=None,
           coarse: bool = False, front_tol: float | None = None,
           delayed: str = DELAYED_DEFAULT, extrapolate: bool = False):
    """(Dataset, CPU s) of the case at N², the material's overrides, a0 (m), σ (in units of
    a0, growing with large patches as by default; None: the material's default), the load path
    (None: the case's) and whether each state starts from the coarse grid's front."""
    raw = read_scene_file(CASE)
    if MATERIALS[material] is not None:
        raw["material"] = dict(MATERIALS[material])
    if loads is not None:
        raw["control"] = {"mean_pressure": list(loads)}
    ov = {"grid.Nx": n, "grid.Ny": n, "adhesion.a0": a0}
    if sigma is not None:
        ov["solver.front_smoothing"] = sigma
    if coarse:
        ov["solver.coarse_start"] = True
    if front_tol is not None:
        ov["solver.front_tol"] = front_tol
    if material == "elastic":  # explicit: the tables say which edge they used
        ov["solver.extrapolate_a0"] = bool(extrapolate)
    if material != "elastic":
        ov["solver.delayed_kernel"] = delayed
    t = time.process_time()
    ds = solve(load_scene(raw, overrides=ov, base_dir=CASE.parent))
    return ds, time.process_time() - t


def run_one(n: int, material: str, a0: float, sigma: float | None,
            coarse: bool = False, loading_only: bool = False,
            front_tol: float | None = None, delayed: str = DELAYED_DEFAULT,
            extrapolate: bool = False, path: str = "direct") -> dict:
    """One load path at N², the material's overrides, a0 (m), σ (units of a0, or None),
    from the adhesiveless start or the coarse grid's front (``coarse``); ``loading_only``:
    the first state of the path only (1e4 Pa); ``front_tol``: solver.front_tol (None: the
    default); ``delayed``: solver.delayed_kernel; ``extrapolate``: solver.extrapolate_a0;
    ``path``: the load path (:data:`PATHS`)."""
    ds, cpu = _solve(n, material, a0, sigma, loads=[1e4] if loading_only else PATHS[path],
                     coarse=coarse, front_tol=front_tol, delayed=delayed,
                     extrapolate=extrapolate)
    return _row(ds, cpu, n, material, a0, sigma, coarse, loading_only, front_tol, delayed,
                extrapolate, path)


def _row(ds, cpu, n, material, a0, sigma, coarse, loading_only, front_tol, delayed,
         extrapolate, path) -> dict:
    """The JSON row of a solved path (:func:`run_one`; ``cpu`` None where not measured)."""
    if "step" not in ds.dims:
        ds = ds.expand_dims("step")
    steps = []
    for k in range(ds.sizes["step"]):
        st = ds.isel(step=k)
        row = {key: float(st[key]) for key in KEYS if key != "mean_gap"}
        row["mean_gap"] = float(st["gap"].mean())
        # μ's other forms (JSON only): the profile force on the mask, and −Σ p v̂·∇u
        row.update(mu_profile=float(st["mu_profile"]), mu_dissipation=float(st["mu_dissipation"]))
        row.update(status=str(st["status"].values), iterations=int(st["iterations"]),
                   substeps=int(st["substeps"]) if "substeps" in st else 1,
                   balanced_fraction=float(st["balanced_fraction"]),
                   mean_pressure=float(st["mean_pressure"]),
                   unresolved_patches=int(st["unresolved_patches"]),
                   unresolved_front=int(st["unresolved_front"]),
                   crack_tip_length=float(st["crack_tip_length"]),
                   message=str(st["solver_message"].values if "solver_message" in st
                               else ds.attrs["solver_message"]))
        steps.append(row)
    hyst = (steps[-1]["area_fraction"] / steps[0]["area_fraction"] - 1.0 if len(steps) > 2
            else float("nan"))
    return dict(N=n, material=material, a0=a0, sigma=sigma, cpu=cpu, steps=steps,
                path="direct" if loading_only else path,
                hysteresis=hyst, coarse_start=coarse, loading_only=loading_only,
                release_rates=RATES, bands=BANDS, brackets=BRACKETS,
                front_tol=front_tol, extrapolate_a0=extrapolate,
                delayed_kernel=None if material == "elastic" else delayed)


def import_run(dataset: Path, material: str, path: str) -> dict:
    """The row of a path solved by ``spectralbem run`` of the case (a long path, whose run
    keeps its finished steps when stopped): its scene must be the one :func:`run_one` solves
    at the dataset's N (the case with ``material``'s overrides, the default a0, σ, kernel,
    tolerance and start, the loads of ``path``); the CPU time is not known (—)."""
    import xarray as xr

    with xr.open_dataset(dataset) as ds:
        ds.load()
    scene = json.loads(ds.attrs["scene"])
    n = int(scene["grid"]["Nx"])
    raw = read_scene_file(CASE)
    if MATERIALS[material] is not None:
        raw["material"] = dict(MATERIALS[material])
    raw["control"] = {"mean_pressure": list(PATHS[path])}
    ov = {"grid.Nx": n, "grid.Ny": n, "adhesion.a0": A0}
    if material != "elastic":
        ov["solver.delayed_kernel"] = DELAYED_DEFAULT
    problems = scene_differences(scene, load_scene(raw, overrides=ov, base_dir=CASE.parent))
    if problems:
        raise SystemExit(f"{dataset}: not the case's {path} path at {n}² with the defaults "
                         f"({', '.join(problems)} differ)")
    return _row(ds, None, n, material, A0, None, False, False, None, DELAYED_DEFAULT, False,
                path)


def scene_differences(scene: dict, want) -> list:
    """The sections in which a dataset's ``scene`` attribute (parsed) differs from the scene
    ``want`` as solved (FFT threads change no state: left out)."""
    want = json.loads(json.dumps(_spec_as_solved(want)))
    for spec in (scene, want):
        spec.get("solver", {}).pop("threads", None)
    return sorted(k for k in set(scene) | set(want) if scene.get(k) != want.get(k))


def _kernel(r: dict):
    """The run's solver.delayed_kernel (None: elastic; rows recorded before the key existed
    were sampled)."""
    return None if r["material"] == "elastic" else r.get("delayed_kernel") or "sampled"


def _key(r: dict) -> tuple:
    """A run's table: material, a0, σ, the start (rows before the coarse start: False),
    whether it is the loading state alone, the tolerance in position (None: default), the
    discretisation of the kernel's delayed part, the extrapolation of the elastic edge
    in a0, the band rule (rows before :data:`BANDS`: "width"), the bracket rule (rows
    before :data:`BRACKETS`: "clip") and the load path (:data:`PATHS`; rows before it:
    "direct")."""
    return (r["material"], r["a0"], r["sigma"], bool(r.get("coarse_start", False)),
            bool(r.get("loading_only", False)), r.get("front_tol"), _kernel(r),
            bool(r.get("extrapolate_a0", False)), r.get("bands", "width"),
            r.get("brackets", "clip"), r.get("path", "direct"))


def scan_one(n: int, a0_cells: float, sigma: float | None) -> dict:
    """The elastic loading state at 1e4 Pa at N² with a0 in cells and σ in units of a0 (a0
    is numerical in an elastic scene): area fraction (the balanced sub-cell front's), the
    mask's fraction of cells in contact, status, balanced fraction, front length, CPU s."""
    ds, cpu = _solve(n, "elastic", a0_cells * SIDE / n, sigma, loads=[1e4])
    return dict(N=n, a0_cells=a0_cells, sigma=sigma, cpu=cpu,
                area_fraction=float(ds["area_fraction"]),
                mask_fraction=float(ds["contact"].mean()), status=str(ds["status"].values),
                balanced_fraction=float(ds["balanced_fraction"]),
                front_length=float(ds["front_length"]),
                unresolved_patches=int(ds["unresolved_patches"]),
                unresolved_front=int(ds["unresolved_front"]))


def _cpu(r: dict) -> str:
    """A path's CPU seconds (— for a path imported from a run that did not measure them)."""
    return "—" if r["cpu"] is None else f"{r['cpu']:.0f}"


def _mm(length) -> str:
    """A length (m) in mm for the tables; — where the row predates the quantity."""
    return "—" if length is None or not np.isfinite(length) else f"{length * 1e3:.2f}"


#: the page's findings (docs/rough_convergence.md, "What this case shows"): numbers read off
#: the tables below and the pages they link; rewrite them when the tables are measured again
FINDINGS = (
    "- **Loading**: the viscoelastic loading state's area moves by 1.2 % and 0.45 % from "
    "256² to 512² to 1024² (the loading-only table), μ by 0.2 % and 0.1 %, G1 by 0.9 % and "
    "0.3 %, G2 by 0.5 % and 1.1 %, μ_a by 2.6 % and 5.1 % (1, 2 and 4 cells per vτ; the "
    "whole path at 1024² reaches the same loading state, 4227 CPU-s). The elastic loading "
    "area at a0 = 7.8 µm, edge extrapolated, moves by 0.2 % from 256² to 512² (0.2917, "
    "0.2922; 2 and 4 cells per a0) and is 1.7 % below at 1024² (0.2873, 8 cells, with 75 "
    "front cells of oscillating features narrower than a0 held unbalanced, [docs/theory.md,"
    " \"Features narrower than a0\"](theory.md#features-narrower-than-a0)); halving a0 to 3.9"
    " µm (one cell) at 256² moves it by −1.2 % (0.2881; −0.3 % at 3e4 Pa, −1.5 % on "
    "unloading; a0, numerical here, is not yet small against the patches). With the edge of"
    " the a0 tests alone (no extrapolation) the elastic loading areas lie 7.0 % and 8.4 % "
    "lower at 256² and 512² (0.2714, 0.2678; the table without \"edge extrapolated\"): the "
    "edge of a band 2 and 4 cells wide still moves with a0, which the extrapolation removes"
    " ([docs/theory.md, \"Extrapolating the elastic "
    "edge\"](theory.md#extrapolating-the-elastic-edge-to-a0--0)).",
    "- **The state at a load is not unique.** Adhesion makes the contact hysteretic: at 1e4"
    " Pa the elastic unloading state holds 5.6 % and 3.6 % more area than the loading state"
    " at 256² and 512² (both balanced), and the states between them are balanced too where "
    "the front is pinned by the roughness or a neck bridges two patches. Which one a solve "
    "reaches depends on its start, its tolerance and its load steps. From the coarse-grid "
    "start (the tables \"coarse-grid start\") the elastic areas read −0.9, −0.5, −0.5 % "
    "(256²) and −2.0, −1.2, −0.6 % (512²) from the adhesiveless start's at load 1e4, 3e4 "
    "and unload 1e4 Pa: as far as 256² from 512². The SLS path from the coarse-grid start "
    "keeps its loading and 3e4 Pa states within 1.4 % in area and μ, but μ_a moves by −5.4 "
    "% and −4.0 % on loading, and its direct unloading step reaches other states: area −2.2"
    " % and −5.6 %, μ −1.1 % and −8.0 %, μ_a −20 % and −14 % at 256² and 512² (the path's "
    "history is its own). Over the balance's tolerance (below, and "
    "[state_spread.md](state_spread.md)) area, μ, G1, G2 stay within 2.2 % and μ_a moves by"
    " up to 14 %. The spread between such states is the resolution of the question \"the "
    "state at this load\" on this surface, and for μ_a it is wider than 5 %.",
    "- **Unloading needs 512²** here. The elastic unloading area moves by 1.7 % from 256² "
    "to 512² (0.3080, 0.3027) and by 0.8 % to 1024² (0.3004), the SLS one by 1.0 % (0.2248,"
    " 0.2271) and its μ by 6.0 % (0.01647, 0.01746) along the direct step from 3e4 Pa. "
    "Unloaded in steps of 5 kPa instead, the two grids agree: area 0.2247 and 0.2241 (0.3 "
    "%), μ 0.01631 and 0.01633 (0.1 %), μ_a 0.9 %, G1 and G2 0.8 % (the table \"in steps\"), "
    "and the direct path at 1024² reads 0.2241 and μ 0.01645 on unloading: the 512² state "
    "of the direct step is the outlier, one of the neighbouring balanced states that step "
    "can reach ([docs/theory.md, \"Load-path steps\"](theory.md#load-path-steps)).",
    "- **Loaded and unloaded in steps of 5 kPa** (`--path stepped`, the table \"in steps\"), "
    "every state converges at 256² and 512², and the three compared states meet the 2 % and"
    " 5 % lines from 256² to 512²: area 1.2, 0.4, 0.3 %, μ 0.2, 0.2, 0.1 %, G1 0.9, 0.5, "
    "0.8 %, G2 0.5, 0.6, 0.8 %, μ_a 2.6, 3.5, 0.9 % at load 1e4, 3e4 and unload 1e4 "
    "(unloading area 0.2247 and 0.2241, μ 0.01631 and 0.01633). The intermediate states do "
    "not all: area, μ, G1 and G2 stay within 1.7 % at every step, but μ_a moves by 5.1, "
    "7.9, 10.8 and 5.7 % at load 1.5e4, 2.5e4 and unload 2e4, 1.5e4 Pa, and by 0.9-3.5 % at"
    " the other five: at 1-2 cells per vτ, a scatter of up to ±12 % whose sign changes from"
    " step to step about a shift of a few per cent. Two 512² unloading steps (to 2.5e4 and "
    "1.5e4 Pa) held front cells of oscillating features narrower than a0 unbalanced in one "
    "step and were solved again in sub-steps: the first balances with none held in two, the"
    " second holds 34 in four (28 in one) ([docs/theory.md, \"Features narrower than "
    "a0\"](theory.md#features-narrower-than-a0), the columns \"unresolved front\" and, in the "
    "JSON, `substeps`). CPU 9, 77 and 1698 s at 128²-512² for the nine states (826 s at "
    "512² without the sub-steps' retries).",
    "- **The stepped path at 1024²** (4 cells per vτ; not in the table: its first seven "
    "states, `spectralbem run cases/rough_convergence.toml --set grid.Nx=1024 --set "
    "grid.Ny=1024 --set solver.threads=2 --set \"control.mean_pressure=[1e4, 1.5e4, 2e4, "
    "2.5e4, 3e4, 2.5e4, 2e4, 1.5e4, 1e4]\"` stopped by SIGTERM in its eighth step, whose "
    "direct state took 462 front iterations, 40 min wall, and held front cells, and whose "
    "sub-steps had not ended 4 min later): every state `partial`, none with held cells. "
    "From 512² to 1024² area, μ, G1 and G2 move by at most 1.9, 0.7, 0.7 and 1.1 % (area "
    "and μ the most at unload 2e4 Pa), but μ_a by −4.9, −0.8, +7.3, +7.4, +3.6, +4.8, −6.3 "
    "% at load 1e4 … 3e4 and unload 2.5e4, 2e4 Pa (2.078, 2.062, 2.062, 1.810, 1.295, "
    "1.706, 1.974 × 10⁻⁴ at 1024²): no smaller than from 256² to 512² (+2.7, +5.4, +1.0, "
    "−7.3, +3.6, +3.6, +12.1 %). Refining from 2 to 4 cells per vτ does not narrow μ_a's "
    "spread: at this surface and a0 the path's μ_a is set to about ±7 % by which of the "
    "neighbouring balanced states a step reaches, not by the grid. Wall times of the seven "
    "steps on two FFT threads: 582 (beside a test run), 249, 339, 437, 393, 470, 898 s.",
    "- **μ_a at 3e4 Pa and on unloading** is not converged along the direct steps: 5.7 % "
    "and 18.5 % from 256² to 512², 4.9 % and 6.3 % from 512² to 1024² (1.21e-4, 1.27e-4 and"
    " 2.60e-4, 2.44e-4 at 512² and 1024²). The 1024² unloading state's 2.44e-4 lies 12 % "
    "below the 2.77e-4 and 2.79e-4 that 256² and 512² read after the 5 kPa steps, and at "
    "3e4 Pa the stepped path and the direct step differ by 6 % at 256² and 3 % at 512² "
    "(1.21e-4 against 1.14e-4, 1.25e-4 against 1.21e-4): there μ_a is set by the path to a "
    "few per cent, and path and grid are not separated ([docs/theory.md, \"Load-path "
    "steps\"](theory.md#load-path-steps)). G1 − G2 is 0.15-0.18 Δγ at these states, so a 1 %"
    " move of G1 moves μ_a by 6-7 %.",
    "- **How far the balance's tolerance sets μ_a** ([state_spread.md](state_spread.md), "
    "`bench/state_spread.py`). The stepped path solved at `front_tol` = 0.5, 0.25 and 0.125"
    " cells (the tables of those tolerances) reaches at every step balanced states whose "
    "area, μ, G1 and G2 agree within 2.2 % (medians 0.1-0.7 %), but whose μ_a differ by up "
    "to 14 % at 256² (median 4.8 %) and 7.7 % at 512² (median 2.5 %, two tolerances), with "
    "no trend in the tolerance (the loading state at 256²: 2.127, 2.279, 2.133 × 10⁻⁴). The"
    " states differ by 1-4 % of their contact cells, a cell or a few at a hundred or more "
    "places along the front (the loading state at 256²), and the change of μ_a comes from "
    "the crack tips next to those places: which front cells there are crack tips and not "
    "held by contact (308 → 335 and 509 → 417 of them), and their G. So on this 1 mm cell "
    "μ_a is defined by \"the state at this load\" to within ±4 % at 512² (half the largest "
    "range), the size of the 512² → 1024² differences of the stepped path (−4.9 … +7.4 %). "
    "Averaged over the tolerances, 256² and 512² agree within 3.4 % on loading and differ "
    "by −4.6 … +9.0 % on unloading, where 256² has one cell per vτ (μ_a 7 % low at one cell"
    " on the sinusoid). On a 2 mm cell at the 256² cell size (512², four times the "
    "crack-tip length) the spread between two tolerances is no narrower (median 2.3 %, "
    "largest 9.3 %, against 2.9 % and 6.9 % at 1 mm), so a larger cell does not average it "
    "away. Averaged over eight tolerances per grid "
    "([state_ensemble.md](state_ensemble.md)), the loading state's μ_a agrees within 2.0 ± "
    "1.2 % and 1.2 ± 0.9 % from 256² to 512² to 1024² (standard errors of the means), while"
    " after the direct unloading step and a slow loading the 256² means are 11-12 % off the "
    "512² ones (256² resolves vτ with one cell), and after the direct unloading step the "
    "512² mean is still 7.9 ± 1.3 % off 1024²'s (two 1024² states).",
)


def report(runs: list, path: Path, scans: list = ()) -> None:
    lines = ["# Rough-surface adhesive contact: grid refinement", "",
             "One physical rough surface (`cases/rough_convergence.toml`: L = 1 mm, H = 0.8, "
             "roll-off 250 µm, cut-off 62.5 µm, rms slope 0.1, seed 3 — the same Fourier "
             "coefficients at every N), elastic (E = 1 MPa) or SLS (E0 = 1 MPa, β = 10, "
             "τ = 10 ms, ζ = 0.1 at the roll-off), Δγ = 0.01 J/m², a0 fixed in metres, "
             "along the load path 1e4 → 3e4 → 1e4 Pa, solved at N = 128 … 1024. "
             "Generated by `python bench/rough_convergence.py --report` from "
             "bench/rough_convergence.json; the title of each table names the options that "
             "rerun it (`python bench/rough_convergence.py --materials … --sizes … "
             "[options]`). To refine a scene of your own the same way: `spectralbem refine` "
             "(docs/user_guide.md).", "",
             *resolution_table(runs),
             "![refinement](figures/rough_convergence.png)", "",
             "The figure: area fraction, μ, the release rates, μ_a at the path's three states "
             "and the crack-tip length it is summed over against N (open markers: "
             "states not verified; dashed: the coarse-grid start; stars and crosses: the "
             "elastic edge extrapolated to a0 → 0, `--extrapolate-a0`; the elastic a0 = one cell "
             "row is the scan below; μ's u-form, −Σ p v̂·∇u on the mask, is drawn for "
             "comparison with the reported μ, "
             "[docs/theory.md, \"Outputs\"](theory.md#outputs)).", "",
             "## How to read the tables", "",
             "- The error columns are Richardson estimates from the three finest grids of a "
             "table: — where the differences do not shrink monotonically or shrink slower "
             "than order ½ or faster than order 4 (no asymptotic range yet: "
             "`spectralbem.refinement.richardson`). They measure the grid error at the "
             "stated a0 only.",
             "- **Elastic scenes**: a0 is numerical, and the answer also moves with a0 while "
             "a0 is not small against the contact patches (compare the tables of 3.9 and "
             "7.8 µm). The default edge is extrapolated to a0 → 0 (`solver.extrapolate_a0`, "
             "on from a0 = 2 cells: the tables marked \"edge extrapolated\"); the other "
             "elastic tables keep the edge of the a0 tests alone. From a0 = 2 cells the band "
             "is a0 wide at every orientation (`criterion.exact_width`), below it whole "
             "layers: the 128² row at 7.8 µm and the 256² row at 3.9 µm have a0 = one cell, "
             "so the Richardson estimates of those tables mix two band rules.",
             "- **Viscoelastic scenes**: the relaxation length vτ (3.98 µm: 0.5, 1, 2, 4 "
             "cells at 128²-1024²) must span about two cells: on the sinusoid against the 1D "
             "method μ_a is within 1 % from 2 cells per vτ and −7 % at one cell "
             "(docs/performance.md, \"Resolving the relaxation length\").",
             "- μ_a = −Σ (G − Δγ)(n·v̂) ds / W is a difference: G1 − Δγ and Δγ − G2 are about a "
             "tenth of Δγ here, so a 1 % move of G1 moves μ_a by about 10 %. G1, G2 and μ_a "
             "are taken over the crack tips only, the column \"crack tips (mm)\" (the part "
             "of the front not held by contact: about a third of the front in the "
             "viscoelastic states, five sixths in the elastic ones; — in rows recorded "
             "before the dataset had it).",
             "- \"unresolved front (cells)\": front cells of oscillating tongues of the "
             "contact or notches of the gap narrower than 2 a0 that the solver held "
             "unbalanced (`unresolved_front`, left out of the status and of G1, G2, μ_a; — in "
             "rows recorded before the dataset had it).",
             "- Compare grids along one start: the tables marked \"coarse-grid start\" solve "
             "the same path from the coarse grid's front (`--coarse-start`, "
             "`solver.coarse_start`) and reach other balanced states (below).", "",
             "## What this case shows", "",
             *FINDINGS, "",
             "## The tables", "",
             "The default tables first (the elastic edge extrapolated to a0 → 0, the sls "
             "path and loading state with the default kernel), then the other numerical "
             "lengths and starts.", ""]
    by = {}
    for r in runs:
        by.setdefault(_key(r), []).append(r)
    for (mat, a0, sig, coarse, only, ftol, dk, ex, _bands, _brackets, pth), rs in sorted(
            by.items(), key=_table_order):
        rs = sorted(rs, key=lambda r: r["N"])
        lines += [f"### {mat}, a0 = {a0 * 1e6:g} µm, front smoothing σ = "
                  f"{f'default ({_default_sigma(mat):g} a0)' if sig is None else f'{sig:g} a0'}"
                  + (", coarse-grid start" if coarse else "")
                  + (f", front_tol = {ftol:g} cells (`--front-tol`)" if ftol is not None else "")
                  + (", loading state only (`--loading-only`)" if only else "")
                  + (", edge extrapolated to a0 → 0 (`--extrapolate-a0`)" if ex else "")
                  + ("" if dk is None else f", delayed kernel: {dk}"
                     + (" (default)" if dk == DELAYED_DEFAULT else " (`--delayed-kernel`)"))
                  + ("" if pth == "direct" else ", loaded and unloaded in steps of 5 kPa "
                     "(`--path stepped`)"),
                  "",
                  "| N | step | status | balanced | area | mean gap (µm) | μ | μ_a | G1/Δγ | "
                  "G2/Δγ | crack tips (mm) | unresolved front (cells) | CPU s (path) |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rs:
            for k, st in enumerate(r["steps"]):
                name = _step_name(r, k)
                lines.append(
                    f"| {r['N']} | {name} | {st['status']} | {st['balanced_fraction']:.3f} | "
                    f"{st['area_fraction']:.4f} | {st['mean_gap'] * 1e6:.4f} | "
                    f"{_num(st['mu'], '.4g')} | {_num(st['mu_adhesive'], '.3g')} | "
                    f"{_num(st['G1'] / 0.01, '.3f')} | {_num(st['G2'] / 0.01, '.3f')} | "
                    f"{_mm(st.get('crack_tip_length'))} | {st.get('unresolved_front', '—')} | "
                    f"{_cpu(r) if k == 0 else ''} |")
        lines.append("")
        if len(rs) >= 3:
            lines += ["Observed order p and Richardson estimate of the relative error at each N "
                      "(from the three finest grids):", "",
                      "| quantity | p | extrapolated | " + " | ".join(
                          f"err N={r['N']}" for r in rs) + " |",
                      "|---|---|---|" + "---|" * len(rs)]
            steps = ((0, "load 1e4"),) if only else ((0, "load 1e4"), (2, "unload 1e4"))
            keys = (("area_fraction", "mean_gap", "mu", "G1", "G2", "mu_adhesive") if only
                    else ("area_fraction", "mean_gap", "mu"))
            for k, name in steps:
                for key in keys:
                    vals = [_state(r, k)[key] for r in rs]
                    if max(abs(v) for v in vals) < 1e-12:  # zero to round-off (elastic μ)
                        continue
                    if not all(_verified(r, k) for r in rs[-3:]):
                        lines.append(f"| {key} ({name}) | unverified state | | "
                                     + " | ".join("" for _ in rs) + " |")
                        continue
                    lines.append(f"| {key} ({name}) | " + _richardson_cells(vals, 5, 2))
            if not only and all(_verified(r, k) for r in rs[-3:] for k in (0, 2)):
                lines.append("| hysteresis | " + _richardson_cells(
                    [r["hysteresis"] for r in rs], 4, 1))
            lines.append("")
        lines += _pair_table(rs, tuple(r["N"] for r in rs[-2:]) if only else (256, 512))
        if not only and rs[-1]["N"] > 512:  # and the two finest grids of a longer path
            lines += _pair_table(rs, tuple(r["N"] for r in rs[-2:]))
    lines += lengths_report(scans)
    path.write_text("\n".join(lines) + "\n")
    figure(runs, scans, path.parent / "figures" / "rough_convergence.png")


def _num(v, fmt: str) -> str:
    """``v`` formatted, "—" where it is not finite (a state that is not verified has no
    release rates)."""
    return format(v + 0.0, fmt) if np.isfinite(v) else "—"  # + 0.0: no "-0"


def _richardson_cells(vals, digits: int, err_digits: int) -> str:
    """The cells "p | extrapolated | errors… |" of a Richardson row; "—" where the grids
    give no estimate (``refinement.richardson``: no asymptotic range yet)."""
    p, finf, errs = richardson(vals)
    if not (np.isfinite(p) and np.isfinite(finf)):
        return (f"{p:.2f} | — | " if np.isfinite(p) else "— | — | ") + " | ".join(
            "—" for _ in errs) + " |"
    return f"{p:.2f} | {finf:.{digits}g} | " + " | ".join(
        f"{e * 100:.{err_digits}f} %" for e in errs) + " |"


def _series(runs, material, step, key, coarse=False, only=None, a0=A0, path="direct"):
    """(N, value, verified) of one quantity of one compared state (:func:`_state`) along a
    table's grids at ``a0`` (the adhesiveless-start path and, where ``only`` is None, the
    loading-only runs too) along the load path ``path``."""
    pts = {}
    for r in runs:
        if (r["material"] != material or bool(r.get("coarse_start", False)) != coarse
                or abs(r["a0"] - a0) > 1e-6 * a0
                or r["sigma"] is not None or r.get("front_tol") is not None
                or r.get("extrapolate_a0", False)
                or _kernel(r) not in (None, DELAYED_DEFAULT)
                or r.get("path", "direct") != path or step >= len(_ref(r))):
            continue
        if only is not None and bool(r.get("loading_only", False)) != only:
            continue
        st = _state(r, step)
        if key in st:
            pts.setdefault(r["N"], (st[key], _verified(r, step)))
    ns = sorted(pts)
    return ns, [pts[n][0] for n in ns], [pts[n][1] for n in ns]


def _plot(ax, ns, vals, ok, label, style="-", marker="o", color=None):
    if not ns:
        return
    line, = ax.plot(ns, vals, style, color=color, label=label)
    c = line.get_color()
    for n, v, good in zip(ns, vals, ok, strict=True):
        ax.plot([n], [v], marker, color=c, mfc=c if good else "white")


def figure(runs: list, scans: list, out: Path) -> None:
    """Area fraction, μ, G1, G2, μ_a and the crack-tip length against N from the JSON
    (docs/rough_convergence.md)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 3, figsize=(15, 7.5))
    (ae, asls, ama), (amu, ag, atip) = axes
    names = {0: "loading 1e4 Pa", 2: "unloading to 1e4 Pa"}
    for k, col in ((0, "C0"), (2, "C3")):
        _plot(ae, *_series(runs, "elastic", k, "area_fraction"), names[k] + ", a0 tests' edge",
              color=col)
        start = "coarse-grid start" if k == 0 else ""
        _plot(ae, *_series(runs, "elastic", k, "area_fraction", coarse=True), start, "--",
              "s", col)
        _plot(asls, *_series(runs, "sls", k, "area_fraction"), names[k], color=col)
        _plot(asls, *_series(runs, "sls", k, "area_fraction", coarse=True), start, "--",
              "s", col)
        _plot(asls, *_series(runs, "sls", k, "area_fraction", path="stepped"),
              "in steps of 5 kPa" if k == 0 else "", "-.", "D", col)
    one = sorted((r for r in scans if r["a0_cells"] == 1 and r["sigma"] is None),
                 key=lambda r: r["N"])
    _plot(ae, [r["N"] for r in one], [r["area_fraction"] for r in one],
          [r["status"] == "partial" for r in one],
          "loading, a0 = one cell", ":", "^", "C2")
    _plot(ae, *_series(runs, "elastic", 0, "area_fraction", a0=A0 / 2),
          f"loading, a0 = {A0 / 2 * 1e6:.2g} µm", "-.", "v", "C4")
    for k, col, mk in ((0, "C0", "*"), (2, "C3", "P")):  # the edge extrapolated to a0 → 0
        ex = sorted((r for r in runs if r["material"] == "elastic" and r.get("extrapolate_a0")
                     and abs(r["a0"] - A0) <= 1e-6 * A0 and len(_ref(r)) > k
                     and r.get("path", "direct") == "direct"),
                    key=lambda r: r["N"])
        if ex:
            _plot(ae, [r["N"] for r in ex], [_state(r, k)["area_fraction"] for r in ex],
                  [_verified(r, k) for r in ex],
                  ("loading" if k == 0 else "unloading") + ", edge extrapolated",
                  ":", mk, col)
    tol1 = sorted((r for r in runs if r["material"] == "elastic" and r.get("front_tol") == 1.0
                   and abs(r["a0"] - A0) <= 1e-6 * A0), key=lambda r: r["N"])
    if tol1:
        ae.plot([r["N"] for r in tol1], [r["steps"][0]["area_fraction"] for r in tol1], "D",
                color="C0", mfc="none", label="loading, front_tol = 1 cell")
    _plot(amu, *_series(runs, "sls", 0, "mu"), "μ (profile force at the front)", color="C0")
    _plot(amu, *_series(runs, "sls", 0, "mu_dissipation"), "u-form −Σ p v̂·∇u / W", ":",
          "x", "C7")
    _plot(ag, *_series(runs, "sls", 0, "G1"), "G1 (trailing)", color="C0")
    _plot(ag, *_series(runs, "sls", 0, "G2"), "G2 (leading)", color="C1")
    # μ_a and the crack tips it is summed over, at the three states of the path (the cells
    # per vτ: 0.5, 1, 2, 4 at 128²-1024²)
    steps = {0: ("loading 1e4 Pa", "C0"), 1: ("3e4 Pa", "C2"), 2: ("unloading to 1e4 Pa", "C3")}
    for k, (name, col) in steps.items():
        _plot(ama, *_series(runs, "sls", k, "mu_adhesive"), name, color=col)
        _plot(ama, *_series(runs, "sls", k, "mu_adhesive", coarse=True),
              "coarse-grid start" if k == 0 else "", "--", "s", col)
        _plot(ama, *_series(runs, "sls", k, "mu_adhesive", path="stepped"),
              "in steps of 5 kPa" if k == 0 else "", "-.", "D", col)
        ns, vals, ok = _series(runs, "sls", k, "crack_tip_length")
        _plot(atip, ns, [1e3 * v for v in vals], ok, name, color=col)
    titles = (f"elastic, a0 = {A0 * 1e6:.2g} µm (and as noted): area fraction",
              f"SLS, a0 = {A0 * 1e6:.2g} µm: area fraction",
              "SLS: adhesive friction μ_a (vτ = 0.5, 1, 2, 4 cells)",
              "SLS, loading: friction coefficient", "SLS, loading: release rates (J/m²)",
              "SLS: crack-tip length (mm), μ_a's support")
    for ax, title in zip(axes.ravel(), titles, strict=True):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("N (cells per side, L = 1 mm)")
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        if ax.get_lines() and ax is not ae:
            ax.legend(fontsize=8)
    lo, hi = ae.get_ylim()  # room above the data for the elastic panel's longer legend
    ae.set_ylim(lo, hi + 0.8 * (hi - lo))
    ae.legend(fontsize=7, ncol=2, loc="upper center")
    ag.axhline(0.01, color="k", lw=0.8, ls=":")
    save_figure(fig, out)


def save_figure(fig, out: Path) -> None:
    """Lay out ``fig``, write it to ``out`` (its folder made if missing) and close it."""
    import matplotlib.pyplot as plt
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)


#: the statuses of a verified state
VERIFIED = ("partial", "full_contact", "detached")


def _verified(run: dict, k: int) -> bool:
    """Whether the k-th compared state (:func:`_state`) holds a verified status."""
    return _state(run, k)["status"] in VERIFIED


#: the quantities compared between 256² and 512² and the relative tolerance each must meet
PAIR = (("area_fraction", 0.02), ("mu", 0.02), ("G1", 0.05), ("G2", 0.05),
        ("mu_adhesive", 0.05))


def _pair_table(rs: list, pair=(256, 512)) -> list:
    """The relative change of each quantity between the grids ``pair`` (N) against its
    tolerance."""
    by_n = {r["N"]: r for r in rs}
    if len(pair) < 2 or pair[0] not in by_n or pair[1] not in by_n:
        return []
    a, b = by_n[pair[0]], by_n[pair[1]]
    lines = [f"{pair[0]}² against {pair[1]}² (relative change; the tolerance after the "
             "slash):", "",
             "| step | " + " | ".join(k for k, _ in PAIR) + " |",
             "|---|" + "---|" * len(PAIR)]
    # every step of a stepped path (its intermediate states too), the compared ones else
    if a.get("path", "direct") == "stepped" and len(a["steps"]) == len(b["steps"]):
        rows = [(j, j, _step_name(a, j)) for j in range(len(a["steps"]))]
    else:
        names = ("load 1e4", "load 3e4", "unload 1e4")
        rows = [(_ref(a)[k], _ref(b)[k], name)
                for k, name in enumerate(names[:min(len(_ref(a)), len(_ref(b)))])]
    for ja, jb, name in rows:
        cells = []
        sa, sb = a["steps"][ja], b["steps"][jb]
        for key, tol in PAIR:
            x, y = sa[key], sb[key]
            if not (sa["status"] in VERIFIED and sb["status"] in VERIFIED):
                cells.append("unverified")
            elif max(abs(x), abs(y)) < 1e-12:
                cells.append("0 (both)")
            else:
                d = abs(x / y - 1.0)
                cells.append(f"{100 * d:.1f} % / {100 * tol:g} % "
                             + ("holds" if d <= tol else "**fails**"))
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines + [""]


#: the quantities of the resolution table and the accuracies it states
RESOLUTION_KEYS = ("area_fraction", "mu", "G1", "G2", "mu_adhesive")
ACCURACIES = (0.05, 0.01)


def _table_runs(runs, material: str, extrapolate: bool, path: str = "direct") -> list:
    """The default table's runs of a material along the whole load path ``path``, by N
    (adhesiveless start, a0 = A0, default σ, tolerance and kernel)."""
    want = (material, A0, None, False, False, None,
            None if material == "elastic" else DELAYED_DEFAULT, extrapolate, BANDS, BRACKETS,
            path)
    return sorted((r for r in runs if _key(r) == want),
                  key=lambda r: r["N"])


def _coarsest(rs: list, k: int, key: str, acc: float) -> str:
    """The coarsest N from which every grid's value lies within ``acc`` of the finest
    grid's, where the two finest agree within acc/2 (else "not yet" and their difference)."""
    rs = [r for r in rs if _verified(r, k)]
    if len(rs) < 2:
        return "—"
    vals = [_state(r, k)[key] for r in rs]
    ref = vals[-1]
    if max(abs(v) for v in vals) < 1e-12:
        return "0 (elastic)"
    dev = [abs(v / ref - 1.0) for v in vals]
    if dev[-2] > acc / 2:
        return f"not yet ({100 * dev[-2]:.1f} %)"
    n = rs[-2]["N"]
    for r, d in zip(reversed(rs[:-1]), reversed(dev[:-1]), strict=True):
        if d > acc:
            break
        n = r["N"]
    return f"{n}²"


def resolution_table(runs: list) -> list:
    """The section "What resolution for 5 % and 1 %": per material, step and quantity, the
    coarsest grid of the default tables (:func:`_coarsest`), and the cells per physical
    length at each N."""
    lines = ["## What resolution for 5 % and 1 %", "",
             "From the default tables below (the elastic edge extrapolated to a0 → 0, the sls "
             "path with the default kernel): the coarsest grid from which every grid's value "
             "lies within 5 % (1 %) of the finest grid's, stated only where the two finest "
             "grids agree within half of that (\"not yet (x %)\": they differ by x %, and "
             "no grid measured reaches that accuracy for certain). In this case's "
             "lengths: N² has N/16 cells per cut-off wavelength (62.5 µm), ≈ N/250 per vτ "
             "(3.98 µm) and N/128 per a0 (7.8 µm); on another surface, scale by those "
             "lengths.", "",
             "| material | step | " + " | ".join(
                 f"{k} {100 * a:g} %" for k in RESOLUTION_KEYS for a in ACCURACIES) + " |",
             "|---|---|" + "---|" * (len(RESOLUTION_KEYS) * len(ACCURACIES))]
    for material, ex, path in (("elastic", True, "direct"), ("sls", False, "stepped"),
                               ("sls", False, "direct")):
        rs = _table_runs(runs, material, ex, path)
        if len(rs) < 2:
            continue
        names = ("load 1e4", "load 3e4", "unload 1e4")
        for k, name in enumerate(names[:min(len(_ref(r)) for r in rs)]):
            cells = [_coarsest(rs, k, key, a) if not (material == "elastic"
                                                      and key != "area_fraction")
                     else "—" for key in RESOLUTION_KEYS for a in ACCURACIES]
            grids = ", ".join(f"{r['N']}²" for r in rs)
            lines.append(f"| {material}{', in steps' if path == 'stepped' else ''} ({grids}) "
                         f"| {name} | " + " | ".join(cells) + " |")
    return lines + [""]


#: the default tables, in the page's order: the elastic path with the edge extrapolated to
#: a0 → 0, the sls path and the sls loading state (every other setting the solver's default)
DEFAULT_TABLES = (("elastic", A0, None, False, False, None, None, True, BANDS, BRACKETS,
                   "direct"),
                  ("sls", A0, None, False, False, None, DELAYED_DEFAULT, False, BANDS,
                   BRACKETS, "stepped"),
                  ("sls", A0, None, False, False, None, DELAYED_DEFAULT, False, BANDS,
                   BRACKETS, "direct"),
                  ("sls", A0, None, False, True, None, DELAYED_DEFAULT, False, BANDS,
                   BRACKETS, "direct"))


def _table_order(item) -> tuple:
    """The page's order of the tables (``by``'s items): the defaults first, then by key."""
    key = item[0]
    return (DEFAULT_TABLES.index(key) if key in DEFAULT_TABLES else len(DEFAULT_TABLES),
            str(key))


def _default_sigma(material: str) -> float:
    """The solver's default σ/a0 for the material (criterion.default_smoothing)."""
    return default_smoothing(None, material != "elastic")


def _mask_columns(r: dict) -> str:
    """The mask's fraction and the mean offset of the balanced edge beyond the mask's edge
    (µm: the area between them per front length); '— | —' for a row measured before the
    scan recorded the mask."""
    if "mask_fraction" not in r:
        return "— | —"
    if r["status"] != "partial":  # no balanced front: no edge beyond the mask
        return f"{r['mask_fraction']:.4f} | —"
    beyond = (r["area_fraction"] - r["mask_fraction"]) * SIDE**2 / r["front_length"]
    return f"{r['mask_fraction']:.4f} | {beyond * 1e6:+.2f}"


def lengths_report(scans: list) -> list:
    """The tables of the elastic loading state against a0 and σ at each N, and of a0 = one
    cell at every N with its Richardson estimate."""
    if not scans:
        return []
    lines = ["## Numerical lengths of the elastic state (loading, 1e4 Pa)", "",
             "`python bench/rough_convergence.py --scan`: a0 and the front smoothing σ "
             f"(default in an elastic scene: {_default_sigma('elastic'):g} a0; every row grows "
             "σ to 0.23 of a large patch's radius), the edge of the a0 tests alone "
             "(`solver.extrapolate_a0 = false`); — where the state is not verified. "
             "area: the balanced sub-cell front's; "
             "mask: the fraction of cells in contact; edge beyond the mask: their difference "
             "per front length, the mean offset of the balanced edge from the mask's edge.", "",
             "| N | a0 (cells) | a0 (µm) | σ/a0 | σ (µm) | status | balanced | area | mask | "
             "edge beyond the mask (µm) | front length (mm) | CPU s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(scans, key=lambda r: (r["N"], r["a0_cells"], -1 if r["sigma"] is None
                                          else r["sigma"])):
        a0 = r['a0_cells'] * SIDE * 1e6 / r['N']
        sig = _default_sigma("elastic") if r['sigma'] is None else r['sigma']
        ok = r["status"] == "partial"  # a verified state: the balanced front's area
        lines.append(f"| {r['N']} | {r['a0_cells']:g} | {a0:.3g} | "
                     f"{'default' if r['sigma'] is None else format(sig, 'g')} | "
                     f"{sig * a0:.3g} | "
                     f"{r['status']} | {r['balanced_fraction']:.3f} | "
                     f"{r['area_fraction'] if ok else '—':{'.4f' if ok else ''}} | "
                     f"{_mask_columns(r)} | {_mm(r['front_length'] if ok else None)} | "
                     f"{r['cpu']:.0f} |")
    one = sorted((r for r in scans if r["a0_cells"] == 1 and r["sigma"] is None),
                 key=lambda r: r["N"])
    if len(one) >= 3:
        vals = [r["area_fraction"] for r in one]
        p, finf, errs = richardson(vals)
        lines += ["", "a0 = one cell and the default σ at every N (both numerical lengths "
                  "shrink with h): observed order and Richardson estimate of the area's "
                  "relative error (three finest grids)", "",
                  "| p | extrapolated | " + " | ".join(f"err N={r['N']}" for r in one) + " |",
                  "|---|---|" + "---|" * len(one),
                  f"| {p:.2f} | {finf:.4f} | " + " | ".join(f"{e * 100:.2f} %" for e in errs)
                  + " |"]
    return lines + [""]


#: the numerical-length scan: (N, a0 in cells, σ in units of a0 or None = default): a0 of
#: one cell at every N; a0 of 2 and 4 cells; σ against a0 = 7.8 µm fixed in metres; the
#: viscoelastic default σ = 1.5 a0 at a0 of one and eight cells (at 1024², a0 = 8 cells, the
#: elastic default ½ a0 wanders: docs/theory.md)
SCAN = ([(n, 1.0, None) for n in (128, 256, 512, 1024)]
        + [(n, m, None) for n in (256, 512) for m in (2.0, 4.0)]
        + [(n, n / 128, sig) for n in (256, 512) for sig in (0.0, 1.5, 3.0)]
        + [(1024, 8.0, 1.5), (256, 1.0, 1.5), (512, 1.0, 1.5)])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=None,
                    help="N of the load paths (default 128 256 512); with --scan: only the "
                         "scan's rows at these N (default all)")
    ap.add_argument("--materials", nargs="+", default=["elastic", "sls"],
                    choices=sorted(MATERIALS))
    ap.add_argument("--a0", type=float, nargs="+", default=[A0])
    ap.add_argument("--sigma", type=float, default=None)
    ap.add_argument("--front-tol", type=float, default=None,
                    help="solver.front_tol in cells (default: the solver's): a separate table")
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name(
        "rough_convergence.json"))
    ap.add_argument("--coarse-start", action="store_true",
                    help="start every state from the coarse grid's front "
                         "(solver.coarse_start): a separate table")
    ap.add_argument("--loading-only", action="store_true",
                    help="the first state of the path only (1e4 Pa): a separate table, for "
                         "grids where the whole path is too long (1024²)")
    ap.add_argument("--delayed-kernel", default=DELAYED_DEFAULT, choices=DELAYED,
                    help="solver.delayed_kernel of the viscoelastic scenes: a separate table")
    ap.add_argument("--extrapolate-a0", action="store_true",
                    help="elastic: solver.extrapolate_a0 (the edge of the tests at a0 and "
                         "a0/2 extrapolated to a0 → 0): a separate table")
    ap.add_argument("--path", default="direct", choices=sorted(PATHS),
                    help="the load path: the case's direct steps 1e4 → 3e4 → 1e4 Pa, or "
                         "steps of 5 kPa both ways (stepped): a separate table")
    ap.add_argument("--import", dest="imported", type=Path, default=None,
                    help="a dataset of `spectralbem run` of the case's --path (one material): "
                         "its row replaces the row of its N (a long path run apart)")
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--scan", action="store_true",
                    help="only the elastic state against a0 and σ (SCAN)")
    args = ap.parse_args(argv)
    runs = json.loads(args.out.read_text()) if args.out.exists() else []
    runs = [r for r in runs if current(r)]  # rows of replaced rules cannot be rerun
    scan_path = args.out.with_name(args.out.stem + "_lengths.json")
    scans = json.loads(scan_path.read_text()) if scan_path.exists() else []
    if args.scan:
        for n, m, sig in SCAN:
            if args.sizes and n not in args.sizes:
                continue
            r = scan_one(n, m, sig)
            scans = [x for x in scans if (x["N"], x["a0_cells"], x["sigma"]) != (n, m, sig)]
            scans.append(r)
            scan_path.write_text(json.dumps(scans, indent=1))
            print(f"elastic N={n} a0={m:g} cells sigma={sig}: area {r['area_fraction']:.4f} "
                  f"{r['status']} cpu {r['cpu']:.0f} s", flush=True)
    elif args.imported is not None:
        if len(args.materials) != 1:
            raise SystemExit("--import takes one --materials")
        r = import_run(args.imported, args.materials[0], args.path)
        runs = [x for x in runs if (x["N"],) + _key(x) != (r["N"],) + _key(r)] + [r]
        args.out.write_text(json.dumps(runs, indent=1))
        print(f"{r['material']} N={r['N']} ({args.path}): areas "
              f"{[round(x['area_fraction'], 4) for x in r['steps']]}", flush=True)
    elif not args.report:
        for mat in args.materials:
            for a0 in args.a0:
                for n in args.sizes or (128, 256, 512):
                    r = run_one(n, mat, a0, args.sigma, args.coarse_start,
                                args.loading_only, args.front_tol, args.delayed_kernel,
                                args.extrapolate_a0, args.path)
                    runs = [x for x in runs if (x["N"],) + _key(x) != (n,) + _key(r)] + [r]
                    args.out.write_text(json.dumps(runs, indent=1))
                    s = r["steps"]
                    print(f"{mat} N={n} a0={a0:g}: areas "
                          f"{[round(x['area_fraction'], 4) for x in s]} statuses "
                          f"{[x['status'] for x in s]} cpu {r['cpu']:.0f} s", flush=True)
    # the documentation's page only from the repository's own JSON; another --out gets its
    # report beside it (OUT.md, figures/), so a side run never overwrites the page
    default = args.out.resolve() == Path(__file__).with_name("rough_convergence.json").resolve()
    page = ROOT / "docs" / "rough_convergence.md" if default else args.out.with_suffix(".md")
    if not default:
        (page.parent / "figures").mkdir(exist_ok=True)
    report(runs, page, scans)


if __name__ == "__main__":
    main()
