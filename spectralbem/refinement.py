"""Grid refinement of one scene on its fixed physical domain (``spectralbem refine``).

``refine(scene_file, [256, 512, 1024], "refine.nc")`` solves the scene at each resolution —
``grid.Nx`` of a physical scene (``grid.Ny`` in proportion, a strip of one or two cells
across kept as it is), ``sinusoid.cells_per_wavelength`` of the seed's 2D scene — with every
physical length unchanged: the domain, the surface (a generated surface is the same surface
at every N: docs/user_guide.md, surfaces), a0, the relaxation length.  What changes is the
cell alone, so the answers' differences are the grid's error.  In an elastic adhesive
scene a0 is numerical: ``a0_cells`` scales it with the cell instead, so that the refinement
approaches the sharp-crack limit G = Δγ (refused where a0 is physical).

The assembled dataset holds every scalar of each grid (and, for a load path, each step) on a
dimension ``N`` (the refined resolution), and for each quantity of :data:`QUANTITIES` the
scene has: ``<name>_order`` (the observed order p), ``<name>_limit`` (Richardson's estimate
f∞ of the N → ∞ value) and ``<name>_error`` (|f − f∞|/|f∞| at each N), from the three finest
grids whose states are verified.  They are nan where the differences do not shrink
monotonically, or shrink slower than order ½ or faster than order 4: there is no asymptotic
range yet, and no error estimate is claimed (:func:`richardson`).  ``<name>_change`` is the
relative change from the previous grid, always defined where both states are verified.

A refinement that stops halfway keeps every finished grid: each is written atomically to
``OUT.parts/N_<N>.nc`` with the refinement's digest (the scene, the overrides, the files it
refers to and the package version), and the same command run again solves only the grids
that are missing.  A parts folder of another refinement is refused, naming it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .conventions import shown
from .io import read_dataset, write_dataset
from .schema import SceneError

__all__ = ["refine", "richardson", "resolution_overrides", "summary", "varying", "QUANTITIES",
           "ORDER_MIN", "ORDER_MAX"]

#: the quantities whose refinement is estimated (those a scene's datasets have)
QUANTITIES = ("area_fraction", "penetration", "mean_pressure", "mu", "mu_adhesive", "G1",
              "G2", "front_length", "crack_tip_length", "a_tilde", "e_tilde", "delta_tilde",
              "p_tilde", "mu_bar", "mu_bar_adhesive", "G1_over_dgamma", "G2_over_dgamma")
#: below this observed order the differences are taken as not yet asymptotic (no estimate)
ORDER_MIN = 0.5
#: above this observed order too: no discretisation of the package converges faster (the
#: band interpolation is second order, the cell-averaged viscoelastic kernel measured 2.6-3.7
#: on the sinusoid, docs/performance.md "Resolving the relaxation length"), so a larger p is
#: a last change that happens to be small (a value crossing its limit), and the estimate
#: |f3 − f2|/(2ᵖ − 1) it gives is no error bound: on the seed's 2D sinusoid at 1000, 2000,
#: 4000 cells per wavelength G2 read p = 9.96 and an error of 0.000 % where the 1D method
#: puts it 0.087 % off
ORDER_MAX = 4.0
#: the states whose values enter the estimates
VERIFIED = ("partial", "full_contact")


def richardson(values, ratio: float = 2.0) -> tuple:
    """(observed order p, extrapolated value f∞, relative error |f − f∞|/|f∞| of each value)
    from the last three of ``values`` on grids refined by a constant ``ratio``:
    p = log|f2 − f1|/|f3 − f2| / log ratio, f∞ = f3 + (f3 − f2)/(ratio^p − 1).
    (p, nan, nans) when p lies outside [:data:`ORDER_MIN`, :data:`ORDER_MAX`]; (nan, nan,
    nans) when the differences change sign or vanish (no asymptotic range)."""
    vals = [float(v) for v in values]
    none = [float("nan")] * len(vals)
    if len(vals) < 3 or not all(math.isfinite(v) for v in vals[-3:]):
        return float("nan"), float("nan"), none
    f1, f2, f3 = vals[-3:]
    d1, d2 = f2 - f1, f3 - f2
    if d1 == 0 or d2 == 0 or d1 * d2 < 0:
        return float("nan"), float("nan"), none
    p = math.log(abs(d1 / d2)) / math.log(ratio)
    if not ORDER_MIN <= p <= ORDER_MAX:
        return p, float("nan"), none
    finf = f3 + d2 / (ratio**p - 1.0)
    scale = max(abs(finf), 1e-300)
    return p, finf, [abs(v - finf) / scale for v in vals]


def _set_aside_unreadable(parts) -> None:
    """The finished grids' files that a child process cannot read (a truncated or damaged
    file can crash netCDF-C, and refused every rerun) are named and moved aside, their grids
    solved again (as a sweep's points, :func:`spectralbem.sweep_parts._check_parts`)."""
    from .io import probe_netcdf
    from .sweep_parts import _set_aside

    present = [p for p in parts if p.exists() or p.is_symlink()]
    for p in present:
        if p.is_symlink() or not p.is_file():
            _set_aside(p, "not a regular file", "grid", "refine")
    present = [p for p in present if p.exists() and not p.is_symlink()]
    found = probe_netcdf(present) if present else {}
    for p in present:
        info, err = found[str(p)]
        if err is None and "status" not in info["variables"]:
            err = "no status variable"
        if err is not None:
            _set_aside(p, err, "grid", "refine")


def _raw_of(source):
    from .scenes import read_scene_file

    if isinstance(source, (str, Path)):
        return read_scene_file(source), Path(source).resolve().parent
    return dict(source), Path(".")


def resolution_overrides(raw: dict, overrides: dict | None, sizes, a0_cells=None,
                         base=None) -> list:
    """The overrides of each refined grid (a list of dicts, one per size), after the checks
    that the scene can be refined on a fixed physical domain (:class:`SceneError` naming
    the key and its value otherwise).  ``a0_cells``: a0 set to that many of each grid's
    cells (the sharp-crack limit of an elastic scene, where a0 is numerical) instead of kept
    fixed; refused where a0 is physical (a viscoelastic solid sliding) or absent."""
    from .scenes import apply_overrides

    spec = apply_overrides(raw, overrides)
    if a0_cells is not None:
        _check_a0_cells(spec, a0_cells, base)
    sizes = _check_sizes(sizes)
    problems = []
    surface = spec.get("surface") or {}
    if surface.get("kind") == "file":
        problems.append("surface.kind: 'file' gives the heights on one grid; only a generated "
                        "surface (self_affine, sinusoid, bisinusoid, paraboloid) is the same "
                        "surface at every N")
    if (spec.get("adhesion") or {}).get("dgamma_map") is not None:
        problems.append("adhesion.dgamma_map: a per-cell map is given on one grid and "
                        "cannot be refined")
    grid, sin = spec.get("grid"), spec.get("sinusoid")
    if isinstance(grid, dict) and "Nx" in grid:
        nx0, ny0 = int(grid["Nx"]), int(grid.get("Ny", grid["Nx"]))
        out = []
        for n in sizes:
            ny = ny0 if ny0 <= 2 else ny0 * n / nx0
            if ny != int(ny):
                problems.append(f"--sizes: Nx = {n} gives Ny = {ny0}·{n}/{nx0} = {ny:g}, not "
                                f"a whole number of cells (keep Nx/Ny = {nx0}/{ny0})")
            ov = {**(overrides or {}), "grid.Nx": n, "grid.Ny": int(ny),
                  "output.fields": False}  # scalars only: no field is stored
            if a0_cells is not None:  # a strip's fronts run along y: its cell along x
                ov["adhesion.a0"] = a0_cells * (grid["Lx"] / n if ny0 <= 2 else
                                                min(grid["Lx"] / n, grid["Ly"] / int(ny)))
            out.append(ov)
    elif isinstance(sin, dict):
        out = [{**(overrides or {}), "sinusoid.cells_per_wavelength": n,
                **({} if a0_cells is None else
                   {"sinusoid.a0_tilde": a0_cells * 2 * math.pi / n})} for n in sizes]
    else:
        problems.append("grid.Nx: the scene has no grid to refine")
        out = []
    if problems:
        raise SceneError(problems)
    return out


def _check_a0_cells(spec: dict, a0_cells, base) -> None:
    """--a0-cells only where a0 is numerical: an adhesive scene of an elastic solid, or of
    a viscoelastic one at rest."""
    from .scenes import load_scene

    if not (isinstance(a0_cells, (int, float)) and 1 <= a0_cells <= 64):
        raise SceneError(f"--a0-cells: {shown(a0_cells)} must be a number of cells in [1, 64]")
    scene = load_scene(spec, base_dir=base)
    if not scene.adhesive:
        raise SceneError("--a0-cells: the scene has no adhesion (adhesion.dgamma = 0): "
                         "there is no a0 to scale")
    if scene.viscoelastic:
        raise SceneError("--a0-cells: a0 is a physical process-zone length in a "
                         "viscoelastic solid in motion; refine with a0 fixed (omit "
                         "--a0-cells)")


def _check_grid_model(scene) -> None:
    """Only the grid model has a resolution: a scene the 1D method solves (``scene.model =
    "sinusoid1d"``, or ``"auto"`` choosing it) would be solved the same way at every size."""
    if scene.model != "grid2d":
        raise SceneError(f"scene.model: {scene.model!r} (the 1D method: no grid, the same "
                         "answer at every --sizes; `model = \"auto\"` chooses it for a "
                         "sinusoid sliding along its wave vector) cannot be refined; allowed: "
                         "'grid2d' (--set scene.model=grid2d)")


def _check_sizes(sizes) -> list:
    try:
        sizes = sorted(int(n) for n in sizes)
    except (TypeError, ValueError):
        raise SceneError(f"--sizes: {shown(sizes)} must be whole numbers of cells") from None
    if len(set(sizes)) < 2:
        raise SceneError(f"--sizes: {sizes} must hold at least two different resolutions "
                         "(three for an error estimate)")
    ratios = [b / a for a, b in zip(sizes, sizes[1:], strict=False)]
    if any(abs(r / ratios[0] - 1.0) > 1e-9 for r in ratios):
        raise SceneError(f"--sizes: {sizes} must grow by a constant ratio (Richardson's "
                         f"estimate needs it); here {', '.join(f'{r:g}' for r in ratios)}")
    return sizes


def _digest(raw, overrides, base, a0_cells) -> str:
    from . import __version__
    from .sweep import _digest as digest
    from .sweep import input_files

    return digest(raw, [("a0_cells", a0_cells)], overrides,
                  input_files(raw, overrides, base), __version__)


def refine(source, sizes, out, *, overrides: dict | None = None, a0_cells=None,
           progress=None, quantities=QUANTITIES, history: str | None = None):
    """Solve the scene ``source`` (TOML path or parsed mapping) at each of ``sizes`` on its
    fixed physical domain and write the assembled dataset to ``out`` (module docstring);
    returns it.  ``a0_cells``: a0 scaled with the cell (:func:`resolution_overrides`; the
    elastic sharp-crack limit), else kept fixed in metres.  ``progress``: a callable (index,
    size, text) told before and after each grid, or None.  ``history``: the CF history line
    of the command that asked (io.cf_attributes).  Every grid's scene is validated (and
    built) before the first solve."""
    import time

    from .io import cf_attributes
    from .scenes import load_scene, solve

    t = time.perf_counter()
    raw, base = _raw_of(source)
    per_size = resolution_overrides(raw, overrides, sizes, a0_cells, base)
    sizes = _check_sizes(sizes)
    # every grid validated before any heavy work; the scenes are the ones solved below
    scenes = [load_scene(raw, overrides=ov, base_dir=base) for ov in per_size]
    _check_grid_model(scenes[0])
    out = Path(out)
    parts = out.with_name(out.name + ".parts")
    parts.mkdir(exist_ok=True)
    digest = _digest(raw, overrides, base, a0_cells)
    _set_aside_unreadable([parts / f"N_{n}.nc" for n in sizes])
    files = []
    for i, (n, scene) in enumerate(zip(sizes, scenes, strict=True)):
        part = parts / f"N_{n}.nc"
        if part.is_file():
            old = read_dataset(part)
            if old.attrs.get("refinement_digest") != digest:
                raise SceneError(f"{part}: a grid of another refinement (scene, overrides, "
                                 "input files or version differ); remove the parts folder "
                                 f"{parts} or choose another output")
            files.append(part)
            if progress:
                progress(i, n, "kept from an earlier run")
            continue
        if progress:
            progress(i, n, "solving")
        ds = solve(scene)
        ds = ds.drop_vars([v for v in ds.variables if not set(ds[v].dims) <= {"step"}])
        ds.attrs.update(refinement_digest=digest, refinement_size=n)
        write_dataset(ds, part)
        files.append(part)
        if progress:
            progress(i, n, "done: " + ", ".join(sorted(set(np.atleast_1d(
                ds["status"].values).astype(str)))))
    rules = _edge_rules(sizes, scenes)
    ds = _assemble([read_dataset(f) for f in files], sizes, quantities,
                   mixed=rules is not None)
    if rules is not None:
        ds.attrs["refinement_edge_rules"] = rules
        ds.attrs["scene_note"] = ("scene: the finest grid's; the others differ in N and in "
                                  "the elastic edge (refinement_edge_rules)")
    ds.attrs.update(refinement_digest=digest,
                    refinement_a0=("fixed (m)" if a0_cells is None else f"{a0_cells:g} × the cell"))
    ds.attrs["wall_time_s"] = time.perf_counter() - t
    cf_attributes(ds, history=history)
    write_dataset(ds, out)
    return ds


def _edge_rules(sizes, scenes) -> str | None:
    """None when every grid's elastic edge follows one rule; else which grids extrapolate
    it to a0 → 0 (a fixed a0 of one cell at the coarsest grid and two or more at the finer
    ones: ``solver.extrapolate_a0``'s default, docs/theory.md), whose values then move with
    the rule as well as with N."""
    rule = [bool(sc.extrapolate_a0) for sc in scenes]
    if len(set(rule)) < 2:
        return None
    by = {r: [str(n) for n, x in zip(sizes, rule, strict=True) if x == r] for r in (False, True)}
    return (f"N = {', '.join(by[False])}: the a0 tests' edge; N = {', '.join(by[True])}: "
            "extrapolated to a0 → 0 (no error estimate across two rules: set "
            "solver.extrapolate_a0 = false, or a0 of two cells or more on every grid, "
            "--a0-cells 2)")


def _assemble(dss, sizes, quantities, mixed: bool = False):
    """One Dataset of every grid on ``N``, with the Richardson variables (``mixed``: the
    grids' elastic edges follow two rules, no estimate is made; the changes are kept)."""
    import xarray as xr

    ds = xr.concat(dss,
                   dim=xr.DataArray(np.asarray(sizes), dims="N", name="N"),
                   data_vars="all", coords="minimal", compat="override",
                   combine_attrs="override")  # each variable's units and long_name
    ds.attrs = {}
    # the finest grid's attributes but those of its solve alone (its message, diagnostics)
    drop = ("refinement_size", "solver_message", "solver_diagnostics", "wall_time_s")
    ds.attrs.update({k: v for k, v in dss[-1].attrs.items() if k not in drop})
    if "scene" in ds.attrs:
        ds.attrs["scene_note"] = "scene: the finest grid's; the others differ in N only"
    ds.attrs["refinement_sizes"] = np.asarray(sizes)
    ds["N"].attrs.update(long_name="refined resolution (grid.Nx, or the seed scene's "
                         "cells per wavelength)", units="1")
    ratio = sizes[1] / sizes[0]
    ok = xr.apply_ufunc(lambda s: np.isin(s.astype(str), VERIFIED), ds["status"])
    for q in quantities:
        if q not in ds or ds[q].dtype.kind not in "fi":
            continue
        vals = ds[q].where(ok).transpose(..., "N")
        order, limit, error, change = _estimates(vals.values, ratio)
        if mixed:
            order[...], limit[...], error[...] = np.nan, np.nan, np.nan
        dims = vals.dims
        units = ds[q].attrs.get("units", "")
        ds[f"{q}_order"] = (dims[:-1], order, {"long_name": f"observed order of {q}",
                                                "units": "1"})
        ds[f"{q}_limit"] = (dims[:-1], limit, {"long_name": f"Richardson estimate of {q} "
                                               "as N → ∞", "units": units})
        ds[f"{q}_error"] = (dims, error, {"long_name": f"estimated relative error of {q}",
                                          "units": "1"})
        ds[f"{q}_change"] = (dims, change, {"long_name": f"relative change of {q} from the "
                                            "previous grid", "units": "1"})
    return ds


def _estimates(vals: np.ndarray, ratio: float):
    """Richardson's order, limit and errors, and the changes, along the last axis of
    ``vals`` (nan: a state not verified)."""
    lead = vals.shape[:-1]
    order, limit = np.full(lead, np.nan), np.full(lead, np.nan)
    error = np.full(vals.shape, np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        prev = np.abs(vals[..., :-1])
        change = np.concatenate([np.full(lead + (1,), np.nan),
                                 (vals[..., 1:] - vals[..., :-1]) / np.where(prev > 0, prev,
                                                                              np.nan)],
                                axis=-1)
    for idx in np.ndindex(*lead):
        p, finf, errs = richardson(vals[idx], ratio)
        order[idx], limit[idx], error[idx] = p, finf, errs
    return order, limit, error, change


def _control(ds) -> str | None:
    """The prescribed control of the refined scene (mean_pressure or penetration; a seed
    scene's p_tilde or delta_tilde), if known."""
    import json

    try:
        scene = json.loads(ds.attrs.get("scene", "{}"))
    except (TypeError, ValueError):
        return None
    control = scene.get("control") or scene.get("sinusoid") or {}
    return next((k for k in ("mean_pressure", "penetration", "p_tilde", "delta_tilde")
                 if control.get(k) is not None), None)


def varying(ds, quantities=QUANTITIES) -> list:
    """The estimated quantities worth a line or a panel: not the prescribed control, not
    constant to 1e-9 (G = Δγ of an elastic scene) and not a friction coefficient that is
    zero to round-off (< 1e-12: an elastic or resting scene)."""
    ctrl = _control(ds)
    out = []
    for q in quantities:
        if f"{q}_error" not in ds or q == ctrl:
            continue
        v = np.asarray(ds[q].values, float)
        v = v[np.isfinite(v)]
        if v.size == 0 or np.abs(v - v.flat[0]).max() <= 1e-9 * np.abs(v).max():
            continue
        if q.startswith("mu") and np.abs(v).max() < 1e-12:
            continue
        if q == "crack_tip_length" and "front_length" in ds and bool(
                (ds[q] == ds["front_length"]).all()):  # every edge a crack tip
            continue
        out.append(q)
    return out


def summary(ds, quantities=QUANTITIES) -> str:
    """A plain-text table of the refinement: each quantity's values against N, the last
    change, the observed order and the estimated error at the finest grid."""
    sizes = [int(n) for n in ds["N"].values]
    steps = range(ds.sizes["step"]) if "step" in ds.dims else [None]
    head = "quantity" + "".join(f" | N={n}" for n in sizes) + " | last change | order | " \
        "error at N=" + str(sizes[-1])
    lines = []
    names = varying(ds, quantities)
    for k in steps:
        sel = ds if k is None else ds.isel(step=k)
        status = [str(s) for s in np.atleast_1d(sel["status"].values)]
        lines.append(("" if k is None else f"step {k}: ") + "status "
                     + ", ".join(f"{n}: {s}" for n, s in zip(sizes, status, strict=True)))
        lines.append(head)
        ok = np.isin(np.asarray(status), VERIFIED)
        why = ("none (two edge rules)" if "refinement_edge_rules" in ds.attrs
               else "none (not asymptotic)" if ok[-3:].all() and ok.size >= 3
               else "none (a state not verified)" if ok.size >= 3 else "none (two grids)")
        for q in names:
            v = sel[q].values
            ch = float(sel[f"{q}_change"].values[-1])
            p = float(sel[f"{q}_order"].values)
            err = float(sel[f"{q}_error"].values[-1])
            lines.append(q + "".join(f" | {x:.6g}" for x in v)
                         + f" | {_pct(ch, True)} | {p:.2f} | "
                         + (_pct(err) if math.isfinite(err) else why))
    if "refinement_edge_rules" in ds.attrs:
        lines.append("elastic edge: " + str(ds.attrs["refinement_edge_rules"]))
    return "\n".join(lines)


def _pct(x: float, sign: bool = False) -> str:
    if not math.isfinite(x):
        return "nan"
    return f"{100 * x:+.2f} %" if sign else f"{100 * x:.2f} %"
