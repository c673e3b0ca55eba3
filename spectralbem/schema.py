"""Scene files (TOML): the schema, and validation that reports every problem at once.

A scene file describes one study.  Two forms exist:

* a **physical scene** (SI units): sections ``[grid]``, ``[surface]``, ``[material]``,
  ``[control]`` and optionally ``[layer]``, ``[adhesion]``, ``[motion]``, ``[solver]``,
  ``[output]``;
* the **seed scene** ``[sinusoid]``: the paper's dimensionless sinusoid problem (ζ, β, Γ, p̃ or
  Δ̃, ã0), run by the 1D method or on the grid.

Both may carry ``[scene]`` (name, description, model).  :func:`validate` walks a parsed TOML
mapping and returns the problems as ``"key.path: message"`` lines (unknown keys, missing keys,
wrong types, values out of range, inconsistent combinations); quantities written with a unit
are converted by :mod:`spectralbem.units`; docs/generate_reference.py renders the schema for
docs/user_guide.md.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from .conventions import plain, shown
from .keys import (  # noqa: F401 (re-exported: the schema's vocabulary)
    BAND_TOL_MAX,
    DELAYED,
    DELAYED_DEFAULT,
    FRONT_TOL,
    HEIGHT,
    LENGTH,
    MODULUS,
    REQUIRED,
    STIFFENING,
    TIME,
    TOL_MIN,
    Key,
    front_tol_max,
)
from .keys import key as _k
from .units import quantity

#: longest text of a value or a name quoted in a message (longer ones are cut, their length
#: stated); scene values are at most this deep (a table of sections, a list of numbers)
SHORT = 60
MAX_DEPTH = 6


def short(v, limit: int = SHORT) -> str:
    """A value as messages quote it: repr, with long strings, long lists and deep nesting cut
    (a 200 kB value is not echoed back whole)."""
    import reprlib

    r = reprlib.Repr()
    r.maxstring = r.maxother = limit
    r.maxlist = r.maxdict = r.maxtuple = 8
    r.maxlevel = 3
    text = r.repr(plain(v))
    if isinstance(v, str) and len(v) > limit:
        text += f" ({len(v)} characters)"
    elif isinstance(v, (list, dict)) and len(v) > 8:
        text += f" ({len(v)} entries)"
    return text


def short_name(name: str, limit: int = SHORT) -> str:
    """A key or section name as messages quote it (cut when longer than ``limit``)."""
    name = str(name)
    return name if len(name) <= limit else f"{name[:limit]}... ({len(name)} characters)"


def too_deep(v, limit: int = MAX_DEPTH) -> bool:
    """Whether lists/tables nest deeper than ``limit`` (checked without recursion, so a
    100 000-deep array is refused instead of exhausting the interpreter's stack)."""
    stack = [(v, 0)]
    while stack:
        x, d = stack.pop()
        if isinstance(x, (list, tuple, dict)):
            if d >= limit:
                return True
            stack.extend((y, d + 1) for y in (x.values() if isinstance(x, dict) else x))
    return False


class SceneError(ValueError):
    """Invalid scene: the message lists every problem, one per line, with its key path."""

    def __init__(self, problems):
        problems = list(problems) if not isinstance(problems, str) else [problems]
        # a safety net for messages that quote a value without short(): no line is longer
        # than this (the key path comes first, so it survives)
        self.problems = [p if len(p) <= 400 else f"{p[:400]}... ({len(p)} characters)"
                         for p in map(str, problems)]
        n = len(self.problems)
        head = "invalid scene" if n == 1 else f"invalid scene ({n} problems)"
        super().__init__(head + ":\n  " + "\n  ".join(self.problems))


# -- sections without kinds ------------------------------------------------------------------
SECTIONS = {
    "scene": {
        "name": _k("string", "short name of the study", default="scene"),
        "description": _k("string", "free text", default=""),
        "model": _k("string", "which model runs: 'auto' picks the 1D method for a "
                    "y-invariant sinusoid it can solve (elastic or standard linear solid, "
                    "half-space, sliding along x), the grid otherwise",
                    choices=("auto", "grid2d", "sinusoid1d"), default="auto"),
    },
    "grid": {
        "Lx": _k("number", "periodic cell length along x", "m", *LENGTH),
        "Ly": _k("number", "periodic cell length along y", "m", *LENGTH),
        "Nx": _k("integer", "cells along x (not only powers of two; the solve's memory "
                 "estimate must fit the machine)", "", 8, 65536),
        "Ny": _k("integer", "cells along y (1 for a y-invariant strip)", "", 1, 65536),
    },
    "adhesion": {
        "dgamma": _k("number", "work of adhesion Δγ (0: adhesiveless)", "J/m²", 0, 1e6,
                     default=0.0),
        "dgamma_map": _k("path", "per-cell Δγ map (.npy, shape (Nx, Ny), J/m², values in "
                         "[0, 1e6]); replaces dgamma", default=None),
        "a0": _k("number", "advance width of the edge energy balance (a process-zone "
                 "length; at least one cell, at most half the cell)", "m", 0, None, True,
                 default=None),
        "flaw_radius": _k("number", "radius of the flaw through which a full contact may "
                          "open (default: a0); in elastic scenes Griffith's condition on it "
                          "decides; at most half the cell", "m", 0, None, True,
                          default=None),
    },
    "motion": {
        "speed": _k("number", "sliding speed |v| of the indenter relative to the slab", "m/s",
                    0, 1e6, default=None),
        "direction_deg": _k("number", "angle of v to the x axis", "deg", -360, 360,
                            default=0.0),
        "velocity": _k("numbers", "velocity vector (vx, vy); alternative to speed and "
                       "direction_deg", "m/s", -1e6, 1e6, default=None),
    },
    "control": {
        "mean_pressure": _k("number_or_numbers", "mean (nominal) pressure, compressive "
                            "positive; a list is a load/unload path run in order", "Pa",
                            -1e12, 1e12, default=None, tiny=1e-9),
        "penetration": _k("number_or_numbers", "penetration Δ (mean-level gauge); below "
                          "max h − mean h on a half-space, an A.5 layer or an incompressible "
                          "glued layer (their mean displacement is 0); a list is a path", "m",
                          -1e3, 1e3, default=None, tiny=1e-15),
    },
    "solver": {
        "tol": _k("number", "relative tolerance of the contact / Krylov solves (not below "
                  "1e-14: double precision cannot reach it)", "", TOL_MIN, 1e-2,
                  default=1e-10),
        "max_iterations": _k("integer", "iteration guard of the contact solver (Polonsky–Keer "
                             "iterations; Newton or active-set steps of a viscoelastic slab, "
                             "200 at most); in an adhesive scene, of its adhesiveless start "
                             "(the front iteration's guard is max_outer)", "", 1, 10**6,
                             default=10000),
        "max_outer": _k("integer", "iteration guard of the adhesive front iteration", "", 1,
                        10**5, default=500),
        "threads": _k("integer", "FFT threads (FFTW; a solve with more than one runs BLAS on "
                      "one thread: docs/performance.md, threads)", "", 1, 256, default=1),
        "front_smoothing": _k("number", "σ of the Gaussian average of the energy balance "
                              "along the front, in units of adhesion.a0 (adhesive scenes; "
                              "default 1.5 in viscoelastic scenes, 0.5 in elastic ones)",
                              "a0", 0, 100, default=None),
        "smoothing_per_radius": _k("number", "σ grows to this fraction of the front "
                                   "radius 2A/P of large contact patches (0: σ fixed)", "", 0, 1,
                                   default=0.23),
        "front_tol": _k("number", "tolerance of the edge balance in position: every resolved "
                        "front cell's balanced edge within ½ + front_tol cells of the mask "
                        "edge (at most max(0.5, a0/(2h)); larger than 0.5 converges faster "
                        "where a0 spans many cells, less accurately, docs/theory.md)",
                        "cells", 0, 100, True, default=FRONT_TOL),
        "band_tol": _k("number", "adhesive 2D scenes: relative tolerance of the band tests' "
                       "masked solves while the front moves (default: 1e3 tol, at most 1e-6); a "
                       "state that balances is tested again at tol before it is accepted. 1e-5 "
                       "costs 13-18 % less on the rough states at 512², same loading states, "
                       "unloading states within their spread (docs/performance.md)", "",
                       TOL_MIN, BAND_TOL_MAX, default=None),
        "criterion": _k("string", "front criterion of adhesive scenes: exact layer tests, the "
                        "zero-solve predictor then exact tests (hybrid), or the predictor "
                        "alone (predictor; less accurate, see docs/performance.md)",
                        choices=("exact", "hybrid", "predictor"), default="exact"),
        "delayed_kernel": _k("string", "viscoelastic scenes: the delayed (creep) part of "
                             "the kernel averaged over the cells (cell), or sampled at the "
                             "grid's wavevectors (sampled: needs about twice the cells per vτ "
                             "for the same accuracy, docs/theory.md)", choices=DELAYED,
                             default=DELAYED_DEFAULT),
        "coarse_start": _k("boolean", "adhesive scenes: start the front from the same scene "
                           "solved on the grid of half the cells per side (recursively, while "
                           "it keeps 64 cells per side and a0 spans a coarse cell; the "
                           "solver's message says when it cannot; fewer front iterations in "
                           "elastic scenes and in the rough viscoelastic state at 1024², see "
                           "docs/performance.md)",
                           default=False),
        "extrapolate_a0": _k("boolean", "adhesive elastic 2D scenes with a0 of two cells or "
                             "more: the sharp-crack edge from the tests at a0 and a0/2, "
                             "extrapolated to a0 → 0 (Richardson; twice the band solves, "
                             "docs/theory.md); default: on in those scenes (a0 is "
                             "numerical there), off elsewhere", default=None),
    },
    "output": {
        "fields": _k("boolean", "store the 2D fields (pressure, gap, ...) in the dataset",
                     default=True),
    },
    "sinusoid": {
        "zeta": _k("number", "ζ = k v τ (0: elastic E0 limit)", "1", 0, 1e12, tiny=1e-12),
        "beta": _k("number", "β = E∞/E0", "1", 1, 1e8),
        "Gamma": _k("number", "Γ = (1-ν²)Δγ/(π E0 k Λ²) (0: adhesiveless)", "1", 0, 10,
                    tiny=1e-12),
        "p_tilde": _k("number_or_numbers", "p̃∞ = p∞/p*, load control (a list is a path)", "1",
                      -10, 100, default=None, tiny=1e-12),
        "delta_tilde": _k("number_or_numbers", "Δ̃ = Δ/Λ, displacement control", "1", -10, 10,
                          default=None),
        "a0_tilde": _k("number", "ã0 = k a0, advance width (0: strict SIF limit, 1D only; "
                       "below 1e-6 the 1D method's quadrature cannot resolve it)", "1", 0, 1,
                       tiny=1e-6),
        "cells_per_wavelength": _k("integer", "grid model: cells per wavelength (at most the "
                                   "grid's 65536 cells along x)", "", 16, 65536,
                                   default=1024),
        "ny": _k("integer", "grid model: cells along y", "", 1, 4096, default=8),
        "direction_deg": _k("number", "grid model: sliding direction to the wave vector",
                            "deg", -360, 360, default=0.0),
    },
}

# -- sections with a 'kind': declared beside their classes (spectralbem.kinds) ----------------
from . import layers, materials, surfaces  # noqa: E402,F401  (each registers its kinds)
from .kinds import KEYS as KINDS  # noqa: E402  (section -> kind -> {key: Key}, live)
from .kinds import check as _check_kind  # noqa: E402

KIND_DEFAULTS = {"layer": "half_space"}

PHYSICAL = ("grid", "surface", "material", "layer", "adhesion", "motion", "control", "solver",
            "output")
_UNIT_STRING = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*[A-Za-zμµ°%/²]+")


def _check_value(path: str, key: Key, v, problems: list):
    """Type and range of one value; returns the normalised value (or None on a problem).
    Messages quote the value shortened (:func:`short`)."""
    unit = f" in {key.units}" if key.units and key.units != "1" else ""
    rng = key.range_text()

    def bad(msg, where=path):
        problems.append(f"{where}: {msg}")
        return None

    def number(x, where=path):
        if isinstance(x, bool) or not isinstance(x, (int, float)):
            if isinstance(x, str):
                try:
                    float(x)
                    return bad(f"expected a number{unit}, got the string {short(x)}: write it "
                               "without quotes", where)
                except ValueError:
                    pass
                if _UNIT_STRING.match(x[:200]):
                    q = quantity(x, key.units)
                    if isinstance(q, str):
                        return bad(q, where)
                    where_, x = f"{where} = {short(x)}", q
                    if not key.allows(x):  # name what was typed, and its SI value
                        return bad(f"{x:.6g} {key.units} is outside the allowed range "
                                   f"{rng}{unit}", where_)
            if not isinstance(x, float):
                return bad(f"expected a number{unit}, got {type(x).__name__} {short(x)}",
                           where)
        try:
            x = float(x)
        except OverflowError:  # an integer beyond the double range
            return bad(f"{short(x)} is outside the allowed range {rng}{unit}", where)
        if not math.isfinite(x):
            return bad(f"{x!r} is not finite; allowed {rng}{unit}", where)
        if not key.allows(x):
            return bad(f"{x!r} is outside the allowed range {rng}{unit}", where)
        return x

    t = key.type
    if t == "number":
        return number(v)
    if t == "integer":
        if isinstance(v, bool) or not isinstance(v, int):
            return bad(f"expected an integer, got {type(v).__name__} {short(v)}")
        if not key.allows(v):
            return bad(f"{short(v)} is outside the allowed range {rng}")
        return int(v)
    if t == "boolean":
        if not isinstance(v, bool):
            return bad(f"expected true or false, got {short(v)}")
        return v
    if t in ("string", "path"):
        if not isinstance(v, str) or (t == "path" and not v.strip()):
            return bad(f"expected a {'file path' if t == 'path' else 'string'}, got {short(v)}")
        if key.choices and v not in key.choices:
            return bad(f"{short(v)} is not allowed; allowed values: {rng}")
        if t == "path" and ("\0" in v or len(v) > 4096):
            return bad(f"{short(v)} is not a usable file path")
        return v
    if t in ("numbers", "number_or_numbers"):
        if t == "number_or_numbers" and not isinstance(v, list):
            return number(v)
        if not isinstance(v, list) or not v:
            return bad(f"expected a non-empty list of numbers{unit}, got {short(v)}")
        if len(v) > MAX_LIST:
            return bad(f"a list of {len(v)} numbers; at most {MAX_LIST} are allowed")
        n0 = len(problems)
        out = []
        for i, x in enumerate(v):
            out.append(number(x, f"{path}[{i}]"))
            if len(problems) - n0 >= 3:  # a long list of bad entries: the first ones suffice
                more = len(v) - i - 1
                if more:
                    problems.append(f"{path}: {more} more entries not checked")
                break
        return None if len(problems) > n0 else out
    raise AssertionError(t)  # pragma: no cover


#: the longest list a scene value may be (a load path of this many steps)
MAX_LIST = 10000


def _check_section(name: str, spec: dict, got, problems: list) -> dict:
    if not isinstance(got, dict):
        problems.append(f"{name}: expected a table [{name}], got {short(got)}")
        return {}
    out = {}
    for key, val in got.items():
        if key not in spec:
            allowed = ", ".join(sorted(spec)) or "(no keys)"
            problems.append(f"{name}.{short_name(key)}: unknown key; allowed keys: {allowed}")
            continue
        out[key] = _check_value(f"{name}.{key}", spec[key], val, problems)
    for key, k in spec.items():
        if key not in got:
            if k.default is REQUIRED:
                problems.append(f"{name}.{key}: missing ({k.doc}{', ' + k.units if k.units else ''}"
                                f"; allowed {k.range_text() or 'a value'})")
            else:
                out[key] = k.default
    return out


def _check_kind_section(name: str, got, problems: list) -> dict:
    kinds = KINDS[name]
    if got is None:
        got = {"kind": KIND_DEFAULTS[name]}
    if not isinstance(got, dict):
        problems.append(f"{name}: expected a table [{name}], got {short(got)}")
        return {}
    kind = got.get("kind", KIND_DEFAULTS.get(name))
    if kind is None:
        problems.append(f"{name}.kind: missing; allowed: {', '.join(kinds)}")
        return {}
    if not isinstance(kind, str) or kind not in kinds:
        what = f"{short(kind)} is not a known {name} kind" if isinstance(kind, str) else (
            f"expected a string, got {type(kind).__name__} {short(kind)}")
        problems.append(f"{name}.kind: {what}; allowed: {', '.join(kinds)}")
        return {}
    rest = {k: v for k, v in got.items() if k != "kind"}
    out = _check_section(name, kinds[kind], rest, problems)
    out["kind"] = kind
    return out


def validate(raw: dict) -> tuple[dict, list]:
    """Check a parsed scene mapping; returns (normalised scene, list of problems).

    The normalised scene has every section present with defaults filled in.
    """
    problems: list[str] = []
    if not isinstance(raw, dict):
        return {}, [f"(top level): expected a table of sections, got {short(raw)}"]
    deep = []
    for s, sec in raw.items():
        if not too_deep(sec, MAX_DEPTH - 1):
            continue
        if not isinstance(sec, dict):
            deep.append(short_name(s))
            continue
        deep += [f"{short_name(s)}.{short_name(k)}" for k, v in sec.items()
                 if too_deep(v, MAX_DEPTH - 2)]
    if deep:  # checked first: the checks below (and copies of the scene) would recurse
        return {}, [f"{d}: nested too deeply; scene values are numbers, strings, booleans "
                    "or lists of numbers" for d in deep]
    known = set(SECTIONS) | set(KINDS)
    for sec in raw:
        if sec not in known:
            problems.append(f"{short_name(sec)}: unknown section; allowed: "
                            f"{', '.join(sorted(known))}")
    out = {"scene": _check_section("scene", SECTIONS["scene"], raw.get("scene", {}), problems)}
    if "sinusoid" in raw:
        mixed = [s for s in PHYSICAL if s in raw and s != "solver"]
        if mixed:
            problems.append(f"{', '.join(mixed)}: not allowed with [sinusoid] (the seed scene "
                            "is dimensionless and complete; [solver] is allowed)")
        if "solver" in raw:
            out["solver"] = _check_section("solver", SECTIONS["solver"], raw["solver"],
                                           problems)
        s = _check_section("sinusoid", SECTIONS["sinusoid"], raw["sinusoid"], problems)
        out["sinusoid"] = s
        if s and (s.get("p_tilde") is None) == (s.get("delta_tilde") is None):
            problems.append("sinusoid.p_tilde / sinusoid.delta_tilde: give exactly one "
                            "(load or displacement control)")
        _check_seed(out, problems)
        return out, problems
    for sec in ("grid", "surface", "material", "control"):
        if sec not in raw:
            problems.append(f"{sec}: missing section [{sec}] (or use a [sinusoid] seed scene)")
    for sec in ("surface", "material", "layer"):
        if sec in raw or sec in KIND_DEFAULTS:
            out[sec] = _check_kind_section(sec, raw.get(sec), problems)
    for sec in ("grid", "adhesion", "motion", "control", "solver", "output"):
        if sec in raw or sec not in ("grid", "control"):
            out[sec] = _check_section(sec, SECTIONS[sec], raw.get(sec, {}), problems)
    _check_physical(out, problems)
    return out, problems


def _check_seed(out, problems):
    s = out.get("sinusoid") or {}
    model = out["scene"].get("model", "auto")
    if model == "grid2d" or (model == "auto" and s.get("direction_deg", 0.0) != 0.0):
        n, a0 = s.get("cells_per_wavelength"), s.get("a0_tilde")
        if n and a0 is not None and (s.get("Gamma") or 0) > 0:
            hc = 2 * math.pi / n
            if a0 < hc * (1 - 1e-9):
                problems.append(f"sinusoid.a0_tilde: {shown(a0)} is smaller than one cell "
                                f"({hc:.4g}) of the grid model; allowed [{hc:.4g}, 1]")
            else:
                _check_front_tol(out, a0 / hc, problems)


def _check_front_tol(out, a0_cells: float, problems) -> None:
    """solver.front_tol within (0, max(0.5, a0/(2h))]: the edge within half the band
    (adhesive.solve_adhesive)."""
    ft = (out.get("solver") or {}).get("front_tol")
    top = front_tol_max(a0_cells)
    if ft is not None and ft > top:
        problems.append(f"solver.front_tol: {shown(ft)} cells is larger than half of a0 "
                        f"({a0_cells:.4g} cells); allowed (0, {top:.4g}]")


def _reported(problems: list, *paths: str) -> bool:
    """Whether a problem of one of the keys ``paths`` is already reported (the key is then
    None in the validated scene: the rules below must not call it missing)."""
    return any(p.startswith(k) and p[len(k):len(k) + 1] in (":", " ", "[")
               for p in problems for k in paths)


def _check_physical(out, problems):
    g, ctl = out.get("grid") or {}, out.get("control") or {}
    adh, mot = out.get("adhesion") or {}, out.get("motion") or {}
    for sec in ("surface", "material", "layer"):
        if out.get(sec):
            _check_kind(sec, out[sec], g, problems)
    if "control" in out and (ctl.get("mean_pressure") is None) == (
            ctl.get("penetration") is None) and not _reported(
            problems, "control.mean_pressure", "control.penetration"):
        problems.append("control.mean_pressure / control.penetration: give exactly one")
    if mot.get("velocity") is not None:
        if len(mot["velocity"]) != 2:
            problems.append(f"motion.velocity: {shown(mot['velocity'])} must have two entries "
                            "(vx, vy) in m/s")
        if mot.get("speed") is not None:
            problems.append("motion.velocity / motion.speed: give one of them, not both")
    dg = adh.get("dgamma") or 0.0
    adhesive = dg > 0 or adh.get("dgamma_map") is not None
    # a Δγ that failed its check: whether the scene is adhesive is unknown
    unknown = _reported(problems, "adhesion.dgamma", "adhesion.dgamma_map")
    if adhesive and adh.get("a0") is None and not _reported(problems, "adhesion.a0"):
        problems.append("adhesion.a0: missing (required when Δγ > 0): the advance width in m, "
                        "at least one cell")
    mp = ctl.get("mean_pressure")
    if not adhesive and not unknown and mp is not None:
        vals = mp if isinstance(mp, list) else [mp]
        if any(v is not None and v <= 0 for v in vals):
            problems.append(f"control.mean_pressure: {shown(mp)} Pa; without adhesion the mean "
                            "pressure must be > 0 (allowed (0, 1e12])")
    if (out.get("scene") or {}).get("model", "auto") == "grid2d":
        check_a0_on_grid(out, problems)  # 'auto': once the model is chosen (scenes)
    if g.get("Lx") and g.get("Nx") and g.get("Ly") and g.get("Ny"):
        fr = adh.get("flaw_radius")
        if adhesive and fr is not None and fr > 0.5 * max(g["Lx"], g["Ly"]):
            # a flaw wider than the cell would open the whole contact at once
            problems.append(f"adhesion.flaw_radius: {shown(fr)} m is larger than half the cell; "
                            f"allowed (0, {0.5 * max(g['Lx'], g['Ly']):.4g}] m")


def check_a0_on_grid(out: dict, problems: list) -> None:
    """adhesion.a0 of an adhesive physical scene solved on the grid: one cell to half the
    cell's side, and solver.front_tol within what it allows (a scene the 1D method solves
    has no cells: its a0 is not checked against the grid)."""
    g, adh = out.get("grid") or {}, out.get("adhesion") or {}
    adhesive = (adh.get("dgamma") or 0.0) > 0 or adh.get("dgamma_map") is not None
    a0 = adh.get("a0")
    if not (adhesive and a0 is not None and g.get("Lx") and g.get("Nx") and g.get("Ly")
            and g.get("Ny")):
        return
    hmin = min(g["Lx"] / g["Nx"], g["Ly"] / g["Ny"])
    if a0 < hmin * (1 - 1e-9):
        problems.append(f"adhesion.a0: {shown(a0)} m is smaller than one cell ({hmin:.4g} "
                        f"m) of the grid model; allowed [{hmin:.4g}, "
                        f"{0.5 * max(g['Lx'], g['Ly']):.4g}] m")
    elif a0 > 0.5 * max(g["Lx"], g["Ly"]):
        problems.append(f"adhesion.a0: {shown(a0)} m is larger than half the cell; allowed "
                        f"[{hmin:.4g}, {0.5 * max(g['Lx'], g['Ly']):.4g}] m")
    else:
        _check_front_tol(out, a0 / hmin, problems)


def section_keys(raw: dict, sec: str) -> dict:
    """The schema's keys of section ``sec`` of the scene mapping ``raw`` (a section with
    kinds: those of its kind)."""
    spec = SECTIONS.get(sec)
    if spec is None and sec in KINDS:
        kind = raw[sec].get("kind") if isinstance(raw.get(sec), dict) else None
        spec = KINDS[sec].get(kind, {})
    return spec or {}


def input_paths(spec: dict, base) -> dict:
    """``{"section.key": path}`` of every file the scene mapping ``spec`` reads (the keys of
    type path: a height map, a modulus table, a Δγ map), relative to ``base``."""
    out = {}
    for sec, body in spec.items():
        if not isinstance(body, dict):
            continue
        for key, k in section_keys(spec, sec).items():
            value = body.get(key)
            if k.type == "path" and isinstance(value, str):
                out[f"{sec}.{key}"] = Path(base) / value
    return out
