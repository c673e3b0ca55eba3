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

from .contact import friction, sliding_direction
from .conventions import control
from .criterion import (
    FRONT_SMOOTHING,
    SMOOTHING_PER_RADIUS,
    front_cells,
    front_tests,
    predictor_tests,
)
from .front import (
    at_front,
    balance_residual,
    bracketed,
    resolved_front,
    sharp_crack_offset,
    sub_cell_offset,
    touching,
    unresolved_patches,
)
from .masked import TRUE_RESIDUAL_MARGIN, solve_masked, solve_packed
from .spectral import SpectralOperator
from .state import AdhesiveState
from .surfaces import check_heights

#: default tolerance of the balance in position (cells): a resolved front point is balanced
#: when its balanced edge lies within ½ h + FRONT_TOL·h of the mask edge, one cell by default
#: (the resolution of the mask; docs/theory.md, the 2D criterion and the sub-cell front)
FRONT_TOL = 0.5
#: load control: the sub-cell front carries the prescribed mean pressure within this
#: fraction of the mean |p| (the mask state carries it minus the front's correction)
LOAD_TOL = 1e-6
#: a cell that has changed state this many times in one solve counts as oscillating
OSCILLATION_FLIPS = 3
#: this many consecutive iterations that move only oscillating cells end the solve
OSCILLATION_RUN = 6

__all__ = ["solve_adhesive"]


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


def _offsets(F_close, F_open, outer, inner, a0, sharp=False):
    """Sub-cell offsets of the balanced edge on the outer front cells (closing test there,
    opening tests of the neighbouring inner cells) and on the inner front cells (the other
    way round); nan elsewhere.  ``sharp``: the sharp-crack edge of an elastic scene
    (front.sharp_crack_offset), else the seed's edge (front.sub_cell_offset)."""
    offset = sharp_crack_offset if sharp else sub_cell_offset
    s_out = np.full(F_close.shape, np.nan)
    s_in = np.full(F_close.shape, np.nan)
    io, ii = np.flatnonzero(outer), np.flatnonzero(inner)
    s_out.ravel()[io] = offset(F_close.ravel()[io], _neighbour_mean(F_open, inner, io), a0)
    s_in.ravel()[ii] = offset(_neighbour_mean(F_close, outer, ii), F_open.ravel()[ii], a0)
    return s_out, s_in


def _moves(tests, mask, s_out, s_in, w, pinned, hmin, wide=None, tol=0.0):
    """The cells that join (add) and leave (remove) the mask: the mask follows the balanced
    front to the nearest cell centre, with no dead band.  A band cell at distance d from the
    front (d = h for the first layer) joins when its front cell's balanced edge lies beyond
    its centre, s > d − h/2; a cell of the inner band leaves when s < −(d − h/2).  A cell
    opens only where its opening leaves a gap (no interpenetration): otherwise the
    nucleation step would close it again at once (an open/close cycle).  ``wide``: cells
    that move only when their front cell is unbalanced (beyond the acceptance band, ``tol``
    cells more: the rescue of an oscillating front, :func:`solve_adhesive`)."""
    b = tests.bands
    half = 0.5 * hmin
    extra = None if wide is None else np.where(wide.ravel(), tol * hmin, 0.0)
    ob = np.flatnonzero(b.outer_band)  # band cells, each with its owning front cell
    ib = np.flatnonzero(b.inner_band & ~pinned & ~_blocked(tests, w))
    reach_out = b.outer_dist.ravel()[ob] - half  # the nearest-centre rule
    reach_in = b.inner_dist.ravel()[ib] - half
    if extra is not None:
        reach_out, reach_in = reach_out + extra[ob], reach_in + extra[ib]
    add = np.zeros(mask.shape, bool)
    add.ravel()[ob] = s_out.ravel()[b.outer_owner.ravel()[ob]] > reach_out
    remove = np.zeros(mask.shape, bool)
    remove.ravel()[ib] = s_in.ravel()[b.inner_owner.ravel()[ib]] < -reach_in
    return add, remove


#: times a cell's stale pin may be released (:func:`_stale_pins`)
PIN_RELEASES = 1


def _stale_pins(tests, mask, s_out, s_in, w, pinned, hmin):
    """Pinned cells whose pin is stale: their opening now leaves a gap (not blocked) and the
    balance, not held by the pin, opens them.  A pin is set when a cell the criterion opened
    interpenetrates at a later Δ; on unloading the front passes through such states, and
    without a release the pins stay closed as slivers under tension (the rough 256²
    viscoelastic case: 175 pinned cells in 76 patches carried 40 % of the friction force).
    The solver releases each cell's stale pin once (``PIN_RELEASES``; a cell pinned again
    is a lattice bind and stays), at the iteration it turns stale, under a compressive
    mean pressure only: under a tensile one, pins of patches without a free edge make the
    state unverified (:func:`_unverified_pins`), and beyond the pull-off releasing them
    only delays that."""
    if not pinned.any():
        return pinned
    _, remove = _moves(tests, mask, s_out, s_in, w, np.zeros_like(pinned), hmin)
    return remove & pinned


def _held_offsets(s_out, s_in, outer, held_in):
    """Offsets where non-penetration holds the edge: a front cell that cannot open (its
    opening leaves the surfaces interpenetrating, or load control closed it again) is a
    compressive edge, not a crack tip; the energy balance's inward offset there is an
    extrapolation of meaningless works (negative gap times compressive pressure), so the
    edge stays at the mask edge, as in an adhesiveless contact: s ≥ 0 on those inner cells
    and on the outer cells next to them (an outward balance still counts)."""
    s_in = np.where(held_in, np.maximum(s_in, 0.0), s_in)
    s_out = np.where(outer & touching(held_in), np.maximum(s_out, 0.0), s_out)
    return s_out, s_in


#: slack of the bound G ≤ β Δγ on the front-averaged G1, G2 (in units of β Δγ): the
#: averages' discretisation error is below 0.45 Δγ on the rough cases at 128²
#: (docs/rough_convergence.md)
RELEASE_SLACK = 0.5


def crack_tips(res_out, held, outer):
    """The resolved outer front cells that are crack tips: not next to an inner front cell
    held by contact (a compressive, adhesiveless edge has no stress singularity)."""
    return res_out & ~touching(held & ~outer)


def _release_out_of_bounds(op, tests, tip, dgamma) -> str:
    """'' or why the balanced front is no equilibrium: a front-averaged G1 or G2 on the
    crack-tip edges (resolved outer front cells not next to an edge held by contact) above
    (1 + RELEASE_SLACK) β Δγ, β = E∞/E0: an edge moving steadily in a viscoelastic solid
    releases at most the glassy factor of Δγ (G = Δγ in an elastic scene).  A 2-cycle that
    brackets no root (a tensile load beyond the pull-off, where each flip also moves Δ)
    passes the test in position and ends here (G1 = 34 Δγ at β = 10).  There is no lower
    bound: the work of a band of finite width a0 can release less than Δγ/β, even a
    negative G (the 1D method: G1 = −0.42 Δγ at β = 10, ζ = 2.15, p̃ = 0.15, ã0 = 0.01)."""
    from .front import release_rates

    if not tip.any():
        return ""
    _, G1, G2 = release_rates(op, tests, tip, dgamma)
    fo = {"G1": G1, "G2": G2}
    beta = op.material.beta
    hi = beta * (1.0 + RELEASE_SLACK)
    dg = float(np.mean(dgamma))
    out = [f"{k} = {fo[k] / dg:.3g} Δγ" for k in ("G1", "G2")
           if np.isfinite(fo[k]) and fo[k] / dg > hi]
    return (f"no equilibrium: the front-averaged energy release rate {', '.join(out)} on "
            f"the crack-tip edges exceeds {hi:.3g} Δγ (G ≤ β Δγ, β = {beta:.3g}, with "
            f"{RELEASE_SLACK:g} β Δγ of slack)") if out else ""


def _unverified_pins(mask, stuck, free_in):
    """The ``stuck`` cells (pinned, could open now, balance beyond the whole band) of the
    contact patches that have no free resolved inner front cell.  A pin stands for a
    lattice bind next to edges that balance (a cell that flips between open and
    interpenetrating); under a tensile load a patch held only by such pins has no edge that
    verifies an equilibrium (a load beyond the pull-off ends this way: a few-cell patch whose
    pinned ends release ~10³ Δγ a0).  Under compression such patches occur as lattice binds
    of rough contacts (a pinned cell releasing ~3 Δγ a0 on a 64² rough case) and are kept."""
    if not stuck.any():
        return stuck
    from scipy import ndimage

    lab, n = ndimage.label(mask)
    free = np.zeros(n + 1, bool)
    free[np.unique(lab[free_in])] = True
    return stuck & ~free[lab]


def _blocked(tests, w):
    """Cells whose opening would leave the surfaces interpenetrating (non-penetration holds
    them closed whatever the balance says)."""
    gtol = 1e-12 * max(1.0, float(np.abs(w).max()))
    return tests.g_open < -gtol


def _predictor_moves(tests, mask, outer, w, pinned, hmin):
    """The predictor's moves: its closing and opening estimates are the same product at a
    front (½ t_i g_j a), so there is no slope to interpolate a sub-cell edge from; the band
    joins where F_close < −ε and leaves where F_open > ε, one band per iteration.
    ε = 4.7 h/r, the predictor's own error at the mean front radius r = 2A/P of the mask
    (docs/theory.md): inside it only the exact tests can tell."""
    n_front = max(1, int(outer.sum()))
    eps = min(0.5, 4.7 * n_front / (2.0 * mask.sum())) if mask.any() else 0.5
    s_out = np.where(tests.F_close < -eps, np.inf, -np.inf)
    s_in = np.where(tests.F_open > eps, -np.inf, np.inf)
    add, remove = _moves(tests, mask, s_out, s_in, w, pinned, hmin)
    return add, remove


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


def _check_inputs(cell, penetration, mean_pressure, dgamma, a0, criterion, front_tol):
    control(mean_pressure, penetration)
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
    if not (0.0 < front_tol <= 0.5):
        raise ValueError(f"front_tol = {front_tol!r} cells is outside the allowed range "
                         "(0, 0.5]")
    return dg


def _next_correction(c, g, prev):
    """The next load correction of a balanced mask: the fixed point c = g(c) of the front's
    correction g (the front's mean pressure minus the mask's), by a secant step through the
    previous (c, g) of the same mask where g contracts clearly, else by substitution
    (measured ratios ~0.3 per state: substitution alone takes 6-8 states for LOAD_TOL)."""
    if prev is None:
        return g
    c0, g0 = prev
    f, f0 = g - c, g0 - c0
    if f == f0 or f == 0.0:
        return g
    step = -f * (c - c0) / (f - f0)
    # the secant only where g contracts clearly, |r| ≤ ½ for g ≈ a + r c (step/f = 1/(1 − r)
    # in [2/3, 2]): near a pull-off r → 1 and an extrapolated step would leave the branch
    return c + step if 2.0 / 3.0 <= step / f <= 2.0 else g


class _Oscillation:
    """Detects a front that only flips cells back and forth (exact cycles and drifting ones):
    counts the changes of each cell; a run of iterations that move only cells already
    flipped OSCILLATION_FLIPS times is an oscillation."""

    def __init__(self, shape):
        self.flips = np.zeros(shape, np.uint16)
        self.run = 0
        self.seen = set()

    def step(self, mask, change) -> str:
        """'' or the reason the iteration must stop (called before the change is applied)."""
        key = hash(mask.tobytes())
        if key in self.seen:
            return "the mask returned to an earlier state (a cycle)"
        self.seen.add(key)
        old = self.flips[change]
        self.run = self.run + 1 if old.size and old.min() >= OSCILLATION_FLIPS else 0
        self.flips[change] += 1
        if self.run >= OSCILLATION_RUN:
            return (f"the front oscillates: {OSCILLATION_RUN} iterations in a row moved only "
                    f"cells that had flipped {OSCILLATION_FLIPS} times or more")
        return ""


def solve_adhesive(op: SpectralOperator, heights: np.ndarray, dgamma, a0: float, *,
                   penetration: float | None = None, mean_pressure: float | None = None,
                   mask0: np.ndarray | None = None, max_outer: int = 500,
                   front_smoothing: float = FRONT_SMOOTHING,
                   smoothing_per_radius: float = SMOOTHING_PER_RADIUS,
                   rtol: float = 1e-10, observables: dict | None = None,
                   criterion: str = "exact", front_tol: float = FRONT_TOL,
                   flaw_radius: float | None = None, progress=None) -> AdhesiveState:
    """Adhesive equilibrium under penetration or mean-pressure control.

    ``dgamma``: work of adhesion Δγ (J/m², scalar or per-cell map); ``a0``: advance width (m),
    at least one cell, used exactly (criterion.band_weights).  In an elastic scene the
    reported edge is the sharp-crack edge G = Δγ of a stress-intensity factor linear over
    the two bands (front.sharp_crack_offset); in a viscoelastic scene a0 is physical and
    the edge is the seed's l* (docs/theory.md).

    ``criterion``: 'exact' (every iteration tests the front layers with masked solves),
    'hybrid' (the zero-solve predictor moves the front until it stops, then the exact tests
    finish) or 'predictor' (the predictor alone; the exact tests are evaluated once on the
    final mask, for the outputs — cheaper, less accurate: docs/performance.md).
    ``front_smoothing``: σ of the average along the front in units of a0
    (criterion.smooth_along_front), raised to ``smoothing_per_radius`` times the front
    radius 2A/P of large patches (criterion.patch_sigmas; 0 keeps σ fixed).

    ``flaw_radius``: radius (m) of the flaw through which a full contact may open (default
    a0; module docstring).  In an elastic scene it decides by Griffith's condition whether
    the full contact opens, so it is a physical input there, unlike a0.

    ``progress``: None or a callable ``progress(iteration, text)`` called at the start of
    every outer iteration and once more, with the same iteration, for the final state (the
    command line's progress bar).

    Status: ``partial`` only when every resolved front cell is balanced within ``front_tol``
    cells (front.balance_residual); ``not_converged`` otherwise (a cycle, an oscillation or
    the iteration limit), with the balanced fraction of the front in the result.
    """
    cell = op.cell
    h = check_heights(heights, cell)
    _check_inputs(cell, penetration, mean_pressure, dgamma, a0, criterion, front_tol)
    hmin = min(cell.hx, cell.hy)
    phase = "exact" if criterion == "exact" else "predictor"
    test_kw = dict(rtol=rtol, vhat=sliding_direction(op), front_smoothing=front_smoothing,
                   smoothing_per_radius=smoothing_per_radius, observables=observables)
    shift = 0.0 if op.viscoelastic else 0.5 * a0
    hmax = float(h.max())
    mask = (h >= hmax - 1e-12 * max(1.0, abs(hmax))) if mask0 is None else mask0.copy()
    delta = penetration
    p = np.zeros(cell.shape)
    corr = 0.0  # load control: the front's mean pressure minus the mask's
    corr_prev = None  # (mask key, corr, new_corr) of the last balanced state (secant)
    osc = _Oscillation(cell.shape)
    wide = None  # the oscillating cells of a rescued front (moved only when unbalanced)
    opened = np.zeros(cell.shape, bool)  # cells the criterion has opened in this solve
    last_change = np.zeros(cell.shape, bool)
    flaw_tried = False
    pinned = np.zeros(cell.shape, bool)  # opened, then closed again by non-penetration
    released = np.zeros(cell.shape, np.int8)  # times each cell's stale pin was released
    solves = 0
    history = []
    status, message, converged = "not_converged", "", False
    tests = None
    s_out = s_in = np.full(cell.shape, np.nan)
    res_out = held = None
    frac, rmax = float("nan"), float("nan")
    it = 0
    for it in range(1, max_outer + 1):
        if progress is not None:
            progress(it, f"{phase}, {int(mask.sum())} cells in contact"
                     + (f", balanced {frac:.3f}" if np.isfinite(frac) else ""))
        if not mask.any():
            status, message = "detached", "the contact vanished"
            p = np.zeros(cell.shape)
            break
        if mask.all():
            # the flaw's balanced edge has the flaw radius: its mask edge lies the
            # sharp-crack shift further out (elastic scenes)
            flaw = None if flaw_tried else _nucleation_flaw(
                op, h, mean_pressure, penetration, (flaw_radius or a0) + shift)
            if flaw is None:
                from .contact import _full_contact

                full = _full_contact(op, h, mean_pressure, penetration)
                if full is not None:  # report the full-contact state itself
                    p, delta = full
                status, message = "full_contact", "the contact covers the cell"
                if flaw_tried:
                    message += " (the nucleation flaw at the peak tension closed)"
                break
            flaw_tried = True  # nucleation rule: open it once, let the criterion decide
            mask = ~flaw
            continue
        if mean_pressure is not None:
            # Σ p fixed, Δ its multiplier: one projected solve (docs/derivations.md §8)
            guard = int(20 * np.sqrt(np.count_nonzero(mask)) + 500)
            p, used, _pairs, rel = solve_packed(op, mask, p, h - hmax,
                                                (mean_pressure - corr) * mask.size, rtol, guard)
            solves += 1
            u = op.apply(p)
            r = (u - (h - hmax))[mask]
            delta = float(r.mean())
            rhs = (h - hmax)[mask]  # scale: the profile's variation or the displacement
            scale = max(float(np.linalg.norm(rhs - rhs.mean())),
                        float(np.linalg.norm(u[mask])), 1e-300)
            rel = float(np.linalg.norm(r - delta)) / scale
            if rel > TRUE_RESIDUAL_MARGIN * rtol:  # the true residual
                message = (f"masked solve: not converged after {used} products (guard "
                           f"{guard}): relative residual {rel:.3e}")
                break
        else:
            res = solve_masked(op, mask, h - hmax + delta, x0=p, rtol=rtol)
            solves += 1
            if not res.converged:
                message = "masked solve: " + res.message
                break
            p = res.field
            u = op.apply(p)
        w = h - hmax + delta
        pen = ~mask & (u - w < -1e-12 * max(1.0, float(np.abs(w).max())))
        if pen.any():  # contact nucleation (JKR jump-in)
            # a cell the criterion opened that interpenetrates at a later Δ (load control)
            # cannot open: it stays closed (pinned) for the rest of this solve
            pinned |= pen & opened
            mask |= pen
            continue
        outer, inner = front_cells(mask)
        if phase == "predictor":
            tests = predictor_tests(op, w, mask, p, dgamma, a0, u=u,
                                    front_smoothing=front_smoothing,
                                    smoothing_per_radius=smoothing_per_radius)
            add, remove = _predictor_moves(tests, mask, outer, w, pinned, hmin)
            stop = osc.step(mask, add | remove) if (add.any() or remove.any()) else "stop"
            if not stop:
                history.append((it, int(mask.sum()), int(add.sum()), int(remove.sum()),
                                float(delta)))
                mask = (mask | add) & ~remove
                opened |= remove
                continue
            # the predictor has brought the front to (or cycling around) its balance: the
            # exact tests take over ("hybrid"), or only evaluate the outputs ("predictor")
            phase = "exact"
            osc = _Oscillation(cell.shape)
        tests = None  # the last state's tests (kept on a balanced mask): freed first
        tests = front_tests(op, w, mask, p, dgamma, a0, u=u, **test_kw)
        solves += tests.solves
        if not tests.converged:
            message = "layer test: " + tests.message
            break
        s_out, s_in = _offsets(tests.F_close, tests.F_open, outer, inner, a0, shift > 0)
        if criterion != "predictor" and p.mean() > 0 and pinned.any():
            free = _stale_pins(tests, mask, s_out, s_in, w, pinned, hmin)
            free &= released < PIN_RELEASES
            released += free
            pinned &= ~free  # these move with the balance from now on
        blocked = _blocked(tests, w)
        held = pinned | blocked
        # under a tensile load, pinned cells that could open now and whose balance lies
        # beyond the whole band are unbalanced where their patch has no free edge
        # (_unverified_pins)
        stuck = pinned & ~blocked & inner & (s_in == -np.inf)
        s_out, s_in = _held_offsets(s_out, s_in, outer, inner & held)
        add, remove = _moves(tests, mask, s_out, s_in, w, pinned, hmin, wide, front_tol)
        res_out, res_in = resolved_front(mask, outer, inner, a0, (cell.hx, cell.hy))
        bracket = bracketed(tests, add, remove, last_change)
        # a bracketed edge lies inside its flipping cell: at that cell's centre ± h/2
        s_out = np.where(bracket, np.clip(s_out, -0.5 * hmin, 0.5 * hmin), s_out)
        s_in = np.where(bracket, np.clip(s_in, -0.5 * hmin, 0.5 * hmin), s_in)
        rmax, r = balance_residual(s_out, s_in, res_out, res_in, ~held, hmin)
        if mean_pressure is not None and mean_pressure < 0:
            stuck = _unverified_pins(mask, stuck & res_in, res_in & ~held)
        else:
            stuck[:] = False
        if stuck.any():
            rmax, r = float("inf"), np.concatenate([r, np.full(int(stuck.sum()), np.inf)])
        frac = float(np.mean(r <= front_tol)) if r.size else 1.0
        history.append((it, int(mask.sum()), int(add.sum()), int(remove.sum()), float(delta)))
        load_ok, new_corr = True, corr
        if mean_pressure is not None:  # the load carried by the sub-cell front
            pf = at_front(tests, np.where(res_out, s_out, np.nan),
                          {"mean_pressure": float(p.mean())}, a0)
            new_corr = pf["mean_pressure"] - float(p.mean())
            load_ok = abs(new_corr - corr) <= LOAD_TOL * float(np.abs(p).mean())
        if not res_out.any():  # no resolved patch: nothing verifies a balance
            rmax, frac = float("inf"), 0.0
        if (rmax <= front_tol and load_ok) or criterion == "predictor":
            converged = status_ok = rmax <= front_tol
            status = "partial" if status_ok else "not_converged"
            message = (f"converged: every resolved front cell balanced within "
                       f"{front_tol:g} cells (largest residual {rmax:.3f})")
            if criterion == "predictor":  # one exact evaluation, no load correction
                message = (f"predictor criterion; exact tests of the final mask: "
                           f"{100 * frac:.1f} % of the front balanced within {front_tol:g} "
                           f"cells (largest residual {rmax:.3f}); the front carries "
                           f"{float(p.mean()) + new_corr:.6g} Pa of mean pressure")
            break
        moving = add.any() or remove.any()
        if not res_out.any() and not moving:
            message = ("every contact patch is too thin for a band of width a0: the balance "
                       "cannot be verified")
            break
        if rmax <= front_tol or not moving:
            # balanced on this mask: the front's load correction moves Δ (updated only
            # here, never with the mask moving: a correction that lags a moving mask makes
            # the edges cycle); a new Δ makes new states
            if it == max_outer:
                message = f"not converged in {max_outer} outer iterations (load)"
                break
            key = hash(mask.tobytes())
            c0 = corr_prev[1:] if corr_prev is not None and corr_prev[0] == key else None
            corr_prev = (key, corr, new_corr)
            corr = _next_correction(corr, new_corr, c0)
            osc.seen.clear()
            tests = res_out = None  # freed before the next state's solves
            continue
        reason = osc.step(mask, add | remove)
        if reason and wide is None and it < max_outer:
            # rescue, once: the cells that oscillate move from now on only when their front
            # cell is unbalanced (beyond the acceptance band), so a front that oscillates
            # inside it settles; the status rule is unchanged (every cell balanced)
            wide = osc.flips >= min(OSCILLATION_FLIPS, int(osc.flips.max()))
            osc = _Oscillation(cell.shape)
            add, remove = _moves(tests, mask, s_out, s_in, w, pinned, hmin, wide, front_tol)
            reason = osc.step(mask, add | remove) if (add.any() or remove.any()) else ""
        if reason or it == max_outer:
            reason = reason or f"not converged in {max_outer} outer iterations"
            message = (f"{reason}; {100 * frac:.1f} % of the resolved front balanced within "
                       f"{front_tol:g} cells (largest residual {rmax:.3f} cells)")
            break
        mask = (mask | add) & ~remove
        last_change = add | remove
        # the tests and bands of the old mask: freed before the next state's solves
        tests = res_out = None
        opened |= remove
    else:  # the guard ran out on a nucleation step
        message = f"not converged in {max_outer} outer iterations"
    pm = float(p.mean())
    if status == "partial":  # the mean pressure carried by the sub-cell front
        pm = at_front(tests, np.where(res_out, s_out, np.nan), {"mean_pressure": pm},
                      a0)["mean_pressure"]
    tips = None
    if status == "partial" and held is not None and res_out is not None:
        tips = crack_tips(res_out, held, outer)
        bad = _release_out_of_bounds(op, tests, tips, dgamma)
        if not tips.any() and res_out.any() and float(p.mean()) < 0:
            bad = ("no equilibrium: the contact carries a tensile mean pressure, but every "
                   "edge is held by contact (no crack tip: an adhesiveless contact carries "
                   "no tension)")
        if bad:
            status, converged = "not_converged", False
            message = (f"{bad}, although every resolved front cell lies within "
                       f"{front_tol:g} cells of its balanced edge")
    if status == "not_converged" and mean_pressure is not None and mean_pressure < 0:
        message += ("; a tensile load beyond the pull-off has no equilibrium (penetration "
                    "control follows the branch through it)")
    if progress is not None:  # the final state's line
        progress(it, f"{status}, {int(mask.sum())} cells in contact"
                 + (f", balanced {frac:.3f}" if np.isfinite(frac) else ""))
    nun = unresolved_patches(mask, a0, (cell.hx, cell.hy))
    if nun:
        message += f"; {nun} contact patches smaller than a disc of radius a0 (unresolved)"
    u = op.apply(p)
    gap = u - (h - hmax + delta)
    gap[mask] = 0.0
    return AdhesiveState(
        pressure=p, displacement=u, gap=gap, contact=mask, penetration=float(delta),
        mean_pressure=pm, status=status, iterations=it, converged=converged, message=message,
        method="front-layer energy balance, sub-cell front", **friction(op, h, p, u),
        tests=tests, offset_out=s_out, offset_in=s_in, solves=solves, history=history, a0=a0,
        unresolved_patches=nun, edge_shift=shift, resolved=res_out, balanced_fraction=frac,
        residual=rmax, crack_tips=tips)
