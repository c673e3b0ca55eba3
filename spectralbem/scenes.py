"""Scenes: one study, validated before any heavy work, and ``solve(scene)`` → Dataset.

A scene comes from a TOML file (:func:`load_scene`, schema in :mod:`spectralbem.schema`) or
from Python (:meth:`Scene.sinusoid` for the seed's dimensionless problem).  The scene decides
the model, and the dataset records which one ran (attribute ``model``):

* ``sinusoid1d`` — the seed's 1D method (a y-invariant sinusoid on an elastic or standard
  linear solid half-space sliding along x; chosen by ``model = "auto"``);
* ``grid2d`` — the periodic grid: Polonsky–Keer for an elastic (or resting) adhesiveless
  scene, the active set for viscoelastic sliding, the front-layer energy balance only when
  Δγ > 0.  An elastic scene never builds E(ω); a half-space never evaluates S.

A list under ``control`` is a load/unload path, solved in order with the contact mask carried
from step to step (adhesion hysteresis is physical: no global minimisation).
"""

from __future__ import annotations

import copy
import dataclasses
import datetime as _dt
import json
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__
from .contact import ContactError, check_penetration, sliding_direction
from .io import FIELDS, SCALARS, STATUS, cf_attributes
from .io import attrs as _attrs
from .layers import GluedLayer, HalfSpace, PressureLayer
from .materials import Elastic, Material, MaterialError, Prony, StandardLinearSolid, Tabulated
from .schema import (
    HEIGHT,
    MODULUS,
    SECTIONS,
    SceneError,
    short,
    short_name,
    too_deep,
    validate,
)
from .spectral import Cell, GridError, SpectralOperator
from .surfaces import (
    MIN_FILE_LIMIT,
    SurfaceError,
    bisinusoid,
    check_input_file,
    file_limit,
    paraboloid,
    read_heights,
    self_affine,
    sinusoid,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["Scene", "SceneError", "load_scene", "read_scene_file", "apply_overrides", "solve"]


@dataclass
class Scene:
    """A validated periodic contact problem, ready to solve.

    Seed scenes (``kind == "sinusoid"``) are in dimensionless sinusoid units
    (k = Λ = E0* = τ = 1, so p* = 1/2); physical scenes are in SI units.
    ``control`` is ``(name, values)``: name ``mean_pressure`` or ``penetration`` and one value
    per step (one step unless the scene is a path); ``p_mean``/``delta`` hold the first step.
    """

    cell: Cell
    material: Material
    heights: np.ndarray
    velocity: tuple
    dgamma: object  # J/m², scalar or per-cell map
    a0: float
    p_mean: float | None = None
    delta: float | None = None
    kind: str = "custom"
    params: dict = field(default_factory=dict)
    layer: object = None
    model: str = "grid2d"
    spec: dict = field(default_factory=dict)  # the normalised scene mapping (for the dataset)
    solver: dict = field(default_factory=lambda: {"tol": 1e-10, "max_iterations": 10000,
                                                  "max_outer": 500, "threads": 1})
    fields: bool = True
    control: tuple = ()
    flaw_radius: float | None = None  # m; None: a0

    @property
    def adhesive(self) -> bool:
        return bool(np.any(np.asarray(self.dgamma) > 0))

    @property
    def steps(self) -> list:
        """Control values of the path (one entry for a single state)."""
        if self.control:
            return list(self.control[1])
        return [self.p_mean if self.p_mean is not None else self.delta]

    def at_step(self, value) -> Scene:
        name = self.control[0] if self.control else (
            "mean_pressure" if self.p_mean is not None else "penetration")
        if name == "mean_pressure":
            return dataclasses.replace(self, p_mean=value, delta=None)
        return dataclasses.replace(self, p_mean=None, delta=value)

    @classmethod
    def sinusoid(cls, zeta: float, beta: float, Gamma: float, *, p_tilde: float | None = None,
                 delta_tilde: float | None = None, a0_tilde: float,
                 cells_per_wavelength: int = 1024, ny: int = 8, direction_deg: float = 0.0,
                 model: str = "grid2d") -> Scene:
        """The seed scene: h = Λ cos(kx) on an Lx = λ by ny-cell periodic cell, sliding at
        ζ = kvτ along the angle ``direction_deg`` to the wave vector.  ``model`` =
        ``"sinusoid1d"`` runs the seed's 1D method instead of the grid."""
        raw = {"scene": {"model": model},
               "sinusoid": {"zeta": zeta, "beta": beta, "Gamma": Gamma, "a0_tilde": a0_tilde,
                            "cells_per_wavelength": cells_per_wavelength, "ny": ny,
                            "direction_deg": direction_deg}}
        for k, v in (("p_tilde", p_tilde), ("delta_tilde", delta_tilde)):
            if v is not None:
                raw["sinusoid"][k] = v
        raw = json.loads(json.dumps(raw, default=_plain))
        spec, problems = validate(raw)
        if problems:
            raise SceneError(problems)
        return _build_seed(spec)


def _plain(x):
    """numpy scalars → Python numbers (so the schema sees plain types)."""
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.floating):
        return float(x)
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(f"{x!r} is not a plain value")


# -- loading ---------------------------------------------------------------------------------
#: the largest scene file read (a scene is a few hundred bytes; a long load path a few kB)
SCENE_FILE_LIMIT = 16 * 2**20


def read_scene_file(path) -> dict:
    """Parse a TOML scene file (errors name the file and line).  The file must be a regular
    file (a FIFO or a device could block or never end) of at most 16 MiB, in UTF-8."""
    path = Path(path)
    name = short(str(path))
    try:
        check_input_file(path, "scene file", SCENE_FILE_LIMIT)
    except SurfaceError as exc:
        raise SceneError(str(exc)) from None
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file {name} is not valid TOML: {exc}") from exc
    except UnicodeDecodeError as exc:
        raise SceneError(f"scene file {name} is not valid UTF-8 (byte {exc.start}: "
                         f"{exc.reason}); TOML files are UTF-8 text") from None
    except RecursionError:
        raise SceneError(f"scene file {name}: values nested too deeply; scene values are "
                         "numbers, strings, booleans or lists of numbers") from None
    except OSError as exc:
        raise SceneError(f"scene file {name} cannot be read: {exc.strerror or exc}") from None


def parse_value(text: str):
    """A command-line value: a TOML literal (number, string, list, boolean) or a bare word."""
    try:
        v = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        if "," in text and "[" not in text:  # 1e3,2e3: a list of numbers
            try:
                v = tomllib.loads(f"v = [{text}]")["v"]
            except tomllib.TOMLDecodeError:
                return text
            if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
                return v
        return text
    except RecursionError:
        raise SceneError(f"value {short(text)}: nested too deeply; scene values are numbers, "
                         "strings, booleans or lists of numbers") from None
    if too_deep(v):
        raise SceneError(f"value {short(text)}: nested too deeply; scene values are numbers, "
                         "strings, booleans or lists of numbers")
    return v


def apply_overrides(raw: dict, overrides: dict | None) -> dict:
    """A copy of ``raw`` with ``{"section.key": value}`` set (sections are created)."""
    deep = [s for s, v in (raw.items() if isinstance(raw, dict) else ()) if too_deep(v)]
    deep += [k for k, v in (overrides or {}).items() if too_deep(v)]
    if deep:  # before the copy below, which would recurse through them
        raise SceneError([f"{short_name(k)}: nested too deeply; scene values are numbers, "
                          "strings, booleans or lists of numbers" for k in deep])
    out = copy.deepcopy(raw)
    for dotted, value in (overrides or {}).items():
        parts = str(dotted).split(".")
        if len(parts) != 2 or not all(parts):
            raise SceneError(f"{short_name(dotted)}: an override key must be 'section.key'")
        sec = out.setdefault(parts[0], {})
        if not isinstance(sec, dict):
            raise SceneError(f"{short_name(parts[0])}: is not a table, cannot set "
                             f"{short_name(dotted)}")
        sec[parts[1]] = value
    return out


def load_scene(source, *, overrides: dict | None = None, base_dir=None) -> Scene:
    """Validate a scene (TOML path or parsed mapping) and build it; every problem is reported
    at once in one :class:`SceneError` before any heavy work.  Relative file paths in the
    scene are resolved against the scene file's folder (or ``base_dir``)."""
    if isinstance(source, (str, Path)):
        raw = read_scene_file(source)
        base = Path(source).resolve().parent if base_dir is None else Path(base_dir)
    else:
        raw = source
        base = Path(base_dir or ".").resolve()
    raw = _grid_from_file(apply_overrides(raw, overrides), base)
    spec, problems = validate(raw)
    if problems:
        raise SceneError(problems)
    if "sinusoid" in spec:
        return _build_seed(spec)
    return _build_physical(spec, base)


def _grid_from_file(raw: dict, base: Path) -> dict:
    """A height-map scene may leave out the grid: Nx, Ny default to the map's shape and Lx,
    Ly to the size the file states (netCDF coordinates); keys given are kept (and checked
    against the file later).  A file that cannot be read is left to the normal checks."""
    sf, g = raw.get("surface"), raw.get("grid", {})
    if not (isinstance(sf, dict) and sf.get("kind") == "file" and isinstance(g, dict)
            and isinstance(sf.get("path"), str)) or all(
            g.get(k) is not None for k in ("Lx", "Ly", "Nx", "Ny")):
        return raw
    try:
        scale = sf.get("scale", 1.0)
        h, size = read_heights(base / sf["path"], variable=sf.get("variable", "heights"),
                               scale=scale if isinstance(scale, (int, float)) else 1.0,
                               max_bytes=file_limit(65536**2))
    except (SurfaceError, TypeError, ValueError, OSError):
        return raw
    out = dict(raw)
    out["grid"] = g = dict(g)
    g.setdefault("Nx", int(h.shape[0]))
    g.setdefault("Ny", int(h.shape[1]))
    if size is not None:
        g.setdefault("Lx", size[0])
        g.setdefault("Ly", size[1])
    return out


#: peak memory of a grid solve per cell (bytes): the peak resident size above the imported
#: package, measured at 512² and 1024² (Polonsky–Keer 200, the viscoelastic active set 345,
#: the adhesive front iteration 460 B/cell), with a margin of 1.4
SOLVE_BYTES_PER_CELL = {"elastic": 280, "viscoelastic": 480, "adhesive": 650}
#: the fields a dataset keeps of each state (five float64 fields and the int8 mask)
FIELD_BYTES_PER_CELL = 41
#: the interpreter with numpy, scipy, xarray and the compiled kernels loaded (measured 220 MB)
BASE_BYTES = 300 * 2**20


def machine_memory() -> int:
    """The machine's physical memory (bytes), or the cgroup's limit when that is lower."""
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    for f in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            v = Path(f).read_text().strip()
        except OSError:
            continue
        if v.isdigit() and 0 < int(v) < total:
            total = int(v)
    return int(total)


def memory_estimate(n_cells: int, *, model: str = "grid2d", viscoelastic: bool = False,
                    adhesive: bool = False, steps: int = 1, fields: bool = True) -> int:
    """Estimated peak memory (bytes) of solving a scene on ``n_cells`` grid cells: the solver's
    arrays (:data:`SOLVE_BYTES_PER_CELL`), the GMRES fallback's Krylov basis of a
    viscoelastic (non-symmetric) solve (masked.RESTART_BYTES, at least 60 vectors), the
    fields the dataset keeps of every path step, and the interpreter.  The 1D method only
    samples the profile on the grid."""
    from .masked import RESTART_BYTES, RESTART_MAX

    n = int(n_cells)
    if model == "sinusoid1d":
        return BASE_BYTES + 16 * n
    kind = "adhesive" if adhesive else ("viscoelastic" if viscoelastic else "elastic")
    est = BASE_BYTES + SOLVE_BYTES_PER_CELL[kind] * n
    if viscoelastic:
        est += max(min(RESTART_BYTES, 8 * n * RESTART_MAX), 8 * n * 60)
    if fields:
        est += FIELD_BYTES_PER_CELL * n * max(1, int(steps))
    return int(est)


def _check_memory(keys: str, shape: tuple, **kw) -> None:
    """Refuse, before any work, a solve whose memory estimate exceeds the machine's memory."""
    n = int(shape[0]) * int(shape[1])
    est, mem = memory_estimate(n, **kw), machine_memory()
    if est <= mem:
        return
    per = (memory_estimate(2**20, **kw) - memory_estimate(0, **kw)) / 2**20
    fit = max(0, int((mem - memory_estimate(0, **kw)) / per))
    raise SceneError(f"{keys}: {shape[0]} × {shape[1]} = {n} cells need an estimated "
                     f"{est / 2**30:.1f} GiB for this solve, more than the machine's memory "
                     f"({mem / 2**30:.1f} GiB); allowed at most about {fit} cells here")


def _build_seed(spec: dict) -> Scene:
    s = spec["sinusoid"]
    model = spec["scene"]["model"]
    if model == "auto":
        model = "sinusoid1d" if s["direction_deg"] == 0.0 else "grid2d"
    elif model == "sinusoid1d" and s["direction_deg"] != 0.0:
        raise SceneError("scene.model: 'sinusoid1d' needs sinusoid.direction_deg = 0 (oblique "
                         "sliding runs on the grid; allowed models here: auto, grid2d)")
    ctl = ("p_tilde", s["p_tilde"]) if s["p_tilde"] is not None else ("delta_tilde",
                                                                      s["delta_tilde"])
    values = ctl[1] if isinstance(ctl[1], list) else [ctl[1]]
    n, ny = s["cells_per_wavelength"], s["ny"]
    _check_memory("sinusoid.cells_per_wavelength × sinusoid.ny", (n, ny), model=model,
                  viscoelastic=s["zeta"] > 0 and s["beta"] > 1, adhesive=s["Gamma"] > 0,
                  steps=len(values))
    lam = 2 * np.pi
    cell = Cell(lam, lam / n * ny, n, ny)
    from .sinusoid1d import dimensionless_material

    mat, v = dimensionless_material(s["zeta"], s["beta"])
    phi = np.radians(s["direction_deg"])
    # p* = 1/2 in these units: the mean pressure is p̃/2
    steps = [0.5 * x for x in values] if ctl[0] == "p_tilde" else list(values)
    name = "mean_pressure" if ctl[0] == "p_tilde" else "penetration"
    p0 = steps[0] if name == "mean_pressure" else None
    d0 = steps[0] if name == "penetration" else None
    params = dict(zeta=s["zeta"], beta=s["beta"], Gamma=s["Gamma"], a0_tilde=s["a0_tilde"],
                  cells_per_wavelength=n, ny=ny, direction_deg=s["direction_deg"])
    if name == "penetration" and model == "grid2d":
        _check_penetration(HalfSpace(), mat.nu, sinusoid(cell, 1.0), steps)
    return Scene(cell, mat, sinusoid(cell, 1.0), (v * np.cos(phi), v * np.sin(phi)),
                 np.pi * s["Gamma"], s["a0_tilde"], p0, d0, "sinusoid", params, None, model,
                 spec, control=(name, steps))


def _material(m: dict, base: Path, problems: list) -> Material | None:
    try:
        k = m["kind"]
        if k == "elastic":
            return Elastic(m["E"], m["nu"])
        if k == "sls":
            return StandardLinearSolid(m["E0"], m["Einf"], m["tau"], m["nu"])
        if k == "prony":
            return Prony(m["E_eq"], tuple(m["moduli"]), tuple(m["times"]), m["nu"])
        path = check_input_file(base / m["path"], "modulus table", MIN_FILE_LIMIT)
        table = Tabulated.from_csv(path, nu=m["nu"])
    except SurfaceError as exc:
        problems.append(f"material.path: {exc}")
        return None
    except MaterialError as exc:
        problems.append(f"material: {str(exc)[:300]}")
        return None
    except (ValueError, RecursionError) as exc:  # e.g. not UTF-8 text
        problems.append(f"material.path: cannot read modulus table {short(m['path'])}: "
                        f"{str(exc)[:200]}")
        return None
    lo, hi = MODULUS
    moduli = np.abs(np.concatenate([table.storage, table.loss]))
    if table.storage[0] < lo or moduli.max() > hi:
        problems.append(f"material.path: the moduli of {short(m['path'])} span "
                        f"[{min(table.storage):g}, {moduli.max():g}] Pa; allowed E' in "
                        f"[{lo:g}, {hi:g}] Pa and |E''| ≤ {hi:g} Pa")
        return None
    return table


def _check_penetration(layer, nu, h, values):
    """Penetrations the slab cannot take (mean u = 0: Δ < max h − mean h), refused while the
    scene is built, before any solve of a path."""
    try:
        check_penetration(layer, nu, h, values)
    except ContactError as exc:
        raise SceneError([f"control.{exc}"]) from exc


def _layer(ly: dict):
    return {"half_space": lambda: HalfSpace(), "glued": lambda: GluedLayer(ly["thickness"]),
            "pressure": lambda: PressureLayer(ly["thickness"])}[ly["kind"]]()


def _heights(sf: dict, g: dict, cell: Cell, base: Path, problems: list):
    k = sf["kind"]
    try:
        if k == "sinusoid":
            return sinusoid(cell, sf["amplitude"], sf["wavelength"])
        if k == "bisinusoid":
            return bisinusoid(cell, sf["amplitude"])
        if k == "paraboloid":
            return paraboloid(cell, sf["radius"])
        if k == "self_affine":
            return self_affine(cell, sf["hurst"], rolloff=2 * np.pi / sf["rolloff_wavelength"],
                               cutoff=2 * np.pi / sf["cutoff_wavelength"],
                               rms_height=sf["rms_height"],
                               rms_slope=sf["rms_slope"], seed=sf["seed"])
        h, size = read_heights(base / sf["path"], variable=sf["variable"], scale=sf["scale"],
                               max_bytes=file_limit(cell.Nx * cell.Ny))
    except SurfaceError as exc:
        problems.append(f"surface{'.path' if k == 'file' else ''}: {exc}")
        return None
    if h.shape != cell.shape:
        problems.append(f"surface.path: the height map has shape {h.shape}, the grid is "
                        f"(grid.Nx, grid.Ny) = {cell.shape}")
        return None
    if size is not None:
        for name, got, want in (("Lx", size[0], g["Lx"]), ("Ly", size[1], g["Ly"])):
            if abs(got - want) > 1e-6 * want:
                problems.append(f"grid.{name}: {want!r} m disagrees with the height map's "
                                f"physical size {got!r} m")
    bad = ~np.isfinite(h)
    if bad.any():
        problems.append(f"surface.path: the height map has {int(bad.sum())} non-finite values "
                        f"(first at index {tuple(int(i) for i in np.argwhere(bad)[0])})")
        return None
    if float(np.abs(h).max()) > HEIGHT[1]:
        problems.append(f"surface.path: heights × surface.scale reach {float(np.abs(h).max()):g} "
                        f"m; allowed within ±{HEIGHT[1]:g} m (check surface.scale)")
        return None
    return h


def _one_d_obstacles(spec: dict, material) -> list:
    """Why a physical scene cannot run as the seed's 1D method (empty: it can)."""
    why = []
    if spec["surface"]["kind"] != "sinusoid":
        why.append("surface.kind is not 'sinusoid'")
    if not isinstance(material, (Elastic, StandardLinearSolid)):
        why.append("the material is neither elastic nor a standard linear solid")
    if spec["layer"]["kind"] != "half_space":
        why.append("layer.kind is not 'half_space'")
    v = _velocity(spec["motion"])
    if v[1] != 0.0:
        why.append("the velocity has a y component")
    if spec["adhesion"]["dgamma_map"] is not None:
        why.append("adhesion.dgamma_map is set")
    return why


def _velocity(mot: dict) -> tuple:
    if mot["velocity"] is not None:
        return tuple(float(v) for v in mot["velocity"])
    s = mot["speed"] or 0.0
    phi = np.radians(mot["direction_deg"])
    vx, vy = s * np.cos(phi), s * np.sin(phi)
    return (float(vx) if abs(vx) > 1e-15 * s else 0.0, float(vy) if abs(vy) > 1e-15 * s else 0.0)


def _dgamma_map(adh: dict, cell: Cell, base: Path, problems: list):
    """The per-cell Δγ map (J/m²) of ``adhesion.dgamma_map``: a regular .npy file holding a
    real array of the grid's shape, values 0 or in the range of ``adhesion.dgamma``."""
    name = short(adh["dgamma_map"])
    key = SECTIONS["adhesion"]["dgamma"]
    try:
        path = check_input_file(base / adh["dgamma_map"], "Δγ map",
                                file_limit(cell.Nx * cell.Ny))
        dg = np.load(path, allow_pickle=False)
    except SurfaceError as exc:
        problems.append(f"adhesion.dgamma_map: {exc}")
        return None
    except (OSError, ValueError, EOFError) as exc:
        problems.append(f"adhesion.dgamma_map: cannot read {name}: {str(exc)[:200]}")
        return None
    if not isinstance(dg, np.ndarray):  # an .npz archive
        dg.close()
        problems.append(f"adhesion.dgamma_map: {name} is an .npz archive; give one array "
                        f"as .npy (shape (Nx, Ny) = {cell.shape}, J/m²)")
        return None
    if not (np.issubdtype(dg.dtype, np.integer) or np.issubdtype(dg.dtype, np.floating)):
        problems.append(f"adhesion.dgamma_map: {name} holds {dg.dtype} values; give real "
                        "numbers in J/m²")
        return None
    dg = dg.astype(float)
    if dg.shape != cell.shape:
        problems.append(f"adhesion.dgamma_map: shape {dg.shape} differs from the grid "
                        f"{cell.shape}")
        return None
    ok = np.isfinite(dg) & (dg >= key.lo) & (dg <= key.hi)
    if not ok.all():
        i = tuple(int(j) for j in np.argwhere(~ok)[0])
        problems.append(f"adhesion.dgamma_map: {int((~ok).sum())} values outside the allowed "
                        f"range {key.range_text()} J/m² (first {dg[i]!r} at index {i})")
        return None
    return dg


def _one_d_ranges(scene: Scene) -> list:
    """The dimensionless groups of a physical sinusoid scene outside the 1D method's ranges
    (those of the seed scene's [sinusoid] section), each with the keys it comes from."""
    d = _dimensionless_groups(scene)
    spec = SECTIONS["sinusoid"]
    src_k = "surface.wavelength (default grid.Lx)"
    groups = [("zeta", d["zeta"], "ζ = k v τ", f"motion, material.tau, {src_k}"),
              ("beta", d["beta"], "β = E∞/E0", "material.Einf, material.E0"),
              ("Gamma", d["Gamma"], "Γ = (1-ν²)Δγ/(π E0* k Λ²)",
               f"adhesion.dgamma, material, surface.amplitude, {src_k}"),
              ("a0_tilde", d["a0_tilde"], "ã0 = k a0", f"adhesion.a0, {src_k}")]
    name, vals = scene.control
    if name == "mean_pressure":
        groups += [("p_tilde", v / d["pstar"], "p̃ = p/p*", "control.mean_pressure")
                   for v in vals]
    else:
        groups += [("delta_tilde", v / d["amp"], "Δ̃ = Δ/Λ", "control.penetration")
                   for v in vals]
    why = []
    for key, x, label, src in groups:
        k = spec[key]
        if not (math.isfinite(x) and k.allows(x)):
            why.append(f"{label} = {x:.6g} (from {src}) is outside the 1D method's range "
                       f"{k.range_text()}")
    return why


def _build_physical(spec: dict, base: Path) -> Scene:
    problems: list[str] = []
    g = spec["grid"]
    try:
        cell = Cell(g["Lx"], g["Ly"], g["Nx"], g["Ny"])
    except GridError as exc:
        raise SceneError(f"grid: {exc}") from exc
    mat = _material(spec["material"], base, problems)
    model = spec["scene"]["model"]
    if mat is not None and model != "grid2d":
        why = _one_d_obstacles(spec, mat)
        if model == "sinusoid1d" and why:
            problems.append("scene.model: 'sinusoid1d' is not possible: " + "; ".join(why)
                            + " (allowed: auto, grid2d)")
        model = "sinusoid1d" if not why else "grid2d"
    adh, ctl = spec["adhesion"], spec["control"]
    name = "mean_pressure" if ctl["mean_pressure"] is not None else "penetration"
    values = ctl[name] if isinstance(ctl[name], list) else [ctl[name]]
    velocity = _velocity(spec["motion"])
    memory = dict(viscoelastic=not isinstance(mat, Elastic) and any(velocity),
                  adhesive=adh["dgamma"] > 0 or adh["dgamma_map"] is not None,
                  steps=len(values), fields=spec["output"]["fields"])
    _check_memory("grid.Nx × grid.Ny", cell.shape, model=model, **memory)  # before any work
    h = _heights(spec["surface"], g, cell, base, problems)
    dgamma = adh["dgamma"]
    if adh["dgamma_map"] is not None:
        dgamma = _dgamma_map(adh, cell, base, problems)
    if problems:
        raise SceneError(problems)
    layer = _layer(spec["layer"])
    scene = Scene(cell, mat, h, velocity, dgamma, adh["a0"] or 0.0,
                  values[0] if name == "mean_pressure" else None,
                  values[0] if name == "penetration" else None, "physical",
                  {"name": spec["scene"]["name"]}, layer, model, spec,
                  dict(spec["solver"]), spec["output"]["fields"], (name, list(values)),
                  adh.get("flaw_radius"))
    if model == "sinusoid1d":
        why = _one_d_ranges(scene)
        if why and spec["scene"]["model"] == "sinusoid1d":
            raise SceneError(["scene.model: 'sinusoid1d' cannot solve this scene: " + w
                              + " (allowed models: auto, grid2d)" for w in why])
        if why:  # 'auto' picks the 1D method only for a scene it can solve
            model = "grid2d"
            _check_memory("grid.Nx × grid.Ny", cell.shape, model=model, **memory)
            scene = dataclasses.replace(scene, model=model)
    if name == "penetration" and model == "grid2d":
        _check_penetration(layer, mat.nu, h, values)
    return scene


def _edges_y_invariant(mask, offset, cell):
    """Trailing/leading edge distances (l1, l2) from the summit, averaged over rows, with the
    sub-cell offsets of the outer front cells."""
    lam = cell.Lx
    x = (cell.x + lam / 2) % lam - lam / 2
    l1s, l2s = [], []
    for j in range(cell.Ny):
        row = mask[:, j]
        if not row.any() or row.all():
            return np.nan, np.nan
        xs = x[row]
        i_lo = int(np.flatnonzero(row & (x == xs.min()))[0])
        i_hi = int(np.flatnonzero(row & (x == xs.max()))[0])
        s_lo = offset[(i_lo - 1) % cell.Nx, j]
        s_hi = offset[(i_hi + 1) % cell.Nx, j]
        l1s.append(-(xs.min() - cell.hx / 2) + (s_lo if np.isfinite(s_lo) else 0.0))
        l2s.append(xs.max() + cell.hx / 2 + (s_hi if np.isfinite(s_hi) else 0.0))
    return float(np.mean(l1s)), float(np.mean(l2s))


SEED_EXTRA = {
    "mu_bar_mask": "μ/Λ̃ from the rigid-profile force on the cell mask",
    "mu_bar_dissipation": "μ/Λ̃ from the spectral dissipation",
    "mu_bar_lateral": "lateral force over normal force, over Λ̃",
}


#: the states whose status promises a verified equilibrium (every other is not_converged)
REPORTED = ("partial", "full_contact", "detached")


def quotient(num: float, den: float, num_scale: float = 0.0, den_scale: float = 0.0) -> float:
    """num/den with the 1D method's convention at no load (sinusoid1d._quotient): 0/0 = 0 (no
    force at no load), ±inf for a finite numerator over 0.  A value within 1e-9 of its scale
    (the sum of the magnitudes it came from) counts as 0: round-off of a vanishing sum."""
    if abs(den) > 1e-9 * den_scale and den != 0.0:
        return num / den
    return 0.0 if abs(num) <= 1e-9 * num_scale else math.copysign(math.inf, num)


def _friction(op, h, p, u) -> dict:
    """contact.friction, with :func:`quotient`'s convention where the net normal force
    vanishes (a detached state, an adhesive contact at zero load): never nan."""
    from .contact import friction

    fr = friction(op, h, p, u)
    if not any(np.isnan(v) for v in fr.values()):
        return fr
    cell = op.cell
    vhat = sliding_direction(op)
    vperp = np.array([-vhat[1], vhat[0]])
    du, dl, dh = (cell.derivative(u, vhat), cell.derivative(u, vperp),
                  cell.derivative(h, vhat))
    ap = np.abs(p)
    forces = dict(mu=(-float(np.sum(p * du)), float(np.sum(ap * np.abs(du)))),
                  mu_lateral=(-float(np.sum(p * dl)), float(np.sum(ap * np.abs(dl)))),
                  mu_profile=(-float(np.sum(p * dh)), float(np.sum(ap * np.abs(dh)))))
    fd = op.dissipation_friction_force(p, vhat) / cell.cell_area if ap.any() else 0.0
    forces["mu_dissipation"] = (fd, forces["mu"][1])
    total, tscale = float(np.sum(p)), float(np.sum(ap))
    return {k: quotient(f, total, fs, tscale) for k, (f, fs) in forces.items()}


def _verify(status: str, message: str, scene: Scene, mask) -> tuple:
    """A status is a promise: (status, message) after the checks a reported state must pass.
    ``detached`` needs a zero pressure field that carries the prescribed load and leaves no
    interpenetration: no compressive load, Δ ≤ 0; an adhesiveless solve that converged
    without a contact cell is that state."""
    if status == "partial" and not np.any(mask):
        status = "detached"
    if status != "detached":
        return status, message
    seed = scene.kind == "sinusoid"
    if scene.p_mean is not None and scene.p_mean > 0:
        load = f"p̃ = {scene.p_mean / 0.5:g}" if seed else f"{scene.p_mean:g} Pa"
        return "not_converged", (f"no equilibrium found: the contact vanished under the "
                                 f"compressive mean pressure {load}, which a detached state "
                                 f"cannot carry (solver: {message})")
    if scene.delta is not None and scene.delta > 0:
        pen = f"Δ̃ = {scene.delta:g}" if seed else f"{scene.delta:g} m"
        return "not_converged", (f"no equilibrium found: the contact vanished at the "
                                 f"penetration {pen} > 0, where a detached state "
                                 f"interpenetrates (solver: {message})")
    return status, message


def _undefined(status: str, message: str, scalars: dict, skip=()) -> tuple:
    """A reported state with a nan scalar is not a verified state: not_converged, naming
    them (the conventions above leave none in a sound state)."""
    bad = [k for k, v in scalars.items() if k not in skip and isinstance(v, float)
           and math.isnan(v)]
    if status in REPORTED and bad:
        return "not_converged", (f"the state's {', '.join(bad)} are undefined (nan), so it "
                                 f"is not reported as {status}; solver: {message}")
    return status, message


def _solve_seed_grid(scene: Scene, mask0=None, rtol: float = 1e-10, progress=None):
    """The seed scene on the grid: the 1D method's dimensionless names."""
    import xarray as xr

    from . import front
    from .adhesive import solve_adhesive
    from .contact import solve_contact

    op = _operator(scene)
    cell, h = scene.cell, scene.heights
    pstar = 0.5
    out = {}
    if scene.adhesive:
        if mask0 is None and scene.kind == "sinusoid":  # start from Johnson's E0 contact
            from . import reference as ref

            pt = scene.p_mean / pstar if scene.p_mean is not None else 0.3
            a = ref.johnson_a(pt, scene.params["Gamma"]) if pt is not None else np.nan
            a = a if np.isfinite(a) else 1.0
            xw = (cell.x + np.pi) % (2 * np.pi) - np.pi
            mask0 = np.repeat((np.abs(xw) < a)[:, None], cell.Ny, axis=1)
        vhat = sliding_direction(op)
        vperp = (-vhat[1], vhat[0])
        obs = {"load": np.ones(cell.shape), "force": -cell.derivative(h, vhat),
               "lateral": -cell.derivative(h, vperp)}
        r = solve_adhesive(op, h, scene.dgamma, scene.a0, penetration=scene.delta,
                           mean_pressure=scene.p_mean, mask0=mask0, rtol=rtol,
                           observables=obs, max_outer=scene.solver["max_outer"],
                           **_smoothing(scene),
                           criterion=scene.solver.get("criterion", "exact"),
                           front_tol=scene.solver.get("front_tol", 0.5),
                           flaw_radius=scene.flaw_radius, progress=progress)
        p, mask, delta, status = r.pressure, r.mask, r.penetration, r.status
        out["p_front"] = r.mean_pressure
        a0e = r.a0
        u = op.apply(p)
        if scene.kind == "sinusoid" and status == "partial":
            l1, l2 = _edges_y_invariant(mask, r.offset_out, cell)
            G = []
            for ci in sorted(r.tests.closing):
                _, dUc, _, Ac, _ = r.tests.closing[ci]
                _, dUo, _, Ao, _ = r.tests.opening[ci]
                col = r.tests.colour_map[ci]
                sel = col & np.isfinite(r.offset_out)  # no balanced edge: s, G undefined
                s = float(r.offset_out[sel].mean()) if sel.any() else np.nan
                Gc, Go = dUc / Ac, dUo / Ao
                # G at the balanced edge: the closing (opening) band's value stands at its
                # start x_b (x_b − a0) in the seed's definition, at its midpoint when the edge
                # is the sharp-crack one (shift a0/2, elastic scenes)
                G.append(Go + (Gc - Go) * (a0e + s - r.edge_shift) / a0e)
            # integrated quantities at the sub-cell front (first order in offset/a0)
            at_front = front.at_front(r.tests, r.offset_out,
                                      {k: float(np.sum(p * f)) for k, f in obs.items()}, a0e)
            scale = {k: float(np.sum(np.abs(p * f))) for k, f in obs.items()}
            for k in ("force", "lateral"):
                out[f"mu_bar_{k}_front"] = quotient(at_front[k], at_front["load"], scale[k],
                                                    scale["load"])
            if r.crack_tips is not None and not r.crack_tips.any():
                G = [0.0]  # every edge held by contact (Γ → 0): no crack tip (front.py)
            if len(G) == 1:
                G = G * 2
            # colour 0 is trailing (v̂·n < 0); for elastic scenes one colour for both edges
            out.update(G1_over_dgamma=G[0] / scene.dgamma, G2_over_dgamma=G[1] / scene.dgamma)
        else:
            l1 = l2 = np.nan
            out.update(G1_over_dgamma=np.nan, G2_over_dgamma=np.nan)
        info = dict(outer_iterations=r.outer_iterations, solves=r.solves, message=r.message,
                    balanced_fraction=r.balanced_fraction, front_residual=r.residual)
        if status in ("detached", "full_contact"):  # no front: nothing unbalanced
            info.update(balanced_fraction=1.0, front_residual=0.0)
    else:
        res = solve_contact(op, h, mean_pressure=scene.p_mean,
                            penetration=scene.delta, tol=rtol,
                            maxiter=scene.solver["max_iterations"])
        p, mask, delta, u = res.pressure, res.mask, res.penetration, res.displacement
        status = "partial" if res.converged and not res.full_contact else (
            "full_contact" if res.full_contact else "not_converged")
        l1 = l2 = np.nan
        if scene.kind == "sinusoid" and status == "partial":
            zeros = np.zeros(cell.shape)
            l1, l2 = _edges_y_invariant(mask, zeros, cell)
        out.update(G1_over_dgamma=np.nan, G2_over_dgamma=np.nan)
        info = dict(iterations=res.iterations, message=res.message)
    status, info["message"] = _verify(status, info["message"], scene, mask)
    if status == "detached":  # the zero field, no edge (the 1D method's values)
        p, u, l1, l2 = np.zeros(cell.shape), np.zeros(cell.shape), 0.0, 0.0
    elif status == "full_contact":
        l1 = l2 = np.pi
    if status in ("detached", "full_contact") or not scene.adhesive:
        out.update(G1_over_dgamma=0.0, G2_over_dgamma=0.0)  # no edge, or no adhesion
    fr = _friction(op, h, p, u)
    pm = out.pop("p_front", float(p.mean()))
    mu = out.pop("mu_bar_force_front", fr["mu_profile"])
    mu_lat = out.pop("mu_bar_lateral_front", fr["mu_lateral"])
    out.update(a_tilde=(l1 + l2) / 2, e_tilde=(l2 - l1) / 2, p_tilde=pm / pstar,
               delta_tilde=float(delta), mu_bar=mu, mu_bar_mask=fr["mu_profile"],
               mu_bar_dissipation=fr["mu_dissipation"], mu_bar_lateral=mu_lat)
    G1, G2 = out["G1_over_dgamma"], out["G2_over_dgamma"]
    out["mu_bar_adhesive"] = 0.0 if G1 == G2 == 0.0 else quotient(
        (G1 - G2) * scene.dgamma, cell.Lx * pm, (abs(G1) + abs(G2)) * scene.dgamma,
        cell.Lx * float(np.abs(p).mean()))
    status, info["message"] = _undefined(status, info["message"], out)
    if status == "partial" and not out["a_tilde"] > 0:
        status, info["message"] = "not_converged", (
            f"the contact edges give ã = {out['a_tilde']!r} ≤ 0, so the state is not "
            f"reported as partial; solver: {info['message']}")
    from .sinusoid1d import SCALARS as names

    names = {**names, **SEED_EXTRA}
    data = {k: ((), float(v), {"units": "1", "long_name": names.get(k, k)})
            for k, v in out.items()}
    data["status"] = ((), status, {"long_name": "partial | full_contact | detached | "
                                                "not_converged", "units": "1"})
    data["pressure_tilde"] = (("x", "y"), p / pstar, {"long_name": "p/p*", "units": "1"})
    data["contact"] = (("x", "y"), mask.astype(np.int8), {"long_name": "contact mask",
                                                          "units": "1"})
    ds = xr.Dataset(data, coords={"x": ("x", cell.x, {"units": "1", "long_name": "k x"}),
                                  "y": ("y", cell.y, {"units": "1", "long_name": "k y"})})
    ds.attrs.update(**scene.params, **info)
    return ds


# -- physical scenes -------------------------------------------------------------------------
def _operator(scene: Scene) -> SpectralOperator:
    return SpectralOperator(scene.cell, scene.material, scene.layer, velocity=scene.velocity,
                            threads=scene.solver["threads"])


def _adhesiveless_mask(op, scene: Scene):
    """Initial mask of an adhesive solve: the adhesiveless contact at the same penetration,
    or at the same load (at |load|, or a light touch at zero load)."""
    from .contact import solve_contact

    h = scene.heights
    if scene.delta is not None:
        if scene.delta <= 0:
            return None
        res = solve_contact(op, h, penetration=scene.delta, tol=1e-6)
    else:
        p = abs(scene.p_mean) or 1e-4 * scene.material.E0 * float(np.std(h)) / max(
            scene.cell.Lx, scene.cell.Ly)
        res = solve_contact(op, h, mean_pressure=p, tol=1e-6)
    return res.mask if res.mask.any() and not res.mask.all() else None


def _solve_grid(scene: Scene, mask0=None, progress=None):
    import xarray as xr

    from .adhesive import solve_adhesive
    from .contact import solve_contact
    from .front import front_outputs

    op = _operator(scene)
    cell, h = scene.cell, scene.heights
    tol = scene.solver["tol"]
    sc = {}
    fields = {"heights": h}
    if scene.adhesive:
        # start from the adhesiveless contact (not from one summit cell); along a path,
        # from the carried mask joined with it (loading: no overshoot of the nucleation at
        # the new load's Δ; unloading: the adhesiveless contact is inside the carried one)
        m_free = _adhesiveless_mask(op, scene)
        mask0 = m_free if mask0 is None else (mask0 | m_free if m_free is not None else mask0)
        r = solve_adhesive(op, h, scene.dgamma, scene.a0, penetration=scene.delta,
                           mean_pressure=scene.p_mean, mask0=mask0, rtol=tol,
                           max_outer=scene.solver["max_outer"],
                           **_smoothing(scene),
                           criterion=scene.solver.get("criterion", "exact"),
                           front_tol=scene.solver.get("front_tol", 0.5),
                           flaw_radius=scene.flaw_radius, progress=progress)
        p, mask, delta, status = r.pressure, r.mask, r.penetration, r.status
        u = op.apply(p)
        msg = r.message
        sc.update(iterations=r.outer_iterations, solves=r.solves,
                  unresolved_patches=r.unresolved_patches,
                  balanced_fraction=r.balanced_fraction, front_residual=r.residual)
        area = None
        pm = r.mean_pressure
        status, msg = _verify(status, msg, scene, mask)
        if status == "partial" and r.tests is not None:
            fo = front_outputs(op, r, scene.dgamma)
            area = fo["area_fraction"]
            mu_a = fo["mu_adhesive"]
            if np.isnan(mu_a):  # no net normal force: 0 when G1 = G2, else ±inf (the sign
                # of −∮(G − Δγ)(n·v̂)ds, that of G1 − G2)
                mu_a = quotient(fo["G1"] - fo["G2"], 0.0, abs(fo["G1"]) + abs(fo["G2"]))
            sc.update(G1=fo["G1"], G2=fo["G2"], mu_adhesive=mu_a,
                      front_length=fo["front_length"])
            fields["G_front"] = fo["G_map"]
        elif status in ("detached", "full_contact"):  # no front (the 1D method's values)
            sc.update(G1=0.0, G2=0.0, mu_adhesive=0.0, front_length=0.0,
                      balanced_fraction=1.0, front_residual=0.0)
            if status == "detached":
                p, mask, u = np.zeros(cell.shape), np.zeros(cell.shape, bool), np.zeros(
                    cell.shape)
        else:
            sc.update(G1=np.nan, G2=np.nan, mu_adhesive=np.nan, front_length=np.nan)
        diag = {"a0": r.a0, "edge_shift": r.edge_shift,
                "method": "front-layer energy balance, sub-cell front",
                "history": r.history[-20:]}
    else:
        res = solve_contact(op, h, mean_pressure=scene.p_mean, penetration=scene.delta,
                            tol=tol, maxiter=scene.solver["max_iterations"])
        p, mask, delta, u = res.pressure, res.mask, res.penetration, res.displacement
        status = ("full_contact" if res.full_contact else "partial") if res.converged else (
            "not_converged")
        msg = res.message
        status, msg = _verify(status, msg, scene, mask)
        sc.update(iterations=res.iterations)
        area, pm = None, float(p.mean())
        diag = {"method": res.method, **res.diagnostics}
    w = h - float(h.max()) + delta
    gap = np.where(mask, 0.0, u - w)
    fr = _friction(op, h, p, u)
    sc.update(mean_pressure=pm, penetration=float(delta),
              area_fraction=float(mask.mean()) if area is None else area, **fr)
    status, msg = _undefined(status, msg, sc)
    data = {k: ((), float(v), _attrs(SCALARS[k]))
            for k, v in sc.items()}
    data["status"] = ((), status, _attrs(STATUS))
    if scene.fields:
        fields.update(pressure=p, displacement=u, gap=gap, contact=mask.astype(np.int8))
        for k, v in fields.items():
            data[k] = (("x", "y"), v, _attrs(FIELDS[k]))
    ds = xr.Dataset(data, coords={
        "x": ("x", cell.x, {"units": "m", "long_name": "position along x"}),
        "y": ("y", cell.y, {"units": "m", "long_name": "position along y"})})
    ds.attrs.update(solver_message=msg, solver_diagnostics=json.dumps(diag, default=str),
                    velocity_x=float(op.velocity[0]), velocity_y=float(op.velocity[1]))
    return ds, mask


def _dimensionless_groups(scene: Scene) -> dict:
    """ζ, β, Γ, ã0, the wave number k, amplitude Λ and p* of a physical sinusoid scene."""
    sf = scene.spec["surface"]
    lam = sf["wavelength"] or scene.cell.Lx
    k, amp = 2 * np.pi / lam, sf["amplitude"]
    m = scene.material
    E0, nu = m.E0, m.nu
    if isinstance(m, StandardLinearSolid) and scene.velocity[0] != 0.0:
        zeta, beta = k * abs(scene.velocity[0]) * m.tau, m.Einf / m.E0
    else:
        zeta, beta = 0.0, 1.0
    from .conventions import gamma_from_dgamma, p_star

    return dict(zeta=zeta, beta=beta, Gamma=gamma_from_dgamma(scene.dgamma, E0, nu, k, amp),
                a0_tilde=k * scene.a0 if scene.adhesive else 0.0, k=k, amp=amp,
                pstar=p_star(E0, nu, k, amp))


def _smoothing(scene) -> dict:
    """The front-smoothing keywords of solve_adhesive: the scene's, else criterion's
    defaults (the schema's defaults are the same numbers, tested)."""
    from .criterion import FRONT_SMOOTHING, SMOOTHING_PER_RADIUS

    return {"front_smoothing": scene.solver.get("front_smoothing", FRONT_SMOOTHING),
            "smoothing_per_radius": scene.solver.get("smoothing_per_radius",
                                                     SMOOTHING_PER_RADIUS)}


def _solve_1d(scene: Scene, guess=None):
    """A sinusoid scene through the seed's 1D method (dimensionless, then SI for physical
    scenes)."""
    from . import sinusoid1d

    phys = scene.kind == "physical"
    d = _dimensionless_groups(scene) if phys else dict(scene.params, k=1.0, amp=1.0, pstar=0.5)
    if not 0.0 <= d["a0_tilde"] <= 1.0:
        raise SceneError(f"adhesion.a0: k a0 = {d['a0_tilde']!r} is outside the 1D method's "
                         "range [0, 1]")
    pt = None if scene.p_mean is None else scene.p_mean / d["pstar"]
    dt = None if scene.delta is None else scene.delta / d["amp"]
    ds = sinusoid1d.solve(d["zeta"], d["beta"], d["Gamma"], p_tilde=pt, delta_tilde=dt,
                          a0_tilde=d["a0_tilde"], guess=guess)
    if not phys:
        return ds
    k, amp, ps = d["k"], d["amp"], d["pstar"]
    dg = scene.dgamma if scene.adhesive else np.nan
    vals = dict(mean_pressure=ds.p_tilde.item() * ps, penetration=ds.delta_tilde.item() * amp,
                area_fraction=ds.a_tilde.item() / np.pi, mu=ds.mu_bar.item() * k * amp,
                mu_adhesive=ds.mu_bar_adhesive.item() * k * amp,
                G1=ds.G1_over_dgamma.item() * dg, G2=ds.G2_over_dgamma.item() * dg,
                contact_half_width=ds.a_tilde.item() / k, eccentricity=ds.e_tilde.item() / k)
    for key, v in vals.items():
        ds[key] = ((), float(v), _attrs(SCALARS[key]))
    ds["pressure"] = (("x",), -ds.sigma_tilde.values * ps,
                      _attrs(FIELDS["pressure"]))
    ds["displacement"] = (("x",), ds.u_tilde.values * amp,
                          _attrs(FIELDS["displacement"]))
    ds = ds.assign_coords(position=("x", ds.x_tilde.values / k,
                                    {"units": "m", "long_name": "position along x"}))
    ds.attrs.update({f"dimensionless_{n}": float(d[n]) for n in ("zeta", "beta", "Gamma",
                                                                  "a0_tilde")})
    return ds


def _solve_one(scene: Scene, state, progress=None):
    """One control value; ``state`` carries the mask (grid) or edges (1D) between steps;
    ``progress``: the adhesive front's per-iteration callback (solve_adhesive)."""
    if scene.model == "sinusoid1d":
        ds = _solve_1d(scene, guess=state)
        ok = ds.status.item() == "partial"
        return ds, ((ds.attrs["l1_tilde"], ds.attrs["l2_tilde"]) if ok else None)
    if scene.kind == "sinusoid":
        ds = _solve_seed_grid(scene, mask0=state, rtol=scene.solver["tol"],
                              progress=progress)
        mask = ds.contact.values.astype(bool) if "contact" in ds else None
        # a detached state carries nothing: the next step starts afresh (an empty mask
        # would be 'detached' at once, whatever the load)
        return ds, mask if mask is not None and mask.any() else None
    ds, mask = _solve_grid(scene, mask0=state, progress=progress)
    return ds, (mask if scene.adhesive and mask.any() and not mask.all() else None)


def solve(scene: Scene, *, mask0=None, progress: bool = False):
    """Solve a scene; returns an xarray Dataset.

    Seed scenes use the 1D method's dimensionless names (``a_tilde``, ``e_tilde``,
    ``p_tilde``, ``delta_tilde``, ``mu_bar``, ``mu_bar_adhesive``, ``G1_over_dgamma``,
    ``G2_over_dgamma``, ``status``); physical scenes SI names (``mean_pressure``, ``mu``,
    ``G1``, ...).  A path scene returns a ``step`` dimension.  Attributes: the model that ran,
    the scene (JSON), package version, UTC timestamp, FFT backend and threads, solver message.
    """
    import xarray as xr

    from . import fft
    from .plausibility import warn

    warn(scene)
    steps = scene.steps
    state = mask0
    out = []
    it = steps
    bar = None
    if progress:
        from tqdm import tqdm

        if len(steps) > 1:
            it = tqdm(steps, desc="path", unit="step")
        if scene.adhesive and scene.model == "grid2d":
            bar = tqdm(desc="front", unit="it", position=int(len(steps) > 1), leave=False)
    for v in it:
        if bar is not None:
            bar.reset()
        ds, state = _solve_one(scene.at_step(v), state, None if bar is None else (
            lambda k, text: (bar.update(1), bar.set_postfix_str(text, refresh=False))))
        out.append(ds)
    if bar is not None:
        bar.close()
    if len(out) == 1:
        ds = out[0]
    else:
        name = scene.control[0]
        for d in out:  # per-step solver messages survive the concatenation as a variable
            msg = d.attrs.get("solver_message", d.attrs.get("message", ""))
            d.attrs.pop("message", None)
            d["solver_message"] = ((), str(msg), {"units": "1",
                                                  "long_name": "solver message of the step"})
        ds = xr.concat(out, dim="step", combine_attrs="drop_conflicts", data_vars="all")
        vals = np.asarray(scene.control[1], float)
        if scene.kind == "sinusoid" and name == "mean_pressure":
            name, vals = "p_tilde", vals / 0.5
        ds = ds.assign_coords(step=("step", np.arange(len(out)), {"units": "1",
                                                                 "long_name": "path step"}),
                              control_value=("step", vals, {
                                  "units": "1" if scene.kind == "sinusoid" else (
                                      "Pa" if name == "mean_pressure" else "m"),
                                  "long_name": f"prescribed {name}"}))
    for var in list(ds.variables.values()):
        var.attrs.setdefault("units", "1")
        var.attrs.setdefault("long_name", var.name if hasattr(var, "name") else "")
    ds.attrs.update(
        title=f"spectralbem result: {scene.spec.get('scene', {}).get('name', scene.kind)}",
        model=scene.model, spectralbem_version=__version__,
        created_utc=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        fft_backend=fft.backend(), fft_threads=int(scene.solver["threads"]),
        fft_planner=fft.planner() if fft.backend() == "pyfftw" else "numpy",
        scene=json.dumps(scene.spec, sort_keys=True, default=str),
        conventions="spectralbem.conventions: SI units; u into the slab, p compressive "
                    "positive; seed Fourier convention (Im E < 0 for ω > 0)")
    return cf_attributes(ds)
