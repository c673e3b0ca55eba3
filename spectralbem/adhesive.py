"""Adhesive contact on the periodic grid (JKR limit, seed Eq. 3 generalised to 2D).

The mask A is the state.  Inside A any stress is allowed (tensile too); the mask moves by the
front-layer energy balance of :mod:`spectralbem.criterion`, evaluated at fixed Δ:

1. solve on A at the current Δ (load control: Δ is fixed exactly by the mean pressure, since
   on a fixed mask p = p_w + Δ p_1 is linear in Δ);
2. nucleation: cells outside A where the surfaces interpenetrate (g < 0) join A (jump-in);
3. closing and opening layer tests; a front cell moves (one layer per iteration) when the
   interpolated balanced edge lies beyond half a cell;
4. repeat until no cell moves.  Hysteresis is physical: the mask is carried from one call to
   the next (``mask0``), there is no global minimisation.

Leaving full contact (nucleation rule): a full contact opens only through a flaw.  When the
mask covers the cell, a flaw — the disc of radius a0 at the peak tension of the full-contact
solution — is opened once and the criterion decides: if it closes again the state is
``full_contact``, if it grows the contact becomes partial.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .contact import sliding_direction
from .criterion import (
    FRONT_SMOOTHING,
    SMOOTHING_PER_RADIUS,
    front_cells,
    front_tests,
    layers,
    predictor_tests,
    sub_cell_offset,
)
from .masked import solve_masked
from .spectral import SpectralOperator
from .surfaces import check_heights

#: a front cell moves when the balanced edge l* lies more than this many cells beyond it
DEAD_BAND = 0.6
#: a mask cycle is accepted as equilibrium when this fraction of front cells is balanced
#: within one cell
CYCLE_ACCEPT = 0.95


@dataclass
class AdhesiveResult:
    pressure: np.ndarray
    mask: np.ndarray
    penetration: float
    mean_pressure: float
    tests: object  # the FrontTest of the final state
    offset_out: np.ndarray  # sub-cell offset l* - x_b on outer front cells (m)
    outer_iterations: int
    solves: int
    converged: bool
    status: str
    message: str
    history: list = field(default_factory=list)
    a0_effective: float = 0.0  # m h, the band width used
    unresolved_patches: int = 0  # contact patches smaller than a disc of radius a0


def unresolved_patches(mask: np.ndarray, a0_cells: float) -> int:
    """Number of contact patches (4-connected, periodic images not merged) with fewer cells
    than a disc of radius a0: their fronts are closer than a0 to each other, so the band
    tests cannot resolve them (reported, not hidden)."""
    from scipy import ndimage

    lab, n = ndimage.label(mask)
    if n == 0:
        return 0
    sizes = np.bincount(lab.ravel())[1:]
    return int(np.sum(sizes < np.pi * a0_cells**2))


def _neighbour_mean(field_: np.ndarray, where: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Mean of ``field_`` over the 4-neighbours (periodic) where ``where`` holds and the
    field is finite, at the flat indices ``at`` (nan where there is none)."""
    nx, ny = field_.shape
    i, j = np.divmod(at, ny)
    f, wh = field_.ravel(), where.ravel()
    s = np.zeros(at.size)
    c = np.zeros(at.size)
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        k = ((i + di) % nx) * ny + (j + dj) % ny
        v = f[k]
        ok = wh[k] & np.isfinite(v)
        s += np.where(ok, v, 0.0)
        c += ok
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(c > 0, s / c, np.nan)


def _offsets(F_close, F_open, outer, inner, a0):
    """Sub-cell offsets of the balanced edge (criterion.sub_cell_offset) on the outer front
    cells (closing test there, opening tests of the neighbouring inner cells) and on the
    inner front cells (the other way round); nan elsewhere."""
    s_out = np.full(F_close.shape, np.nan)
    s_in = np.full(F_close.shape, np.nan)
    io, ii = np.flatnonzero(outer), np.flatnonzero(inner)
    s_out.ravel()[io] = sub_cell_offset(F_close.ravel()[io],
                                        _neighbour_mean(F_open, inner, io), a0)
    s_in.ravel()[ii] = sub_cell_offset(_neighbour_mean(F_close, outer, ii),
                                       F_open.ravel()[ii], a0)
    return s_out, s_in


def _moves(tests, mask, outer, inner, a0, hmin, w, pinned, sign_rule=False):
    """The sub-cell offsets and the cells that join (add) and leave (remove) the mask.

    Dead band of ±0.6 h: the outputs use the sub-cell front l*, so the cell boundary only has
    to lie near it; a band wider than ½ h stops two-state lattice cycles (under load control
    the Δ update couples the edges).  A band cell at distance d from the front joins (leaves)
    when its front cell's balanced edge lies beyond d − (1 − DEAD_BAND) h: up to m layers per
    iteration.  A cell opens only where its opening leaves a gap (no interpenetration):
    otherwise the nucleation step would close it again at once (an open/close cycle).

    ``sign_rule`` (the predictor): its closing and opening estimates are the same product at
    a front (½ t_i g_j a), so there is no slope to interpolate a sub-cell edge from; the band
    joins where F_close < −ε (closing costs less elastic work than the adhesion it gains: the
    balanced edge lies ahead, as in :func:`criterion.sub_cell_offset`) and leaves where
    F_open > ε, one band per iteration.  ε = 4.7 h/r, the predictor's own error
    (criterion.md §4.3) at the mean front radius r = 2A/P of the mask: inside it only the
    exact tests can tell."""
    if sign_rule:
        n_front = max(1, int(outer.sum()))
        eps = min(0.5, 4.7 * n_front / (2.0 * mask.sum())) if mask.any() else 0.5
        s_out = np.where(tests.F_close < -eps, np.inf, -np.inf)
        s_in = np.where(tests.F_open > eps, -np.inf, np.inf)
    else:
        s_out, s_in = _offsets(tests.F_close, tests.F_open, outer, inner, a0)
    b = tests.bands
    slack = (1.0 - DEAD_BAND) * hmin
    ob = np.flatnonzero(b.outer_band)  # band cells, each with its owning front cell
    add = np.zeros(mask.shape, bool)
    add.ravel()[ob] = (s_out.ravel()[b.outer_owner.ravel()[ob]]
                       > b.outer_dist.ravel()[ob] - slack)
    gtol = 1e-12 * max(1.0, float(np.abs(w).max()))
    ib = np.flatnonzero(b.inner_band & ~pinned & ~(tests.g_open < -gtol))
    remove = np.zeros(mask.shape, bool)
    remove.ravel()[ib] = (s_in.ravel()[b.inner_owner.ravel()[ib]]
                          < -(b.inner_dist.ravel()[ib] - slack))
    return s_out, s_in, add, remove


def _nucleation_flaw(op, h, mean_pressure, penetration, a0):
    """The documented rule for leaving full contact: a flaw, the disc of radius a0 centred on
    the cell of largest tension of the full-contact solution (at the prescribed load; under
    penetration control of a half-space no full-contact solution exists at an arbitrary Δ).
    None when the full contact is nowhere tensile (it cannot open) or undefined."""
    from .contact import _full_contact

    full = _full_contact(op, h, mean_pressure, penetration)
    if full is None:
        return None
    p = full[0]
    if p.min() >= 0:
        return None
    cell = op.cell
    i, j = np.unravel_index(int(np.argmin(p)), p.shape)
    X, Y = cell.coordinates()
    dx = (X - X[i, j] + cell.Lx / 2) % cell.Lx - cell.Lx / 2
    dy = (Y - Y[i, j] + cell.Ly / 2) % cell.Ly - cell.Ly / 2
    return np.hypot(dx, dy) <= a0 * (1 + 1e-9)


def solve_adhesive(op: SpectralOperator, heights: np.ndarray, dgamma, a0: float, *,
                   penetration: float | None = None, mean_pressure: float | None = None,
                   mask0: np.ndarray | None = None, max_outer: int = 500,
                   front_smoothing: float = FRONT_SMOOTHING,
                   smoothing_per_radius: float = SMOOTHING_PER_RADIUS,
                   rtol: float = 1e-10, observables: dict | None = None,
                   criterion: str = "exact") -> AdhesiveResult:
    """Adhesive equilibrium under penetration or mean-pressure control.

    ``criterion``: 'exact' (every iteration tests the front layers with masked solves),
    'hybrid' (the zero-solve predictor of criterion.md §4.3 moves the front until it stops,
    then the exact tests finish) or 'predictor' (the predictor alone; the exact tests are
    evaluated once on the final mask, for the outputs — cheaper, less accurate: see the
    accuracy-cost map in docs/performance.md).

    ``dgamma``: work of adhesion Δγ (J/m², scalar or per-cell map); ``a0``: advance width (m),
    at least one cell.  ``front_smoothing``: σ (cells) of the average along the front
    (criterion.smooth_along_front, default :data:`criterion.FRONT_SMOOTHING`), raised to
    ``smoothing_per_radius`` times the front radius 2A/P of large contact patches
    (criterion.patch_sigmas; 0 keeps σ fixed).
    """
    cell = op.cell
    h = check_heights(heights, cell)
    if (penetration is None) == (mean_pressure is None):
        raise ValueError("give exactly one of penetration and mean_pressure")
    for name, v in (("penetration", penetration), ("mean_pressure", mean_pressure)):
        if v is not None and not np.isfinite(v):
            raise ValueError(f"{name} = {v!r} must be a finite number")
    dg = np.asarray(dgamma, dtype=float)
    if dg.ndim and dg.shape != cell.shape:
        raise ValueError(f"dgamma map has shape {dg.shape}, the grid is {cell.shape}")
    if not np.all(np.isfinite(dg)) or np.any(dg < 0) or not np.any(dg > 0):
        raise ValueError(f"dgamma (work of adhesion, J/m²) must be finite, >= 0 and somewhere "
                         f"> 0; got min {dg.min()!r}, max {dg.max()!r}")
    hmin = min(cell.hx, cell.hy)
    a0_max = 0.5 * max(cell.Lx, cell.Ly)
    if not (hmin * (1 - 1e-9) <= a0 <= a0_max):
        raise ValueError(f"a0 = {a0!r} m is outside the allowed range [{hmin!r}, {a0_max!r}] "
                         "m (one cell to half the cell)")
    if criterion not in ("exact", "hybrid", "predictor"):
        raise ValueError(f"criterion = {criterion!r}; allowed: 'exact', 'hybrid', 'predictor'")
    phase = "exact" if criterion == "exact" else "predictor"
    test_kw = dict(rtol=rtol, vhat=sliding_direction(op), front_smoothing=front_smoothing,
                   smoothing_per_radius=smoothing_per_radius, observables=observables)
    a0 = layers(a0, cell.hx, cell.hy) * hmin  # the band width actually used (m layers)
    hmax = float(h.max())
    mask = (h >= hmax - 1e-12 * max(1.0, abs(hmax))) if mask0 is None else mask0.copy()
    delta = penetration
    p = np.zeros(cell.shape)
    p1 = None
    seen = {}
    states = {}
    last_removed = np.zeros(cell.shape, bool)
    flaw_tried = False
    pinned = np.zeros(cell.shape, bool)  # opened, then closed at once by non-penetration
    solves = 0
    history = []
    status, message, converged = "not_converged", "", False
    tests = None
    s_out = np.full(cell.shape, np.nan)
    it = 0
    for it in range(1, max_outer + 1):
        if not mask.any():
            status, message = "detached", "the contact vanished"
            break
        if mask.all():
            flaw = None if flaw_tried else _nucleation_flaw(op, h, mean_pressure, penetration,
                                                            a0)
            if flaw is None:
                from .contact import _full_contact

                full = _full_contact(op, h, mean_pressure, penetration)
                if full is not None:  # report the full-contact state itself
                    p, delta = full
                status, message = "full_contact", "the contact covers the cell"
                if flaw_tried:
                    message += " (a flaw of radius a0 nucleated at the peak tension closed)"
                break
            flaw_tried = True  # nucleation rule: open it once, let the criterion decide
            mask = ~flaw
            continue
        if mean_pressure is not None:
            rw = solve_masked(op, mask, h - hmax, x0=p, rtol=rtol)
            r1 = solve_masked(op, mask, np.ones(cell.shape), x0=p1, rtol=rtol)
            solves += 2
            if not (rw.converged and r1.converged):
                message = "masked solve: " + (rw.message if not rw.converged else r1.message)
                break
            p1 = r1.field
            delta = (mean_pressure * mask.size - rw.field.sum()) / p1.sum()
            p = rw.field
            p += delta * p1  # in place: rw's field becomes p
            rw = r1 = None
        else:
            res = solve_masked(op, mask, h - hmax + delta, x0=p, rtol=rtol)
            solves += 1
            if not res.converged:
                message = "masked solve: " + res.message
                break
            p = res.field
        w = h - hmax + delta
        u = op.apply(p)
        pen = ~mask & (u - w < -1e-12 * max(1.0, float(np.abs(w).max())))
        if pen.any():  # contact nucleation (JKR jump-in)
            # a cell the criterion just opened that interpenetrates at the new Δ (load
            # control) cannot open: it stays closed (pinned) for the rest of this solve
            pinned |= pen & last_removed
            mask |= pen
            continue
        if phase == "predictor":
            tests = predictor_tests(op, w, mask, p, dgamma, a0, u=u,
                                    front_smoothing=front_smoothing,
                                    smoothing_per_radius=smoothing_per_radius)
        else:
            tests = front_tests(op, w, mask, p, dgamma, a0, u=u, **test_kw)
        solves += tests.solves
        if not tests.converged:
            message = "layer test: " + tests.message
            break
        outer, inner = front_cells(mask)
        s_out, s_in, add, remove = _moves(tests, mask, outer, inner, a0, hmin, w, pinned,
                                          sign_rule=phase == "predictor")
        key = hash(mask.tobytes())
        if phase == "predictor" and ((not add.any() and not remove.any()) or key in seen):
            # the predictor has brought the front to (or cycling around) its balance: the
            # exact tests take over ("hybrid"), or only evaluate the outputs ("predictor")
            tests = front_tests(op, w, mask, p, dgamma, a0, u=u, **test_kw)
            solves += tests.solves
            if not tests.converged:
                message = "layer test: " + tests.message
                break
            if criterion == "predictor":
                s_out, _ = _offsets(tests.F_close, tests.F_open, outer, inner, a0)
                history.append((it, int(mask.sum()), 0, 0, float(delta)))
                converged, status = True, "partial"
                message = "converged (predictor criterion; exact tests of the final mask)"
                break
            phase = "exact"
            seen.clear()
            states.clear()
            s_out, s_in, add, remove = _moves(tests, mask, outer, inner, a0, hmin, w, pinned)
        history.append((it, int(mask.sum()), int(add.sum()), int(remove.sum()), float(delta)))
        if not add.any() and not remove.any():
            converged, status, message = True, "partial", "converged"
            break
        if key in seen:
            # a lattice cycle: accept when the balanced front lies within one cell of the
            # mask boundary at (nearly) every front cell — the outputs use the sub-cell front
            # — or when the cells that flip along the cycle are a small part of the front
            fronts = np.concatenate([s_out[outer], s_in[inner]])
            within = float(np.mean(np.abs(fronts) <= hmin))
            flips = np.zeros(cell.shape, bool)
            for k in range(seen[key], it):
                if k in states:
                    flips |= np.unpackbits(states[k], count=mask.size).reshape(
                        mask.shape).astype(bool) ^ mask
            flip_frac = flips.sum() / max(1, int(outer.sum() + inner.sum()))
            period = it - seen[key]
            if within >= CYCLE_ACCEPT or flip_frac <= 1.0 - CYCLE_ACCEPT:
                converged, status = True, "partial"
                message = (f"lattice cycle of period {period} accepted: {100 * within:.1f} % "
                           f"of front cells within one cell of balance, {int(flips.sum())} "
                           f"cells ({100 * flip_frac:.1f} % of the front) flip")
            else:
                status = "not_converged"
                message = (f"the mask cycles between states (period {period}; "
                           f"{100 * within:.1f} % of front cells within one cell of balance, "
                           f"{100 * flip_frac:.1f} % of the front flips)")
            break
        seen[key] = it
        states[it] = np.packbits(mask)  # 1 bit per cell
        states.pop(it - 12, None)  # cycles longer than a dozen states are not accepted
        seen = {k_: v for k_, v in seen.items() if v > it - 12}
        if it == max_outer:  # keep the state (mask, p, tests) consistent: no last move
            message = f"not converged in {max_outer} outer iterations"
            break
        mask = (mask | add) & ~remove
        # the tests and bands of the old mask: freed before the next state's solves
        tests = s_in = add = None
        last_removed = remove
    else:  # the guard ran out on a nucleation step
        message = f"not converged in {max_outer} outer iterations"
    nun = unresolved_patches(mask, a0 / hmin)
    if nun:
        message += f"; {nun} contact patches smaller than a disc of radius a0 (unresolved)"
    return AdhesiveResult(p, mask, float(delta), float(p.mean()), tests, s_out, it, solves,
                          converged, status, message, history, a0, nun)
