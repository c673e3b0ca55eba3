"""Averages along a contact front: the Gaussian average of the energy balance over the front
cells of one connected front (:func:`smooth_along_front`, with the per-patch σ of
:func:`patch_sigmas`) and the effective widths of the band tests (:func:`band_widths`),
used by :mod:`spectralbem.criterion` (docs/theory.md, "The 2D criterion and the sub-cell
front")."""

from __future__ import annotations

from functools import lru_cache
from math import gcd

import numpy as np
from scipy import ndimage

from . import kernels
from .bands import bands, bands_reach
from .front import front_length_weights

__all__ = ["band_widths", "layer_weights", "straight_front_weights", "band_levels",
           "band_levels_needed", "BAND_LEVELS",
           "patch_sigmas", "smooth_along_front", "front_average",
           "WIDTH_SMOOTHING", "WIDTH_RANGE", "FRONT_GRAPH", "STRAIGHT_FRONT_DENOMINATOR",
           "STRAIGHT_FRONT_CELLS"]

#: average along the front graph (True) or with a grid Gaussian restricted to front cells
FRONT_GRAPH = True
#: the effective band widths are averaged along the front over at least this many cells
WIDTH_SMOOTHING = 2.0
#: ... and kept within these multiples of a0 (a front cell's band is a0 wide on a straight
#: axis-aligned front, 0.7-1 a0 on oblique digital fronts of an elastic scene: docs/theory.md)
WIDTH_RANGE = (0.5, 1.5)


def band_widths(b, area, normal, sigma: float, a0: float):
    """The effective width (m) of each front cell's closing (outer front cells) and opening
    (inner front cells) band, nan elsewhere: its area per front length ds
    (front.front_length_weights), averaged along the front over max(σ, WIDTH_SMOOTHING)
    cells.  ``area``: each front cell's band area (N², both sides in one array), overwritten
    by the result (the largest transient of a front test is one N² array less).

    An elastic scene's band holds the cells whose centre lies within a0 of the other
    side's centres: on an axis-aligned front that is a0 of width, on an oblique digital
    front less (two diagonal layers, √2 h of width, at a0 = 2h and 45°); a viscoelastic
    scene's band (:func:`layer_weights`) is a0 wide wherever its two bands bracket a0.
    The sub-cell edge interpolates the band means over their actual widths
    (moves.offsets): with a0 in their place the offset is too large where the band is
    thinner, and the mask edge over-shoots its balanced edge (a JKR disc's estimated
    radius then falls by 0.12 h per cell of mask radius; with the widths by 0.02 h)."""
    fronts = (b.outer_front, b.inner_front)
    fidx = np.flatnonzero(fronts[0] | fronts[1])
    # ds on the front cells, packed (sorted flat cells, values): no N² array of it
    ds = (fidx, front_length_weights([n.ravel()[fidx] for n in normal], *b.spacing))
    sig = max(sigma, WIDTH_SMOOTHING)
    lo, hi = WIDTH_RANGE
    oks = [front & (area > 0) for front in fronts]
    # Σ K area / Σ K ds: the ratio area/ds averaged with the weights ds; the smoothing reads
    # only a side's own cells, so each side's result is written over its own front cells
    sel = (oks[0] | oks[1]).ravel()[fidx]
    area.ravel()[fidx[sel]] /= ds[1][sel]
    for ok, front in zip(oks, fronts, strict=True):
        smooth_along_front(area, ok, sig, ds, normal, out=area)
        area[front & ~ok] = np.nan
    area[~(fronts[0] | fronts[1])] = np.nan
    np.clip(area, lo * a0, hi * a0, out=area)  # nan stays nan
    return area


def band_levels(b, a0: float, top: int) -> np.ndarray:
    """The level of each band cell of ``b`` (uint8, N²): 0 for the cells within a0 of the
    other side, k ≤ ``top`` for those within the k-th reach of their front cell — the
    distance of the nearest band cell it owns beyond the (k − 1)-th (the 0-th: a0), one
    digital layer more along the normal each (h further on an axis-aligned front, 0.6-0.8 h
    at 45°, a few hundredths of h at some slopes p/q of large p, q) — so that the widths of
    the bands of levels ≤ k bracket a0 closely at every orientation
    (:func:`layer_weights`); ``top + 1`` for band cells beyond, 255 off the bands.  The
    k-th reach is at most that of bands.bands_reach with k levels (a front cell that owns
    no cell between the two reaches takes all of its cells within it), so that a cell's
    level does not depend on how far the bands of ``b`` reach."""
    hx, hy = b.spacing
    tol = 1e-9 * min(hx, hy)
    out = np.full(b.mask.shape, 255, np.uint8)
    flat = out.ravel()
    for owner, dist in ((b.outer_owner, b.outer_dist), (b.inner_owner, b.inner_dist)):
        own, d = owner.ravel(), dist.ravel()  # the two sides' owners are disjoint cells
        sel = np.flatnonzero(own >= 0)
        ds = d[sel]
        owners, o = np.unique(own[sel], return_inverse=True)  # o: each cell's owner's slot
        level = np.where(ds <= a0 + tol, 0, top + 1).astype(np.uint8)
        prev = np.full(owners.size, a0)  # the last reach of each front cell
        for k in range(1, top + 1):
            cap = bands_reach(a0, hx, hy, b.mask.shape, k)
            reach = np.full(owners.size, cap)
            beyond = (ds > prev[o] + tol) & (ds <= cap + tol)
            np.minimum.at(reach, o[beyond], ds[beyond])
            level[(level > k) & (ds <= reach[o] + tol)] = k
            prev = reach
        flat[sel] = level
    return out


def band_levels_needed(a0: float, hx: float, hy: float, shape) -> int:
    """The number of levels beyond a0 that the tests' bands must reach (at least one) for
    the band to be a0 wide at every orientation of :func:`straight_front_weights` (one below
    1.79 cells; two at some a0 from 1.79 cells on: 1.79-1.99, 2.13-2.23, 2.69-2.82,
    2.85-2.99, 3.14-3.16, 3.48-3.60, 3.80-3.99, … cells; three at some from 29 cells)."""
    _, lo, li = _table(a0, hx, hy, shape)
    return max(1, int(np.ceil(max(lo.max(), li.max()) - 1e-12)))


def _table(a0: float, hx: float, hy: float, shape) -> tuple:
    """:func:`straight_front_weights` of a grid's cells: the key rounded relatively (a0/hx
    and hy/hx of any size keep 12 digits, far inside the table's 1e-9 h of tolerance); a
    strip (one cell across) has fronts along its axis only."""
    return straight_front_weights(float(f"{a0 / hx:.12g}"), float(f"{hy / hx:.12g}"),
                                  min(shape) > 1)


def layer_weights(b, a0: float, normal) -> tuple:
    """(outer, inner): the level coordinate λ ∈ [0, :data:`BAND_LEVELS`] of the band on each
    outer and inner front cell (packed, in the flat order of ``b.outer_front``,
    ``b.inner_front``): the band of levels ≤ k (:func:`band_levels`) weighs
    max(0, 1 − |λ − k|), so that λ = k + θ interpolates the bands of levels k and k + 1
    with the weights 1 − θ and θ: the band of the front advanced by a0 along its normal,
    with the lattice's orientation deficit removed.

    A band of reach r holds the cells whose centre lies within r of the other side's
    centres: on an axis-aligned front ⌊r/h⌋ h wide, on an oblique digital front less (at
    45°, r = 2h holds two diagonal layers, √2 h wide; r = 3h four, 2√2 h).  λ makes the
    interpolated band exactly a0 wide on the straight digital front of the front cell's
    normal (:func:`straight_front_weights`, interpolated in the normal's angle); no
    curvature enters it, so on a curved front the band keeps the area of the continuous
    front's advance, a0 (1 ± κa0/2) per length (wider on the convex side, narrower on the
    concave one), as a band of the cells within a0 does as h → 0.  On an axis-aligned front
    with a0 = (m + θ) h this is the whole-layer weight θ of bands.band_split."""
    phi_t, th_out, th_in = _table(a0, *b.spacing, b.mask.shape)
    out = []
    for front, th in ((b.outer_front, th_out), (b.inner_front, th_in)):
        phi = np.arctan2(np.abs(normal[1][front]), np.abs(normal[0][front]))
        out.append(np.clip(np.interp(phi, phi_t, th), 0.0, BAND_LEVELS))
    return tuple(out)


#: the straight digital fronts of :func:`straight_front_weights` run at the slopes p/q of
#: cells with coprime 0 ≤ p, q ≤ this (93 orientations, 0.6-4.8° apart)
STRAIGHT_FRONT_DENOMINATOR = 12
#: ... on periodic grids of at most this many cells (all 93 up to a0 ≈ 65 cells; the two
#: axes at any a0)
STRAIGHT_FRONT_CELLS = 2**20
#: the most levels beyond a0 a band interpolates (:func:`band_levels`; at a0 = 68 cells
#: the table's λ reaches 3.09)
BAND_LEVELS = 4


@lru_cache(maxsize=16)
def straight_front_weights(a0_cells: float, aspect: float, oblique: bool = True) -> tuple:
    """(φ, λ_outer, λ_inner), sorted by φ: for straight digital fronts whose normal makes
    the angle φ ∈ [0, π/2] with the x axis (in metres: φ = atan2(|n_y|, |n_x|)), the level
    coordinate λ = k + θ (:func:`layer_weights`) whose interpolation (1 − θ) w_k + θ w_k+1
    of the widths of the bands of levels ≤ k and ≤ k + 1 (:func:`band_levels`) is a0 on the
    closing (outer) and opening (inner) side.  The widths are areas per front length over
    whole periods of periodic stripes ((i p − j q) mod M < M/2 on a (M/gcd(M, p)) ×
    (M/gcd(M, q)) cell grid, every offset of the digital line once), cells of hx = 1 and hy
    = ``aspect`` with a0 = ``a0_cells`` hx, the bands reaching :data:`BAND_LEVELS` layers
    beyond a0 (bands.bands_reach).  λ ≤ 1 at every orientation below a0 = 1.79 cells; at
    some a0 beyond, some slopes add only a few cells per layer and need more; λ =
    :data:`BAND_LEVELS` where even those do not reach a0.  Oblique orientations whose grid
    would exceed :data:`STRAIGHT_FRONT_CELLS` cells are left out (a0 beyond about 65
    cells), and all of them without ``oblique`` (a strip); the axes never are, so that a
    band of any a0 has a table.  The arrays are read-only (cached)."""
    hx, hy = 1.0, float(aspect)
    hmin = min(hx, hy)
    a0 = float(a0_cells) * hx
    tol = 1e-9 * hmin
    qmax = STRAIGHT_FRONT_DENOMINATOR
    pairs = [(0, 1), (1, 0)] + [(p, q) for p in range(1, qmax + 1)
                                for q in range(1, qmax + 1) if oblique and gcd(p, q) == 1]
    rows = []
    for p, q in pairs:
        grad = np.hypot(p / hx, q / hy)  # |∇s| of s = i p − j q (per metre)
        # stripes 2 (a0 + (BAND_LEVELS + 3) h_n) wide, h_n = hx |n_x| + hy |n_y| the cell's
        # thickness along the normal, at least a layer's spacing: each edge owns its bands
        need = int(np.ceil(4 * (a0 * grad + (BAND_LEVELS + 3) * (p + q))))
        M = p * q * int(np.ceil(need / (p * q))) if p and q else max(need, 4)
        nx = M // gcd(M, p) if p else 4
        ny = M // gcd(M, q) if q else 4
        if nx * ny > STRAIGHT_FRONT_CELLS:
            if p and q:
                continue  # a0 of tens of cells: this orientation is left to the interpolation
            # an axis: its layers lie h apart along the normal, the band within a0 holds
            # ⌊a0/h⌋ of them (what the stripe gives, without its grid)
            rows.append((np.arctan2(q / hy, p / hx), *[_axis_coordinate(
                a0, hx if p else hy, tol)] * 2))
            continue
        i, j = np.indices((nx, ny))
        mask = np.mod(i * p - j * q, M) < M // 2
        b = bands(mask, hx, hy, a0,
                  reach=bands_reach(a0, hx, hy, mask.shape, levels=BAND_LEVELS))
        level = band_levels(b, a0, BAND_LEVELS)
        length = 2 * nx * ny * hx * hy * grad / M  # both edges of every stripe
        rows.append((np.arctan2(q / hy, p / hx),
                     *(_level_coordinate(level[owner >= 0], a0, hx * hy / length, tol)
                       for owner in (b.outer_owner, b.inner_owner))))
    rows.sort()
    out = tuple(np.array(c) for c in zip(*rows, strict=True))
    for c in out:
        c.flags.writeable = False
    return out


def _axis_coordinate(a0: float, h: float, tol: float) -> float:
    """λ of an axis-aligned straight front whose layers lie ``h`` apart."""
    return max(0.0, a0 / h - np.floor((a0 + tol) / h))


def _level_coordinate(level, a0: float, per_cell: float, tol: float) -> float:
    """λ of one side of a straight front: its band cells' levels ``level``, each cell
    ``per_cell`` of width."""
    widths = np.cumsum(np.bincount(level, minlength=BAND_LEVELS + 2)[:BAND_LEVELS + 1]
                       ) * per_cell
    # the first pair of levels that brackets a0 (the last pair where none does)
    k = next((k for k in range(BAND_LEVELS - 1) if widths[k + 1] >= a0 - tol),
             BAND_LEVELS - 1)
    lo, hi = widths[k], widths[k + 1]
    return k + ((a0 - lo) / (hi - lo) if hi > lo + tol else 0.0)


def _slots(cells: np.ndarray, idx: np.ndarray) -> tuple:
    """(slot, found): the position in the sorted flat cells ``cells`` of each of ``idx``, and
    whether it is listed there (slot is a valid index, 0, where it is not)."""
    if not cells.size:
        return np.zeros(idx.size, np.intp), np.zeros(idx.size, bool)
    slot = np.minimum(np.searchsorted(cells, idx), cells.size - 1)
    return slot, cells[slot] == idx


def patch_sigmas(mask, outer_front, inner_front, sigma: float, per_radius: float):
    """σ (cells) for the outer and inner front cells: σ_patch = max(σ, per_radius · r) with
    r = min(2A/P, P/2π) the front radius (cells) of the 4-connected contact patch the front
    cell belongs to (area A, perimeter P: the radius of a disc, small on a convoluted patch
    and on a short straight front); an outer front cell belongs to its neighbouring patch of
    largest σ.  Returns (σ, σ) when every front cell gets σ, else for each side a dict
    {"cells": flat indices of its front cells, "sigma": their σ}."""
    if per_radius <= 0:
        return sigma, sigma
    lab, n = ndimage.label(mask)
    if n == 0:
        return sigma, sigma
    area = np.bincount(lab.ravel(), minlength=n + 1)
    perimeter = np.bincount(lab[inner_front], minlength=n + 1)
    # front radius: 2A/P and P/2π are both the radius for a disc (P counted in inner front
    # cells, 0.89·2πr on a digital disc); 2A/P is small for a convoluted (rough,
    # percolating) patch of any area, P/2π for a short straight front (a y-invariant strip,
    # where σ does not matter and a large one would only cost time)
    r = np.minimum(2 * 0.89 * area / np.maximum(perimeter, 1), perimeter / (2 * np.pi * 0.89))
    sig = np.maximum(sigma, per_radius * r)
    sig[0] = sigma
    if not np.any(sig[1:] > sigma):
        return sigma, sigma
    nx, ny = mask.shape
    io = np.flatnonzero(outer_front)
    i, j = np.divmod(io, ny)
    lab_f = lab.ravel()
    best = np.zeros(io.size, lab.dtype)
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        k = lab_f[((i + di) % nx) * ny + (j + dj) % ny]
        best = np.where(sig[k] > sig[best], k, best)
    ii = np.flatnonzero(inner_front)
    return ({"cells": io, "sigma": sig[best]}, {"cells": ii, "sigma": sig[lab_f[ii]]})


def smooth_along_front(F: np.ndarray, front: np.ndarray, sigma,
                       weights: np.ndarray | None = None, normal=None,
                       out: np.ndarray | None = None) -> np.ndarray:
    """Gaussian average of F over the front cells only (σ in cells).

    On a pixelated curved front the per-cell layer work scatters by ±30 % around the local
    release rate (measured on a JKR disc: the layer means bracket the analytic G, the cells
    do not); averaging along the front removes the staircase noise.  A straight grid-aligned
    front is unchanged (all its cells carry the same value per edge).  ``sigma``: a number,
    or per-cell values from :func:`patch_sigmas` (each group of front cells with the same σ
    is averaged over itself only).  With the front's unit ``normal`` the average runs along
    the front itself (:func:`_smooth_on_front_graph`: never across a gap, a neck or to another
    patch); without it, a Gaussian over the grid restricted to front cells.  ``weights``: an
    N² array or packed, (sorted flat cells, values).  ``out`` (with ``normal``): the array
    whose ``front`` cells receive the average (nan where there is none), which may be F
    itself; the other cells are left as they are.
    """
    if normal is not None and (isinstance(sigma, dict) or sigma > 0):
        return _smooth_on_front_graph(F, front, sigma, weights, normal, out)
    if isinstance(weights, tuple):  # packed (cells, values): the grid average reads N²
        full = np.zeros(F.shape)
        full.ravel()[weights[0]] = weights[1]
        weights = full
    if isinstance(sigma, dict):
        res = np.full(F.shape, np.nan)
        for s_ in np.unique(sigma["sigma"]):
            sel = np.zeros(F.shape, bool)
            sel.ravel()[sigma["cells"][sigma["sigma"] == s_]] = True
            part = smooth_along_front(F, front & sel, float(s_), weights, normal)
            res[sel] = part[sel]
    elif sigma <= 0:
        res = F
    else:
        ok = front & np.isfinite(F)
        wt = np.where(ok, 1.0 if weights is None else weights, 0.0)
        res = np.where(ok, F, 0.0)
        res *= wt
        ndimage.gaussian_filter(res, sigma, mode="wrap", output=res)  # in place
        ndimage.gaussian_filter(wt, sigma, mode="wrap", output=wt)
        sel = ok & (wt > 0)
        res[sel] /= wt[sel]
        res[~sel] = np.nan
    if out is None:
        return res
    out[front] = res[front]
    return out


def _at(values, idx) -> np.ndarray:
    """``values`` at the flat cells ``idx``: an N² array, or packed as (sorted flat cells,
    values), 0 at cells it does not list."""
    if not isinstance(values, tuple):
        return values.ravel()[idx].astype(float)
    cells, v = values
    slot, found = _slots(cells, idx)
    return np.where(found, v[slot], 0.0) if cells.size else np.zeros(idx.size)


def _smooth_on_front_graph(F, front, sigma, weights, normal, out=None) -> np.ndarray:
    """Weighted average of F along the front graph: the front cells (finite F, and a σ)
    joined to their 8-neighbours on the front whose normals agree (n_i·n_j > 0, so the two
    sides of a neck or of a narrow gap stay apart) and whose σ is the same; the kernel is
    the lazy walk ½(I + D⁻¹ Adj) applied 2σ² times, a Gaussian of σ cells along a straight
    front (variance ½ cell² a step).  A ratio of sums: Σ K w F / Σ K w.  ``sigma``: a
    number, or the groups of :func:`patch_sigmas` ({"cells": sorted flat indices, "sigma":
    their σ}), each group of one σ walking on its own; cells of σ ≤ 0 keep F.  The result
    goes to ``out``'s front cells (a new array of nan elsewhere when None; ``out`` may be F:
    F is read before it is written).  The walk's matrix and the walk are compiled
    (:func:`spectralbem.kernels.front_graph`, :func:`spectralbem.kernels.front_walk`)."""
    shape = F.shape
    fidx = np.flatnonzero(front)
    idx = fidx[np.isfinite(F.ravel()[fidx])]
    if isinstance(sigma, dict):  # the packed groups: no N² array of σ
        slot, has = _slots(sigma["cells"], idx)
        idx, sig = idx[has], np.asarray(sigma["sigma"], float)[slot[has]]
    else:
        sig = np.full(idx.size, float(sigma))
    n = idx.size
    indptr, indices, data = kernels.front_graph(idx, shape, normal[0].ravel()[idx],
                                                normal[1].ravel()[idx], sig)
    w = np.ones(n) if weights is None else _at(weights, idx)
    Fi = F.ravel()[idx]
    num, den = w * Fi, w.copy()
    steps = np.rint(2 * np.maximum(sig, 0.0) ** 2).astype(np.int64)
    kernels.front_walk(indptr, indices, data, steps, num, den)
    good = den > 0
    val = np.where(good, num / np.where(good, den, 1.0), np.nan)
    keep = sig <= 0
    val[keep] = Fi[keep]
    if out is None:
        out = np.full(shape, np.nan)
    else:
        out.ravel()[fidx] = np.nan
    out.ravel()[idx] = val
    return out


def front_average(b, F, W, sigma: float, per_radius: float, normal=None):
    """A per-owner ratio F = Σ num / Σ den of the front tests (the balance, δL_P/δA) on the
    closing (outer front cells of ``F``) and opening (inner front cells) sides averaged
    along their fronts as a ratio of sums, each front cell weighing by its band's ``W``
    (Δγ·area, or area), with the per-patch σ (cells) of :func:`patch_sigmas`; in place of
    ``F``, nan off the front (each side's average reads its own cells only).

    The ratio of sums matters on curved digital fronts: the owners of a band (the nearest
    front cell of each band cell) are unequal — a staircase corner owns a fan reaching a0
    deep, the cells of a flat run only shallow rows — so the per-owner ratios of a
    quantity that varies across the band scatter and their plain mean is biased, the more
    the more cells a0 spans (docs/theory.md, "Release rates along the front")."""
    sig_out, sig_in = patch_sigmas(b.mask, b.outer_front, b.inner_front, sigma, per_radius)
    if not FRONT_GRAPH:
        normal = None
    elif normal is None:
        normal = b.normal
    for front, sig in ((b.outer_front, sig_out), (b.inner_front, sig_in)):
        smooth_along_front(F, front, sig, W, normal, out=F)  # each side reads its own cells
    F[~(b.outer_front | b.inner_front)] = np.nan
    return F
