"""The contact-domain criterion on the grid: the seed's local energy balance (Eqs. 3, 8-10)
applied to whole front layers (docs/derivations.md §9, docs/theory.md).

At fixed Δ, for the mask A (the state):

* closing test — the band D of width a0 just outside the front (cells whose centre lies within
  a0 of A) is closed in one masked solve on A ∪ D; each cell of D does the work
  ``δL_j = ½ g_j(A) t_j(A ∪ D) h²`` (Eq. 8 restricted to D, where it is supported, with the
  tensile stress t = -p);
* opening test — the band R of width a0 inside the front is opened, one solve on A ∖ R, and
  ``δL_j = ½ g_j(A ∖ R) t_j(A) h²``: the same closing test taken from the state with R removed.

The work of each band cell is attributed to its nearest front cell; per front cell
``F = Σ δL_j / Σ Δγ_j h² - 1`` (per-cell Δγ maps are supported).  Trailing (v̂·n < 0) and
leading (v̂·n > 0) parts of the front are tested in separate solves, so a y-invariant mask
reproduces the 1D closure Eqs. (16)-(17) with the other edge fixed.  Single-cell tests are
never used: they carry a mesh-independent bias (docs/derivations.md §9).

Closing is evaluated with the edge at the cell boundary x_b, opening with the edge at
x_b - a0; F is interpolated linearly between them to the sub-cell front l*.  The band is
exactly a0 wide for any a0/h ≥ 1: the tests of m and m + 1 whole layers are interpolated in
the width (:func:`band_weights`); at every orientation of the front (a viscoelastic scene,
and an elastic one with a0 of two cells or more, :func:`exact_width`): the band within a0
and the bands one, two, … digital layers wider (along_front.band_levels), with weights per
front cell from their actual widths (along_front.layer_weights).  docs/theory.md, "The 2D
criterion and the sub-cell front".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from .adjoint import complete_adjoint
from .along_front import (
    band_levels,
    band_levels_needed,
    band_widths,
    front_average,
    layer_weights,
)
from .band_starts import BandStarts
from .bands import (  # noqa: F401  (front_cells, band_split: part of this module's API)
    Bands,
    band_split,
    band_weights,
    bands,
    bands_reach,
    colours,
    front_cells,
)
from .masked import solve_masked
from .observables import observe
from .spectral import SpectralOperator

#: σ of the average of the balance along the front, in units of a0 (docs/theory.md,
#: "Averaging along the front", where the measurements of σ live): viscoelastic scenes,
#: where a0 and σ are physical lengths
FRONT_SMOOTHING = 1.5

#: the same in elastic scenes, where both are numerical and the answer is the local balance
#: (σ → 0): σ = ½ a0 gives the area of σ = 0 to 0.1 % in half its front iterations
FRONT_SMOOTHING_ELASTIC = 0.5


def default_smoothing(front_smoothing: float | None, viscoelastic: bool) -> float:
    """``front_smoothing`` as given, or the default of the scene's kind (None)."""
    if front_smoothing is not None:
        return float(front_smoothing)
    return FRONT_SMOOTHING if viscoelastic else FRONT_SMOOTHING_ELASTIC


#: σ = max(FRONT_SMOOTHING a0, SMOOTHING_PER_RADIUS r) for a patch of front radius r
#: (:func:`patch_sigmas`; measured in docs/performance.md, the adhesive sphere); 0: σ fixed
SMOOTHING_PER_RADIUS = 0.23

#: the band tests of the adhesive solve's intermediate states stop their masked solves at
#: this many times the state's relative tolerance, at most 1e-6 (1e-7 at the default 1e-10);
#: the final state is tested at the state's tolerance (docs/performance.md, "The adhesive
#: state against its adhesiveless solve": the same masks on the rough states, 25-33 % fewer
#: Krylov products in the band tests)
BAND_RTOL_FACTOR = 1e3


def loose_band_rtol(rtol: float) -> float:
    """The band tests' tolerance of an intermediate state (:data:`BAND_RTOL_FACTOR`)."""
    return max(rtol, min(BAND_RTOL_FACTOR * rtol, 1e-6))


class LayerWork(NamedTuple):
    """The energies of one band test (one colour, the band exactly a0 wide): the work δL of
    the tractions over the band (Eq. 8), the change of stored energy δU (Eq. 9), the work of
    the internal stresses δL_P (Eq. 10, 0 in an elastic scene), all in J, the band's area
    (m²) and the observables (name -> Σ p f) of the test's state."""

    dL: float
    dU: float
    dLP: float
    area: float
    observables: dict


@dataclass
class FrontTest:
    """Per-front-cell results of the closing and opening tests at fixed Δ.

    The outer and inner front cells are disjoint, so a quantity of both tests is one N²
    array: the closing test's value on the outer front cells, the opening test's on the
    inner ones, nan elsewhere (``F``, ``width``, ``rate``); the one-sided views (``F_close``
    and ``F_open``, ...) are built on access.  Memory: docs/performance.md, "Scaling"."""

    F: np.ndarray  # the balance: closing on outer front cells, opening on inner front cells
    #: gap of each inner band cell in its opening-test state (flat order of the inner band;
    #: nan where untested)
    g_band: np.ndarray
    closing: dict  # colour -> LayerWork of the closing band
    opening: dict  # colour -> LayerWork of the opening band
    colour_map: list  # colour -> bool array of the front cells it contains
    bands: Bands
    solves: int
    converged: bool
    message: str
    #: the bands' area per front length (m): closing on the outer, opening on the inner cells
    width: np.ndarray | None = None
    #: filled by ``adjoint.complete_adjoint``: δL_P/δA (J/m²) of each front cell's band (closing
    #: on the outer cells; opening on the inner cells in a viscoelastic scene, ``rate_in``),
    #: δL_P (J) of each band cell (closing: the outer band's cells in flat order, opening:
    #: the inner band's) and the conservative release rate (δL − δL_P)/δA of the outer front
    #: cells (flat indices, values)
    rate: np.ndarray | None = None
    rate_in: bool = False
    dLP_band: tuple | None = None
    g_close: tuple | None = None
    #: what the adjoint split of δL_P still needs (``adjoint.complete_adjoint``): the prescribed
    #: w and, per colour, the owners, band cells and weights of the closing and opening
    #: tests; None once filled
    pending: dict | None = None
    #: (σ in cells, σ per front radius) of the average along the front, with which the
    #: adjoint split's rates are averaged as the balance is (``adjoint.complete_adjoint``)
    smoothing: tuple | None = None

    def _side(self, field_, outer: bool):
        if field_ is None:
            return None
        return np.where(self.bands.outer_front if outer else self.bands.inner_front, field_,
                        np.nan)

    @property
    def dLP_cells(self):
        """δL_P (J) of each band cell on the grid: closing outside A, opening in A (0
        elsewhere; None before the split)."""
        if self.dLP_band is None:
            return None
        out = np.zeros(self.F.shape)
        out.ravel()[np.flatnonzero(self.bands.outer_band)] = self.dLP_band[0]
        out.ravel()[np.flatnonzero(self.bands.inner_band)] += self.dLP_band[1]
        return out

    @property
    def g_open(self):
        """The opened cells' gaps on the grid (nan off the inner band)."""
        out = np.full(self.F.shape, np.nan)
        out.ravel()[np.flatnonzero(self.bands.inner_band)] = self.g_band
        return out

    F_close = property(lambda self: self._side(self.F, True))
    F_open = property(lambda self: self._side(self.F, False))
    width_out = property(lambda self: self._side(self.width, True))
    width_in = property(lambda self: self._side(self.width, False))
    dLP_rate = property(lambda self: self._side(self.rate, True))
    dLP_rate_in = property(lambda self: self._side(self.rate, False) if self.rate_in else None)

    @property
    def G_close(self):
        """(δL − δL_P)/δA on the outer front cells (nan elsewhere; None before the split)."""
        if self.g_close is None:
            return None
        out = np.full(self.F.shape, np.nan)
        out.ravel()[self.g_close[0]] = self.g_close[1]
        return out


def _balance(dL, cells, owner, dg_area, F, W) -> None:  # dg_area: Δγ·a on ``cells``
    """Per owning front cell: F = Σ δL / Σ Δγ a - 1 over its band cells, W = Σ Δγ a (the
    weight of the ratio of sums along the front).  ``dL`` holds the work of the band cells
    ``cells`` (flat indices), ``owner`` their front cells; fills F and W in place."""
    owners, slot = np.unique(owner, return_inverse=True)
    num = np.bincount(slot, weights=dL, minlength=owners.size)
    den = np.bincount(slot, weights=dg_area, minlength=owners.size)
    has = den > 0
    F.ravel()[owners[has]] = num[has] / den[has] - 1.0
    W.ravel()[owners[has]] = den[has]


def _dg_area(dg: np.ndarray, area: float, cells: np.ndarray) -> np.ndarray:
    """Δγ·a on the flat ``cells`` (a scalar Δγ is never expanded to the grid)."""
    return area * (dg.ravel()[cells] if dg.ndim else np.full(cells.size, float(dg)))


def _sigma_cells(front_smoothing: float, a0: float, hmin: float, shape) -> float:
    """σ in cells from σ in units of a0, at most half the grid's longer side (a wider
    average is the mean over the front; the walk's cost grows as σ²)."""
    return min(front_smoothing * a0 / hmin, 0.5 * max(shape))


def _owner_sums(values: dict, owner: np.ndarray, owners: np.ndarray, weight, acc: dict
                ) -> None:
    """acc[k][slot] += Σ weight · values[k] over the band cells of each owner (``owners``:
    the sorted front cells of the widest band, ``owner``: the owner of each cell;
    ``weight``: per cell, or one number)."""
    slot = np.searchsorted(owners, owner)
    for k, v in values.items():
        acc[k] += np.bincount(slot, weights=weight * v, minlength=owners.size)


def _weighted(parts: list, area: float) -> LayerWork:
    """The LayerWork of one test from those of its bands (``parts``: LayerWork of the
    narrower band first), interpolated linearly between the two whose areas bracket
    ``area`` (the sum of the per-owner weighted areas: one weight for the whole test)."""
    wts = [0.0] * len(parts)
    if len(parts) == 1:
        wts[0] = 1.0
    else:
        areas = [t.area for t in parts]
        k = int(np.clip(np.searchsorted(areas, area) - 1, 0, len(parts) - 2))
        lo, hi = areas[k], areas[k + 1]
        th = (area - lo) / (hi - lo) if hi > lo else 0.0
        wts[k], wts[k + 1] = 1.0 - th, th
    obs = {k: sum(w * t.observables[k] for w, t in zip(wts, parts, strict=True))
           for k in parts[0].observables}
    return LayerWork(*(float(sum(w * t[i] for w, t in zip(wts, parts, strict=True)))
                       for i in range(4)), obs)


#: an elastic scene's band is a0 wide at every orientation (as a viscoelastic scene's) from
#: this many cells of a0 on; below it, the whole layers of :func:`band_weights`
#: (docs/theory.md, "The band is a0 wide at every orientation")
EXACT_WIDTH_MIN_CELLS = 2.0


def exact_width(op: SpectralOperator, a0: float) -> bool:
    """Whether the tests' band is a0 wide at every orientation of the front (the band within
    a0 and the next digital layers, interpolated per front cell): always in a viscoelastic
    scene, where a0 is physical; in an elastic one from :data:`EXACT_WIDTH_MIN_CELLS` cells
    of a0 on.  Measured (docs/theory.md): on the rough elastic case the whole layers, thinner
    than a0 on oblique fronts, moved the area by 2.1 % between 256² and 512² at a0 = 7.8 µm,
    the exact width by 0.01 %; at a0 of one cell the per-cell interpolation between one and
    two layers put the JKR sphere's radius 0.64 % apart on its loading and unloading
    branches, one layer 0.11 %."""
    cell = op.cell
    return bool(op.viscoelastic
                or a0 >= EXACT_WIDTH_MIN_CELLS * min(cell.hx, cell.hy) * (1 - 1e-9))


def _band_plan(op, b: Bands, a0: float, normal, exact: bool, levels: int):
    """The bands each test interpolates: [(reach, outer weights, inner weights), ...] with
    the reach of a band (m: the cells whose centre lies within it of the other side's
    centres; an int k: the cells of along_front.band_levels ≤ k, that array returned too,
    else None) and the weights packed over the outer and inner front cells.

    Where :func:`exact_width` (viscoelastic scenes; elastic ones with a0 of two cells or
    more): the bands of levels 0 (the cells within a0) to ``levels`` (one digital layer
    more each), with hat weights per front cell from their actual widths, so that the
    band is exactly a0 wide along the normal at every orientation of the front
    (along_front.layer_weights).  Otherwise (an elastic scene's a0 below two cells, where
    the edge is the sharp-crack edge fitted over the bands' actual widths): the whole
    layers of :func:`band_weights`, one weight each."""
    n_out, n_in = int(np.count_nonzero(b.outer_front)), int(np.count_nonzero(b.inner_front))
    if not exact:
        h = min(b.spacing)
        return [(m * h, np.full(n_out, wt), np.full(n_in, wt))
                for m, wt in band_weights(a0, *b.spacing)], None
    level = band_levels(b, a0, levels)  # uint8: an eighth of an N² array
    lam = layer_weights(b, a0, normal)
    return [(k, *(np.maximum(0.0, 1.0 - np.abs(x - k)) for x in lam))
            for k in range(levels + 1)], level


def _side_tests(test, plan, band, own, dist, io, level, tol, dg, area, shape, key):
    """The closing (``test`` = _Tester.close) or opening tests of one colour's band cells
    ``band`` (flat bool) on one side of the front: each band of ``plan`` ([(reach, weights
    packed over the side's front cells ``io``)], :func:`_band_plan`, with its ``level``
    array) that some front cell needs is tested, and its per-cell works summed per owner
    with the cells' weights.
    ``shape``: the grid's; ``key``: (colour, side) of the tests' warm starts.  Returns
    (owners, the sums dL, dg, area per owner, the interpolated LayerWork, runs [(reach,
    cells, weights, the test's third output: a·p on the closed band, the opened band's gaps,
    the band's warm-start key)])."""
    owners = np.unique(own[band])
    acc = {k: np.zeros(owners.size) for k in ("dL", "dg", "area")}
    parts, runs = [], []
    for k, (reach, wo) in enumerate(plan):
        wo = wo[np.searchsorted(io, owners)]
        if not wo.any():  # no front cell needs this band (axis-aligned, a0/h whole)
            continue
        sel = band & (dist <= reach + tol if level is None else level.ravel() <= reach)
        cells, dL, extra, layer = test(sel.reshape(shape), key + (k,))
        wt = wo[np.searchsorted(owners, own[cells])]
        parts.append(layer)
        runs.append((reach, cells, wt, extra, key + (k,)))
        _owner_sums({"dL": dL, "dg": _dg_area(dg, area, cells),
                     "area": np.full(cells.size, area)}, own[cells], owners, wt, acc)
    return owners, acc, _weighted(parts, float(acc["area"].sum())), runs


def _store_balance(F, balances) -> tuple:
    """F = δL/(Δγ a) − 1 on the owners of each test of ``balances`` ([(owners, their sums)])
    whose band has a Δγ·area; returns W = Δγ a on them, packed (sorted flat cells, values:
    the weights of along_front.front_average, no N² array)."""
    cells, vals = [np.zeros(0, np.intp)], [np.zeros(0)]
    for owners, acc in balances:
        has = acc["dg"] > 0
        F.ravel()[owners[has]] = acc["dL"][has] / acc["dg"][has] - 1.0
        cells.append(owners[has])
        vals.append(acc["dg"][has])
    cells, vals = np.concatenate(cells), np.concatenate(vals)
    order = np.argsort(cells, kind="stable")
    return cells[order], vals[order]


class _Tester:
    """The closing and opening tests of one state: the solves and per-cell works of
    :func:`front_tests` (one instance per call)."""

    def __init__(self, op, w, mask, p, u, dg, rtol, observables, starts=None):
        self.op, self.w, self.mask, self.p, self.u = op, w, mask, p, u
        self.dg, self.rtol, self.observables = dg, rtol, observables  # rtol: the band solves'
        self.starts = starts  # band_starts.BandStarts of the adhesive solve, or None
        self.area = op.cell.cell_area
        self.solves, self.ok, self.msg = 0, True, "converged"

    def observe(self, q):
        """Σ q f of each observable (:func:`spectralbem.observables.observe`), and the mean
        pressure (key ``mean_pressure``)."""
        out = observe(self.observables, q)
        out["mean_pressure"] = float(q.mean())
        return out

    def solve(self, mask, key=None):
        st = self.starts if key is not None else None
        res = solve_masked(self.op, mask, self.w, x0=self.p, rtol=self.rtol,
                           x0_add=None if st is None else st.start(key))
        if st is not None and res.converged:
            st.keep(key, res.field, self.p)
        self.solves += 1
        self.ok &= res.converged
        if not res.converged:
            self.msg = res.message
        return res.field

    def close(self, D, key=None):
        """Close the band D at fixed Δ: per-cell δL_j = ½ g_j(A) t_j(A ∪ D) a (Eq. 8, t = −p),
        a·p_j(A ∪ D) on the band (what the adjoint split of δL_P weighs,
        ``adjoint.complete_adjoint``) and the layer's :class:`LayerWork` from Eqs. (8)-(10) with
        the actual fields."""
        a, p, u, w = self.area, self.p, self.u, self.w
        pp = self.solve(self.mask | D, key)
        cells = np.flatnonzero(D)
        apD = a * pp.ravel()[cells]
        dL = -0.5 * (u.ravel()[cells] - w.ravel()[cells]) * apD
        up = self.op.apply(pp)
        dU = 0.5 * a * (np.vdot(pp, up) - np.vdot(p, u))
        dLP = 0.5 * a * (np.vdot(up, p) - np.vdot(u, pp))
        layer = LayerWork(float(dL.sum()), float(dU), float(dLP), float(cells.size * a),
                          self.observe(pp))
        return cells, dL, apD, layer

    def open(self, R, key=None):
        """Open the band R at fixed Δ: δL_j = ½ g_j(A ∖ R) t_j(A) a, the gap of each opened
        cell and the layer's :class:`LayerWork`."""
        a, p, u, w = self.area, self.p, self.u, self.w
        if (self.mask & ~R).any():
            pr = self.solve(self.mask & ~R, key)
            ur = self.op.apply(pr)
        else:  # the band is the whole contact: opening it detaches (no stress left)
            pr, ur = np.zeros_like(p), np.zeros_like(u)
        cells = np.flatnonzero(R)
        gr = ur.ravel()[cells] - w.ravel()[cells]
        dL = -0.5 * a * gr * p.ravel()[cells]
        dU = 0.5 * a * (np.vdot(p, u) - np.vdot(pr, ur))
        dLP = 0.5 * a * (np.vdot(u, pr) - np.vdot(ur, p))
        layer = LayerWork(float(dL.sum()), float(dU), float(dLP), float(cells.size * a),
                          self.observe(pr))
        return cells, dL, gr, layer


def front_tests(op: SpectralOperator, w: np.ndarray, mask: np.ndarray, p: np.ndarray,
                dgamma, a0: float, *, rtol: float = 1e-10, vhat=(1.0, 0.0),
                observables: dict | None = None, front_smoothing: float | None = None,
                smoothing_per_radius: float = SMOOTHING_PER_RADIUS,
                u: np.ndarray | None = None, adjoint: bool = True,
                band_rtol: float | None = None, starts: BandStarts | None = None,
                exact: bool | None = None) -> FrontTest:
    """Closing and opening tests of every front cell at fixed Δ (Eqs. 3, 8-10 on bands).

    The band is exactly ``a0`` wide for any a0/h ≥ 1: the works (and every integrated
    quantity) of two bands are interpolated linearly in the width (:func:`_band_plan`):
    the band within a0 and the bands one or more digital layers wider, with weights per
    front cell,
    so that the band is a0 wide along the normal at every orientation (:func:`exact_width`:
    viscoelastic scenes, elastic ones from two cells of a0), else the whole layers of
    :func:`band_weights`.  ``w`` is the
    displacement prescribed in contact, ``p`` the solution on ``mask``, ``u`` its
    displacement C p if the caller has it.  ``observables``: name -> field f, a scalar or a
    :class:`~spectralbem.observables.ProfileSlope`; the sums Σ p f of each test state are
    recorded (in ``closing``/``opening`` entries' fifth item) so that integrated
    quantities can be interpolated to the sub-cell front — by the tests at the state's
    tolerance only (an intermediate state's tests at ``band_rtol`` record none).
    ``front_smoothing``: σ of the average along the front in units of a0 (None: the
    default of the scene's kind, :func:`default_smoothing`), raised to
    ``smoothing_per_radius`` times the front radius of large patches (:func:`patch_sigmas`).
    ``adjoint``: split δL_P over the closing bands' cells now (G_close, dLP_rate, dLP_cells;
    one transposed solve in a viscoelastic scene); False leaves it to
    ``adjoint.complete_adjoint`` — the balance itself (F) never needs it, only the outputs of
    the final state do.  ``band_rtol``: the band states' solve tolerance (None: ``rtol``;
    :func:`loose_band_rtol` for an intermediate state whose tests only move the front).
    ``starts``: the adhesive solve's :class:`~spectralbem.band_starts.BandStarts` (each band
    solve starts from p plus that band's correction at the last test; None: from p).
    """
    cell = op.cell
    area = cell.cell_area
    dg = np.asarray(dgamma, dtype=float)
    hmin = min(cell.hx, cell.hy)
    exact = exact_width(op, a0) if exact is None else exact
    levels = band_levels_needed(a0, cell.hx, cell.hy, mask.shape) if exact else 0
    b = bands(mask, cell.hx, cell.hy, a0,
              reach=bands_reach(a0, cell.hx, cell.hy, mask.shape, levels) if exact else None)
    if u is None:
        u = op.apply(p)
    if starts is not None:
        starts.begin(mask | b.outer_band)
    # only a test at the state's tolerance can be the final state's, whose outputs read
    # the observables: an intermediate state's loose tests skip them
    final = band_rtol is None or band_rtol <= rtol
    tester = _Tester(op, w, mask, p, u, dg, rtol if band_rtol is None else band_rtol,
                     (observables or {}) if final else {}, starts)
    ib = np.flatnonzero(b.inner_band)
    g_band = np.full(ib.size, np.nan)
    force_close = np.zeros(mask.shape, bool)
    closing, opening = {}, {}
    balances = []  # (owners, their sums) of each side's tests, packed until the solves end
    pending = {"w": w, "close": [], "open": []}  # what the adjoint split needs
    normal = b.normal  # two N² arrays: for the colours and the plan, again after the solves
    b.outer_normal(normal)  # kept packed for the interpolations to the sub-cell front
    cols = colours(b, vhat, op.viscoelastic, normal)
    sigma = _sigma_cells(default_smoothing(front_smoothing, op.viscoelastic), a0, hmin,
                         mask.shape)
    plan, level = _band_plan(op, b, a0, normal, exact, levels)
    del normal  # not held while the band solves run (the peak of a front test)
    io_out, io_in = np.flatnonzero(b.outer_front), np.flatnonzero(b.inner_front)
    own, own_i = b.outer_owner.ravel(), b.inner_owner.ravel()
    d_out, d_in = b.outer_dist.ravel(), b.inner_dist.ravel()
    tol = 1e-9 * hmin
    for ci, col in enumerate(cols):
        col_flat = col.ravel()
        band = (own >= 0) & col_flat[np.maximum(own, 0)]
        if band.any() and (mask.ravel() | (band & (d_out <= b.step_reach + tol))).all():
            # the band is the whole remaining gap: closing it is full contact, where the
            # half-space gauge leaves no solution at an arbitrary Δ; a gap narrower than the
            # band closes (the outer loop then reports full_contact)
            force_close.ravel()[np.unique(own[band])] = True
        elif band.any():
            owners, acc, closing[ci], runs = _side_tests(
                tester.close, [(r, wo) for r, wo, _ in plan], band, own, d_out, io_out,
                level, tol, dg, area, mask.shape, (ci, "close"))
            has = acc["dg"] > 0
            balances.append((owners, acc))
            pending["close"].append((owners[has], [(c, wt, apD) for _, c, wt, apD, _ in runs],
                                     acc["dg"][has], acc["area"][has]))
        band = (own_i >= 0) & col_flat[np.maximum(own_i, 0)]
        if band.any():
            owners, acc, opening[ci], runs = _side_tests(
                tester.open, [(r, wi) for r, _, wi in plan], band, own_i, d_in, io_in,
                level, tol, dg, area, mask.shape, (ci, "open"))
            for _, cells, _, gr, _ in runs:
                slot = np.searchsorted(ib, cells)
                # levels: the narrowest band's gaps kept where wider ones are tested too;
                # whole layers: the widest band's gaps last
                fresh = np.isnan(g_band[slot]) | (level is None)
                g_band[slot[fresh]] = gr[fresh]
            has = acc["dg"] > 0
            balances.append((owners, acc))
            pending["open"].append((owners[has], [(c, wt, key) for _, c, wt, _, key in runs],
                                    acc["area"][has]))
    del plan, level
    # one array per quantity: the outer (closing) and inner (opening) front cells are
    # disjoint; the widths first, then the balance, so that the two never meet the N² arrays
    # of the other (the peak of a front test's end)
    band_area = np.zeros(mask.shape)  # each front cell's band area (widths interpolated)
    for owners, acc in balances:
        band_area.ravel()[owners] = acc["area"]
    normal = b.normal
    width = band_widths(b, band_area, normal, sigma, a0)  # in place of band_area
    del band_area
    F = np.full(mask.shape, np.nan)
    W = _store_balance(F, balances)  # Δγ·area of each owner's band, packed
    del balances
    # ratio of sums along the front: each front cell weighs by its band's Δγ·area, so that
    # owners of unequal band patches (staircase corners) do not bias the local balance
    F = front_average(b, F, W, sigma, smoothing_per_radius, normal)  # in place
    del normal, W
    F[force_close] = -np.inf
    out = FrontTest(F, g_band, closing, opening, cols, b, tester.solves, bool(tester.ok),
                    tester.msg, width, pending=pending,
                    smoothing=(sigma, smoothing_per_radius))
    return complete_adjoint(out, op, mask, p, rtol, starts) if adjoint else out


def _mirror(field_: np.ndarray, valid: np.ndarray, cells: np.ndarray, owners: np.ndarray,
            normal, shift: float, spacing) -> np.ndarray:
    """``field_`` at the points x_c + shift·n̂(owner) of the cells ``cells`` (flat), by
    bilinear interpolation over the ``valid`` cells only (periodic): Σ w f / Σ w over the
    valid corners (nan where none is valid)."""
    nx_, ny_ = normal
    shape = field_.shape
    i, j = np.divmod(cells, shape[1])
    ci = i + shift * nx_.ravel()[owners] / spacing[0]
    cj = j + shift * ny_.ravel()[owners] / spacing[1]
    v = valid.astype(float)
    num = ndimage.map_coordinates(np.where(valid, field_, 0.0), [ci, cj], order=1,
                                  mode="grid-wrap")
    den = ndimage.map_coordinates(v, [ci, cj], order=1, mode="grid-wrap")
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 1e-12, num / np.maximum(den, 1e-300), np.nan)


def predictor_tests(op: SpectralOperator, w: np.ndarray, mask: np.ndarray, p: np.ndarray,
                    dgamma, a0: float, *, u: np.ndarray | None = None,
                    front_smoothing: float | None = None,
                    smoothing_per_radius: float = SMOOTHING_PER_RADIUS) -> FrontTest:
    """The zero-extra-solve predictor of docs/derivations.md §10 (modified VCCT): the closing and
    opening balances of :func:`front_tests` with the post-perturbation fields replaced by the
    current ones translated by a0 along the front normal (the tip field assumed to move
    rigidly): a closing-band cell gets the pressure found a0 inside it, δL_j = −½ a g_j(A)
    p(x_j − a0 n̂); an opening-band cell gets the gap found a0 outside it.  With one layer
    this is ½ t_i g_j a of the inner neighbour.  Error ≈ 4.7 h/a in δL (docs/derivations.md §10):
    use it to bring the front near balance, then the exact tests.  No solves; the energy
    split (δU, δL_P, G_close) is not available (nan).  ``front_smoothing`` as in
    :func:`front_tests`.
    """
    cell = op.cell
    area = cell.cell_area
    hmin = min(cell.hx, cell.hy)
    dg = np.asarray(dgamma, dtype=float)
    b = bands(mask, cell.hx, cell.hy, a0)
    if u is None:
        u = op.apply(p)
    g = u - w
    normal = b.normal
    # one array per quantity: the outer (closing) and inner (opening) front cells are disjoint
    F = np.full(mask.shape, np.nan)
    W = np.zeros(mask.shape)
    g_band = np.zeros(0)

    cells = np.flatnonzero(b.outer_band)
    if cells.size:
        own = b.outer_owner.ravel()[cells]
        p_plus = _mirror(p, mask, cells, own, normal, -a0, b.spacing)
        dL = -0.5 * area * g.ravel()[cells] * np.nan_to_num(p_plus)
        _balance(dL, cells, own, _dg_area(dg, area, cells), F, W)
    cells = np.flatnonzero(b.inner_band)
    if cells.size:
        own = b.inner_owner.ravel()[cells]
        g_minus = _mirror(g, ~mask, cells, own, normal, a0, b.spacing)
        g_band = g_minus
        dL = -0.5 * area * np.nan_to_num(g_minus) * p.ravel()[cells]
        _balance(dL, cells, own, _dg_area(dg, area, cells), F, W)
    sigma = _sigma_cells(default_smoothing(front_smoothing, op.viscoelastic), a0, hmin,
                         mask.shape)
    F = front_average(b, F, W, sigma, smoothing_per_radius)
    return FrontTest(F, g_band, {}, {}, [np.ones(mask.shape, bool)],
                     b, 0, True, "predictor (no solves)")
