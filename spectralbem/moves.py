"""How the contact mask of an adhesive solve follows its balanced front
(:func:`spectralbem.adhesive.solve_adhesive`): the sub-cell offsets from the band tests, the
cells that join and leave, the edges non-penetration holds, the pins of cells load control
closed again, the load correction of the sub-cell front, and the detection of an oscillating
front (docs/theory.md, "The 2D criterion and the sub-cell front")."""

from __future__ import annotations

import numpy as np

from .front import (
    band_crack_offset,
    mean_width,
    neighbour_mean,
    sharp_crack_offset,
    sub_cell_offset,
    touching,
)

__all__ = ["offsets", "moves", "stale_pins", "overloaded_pins", "held_offsets", "crack_tips",
           "release_out_of_bounds", "release_bound", "unverified_pins", "blocked",
           "predictor_moves", "next_correction", "LoadCorrection", "Oscillation",
           "PIN_RELEASES", "RELEASE_SLACK", "release_pins", "OSCILLATION_FLIPS",
           "OSCILLATION_RUN", "OSCILLATING_SHARE"]

#: a cell that has changed state this many times in one solve counts as oscillating
OSCILLATION_FLIPS = 3
#: this many consecutive iterations that move only oscillating cells end the solve
OSCILLATION_RUN = 6
#: a front wanders when this many consecutive iterations (OSCILLATION_RUN) move mostly
#: oscillating cells, at least this share of the moved ones: the rescue of an oscillating
#: front starts then (the end of the solve still needs the strict run).  Measured on the
#: rough elastic loading state at 256² (cases/rough_convergence.toml, a0 = 2 cells): from
#: the 40th front iteration 30-55 cells in 10-20 patches, 80-100 % of them flipped three
#: times or more, moved at every front test while a new cell or two now and then broke the
#: strict run, for 50 iterations before the front balanced (93 in all; 57 with this rule)
OSCILLATING_SHARE = 0.8


def offsets(F_close, F_open, outer, inner, a0, sharp=False, widths=None, field=False):
    """Sub-cell offsets of the balanced edge on the outer front cells (closing test there,
    opening tests of the neighbouring inner cells) and on the inner front cells (the other
    way round); nan elsewhere.  ``sharp``: the sharp-crack edge of an elastic scene
    (front.sharp_crack_offset), else the seed's edge by the linear fit of the band means
    (front.sub_cell_offset) or, with ``field``, by the fit of a square-root field
    (front.band_crack_offset: the viscoelastic mask's moves).  ``widths``:
    (outer, inner) effective band widths (along_front.band_widths; None, or a pair of None
    from the predictor: a0): the band means are interpolated over the mean of the two bands'
    widths (a0 where none is known)."""
    offset = (sharp_crack_offset if sharp else band_crack_offset if field
              else sub_cell_offset)
    s_out = np.full(F_close.shape, np.nan)
    s_in = np.full(F_close.shape, np.nan)
    io, ii = np.flatnonzero(outer), np.flatnonzero(inner)
    w_out = w_in = a0
    if widths is not None and widths[0] is not None:
        wo, wi = widths
        w_out = mean_width(wo.ravel()[io], neighbour_mean(wi, inner, io), a0)
        w_in = mean_width(wi.ravel()[ii], neighbour_mean(wo, outer, ii), a0)
    s_out.ravel()[io] = offset(F_close.ravel()[io], neighbour_mean(F_open, inner, io), w_out)
    s_in.ravel()[ii] = offset(neighbour_mean(F_close, outer, ii), F_open.ravel()[ii], w_in)
    return s_out, s_in


def moves(tests, mask, s_out, s_in, w, pinned, hmin, wide=None, tol=0.0):
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
    tol = 1e-9 * hmin
    # band cells within a step of the front, each with its owning front cell
    ob = np.flatnonzero(b.outer_band & (b.outer_dist <= b.step_reach + tol))
    ib = np.flatnonzero(b.inner_band & (b.inner_dist <= b.step_reach + tol) & ~pinned
                        & ~blocked(tests, w))
    reach_out = b.outer_dist.ravel()[ob] - half  # the nearest-centre rule
    reach_in = b.inner_dist.ravel()[ib] - half
    if extra is not None:
        reach_out, reach_in = reach_out + extra[ob], reach_in + extra[ib]
    add = np.zeros(mask.shape, bool)
    add.ravel()[ob] = s_out.ravel()[b.outer_owner.ravel()[ob]] > reach_out
    remove = np.zeros(mask.shape, bool)
    remove.ravel()[ib] = s_in.ravel()[b.inner_owner.ravel()[ib]] < -reach_in
    return add, remove


#: times a cell's stale pin may be released (:func:`stale_pins`).  Measured on the rough SLS
#: path of docs/rough_convergence.md at 512², its direct unloading step 3e4 → 1e4 Pa: with one
#: release it ended held by 11 overloaded pins after 215 outer iterations and was solved
#: again in two half steps (path 503 CPU-s); with two it converges directly in 211 (path 241 s)
PIN_RELEASES = 2


def stale_pins(tests, mask, s_out, s_in, w, pinned, hmin):
    """Pinned cells whose pin is stale: their opening now leaves a gap (not blocked) and the
    balance, not held by the pin, opens them.  A pin is set when a cell the criterion opened
    interpenetrates at a later Δ; on unloading the front passes through such states, and
    without a release the pins stay closed as slivers under tension (the rough 256²
    viscoelastic case: 175 pinned cells in 76 patches carried 40 % of the friction force).
    The solver releases each cell's stale pin at most ``PIN_RELEASES`` times (a cell pinned
    once more is a lattice bind and stays), at the iteration it turns stale, under a compressive
    mean pressure only: under a tensile one, pins of patches without a free edge make the
    state unverified (:func:`unverified_pins`), and beyond the pull-off releasing them
    only delays that."""
    if not pinned.any():
        return pinned
    _, remove = moves(tests, mask, s_out, s_in, w, np.zeros_like(pinned), hmin)
    return remove & pinned


def release_pins(stale, pinned, released, limit: int = PIN_RELEASES):
    """Release the ``stale`` pins of cells released fewer than ``limit`` times, in place:
    they leave ``pinned`` and their count in ``released`` grows by one.  Returns the stale
    pins that stay (released ``limit`` times already: lattice binds)."""
    free = stale & (released < limit)
    released += free
    pinned &= ~free
    return stale & ~free


def overloaded_pins(stale, p, free_edge, factor: float = 1.0) -> int:
    """How many ``stale`` pins (pinned cells that would open now, their pin already
    released: :func:`stale_pins`) carry more than ``factor`` times the tension of the most
    tensile free edge cell of the front (``free_edge``: the resolved inner front cells not
    held by contact).  A pin that flips with Δ (opened, it interpenetrates at the next Δ;
    closed, the balance opens it) holds an edge inside its cell, a lattice bind, and carries
    the tension of a balanced edge.  The tension of an edge cell grows with the stress
    intensity K and G with K², so a pin at ``factor`` times the tension of a balanced edge
    holds about ``factor``² times its G; :func:`solve_adhesive` takes the factor of the
    bound G ≤ (1 + RELEASE_SLACK) β Δγ, √(:func:`release_bound`).  Measured on the rough
    viscoelastic case (β = 10, bound 3.9): unloading at 256², 5 stale pins at 1.6× the
    free edges' tension (kept); at 512², 422 stale pins up to 9.7× (15 beyond 3.9), which
    carried two thirds of the friction force.  None: no stale pin."""
    if stale is None or not stale.any():
        return 0
    floor = float(p[free_edge].min()) if free_edge.any() else 0.0
    return int(np.count_nonzero(stale & (p < factor * min(floor, 0.0))))


def held_offsets(s_out, s_in, outer, held_in):
    """Offsets where non-penetration holds the edge: a front cell that cannot open (its
    opening leaves the surfaces interpenetrating, or load control closed it again) is a
    compressive edge, not a crack tip; the energy balance's inward offset there is an
    extrapolation of meaningless works (negative gap times compressive pressure), so the
    edge stays at the mask edge, as in an adhesiveless contact: s ≥ 0 on those inner cells
    and on the outer cells next to them (an outward balance still counts).  In place of
    ``s_out`` and ``s_in`` (returned): no copies of the two N² arrays."""
    np.maximum(s_in, 0.0, out=s_in, where=held_in)
    np.maximum(s_out, 0.0, out=s_out, where=outer & touching(held_in))
    return s_out, s_in


#: slack of the bound G ≤ β Δγ on the front-averaged G1, G2 (in units of β Δγ): the
#: averages' discretisation error is below 0.45 Δγ on the rough cases at 128²
#: (docs/rough_convergence.md)
RELEASE_SLACK = 0.5


def release_bound(op) -> float:
    """The largest front-averaged release rate a balanced edge may show, in units of Δγ:
    (1 + RELEASE_SLACK) β with β = E∞/E0 (1 in an elastic scene)."""
    return (1.0 + RELEASE_SLACK) * op.material.beta


def crack_tips(res_out, held, outer):
    """The resolved outer front cells that are crack tips: not next to an inner front cell
    held by contact (a compressive, adhesiveless edge has no stress singularity)."""
    return res_out & ~touching(held & ~outer)


def release_out_of_bounds(op, tests, tip, dgamma, offset_out=None, a0=None) -> str:
    """'' or why the balanced front is no equilibrium: a front-averaged G1 or G2 on the
    crack-tip edges (resolved outer front cells not next to an edge held by contact) above
    (1 + RELEASE_SLACK) β Δγ or below its negative, β = E∞/E0: an edge moving steadily in a
    viscoelastic solid releases at most the glassy factor of Δγ (G = Δγ in an elastic
    scene).  A 2-cycle that brackets no root (a tensile load beyond the pull-off, where each
    flip also moves Δ) passes the test in position and ends here (G1 = 34 Δγ at β = 10).
    The work of a band of
    finite width a0 can release less than Δγ/β, even a negative G (the 1D method: G1 =
    −0.42 Δγ at β = 10, ζ = 2.15, p̃ = 0.15, ã0 = 0.01), so the sharp-crack lower bound Δγ/β
    does not apply; the same glassy factor is allowed below zero, G ≥ −(1 + RELEASE_SLACK)
    β Δγ, 36 times beyond that lowest 1D value: a 2-cell contact pulled beyond the pull-off
    (the rough SLS case at 64², a0 one cell, −1000 Pa) balanced in position with G2 =
    −2826 Δγ."""
    from .front import release_rates

    if not tip.any():
        return ""
    _, G1, G2 = release_rates(op, tests, tip, dgamma, offset_out=offset_out, a0=a0)
    fo = {"G1": G1, "G2": G2}
    beta = op.material.beta
    hi = release_bound(op)
    dg = float(np.mean(dgamma))
    out = [f"{k} = {fo[k] / dg:.3g} Δγ" for k in ("G1", "G2")
           if np.isfinite(fo[k]) and abs(fo[k] / dg) > hi]
    return (f"no equilibrium: the front-averaged energy release rate {', '.join(out)} on "
            f"the crack-tip edges lies beyond ±{hi:.3g} Δγ (|G| ≤ β Δγ, β = {beta:.3g}, "
            f"with {RELEASE_SLACK:g} β Δγ of slack)") if out else ""


def unverified_pins(mask, stuck, free_in):
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


def blocked(tests, w):
    """Cells whose opening would leave the surfaces interpenetrating (non-penetration holds
    them closed whatever the balance says)."""
    gtol = 1e-12 * max(1.0, float(np.abs(w).max()))
    out = np.zeros(tests.F.shape, bool)
    out.ravel()[np.flatnonzero(tests.bands.inner_band)] = tests.g_band < -gtol
    return out


def predictor_moves(tests, mask, outer, w, pinned, hmin):
    """The predictor's moves: its closing and opening estimates are the same product at a
    front (½ t_i g_j a), so there is no slope to interpolate a sub-cell edge from; the band
    joins where F_close < −ε and leaves where F_open > ε, one band per iteration.
    ε = 4.7 h/r, the predictor's own error at the mean front radius r = 2A/P of the mask
    (docs/theory.md): inside it only the exact tests can tell."""
    n_front = max(1, int(outer.sum()))
    eps = min(0.5, 4.7 * n_front / (2.0 * mask.sum())) if mask.any() else 0.5
    s_out = np.where(tests.F_close < -eps, np.inf, -np.inf)
    s_in = np.where(tests.F_open > eps, -np.inf, np.inf)
    add, remove = moves(tests, mask, s_out, s_in, w, pinned, hmin)
    return add, remove


def next_correction(c, g, prev):
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


#: :class:`LoadCorrection`: a bracket whose ends miss the load by more than this many times
#: its width is a jump of the front's load, not a steep continuous map
JUMP_SLOPE = 20.0
#: ... and by more than this many load tolerances (measured jumps: 1e3-1e4 of them)
JUMP_TOLS = 100.0


class LoadCorrection:
    """The load corrections of one balanced mask after another (:func:`next_correction`),
    bracketed: once two corrections of the same mask leave the front's load on either side
    of the prescribed one (f = g − c of opposite signs), the next lies between them (regula
    falsi, with Illinois' halving where one end stays twice), so an oscillating map
    converges; a bracket whose ends miss the prescribed load by more than :data:`JUMP_SLOPE`
    times its width is a jump of the front's load across the prescribed one, not a fixed
    point (:meth:`next` returns None).  A jump occurs where a front cell's hold by
    non-penetration (:func:`blocked`) changes with Δ: its balanced edge moves by up to a
    cell within the acceptance band, and on a small contact the load it carries exceeds the
    tolerance (measured: 50 Pa of 3000 Pa on a 104-cell contact at 64²)."""

    def __init__(self):
        self.key = None
        self.prev = None  # (c, g) of the last correction of the mask ``key``
        self.ends = {}  # sign of f -> (c, f): the bracket's ends (f halved by Illinois)
        self.missed = {}  # sign of f -> f at that end as measured (Pa)
        self.kept = 0  # the end kept by the last bracketed step (+1, -1), 0 if none

    def next(self, key, c: float, g: float, tol: float):
        """The correction after (c, g) of the mask ``key``, or None at a jump: the ends miss
        by more than :data:`JUMP_SLOPE` bracket widths and :data:`JUMP_TOLS` times the load
        tolerance ``tol`` (the band tests' round-off of the front's load is below it)."""
        if key != self.key:
            self.key, self.prev, self.ends, self.missed, self.kept = key, None, {}, {}, 0
        f = g - c
        prev, self.prev = self.prev, (c, g)
        side = 1 if f > 0 else -1 if f < 0 else 0
        if side == 0:
            return g
        bracketed = -side in self.ends
        if bracketed and self.kept == -side:  # that end kept twice: Illinois' halving
            cb, fb = self.ends[-side]
            self.ends[-side] = (cb, 0.5 * fb)
        self.ends[side], self.missed[side] = (c, f), f
        if not bracketed:
            return next_correction(c, g, prev)
        self.kept = -side
        (ca, fa), (cb, fb) = self.ends[1], self.ends[-1]
        # a continuous g of slope r changes f = g − c by |1 − r| times the bracket's width:
        # ends that miss by more than JUMP_SLOPE widths are a jump (measured slopes r ~ 0.3,
        # r → 1 near a pull-off); the bracket shrinks onto a jump until they do
        missed = self.missed[1] - self.missed[-1]
        if missed > JUMP_SLOPE * abs(ca - cb) and missed > JUMP_TOLS * tol:
            return None
        return ca - fa * (cb - ca) / (fb - fa)


class Oscillation:
    """Detects a front that only flips cells back and forth (exact cycles and drifting ones):
    counts the changes of each cell; a run of iterations that move only cells already
    flipped OSCILLATION_FLIPS times is an oscillation; a run that moves mostly such cells
    (OSCILLATING_SHARE of them) is a wandering front (``wandering``: time for the rescue)."""

    def __init__(self, shape):
        self.flips = np.zeros(shape, np.uint16)
        self.run = 0
        self.mostly = 0  # the run of iterations moving mostly oscillating cells
        self.seen = set()

    @property
    def wandering(self) -> bool:
        return self.mostly >= OSCILLATION_RUN

    def step(self, mask, change) -> str:
        """'' or the reason the iteration must stop (called before the change is applied)."""
        key = hash(mask.tobytes())
        if key in self.seen:
            return "the mask returned to an earlier state (a cycle)"
        self.seen.add(key)
        oscillating = self.flips[change] >= OSCILLATION_FLIPS
        share = float(oscillating.mean()) if oscillating.size else 0.0
        self.run = self.run + 1 if share == 1.0 else 0
        self.mostly = self.mostly + 1 if share >= OSCILLATING_SHARE else 0
        self.flips[change] += 1
        if self.run >= OSCILLATION_RUN:
            return (f"the front oscillates: {OSCILLATION_RUN} iterations in a row moved only "
                    f"cells that had flipped {OSCILLATION_FLIPS} times or more")
        return ""
