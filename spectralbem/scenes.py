"""Scenes: one study, validated and built before any heavy work; ``solve(scene)`` → Dataset
runs it (:mod:`spectralbem.solving`).

A scene comes from a TOML file (:func:`load_scene`, schema in :mod:`spectralbem.schema`) or
from Python (:meth:`Scene.sinusoid` for the seed's dimensionless problem).  The scene decides
the model, and the dataset records which one ran (attribute ``model``):

* ``sinusoid1d`` — the seed's 1D method (a y-invariant sinusoid on an elastic or standard
  linear solid half-space sliding along x; chosen by ``model = "auto"``);
* ``grid2d`` — the periodic grid: Polonsky–Keer (elastic or resting), semismooth Newton
  (viscoelastic sliding); the front energy balance only when Δγ > 0.

A list under ``control`` is a load/unload path, solved in order with the contact mask carried
from step to step (adhesion hysteresis is physical: no global minimisation).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import kinds
from .contact import ContactError, check_penetration
from .conventions import shown
from .keys import EXTRAPOLATE_MIN_CELLS, extrapolable
from .layers import HalfSpace, LayerError
from .materials import Elastic, Material, MaterialError, StandardLinearSolid
from .schema import (
    SECTIONS,
    SceneError,
    check_a0_on_grid,
    input_paths,
    short,
    short_name,
    too_deep,
    validate,
)
from .spectral import Cell, GridError
from .surfaces import (
    TEXT_SUFFIXES,
    SurfaceError,
    check_input_file,
    file_limit,
    read_heights,
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
    per step (one step unless the scene is a path); ``mean_pressure``/``penetration`` hold the
    step being solved (the first one of a path), the other is None.
    """

    cell: Cell
    material: Material
    heights: np.ndarray
    velocity: tuple
    dgamma: object  # J/m², scalar or per-cell map
    a0: float
    mean_pressure: float | None = None  # Pa (seed scenes: k = Λ = E0* = 1 units)
    penetration: float | None = None  # m (seed scenes: k = Λ = E0* = 1 units)
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
    def viscoelastic(self) -> bool:
        """A rate-dependent solid in motion (the operator's ``viscoelastic``): a0 is then a
        physical length; at rest, or with an elastic solid, it is numerical."""
        return not self.material.is_elastic and bool(np.any(np.asarray(self.velocity) != 0))

    @property
    def extrapolate_a0(self) -> bool:
        """``solver.extrapolate_a0`` as the solve uses it: the scene's value, else (the
        default) on in an adhesive elastic grid scene whose a0 spans two cells or more, where
        a0 is numerical and the edge's a0² term would otherwise move the answer with it
        (docs/theory.md, "Extrapolating the elastic edge"), off everywhere else."""
        value = self.solver.get("extrapolate_a0")
        if value is not None:
            return bool(value)
        return (self.model == "grid2d" and self.adhesive and not self.viscoelastic
                and extrapolable(self.a0 / min(self.cell.hx, self.cell.hy)))

    @property
    def steps(self) -> list:
        """Control values of the path (one entry for a single state)."""
        if self.control:
            return list(self.control[1])
        return [self.mean_pressure if self.mean_pressure is not None else self.penetration]

    def at_step(self, value) -> Scene:
        name = self.control[0] if self.control else (
            "mean_pressure" if self.mean_pressure is not None else "penetration")
        if name == "mean_pressure":
            return dataclasses.replace(self, mean_pressure=value, penetration=None)
        return dataclasses.replace(self, mean_pressure=None, penetration=value)

    @classmethod
    def sinusoid(cls, zeta: float, beta: float, Gamma: float, *, p_tilde: float | None = None,
                 delta_tilde: float | None = None, a0_tilde: float,
                 cells_per_wavelength: int = 1024, ny: int = 8, direction_deg: float = 0.0,
                 model: str = "grid2d", solver: dict | None = None) -> Scene:
        """The seed scene: h = Λ cos(kx) on an Lx = λ by ny-cell periodic cell, sliding at
        ζ = kvτ along the angle ``direction_deg`` to the wave vector.  ``model`` =
        ``"sinusoid1d"`` runs the seed's 1D method instead of the grid; ``solver``: entries of
        the scene's ``[solver]`` table."""
        raw = {"scene": {"model": model},
               "sinusoid": {"zeta": zeta, "beta": beta, "Gamma": Gamma, "a0_tilde": a0_tilde,
                            "cells_per_wavelength": cells_per_wavelength, "ny": ny,
                            "direction_deg": direction_deg}}
        for k, v in (("p_tilde", p_tilde), ("delta_tilde", delta_tilde)):
            if v is not None:
                raw["sinusoid"][k] = v
        if solver:
            raw["solver"] = dict(solver)
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
    raw, unread = _grid_from_file(apply_overrides(raw, overrides), base)
    spec, problems = validate(raw)
    if unread:  # the grid keys left out were to come from the file: its failure is the cause
        why, keys = unread
        problems = [why] + [p for p in problems if not p.startswith((
            "grid: missing section", *(f"grid.{k}: missing" for k in keys)))]
    if problems:
        raise SceneError(problems)
    if "sinusoid" in spec:
        return _build_seed(spec)
    return _build_physical(spec, base)


#: the grid keys a height map may give (Nx, Ny: its shape; Lx, Ly: a stated size)
_FROM_FILE = ("Nx", "Ny", "Lx", "Ly")
#: height-map formats that state no size (Lx, Ly are never taken from them)
_NO_SIZE = (".npy", *TEXT_SUFFIXES)


def _grid_from_file(raw: dict, base: Path) -> tuple:
    """A height-map scene may leave out the grid: Nx, Ny default to the map's shape and Lx,
    Ly to the size the file states (netCDF coordinates); keys given are kept (and checked
    against the file later).  Returns (scene, unread): unread is None, or, when keys were left
    out for the file to give and it cannot be read, (the problem ``surface.path: ...`` naming
    the file and why, the keys it was to give); other problems are left to the checks."""
    sf, g = raw.get("surface"), raw.get("grid", {})
    if not (isinstance(sf, dict) and sf.get("kind") == "file" and isinstance(g, dict)
            and isinstance(sf.get("path"), str)) or all(
            g.get(k) is not None for k in _FROM_FILE):
        return raw, None
    sized = Path(sf["path"]).suffix.lower() not in _NO_SIZE
    keys = [k for k in _FROM_FILE if g.get(k) is None and (sized or k in ("Nx", "Ny"))]
    try:
        scale = sf.get("scale", 1.0)
        h, size = read_heights(base / sf["path"], variable=sf.get("variable", "heights"),
                               scale=scale if isinstance(scale, (int, float)) else 1.0,
                               max_bytes=file_limit(65536**2))
    except (SurfaceError, OSError) as exc:
        why = str(exc) if isinstance(exc, SurfaceError) else (
            f"cannot read height map {short(str(base / sf['path']))}: {exc.strerror or exc}")
        left = ", ".join(f"grid.{k}" for k in keys) + (" is" if len(keys) == 1 else " are")
        return raw, (f"surface.path: {why.rstrip('.')}; {left} left out, to be taken from the "
                     "height map, so it must be readable (or give them in [grid])",
                     keys) if keys else None
    except (TypeError, ValueError):  # a key of the wrong type: the schema names it
        return raw, None
    out = dict(raw)
    out["grid"] = g = dict(g)
    g.setdefault("Nx", int(h.shape[0]))
    g.setdefault("Ny", int(h.shape[1]))
    if size is not None:
        g.setdefault("Lx", size[0])
        g.setdefault("Ly", size[1])
    return out, None


#: peak memory of a grid solve per cell (bytes), with a margin (docs/performance.md, scaling)
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
    memory = dict(viscoelastic=s["zeta"] > 0 and s["beta"] > 1, adhesive=s["Gamma"] > 0)
    _check_memory("sinusoid.cells_per_wavelength × sinusoid.ny", (n, ny), model=model,
                  steps=len(values), **memory)
    lam = 2 * np.pi
    cell = Cell(lam, lam / n * ny, n, ny)
    from .oned import dimensionless_material

    mat, v = dimensionless_material(s["zeta"], s["beta"])
    phi = np.radians(s["direction_deg"])
    # p* = 1/2 in these units: the mean pressure is p̃/2
    steps = [0.5 * x for x in values] if ctl[0] == "p_tilde" else list(values)
    name = "mean_pressure" if ctl[0] == "p_tilde" else "penetration"
    p0 = steps[0] if name == "mean_pressure" else None
    d0 = steps[0] if name == "penetration" else None
    params = dict(zeta=s["zeta"], beta=s["beta"], Gamma=s["Gamma"], a0_tilde=s["a0_tilde"],
                  cells_per_wavelength=n, ny=ny, direction_deg=s["direction_deg"])
    if name == "penetration":  # the 1D method's bound too (Δ̃ < 1), named by its key
        _check_penetration(HalfSpace(), mat.nu, sinusoid(cell, 1.0), steps,
                           "sinusoid.delta_tilde")
    extra = {"solver": dict(spec["solver"])} if "solver" in spec else {}
    if extra and extra["solver"].get("extrapolate_a0"):  # before any solve, as a scene error
        _check_extrapolation(cell, s["a0_tilde"], model, memory)
    return Scene(cell, mat, sinusoid(cell, 1.0), (v * np.cos(phi), v * np.sin(phi)),
                 np.pi * s["Gamma"], s["a0_tilde"], p0, d0, "sinusoid", params, None, model,
                 spec, control=(name, steps), **extra)


def _build(section: str, spec: dict, cell: Cell, base: Path, problems: list):
    """The object of a kind section ([surface], [material], [layer]) by its registered
    builder (:mod:`spectralbem.kinds`); its errors become problems (None then)."""
    try:
        return kinds.build(section, spec, kinds.Context(cell, base, problems))
    except (MaterialError, SurfaceError, LayerError) as exc:
        problems.append(f"{section}: {str(exc)[:300]}")
        return None


def _check_penetration(layer, nu, h, values, key: str = "control.penetration"):
    """Penetrations the slab cannot take (mean u = 0: Δ < max h − mean h), refused while the
    scene is built, before any solve of a path; ``key``: the scene key that set them."""
    try:
        check_penetration(layer, nu, h, values)
    except ContactError as exc:
        raise SceneError([key + str(exc).removeprefix("penetration")]) from exc


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
                        f"range {key.range_text()} J/m² (first {shown(dg[i])} at index {i})")
        return None
    return dg


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
    # the files it reads by their absolute paths, so that the dataset's scene reruns as it is
    for dotted, path in input_paths(spec, base).items():
        sec, key = dotted.split(".")
        spec = {**spec, sec: {**spec[sec], key: str(Path(os.path.abspath(path)))}}
    g = spec["grid"]
    try:
        cell = Cell(g["Lx"], g["Ly"], g["Nx"], g["Ny"])
    except GridError as exc:
        raise SceneError(f"grid: {exc}") from exc
    mat = _build("material", spec["material"], cell, base, problems)
    model = spec["scene"]["model"]
    if mat is not None and model != "grid2d":
        why = _one_d_obstacles(spec, mat)
        if model == "sinusoid1d" and why:
            problems.append("scene.model: 'sinusoid1d' is not possible: " + "; ".join(why)
                            + " (allowed: auto, grid2d)")
        model = "sinusoid1d" if not why else "grid2d"
    if model == "grid2d" and spec["scene"]["model"] != "grid2d":
        check_a0_on_grid(spec, problems)  # 'auto' chose the grid: its a0 against the cells
    adh, ctl = spec["adhesion"], spec["control"]
    name = "mean_pressure" if ctl["mean_pressure"] is not None else "penetration"
    values = ctl[name] if isinstance(ctl[name], list) else [ctl[name]]
    velocity = _velocity(spec["motion"])
    memory = dict(viscoelastic=not isinstance(mat, Elastic) and any(velocity),
                  adhesive=adh["dgamma"] > 0 or adh["dgamma_map"] is not None,
                  steps=len(values), fields=spec["output"]["fields"])
    _check_memory("grid.Nx × grid.Ny", cell.shape, model=model, **memory)  # before any work
    if spec["solver"].get("extrapolate_a0"):
        _check_extrapolation(cell, adh["a0"], model, memory)
    h = _build("surface", spec["surface"], cell, base, problems)
    dgamma = adh["dgamma"]
    if adh["dgamma_map"] is not None:
        dgamma = _dgamma_map(adh, cell, base, problems)
    if problems:
        raise SceneError(problems)
    layer = _build("layer", spec["layer"], cell, base, problems)
    if problems:
        raise SceneError(problems)
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
            check_a0_on_grid(spec, problems)
            if problems:
                raise SceneError(problems)
            _check_memory("grid.Nx × grid.Ny", cell.shape, model=model, **memory)
            scene = dataclasses.replace(scene, model=model)
    if name == "penetration":  # either model: named by its key before any solve
        _check_penetration(layer, mat.nu, h, values)
    return scene


def _check_extrapolation(cell: Cell, a0, model: str, memory: dict) -> None:
    """solver.extrapolate_a0 needs an adhesive elastic grid scene with a0 of two cells or more
    (adhesive.solve_adhesive)."""
    cells = (a0 or 0.0) / min(cell.hx, cell.hy)
    if memory["viscoelastic"] or not memory["adhesive"] or model != "grid2d" \
            or not extrapolable(cells):
        raise SceneError([f"solver.extrapolate_a0: true needs an adhesive elastic 2D scene "
                          f"with a0 of at least {EXTRAPOLATE_MIN_CELLS:g} cells (a0 "
                          f"is numerical there); "
                          f"this one: viscoelastic {memory['viscoelastic']}, adhesive "
                          f"{memory['adhesive']}, model {model}, a0 = {cells:g} cells"])


def solve(scene: Scene, *, mask0=None, progress: bool = False):
    """Solve a scene; returns an xarray Dataset (:func:`spectralbem.solving.solve`)."""
    from .solving import solve as _solve

    return _solve(scene, mask0=mask0, progress=progress)
