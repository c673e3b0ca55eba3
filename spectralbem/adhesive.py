"""Adhesive contact on the periodic grid (JKR limit, seed Eq. 3 generalised to 2D).

The mask A is the state.  Inside A any stress is allowed (tensile too); the mask moves by the
front-layer energy balance of :mod:`spectralbem.criterion`, evaluated at fixed Δ:

1. solve on A at the current Δ (load control: Δ is fixed exactly by the mean pressure, since
   on a fixed mask p = p_w + Δ p_1 is linear in Δ);
2. nucleation: cells outside A where the surfaces interpenetrate (g < 0) join A (jump-in);
3. closing and opening band tests of width a0 give the balanced sub-cell edge of every front
   cell (in an elastic scene the sharp-crack edge G = Δγ); the mask follows it to the
   nearest cell centre, with no dead band;
4. repeat until every resolved front cell is balanced within ``front_tol`` cells and, under
   load control, the sub-cell front carries the load (docs/theory.md).  Hysteresis is
   physical: the mask is carried from one call to the next (``mask0``), there is no global
   minimisation.

Leaving full contact (nucleation rule): a full contact opens only through a flaw.  When the
mask covers the cell, a flaw — the disc of radius ``flaw_radius`` (default a0; that is the
radius of its balanced edge, so in an elastic scene its mask is a0/2 wider) at the peak
tension of the full-contact solution — is opened once and the criterion decides: if it closes
again the state is ``full_contact``, if it grows the contact becomes partial.
"""

from __future__ import annotations

import numpy as np

from . import coarse
from .conventions import control, shown
from .criterion import SMOOTHING_PER_RADIUS
from .fft import with_fft_threads_only
from .friction import sliding_direction
from .front_iteration import FrontIteration
from .keys import (
    BAND_TOL_MAX,
    EXTRAPOLATE_MIN_CELLS,
    FRONT_TOL,
    extrapolable,
    front_tol_max,
)
from .spectral import SpectralOperator
from .state import AdhesiveState
from .surfaces import check_heights

__all__ = ["solve_adhesive"]


def _check_extrapolation(op, a0) -> None:
    """``extrapolate_a0`` is for elastic scenes (a0 numerical) with a0 of two cells or more
    (the a0/2 bands hold at least one cell)."""
    if op.viscoelastic:
        raise ValueError("extrapolate_a0 = True needs an elastic scene: in a viscoelastic one "
                         "a0 is a physical length (docs/theory.md)")
    cells = a0 / min(op.cell.hx, op.cell.hy)
    if not extrapolable(cells):
        raise ValueError(f"extrapolate_a0 = True needs a0 of at least "
                         f"{EXTRAPOLATE_MIN_CELLS:g} cells (a0/2 at least one); a0 = "
                         f"{cells:g} cells")


def _check_inputs(cell, penetration, mean_pressure, dgamma, a0, criterion, front_tol):
    control(mean_pressure, penetration)
    dg = np.asarray(dgamma, dtype=float)
    if dg.ndim and dg.shape != cell.shape:
        raise ValueError(f"dgamma map has shape {dg.shape}, the grid is {cell.shape}")
    if not np.all(np.isfinite(dg)) or np.any(dg < 0) or not np.any(dg > 0):
        raise ValueError(f"dgamma (work of adhesion, J/m²) must be finite, >= 0 and somewhere "
                         f"> 0; got min {shown(dg.min())}, max {shown(dg.max())}")
    hmin = min(cell.hx, cell.hy)
    a0_max = 0.5 * max(cell.Lx, cell.Ly)
    if not (hmin * (1 - 1e-9) <= a0 <= a0_max):
        raise ValueError(f"a0 = {shown(a0)} m is outside the allowed range [{shown(hmin)}, "
                         f"{shown(a0_max)}] m (one cell to half the cell)")
    if criterion not in ("exact", "hybrid", "predictor"):
        raise ValueError(f"criterion = {criterion!r}; allowed: 'exact', 'hybrid', 'predictor'")
    top = front_tol_max(a0 / hmin)
    if not (0.0 < front_tol <= top):
        raise ValueError(f"front_tol = {shown(front_tol)} cells is outside the allowed range "
                         f"(0, {top:g}] (0.5 cells or half of a0 = {a0 / hmin:g} cells)")
    return dg


@with_fft_threads_only
def solve_adhesive(op: SpectralOperator, heights: np.ndarray, dgamma, a0: float, *,
                   penetration: float | None = None, mean_pressure: float | None = None,
                   mask0: np.ndarray | None = None, max_outer: int = 500,
                   front_smoothing: float | None = None,
                   smoothing_per_radius: float = SMOOTHING_PER_RADIUS,
                   rtol: float = 1e-10, observables: dict | None = None,
                   criterion: str = "exact", front_tol: float = FRONT_TOL,
                   flaw_radius: float | None = None, progress=None,
                   coarse_start: bool = False, extrapolate_a0: bool = False,
                   band_tol: float | None = None) -> AdhesiveState:
    """Adhesive equilibrium under penetration or mean-pressure control.

    ``dgamma``: work of adhesion Δγ (J/m², scalar or per-cell map); ``a0``: advance width (m),
    at least one cell, used exactly (criterion.band_weights; a0 wide at every orientation of
    the front in a viscoelastic scene and from two cells on, criterion.exact_width).  In an
    elastic scene the
    reported edge is the sharp-crack edge G = Δγ of a stress-intensity factor linear over
    the two bands (front.sharp_crack_offset); in a viscoelastic scene a0 is physical and
    the edge is the seed's l* (docs/theory.md).

    ``criterion``: 'exact' (every iteration tests the front layers with masked solves),
    'hybrid' (the zero-solve predictor moves the front until it stops, then the exact tests
    finish) or 'predictor' (the predictor alone; the exact tests are evaluated once on the
    final mask, for the outputs — cheaper, less accurate: docs/performance.md).
    ``front_smoothing``: σ of the average along the front in units of a0
    (along_front.smooth_along_front; None: 1.5 in a viscoelastic scene, 0.5 in an elastic
    one, criterion.default_smoothing), raised to ``smoothing_per_radius`` times the front
    radius 2A/P of large patches (along_front.patch_sigmas; 0 keeps σ fixed).

    ``flaw_radius``: radius (m) of the flaw through which a full contact may open (default
    a0; module docstring).  In an elastic scene it decides by Griffith's condition whether
    the full contact opens, so it is a physical input there, unlike a0.

    ``coarse_start``: start from the same scene's balanced front on the grid of half the
    cells per side, solved first the same way (recursively; :mod:`spectralbem.coarse`):
    fewer outer iterations on fine grids; ignored where the grid does not halve into one
    of at least ``coarse.COARSE_MIN`` cells per side no wider than a0.

    ``progress``: None or a callable ``progress(iteration, text)`` called at the start of
    every outer iteration and once more, with the same iteration, for the final state (the
    command line's progress bar).

    ``front_tol``: tolerance of the balance in position, cells beyond the half cell the mask
    edge stands for (at most max(0.5, a0/(2h))).

    ``band_tol``: the relative tolerance of the band tests' masked solves while the front
    moves (None: criterion.loose_band_rtol, 1e3 ``rtol`` and at most 1e-6; at most
    keys.BAND_TOL_MAX); a state that balances is tested again with the band solves at
    ``rtol`` before it is accepted, so the tolerance decides the path, not the check
    (docs/performance.md).

    ``extrapolate_a0`` (elastic scenes, a0 of two cells or more): the sharp-crack edge from
    the tests at a0 and at a0/2, extrapolated to a0 → 0 by Richardson's rule, which removes
    the O(a0²) error of a stress-intensity factor taken as linear over the bands (rough
    elastic case at 256²: halving a0 from 2 cells to one moves the area by −0.9 %, +5.1 %
    without); twice the band solves per test (docs/theory.md).  Off here unless asked for; a
    scene turns it on by default where it applies (``Scene.extrapolate_a0``).

    Status: ``partial`` only when every resolved front cell is balanced within ``front_tol``
    cells (front.balance_residual) and no pin holds a crack tip beyond the glassy bound
    (moves.overloaded_pins); ``not_converged`` otherwise (a cycle, an oscillation, the
    iteration limit or such pins), with the balanced fraction of the front in the result.
    """
    cell = op.cell
    h = check_heights(heights, cell)
    _check_inputs(cell, penetration, mean_pressure, dgamma, a0, criterion, front_tol)
    if band_tol is not None and not (0.0 < band_tol <= BAND_TOL_MAX):
        raise ValueError(f"band_tol = {shown(band_tol)} is outside the allowed range "
                         f"(0, {BAND_TOL_MAX:g}]")
    if extrapolate_a0:
        _check_extrapolation(op, a0)
    if coarse_start and coarse.eligible(cell, a0):
        mask0 = _coarse_start(op, h, dgamma, a0, penetration, mean_pressure, mask0, dict(
            max_outer=max_outer, front_smoothing=front_smoothing,
            smoothing_per_radius=smoothing_per_radius, rtol=rtol, criterion=criterion,
            front_tol=front_tol, flaw_radius=flaw_radius,
            extrapolate_a0=extrapolate_a0, band_tol=band_tol), progress)
    test_kw = dict(rtol=rtol, vhat=sliding_direction(op), front_smoothing=front_smoothing,
                   smoothing_per_radius=smoothing_per_radius, observables=observables)
    run = FrontIteration(op, h, dgamma, a0, penetration, mean_pressure, mask0, test_kw,
                         criterion, front_tol, flaw_radius, extrapolate_a0, band_tol)
    state = run.solve(max_outer, progress)
    if coarse_start and not coarse.eligible(cell, a0):  # asked for, and not possible here
        state.message += (f"; solver.coarse_start not used: the grid does not halve into "
                          f"{coarse.COARSE_MIN} cells per side or more whose cells a0 spans")
    return state


def _coarse_start(op, h, dgamma, a0, penetration, mean_pressure, mask0, kw, progress):
    """The fine start of :func:`solve_adhesive`: the balanced front of the same scene on
    the grid of half the cells per side (solved from the restricted ``mask0``, itself with a
    coarse start), sampled at the fine centres; ``mask0`` itself when that solve does not
    end on a verified partial contact or its front holds no fine cell centre (an empty
    start would read as detached)."""
    cop = coarse.coarse_operator(op)
    hc = coarse.restrict(h)
    if penetration is not None:  # the same rigid-body position: Δ is measured from max h
        penetration = penetration - (float(h.max()) - float(hc.max()))
    if progress is not None:
        progress(0, f"coarse start on {cop.cell.Nx}×{cop.cell.Ny}")
    # the tolerance in cells, within what the coarse band allows (a0 spans half the cells),
    # and the extrapolation in a0 where a0 still spans two coarse cells
    a0_cells = a0 / min(cop.cell.hx, cop.cell.hy)
    kw = dict(kw, front_tol=min(kw["front_tol"], front_tol_max(a0_cells)),
              extrapolate_a0=kw["extrapolate_a0"] and extrapolable(a0_cells))
    state = solve_adhesive(cop, hc, coarse.restrict(dgamma), a0, penetration=penetration,
                           mean_pressure=mean_pressure,
                           mask0=None if mask0 is None else coarse.restrict(mask0),
                           coarse_start=True, **kw)
    if state.status != "partial":
        return mask0
    fine = coarse.prolong(state, op.cell)
    return fine if fine.any() else mask0

