"""Plausibility of a physical scene, checked before its solve.

A scene can be valid (every key inside its range) and still be a mistake: a modulus written
in MPa as a number of pascals, a height map whose unit was forgotten, a modulus table that
does not reach the frequencies the sliding excites.  :func:`scene_warnings` lists what looks
implausible, each message naming the key, its value and the threshold; ``spectralbem run``
and ``sweep`` print them before the solve (``--strict`` turns them into errors), and
:func:`spectralbem.solve` issues them as :class:`PlausibilityWarning`.

The thresholds (module constants) mark where the model's own assumptions stop holding, not
where the solver fails: linear elasticity of a half-space (small strains: p̄/E* ≪ 1, slopes
≪ 1), a surface much lower than the cell is wide, a viscoelastic modulus known at every
excited frequency, an advance width a0 small against the smallest asperities
(docs/theory.md: a0 beyond a tenth of the patches moves the area by several per cent).
Before the solve the cut-off wavelength stands for the patches' size; after an adhesive 2D
solve :func:`state_warnings` checks a0 against the patches found (the dataset's
``small_patch_diameter``), and ``run`` prints those too.
"""

from __future__ import annotations

import warnings

import numpy as np

from .keys import DELAYED_DEFAULT

#: mean pressure over the relaxed contact modulus E0/(1 − ν²) above which a warning is given
PRESSURE_OVER_MODULUS = 0.1
#: rms slope of the surface above which a warning is given (small-slope theory)
RMS_SLOPE = 0.5
#: rms height over the cell's larger side above which a warning is given
HEIGHT_OVER_CELL = 0.1
#: a0 over the surface's short-wavelength cut-off above which a warning is given
A0_OVER_CUTOFF = 0.1
#: a0 over the small patches' diameter (dataset ``small_patch_diameter``) above which a
#: warning is given after the solve
A0_OVER_PATCH = 0.1
#: a0 in cells above which an elastic 2D adhesive scene is warned: a0 is numerical there, the
#: answer moves with it and the front may wander (docs/theory.md, known limits)
A0_CELLS_ELASTIC = 4.0

#: cells per relaxation length vτ below which a viscoelastic (SLS) 2D adhesive scene is
#: warned, per solver.delayed_kernel: the y-invariant sinusoid against the 1D method
#: (bench/relaxation_length.py, docs/performance.md) has its adhesive friction within 5 %
#: from 2.5 cells on with the sampled kernel (2 % from 4), and within 1 % from 2 cells on
#: with the delayed part averaged over the cells (where a0 spans 2 cells or more; −6.8 % at
#: one cell)
VTAU_CELLS = {"sampled": 2.5, "cell": 2.0}

__all__ = ["scene_warnings", "state_warnings", "PlausibilityWarning"]


class PlausibilityWarning(UserWarning):
    """A scene that is valid but implausible (see :func:`scene_warnings`)."""


def scene_warnings(scene) -> list[str]:
    """The plausibility warnings of a physical scene (none for the seed's dimensionless
    scenes, whose inputs are the paper's groups)."""
    if scene.kind != "physical":
        return []
    out = []
    mat, cell, h = scene.material, scene.cell, scene.heights
    estar = mat.E0 / (1.0 - mat.nu**2)
    name, values = scene.control
    if name == "mean_pressure":
        p = max(abs(float(v)) for v in values)
        if p > PRESSURE_OVER_MODULUS * estar:
            out.append(f"control.mean_pressure: {p:.4g} Pa is {p / estar:.3g} of the relaxed "
                       f"contact modulus E0/(1-ν²) = {estar:.4g} Pa (warned above "
                       f"{PRESSURE_OVER_MODULUS:g}: the linear theory assumes small strains; "
                       "a modulus meant in MPa but written in Pa?)")
    dx = cell.derivative(h, (1.0, 0.0))
    dy = cell.derivative(h, (0.0, 1.0))
    slope = float(np.sqrt(np.mean(dx**2 + dy**2)))
    if slope > RMS_SLOPE:
        out.append(f"surface: the rms slope is {slope:.3g} (warned above {RMS_SLOPE:g}: the "
                   "theory assumes small slopes; heights in µm read as metres?)")
    rms = float(np.std(h))
    side = max(cell.Lx, cell.Ly)
    if rms > HEIGHT_OVER_CELL * side:
        out.append(f"surface: the rms height {rms:.4g} m is {rms / side:.3g} of the cell's "
                   f"side {side:.4g} m (warned above {HEIGHT_OVER_CELL:g}: a forgotten "
                   "surface.scale?)")
    out += _table_coverage(scene)
    out += _a0_against_cutoff(scene)
    out += _a0_cells_elastic(scene)
    out += _relaxation_length(scene)
    return out


def _relaxation_length(scene) -> list[str]:
    """A sliding SLS 2D adhesive scene whose relaxation length vτ spans few cells (the
    creep time τ of Eq. (14); a Prony series or a table has no single τ and is not
    checked)."""
    tau = getattr(scene.material, "tau", None)
    speed = float(np.hypot(*scene.velocity))
    if not scene.adhesive or scene.model != "grid2d" or tau is None or speed == 0.0:
        return []
    cells = speed * tau / max(scene.cell.hx, scene.cell.hy)
    kind = scene.solver.get("delayed_kernel", DELAYED_DEFAULT)
    if cells >= VTAU_CELLS[kind]:
        return []
    if kind == "sampled":
        hint = ("the trailing edge's G2 and the adhesive friction μ_a are resolved within 5 % "
                "only from 2.5 cells per vτ on, 2 % from 4 with the sampled kernel, within 1 % "
                "from 2 cells with solver.delayed_kernel = \"cell\" (the sinusoid against "
                "the 1D method, docs/performance.md, \"Resolving the relaxation length\"); "
                "set it or refine the grid")
    else:
        hint = ("μ_a is within 1 % from 2 cells per vτ on with the delayed kernel averaged "
                "over the cells, 7 % off at one cell (docs/performance.md, \"Resolving the "
                "relaxation length\"); refine the grid")
    return [f"motion.speed: the relaxation length vτ = {speed * tau:.4g} m is {cells:.3g} "
            f"cells long (warned below {VTAU_CELLS[kind]:g}): {hint}"]


def _a0_cells_elastic(scene) -> list[str]:
    """An elastic 2D adhesive scene whose a0 spans many cells."""
    if not scene.adhesive or scene.viscoelastic or scene.model != "grid2d":
        return []
    cells = scene.a0 / min(scene.cell.hx, scene.cell.hy)
    if cells <= A0_CELLS_ELASTIC:
        return []
    moves = ("with the edge extrapolated to a0 → 0 (solver.extrapolate_a0, the default "
             "here) the rough case of docs/rough_convergence.md reads 0.7-2.3 % more area at 2-8 "
             "cells than at one" if scene.extrapolate_a0 else
             "the rough case of docs/rough_convergence.md reads 5 % less area at 4 cells than "
             "at one, 6 % at 8 cells (solver.extrapolate_a0 = true removes most of it)")
    return [f"adhesion.a0: {scene.a0:.4g} m spans {cells:.3g} cells in an elastic scene "
            f"(warned above {A0_CELLS_ELASTIC:g}): a0 is numerical here and the answer moves "
            f"with it ({moves}), and wide bands take many front iterations (89 at 8 cells "
            "on that case's 1024² loading state); one cell is the most accurate "
            "(docs/theory.md)"]


def _table_coverage(scene) -> list[str]:
    """A tabulated modulus that does not cover the frequencies q·v of the scene's grid
    (|q| from 2π/L to the Nyquist wavenumber): outside the table E is extrapolated."""
    omega = getattr(scene.material, "omega", None)
    speed = float(np.hypot(*scene.velocity))
    if omega is None or speed == 0.0:
        return []
    cell = scene.cell
    lo = speed * 2 * np.pi / max(cell.Lx, cell.Ly)
    hi = speed * np.pi * np.hypot(1.0 / cell.hx, 1.0 / cell.hy)
    if omega[0] <= lo and omega[-1] >= hi:
        return []
    return [f"material: the modulus table covers ω in [{omega[0]:.3g}, {omega[-1]:.3g}] "
            f"rad/s but the sliding excites q·v in [{lo:.3g}, {hi:.3g}] rad/s; outside the "
            "table E is extrapolated (storage constant, loss ∝ ω toward 0 and ∝ 1/ω above)"]


def _a0_against_cutoff(scene) -> list[str]:
    """a0 large against the smallest asperities (the self-affine cut-off wavelength)."""
    surf = scene.spec.get("surface", {}) if isinstance(scene.spec, dict) else {}
    cut = surf.get("cutoff_wavelength") if surf.get("kind") == "self_affine" else None
    adhesive = np.any(np.asarray(scene.dgamma) > 0)
    if not adhesive or not cut or scene.a0 <= A0_OVER_CUTOFF * cut:
        return []
    return [f"adhesion.a0: {scene.a0:.4g} m is {scene.a0 / cut:.3g} of the surface's cut-off "
            f"wavelength {cut:.4g} m (warned above {A0_OVER_CUTOFF:g}: contact patches of "
            f"that size are barely wider than the advance band; {_a0_advice(scene)}, "
            "docs/theory.md)"]


def _a0_advice(scene) -> str:
    """What to do about an a0 large against the contact's lengths: in an elastic scene (or a
    viscoelastic one at rest) a0 is numerical, in a viscoelastic one in motion physical."""
    if scene.viscoelastic:
        return ("a0 is a physical process-zone length in this sliding viscoelastic scene: "
                "the answer is the one of this a0, with the small patches' edges blunted by it")
    return "in an elastic scene a0 is numerical and one cell is the most accurate"


def state_warnings(scene, ds) -> list[str]:
    """After an adhesive 2D solve: a0 above ``A0_OVER_PATCH`` of the diameter below which a
    tenth of the resolved contact area lies (``small_patch_diameter``, per step)."""
    if "small_patch_diameter" not in ds or not scene.adhesive:
        return []
    d = np.atleast_1d(np.asarray(ds["small_patch_diameter"].values, float))
    bad = np.flatnonzero(np.isfinite(d) & (d > 0) & (scene.a0 > A0_OVER_PATCH * d))
    if bad.size == 0:
        return []
    k = int(bad[np.argmin(d[bad])])
    where = f" (step {k}; {bad.size} of {d.size} steps)" if d.size > 1 else ""
    return [f"adhesion.a0: {scene.a0:.4g} m is {scene.a0 / d[k]:.3g} of the small contact "
            f"patches' diameter {d[k]:.4g} m{where}: a tenth of the contact area lies in "
            f"patches that narrow (warned above {A0_OVER_PATCH:g}: their edges are not "
            f"sharp against the band; {_a0_advice(scene)}, docs/theory.md)"]


def warn(scene, ds=None) -> None:
    """Issue :func:`scene_warnings` (or, given the solve's dataset, :func:`state_warnings`)
    as :class:`PlausibilityWarning`."""
    for msg in (scene_warnings(scene) if ds is None else state_warnings(scene, ds)):
        warnings.warn(msg, PlausibilityWarning, stacklevel=3)
