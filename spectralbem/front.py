"""The balanced sub-cell front of an adhesive state: its offsets from the mask edge
(:func:`sub_cell_offset`, :func:`band_crack_offset`, :func:`sharp_crack_offset`), its
patches (:func:`patch_labels`, :func:`resolved_front`), the residual of its balance
(:func:`balance_residual`) and the outputs integrated over it.

The mask of :func:`spectralbem.adhesive.solve_adhesive` holds the front to the nearest cell
boundary; the balanced edge of each outer front cell lies ``offset_out`` beyond it (m).  The
quantities below are integrals over that sub-cell front, on the resolved patches only
(patches smaller than a disc of radius a0 are counted, not averaged):

* the contact area: the mask's area plus Σ offset·ds over the outer front of the resolved
  patches (an unresolved patch counts with its mask);
* the front length Σ ds, with ds = 1/max(|n_x|/h_y, |n_y|/h_x) the length of front each
  outer front cell stands for (a digital disc's outer front cells sum to its perimeter
  within 0.5 % at 50-150 cells of radius);
* the energy release rate at the balanced edge, G = Δγ − δL_P/δA (Eqs. 3, 6: there
  δL = Δγ δA), with δL_P/δA of the closing band (Eq. 10, adjoint attribution);
* G1 and G2: front-length averages of G over the trailing (v̂·n < 0) and leading
  (v̂·n ≥ 0) parts of the crack tips, the front cells not next to an edge held by contact
  (a compressive edge has no crack tip and no release rate); in an elastic scene one
  average for both; G and μ_a are taken over the same crack-tip cells;
* μ_a = −Σ (G − Δγ)(n·v̂) ds / W for a uniform Δγ (the uniform part closes to zero around
  every closed front, ∮ n ds = 0), −Σ G (n·v̂) ds / W for a Δγ map; W the normal force;
* a front whose every edge is held by contact (the surfaces would interpenetrate if it
  opened: a compressive, adhesiveless edge, as Δγ → 0) has no crack tip: G1 = G2 = μ_a = 0.
"""

from __future__ import annotations

import numpy as np

from .friction import sliding_direction
from .keys import LOAD_TOL

__all__ = ["front_outputs", "sub_cell_area", "release_rates", "patch_labels",
           "small_patch_diameter"]


def front_length_weights(normal, hx: float, hy: float) -> np.ndarray:
    """ds (m) of each outer front cell of a digital front with unit normal (nx, ny)."""
    nx, ny = normal
    return 1.0 / np.maximum(np.maximum(np.abs(nx) / hy, np.abs(ny) / hx), 1e-300)


def at_front(tests, offset_out, base: dict, a0: float) -> dict:
    """Integrated quantities of the state whose edge is the balanced sub-cell front: each
    colour's part of the front moves by its length-weighted mean outward offset toward the
    state with its closing band closed, and by its mean inward offset toward the state with
    its opening band opened (both at the same Δ), to first order in offset/a0: by the share
    Σ s ds / (band area) of the band the sub-cell front covers.  ``base``:
    the mask state's values (names of the tests' observables, e.g. ``mean_pressure``);
    ``offset_out``: nan on front cells that must not move (unresolved patches)."""
    b = tests.bands
    io = np.flatnonzero(b.outer_front)  # on the outer front cells only (packed)
    ds = front_length_weights(b.outer_normal(), *b.spacing)
    # only a tested interval is interpolated: offsets beyond ±a0 (extrapolations of a front
    # far from balance) and untested cells (nan, ±inf) count as ±a0 and 0
    s = np.asarray(offset_out, float).ravel()[io]
    s = np.clip(np.where(np.isfinite(s), s, 0.0), -a0, a0)
    out = dict(base)
    for ci, col in enumerate(tests.colour_map):
        sel = col.ravel()[io]
        L = float(np.sum(ds[sel]))
        if L == 0.0:
            continue
        for test, part in ((tests.closing, np.maximum(s, 0.0)),
                           (tests.opening, np.maximum(-s, 0.0))):
            if ci in test:
                # the share of the band's area (a0 L on an axis-aligned front, less on
                # oblique ones: along_front.band_widths) that the sub-cell front covers
                frac = float(np.sum(part[sel] * ds[sel])) / (test[ci].area or a0 * L)
                for k in base:
                    out[k] += frac * (test[ci].observables[k] - base[k])
    return out


def neighbour_mean(field_: np.ndarray, where: np.ndarray, at: np.ndarray) -> np.ndarray:
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


def mean_width(own, other, a0):
    """The mean of a front cell's band width and its neighbours' (a0 where neither is
    known, the known one where one is)."""
    w = np.where(np.isfinite(own) & np.isfinite(other), 0.5 * (own + other),
                 np.where(np.isfinite(own), own, other))
    return np.where(np.isfinite(w), w, a0)


def rate_at_edge(tests, offset_out, a0: float) -> np.ndarray:
    """δL_P/δA at the balanced sub-cell edge of each outer front cell (nan elsewhere): the
    closing band's rate, whose band starts at the mask edge x_b, and the opening band's (the
    mean over the inner neighbours), whose band starts at x_b − w, interpolated linearly to
    the edge x_b + s — the seed's convention, a band's value standing at its start (the
    1D method's G at l*), with w the bands' mean effective width, as in the offsets
    (moves.offsets).  Offsets beyond ±a0 count as ±a0 (front.at_front); the closing rate
    alone where the opening rate or the offset is unknown."""
    b = tests.bands
    rate = np.array(tests.dLP_rate, dtype=float)
    if tests.dLP_rate_in is None:
        return rate
    io = np.flatnonzero(b.outer_front)
    ro = neighbour_mean(tests.dLP_rate_in, b.inner_front, io)
    s = np.clip(offset_out.ravel()[io], -a0, a0)
    w = np.full(io.size, a0)
    if tests.width_out is not None:
        w = mean_width(tests.width_out.ravel()[io],
                       neighbour_mean(tests.width_in, b.inner_front, io), a0)
    rc = rate.ravel()[io]
    t = (w + s) / w  # 1 at the closing band's start, 0 at the opening band's
    rate.ravel()[io] = np.where(np.isfinite(ro) & np.isfinite(s), ro + (rc - ro) * t, rc)
    return rate


def release_rates(op, tests, where, dgamma, ds=None, offset_out=None, a0=None):
    """(G map, G1, G2): the energy release rate G = Δγ − δL_P/δA on the outer front cells
    ``where`` (nan elsewhere; Eqs. 3, 6, 10) and its front-length averages over the trailing
    and leading colours (one colour: the same average twice).  With the balanced edge's
    offsets ``offset_out`` (and ``a0``), δL_P/δA is that of the balanced sub-cell edge
    (:func:`rate_at_edge`), else the closing band's at the mask edge.  ``ds``: the
    front-length weights if the caller has them (:func:`front_length_weights`)."""
    cell = op.cell
    if ds is None:
        ds = front_length_weights(tests.bands.normal, cell.hx, cell.hy)
    dg = np.broadcast_to(np.asarray(dgamma, float), cell.shape)
    rate = (tests.dLP_rate if offset_out is None
            else rate_at_edge(tests, offset_out, a0))
    if rate is None:  # tests without the adjoint split (a state that did not balance)
        rate = np.full(cell.shape, np.nan)
    G = np.where(where & np.isfinite(rate), dg - rate, np.nan)
    ok = np.isfinite(G)
    avg = []
    for col in tests.colour_map:
        sel = ok & col
        avg.append(float(np.sum(G[sel] * ds[sel]) / np.sum(ds[sel])) if sel.any() else np.nan)
    if len(avg) == 1:
        avg *= 2
    return G, avg[0], avg[1]


def sub_cell_area(r, cell, ds=None) -> float:
    """The area (m²) inside the balanced sub-cell front of the adhesive result ``r`` (its
    last front test): the mask's area plus Σ offset·ds over the outer front cells of the
    resolved patches, each offset within ±a0 (an unresolved patch counts with its mask);
    ``ds``: the outer front cells' lengths (packed), computed when not given."""
    b = r.tests.bands
    io = np.flatnonzero(b.outer_front)
    if ds is None:
        ds = front_length_weights(b.outer_normal(), cell.hx, cell.hy)
    ok = b.outer_front & (r.resolved if r.resolved is not None else True)
    s = r.offset_out.ravel()[io]
    s = np.clip(np.where(ok.ravel()[io] & np.isfinite(s), s, 0.0), -r.a0, r.a0)
    return float(r.contact.sum() * cell.cell_area + np.sum(s * ds))


def front_outputs(op, r, dgamma) -> dict:
    """The sub-cell front's outputs of the adhesive result ``r`` (see the module docstring):
    area (m²), area_fraction, front_length (m), crack_tip_length (m: the part of the front
    that is a crack tip, over which G1, G2 and mu_adhesive are taken; the rest is held by
    contact), G1, G2 (J/m²), mu_adhesive, the G map on the outer front (nan elsewhere) and
    the number of unresolved patches.  Raises a ValueError for a state that is not
    `partial` (its final tests carry no release rates)."""
    cell = op.cell
    t = r.tests
    if t is None or t.dLP_rate is None:  # the adjoint split is solved for a partial state
        raise ValueError(f"front_outputs: the state's status is {r.status!r}; the front's "
                         f"outputs (release rates, μ_a) exist for a 'partial' state only")
    b = t.bands
    # on the outer front cells (packed: the normal of the tests, no N² normal is made)
    io = np.flatnonzero(b.outer_front)
    nx, ny = b.outer_normal()
    ds_p = front_length_weights((nx, ny), cell.hx, cell.hy)
    ds = np.zeros(cell.shape)  # the weights on the grid, where release_rates reads them
    ds.ravel()[io] = ds_p
    ok = b.outer_front & (r.resolved if r.resolved is not None else True)
    area = sub_cell_area(r, cell, ds_p)
    dg = np.broadcast_to(np.asarray(dgamma, float), cell.shape)
    edge = ok & np.isfinite(t.dLP_rate)
    length = float(np.sum(ds[edge]))
    if r.crack_tips is not None:  # edges held by contact are no crack tips
        ok &= r.crack_tips
    G, *G1G2 = release_rates(op, t, ok, dgamma, ds, r.offset_out, r.a0)
    ok &= np.isfinite(G)
    if r.crack_tips is not None:
        # a side (trailing, leading) whose every edge is held by contact has no crack tip:
        # G = 0 there, as at an adhesiveless edge (Γ → 0: both sides)
        cols = list(t.colour_map) * (2 if len(t.colour_map) == 1 else 1)
        G1G2 = [0.0 if (edge & col).any() and not (ok & col).any() else g
                for g, col in zip(G1G2, cols[:2], strict=True)]
    vhat = sliding_direction(op)
    nv = nx * vhat[0] + ny * vhat[1]
    Gp = G.ravel()[io]
    release = Gp - dg.ravel()[io] if np.ndim(dgamma) == 0 else Gp
    force = -float(np.sum(np.where(ok.ravel()[io], release * nv * ds_p, 0.0)))
    # the normal force the balanced front carries (μ's, and the prescribed one under load
    # control), not the mask's (they differ by the load correction, ~1 % on the rough SLS
    # case); no net force where it lies within the load tolerance of the mean |p|
    W = float(r.mean_pressure) * cell.Lx * cell.Ly
    small = abs(W) <= LOAD_TOL * float(np.abs(r.pressure).sum()) * cell.cell_area
    return dict(area=area, area_fraction=area / (cell.Lx * cell.Ly),
                front_length=length, crack_tip_length=float(np.sum(ds[ok])),
                G1=G1G2[0], G2=G1G2[1],
                mu_adhesive=np.nan if small else force / W,
                G_map=np.where(ok, G / dg, np.nan),
                unresolved_patches=r.unresolved_patches)


def sub_cell_offset(F_close, F_open, a0: float):
    """Offset of the balanced edge l* from the current edge x_b (length units), seed Eq. (3)
    with the band measured from the edge (viscoelastic scenes: a0 is physical).

    F is evaluated with the edge at x_b (closing test) and at x_b - a0 (opening test); on a
    stable branch it increases with the edge position, and l* follows by linear inter- or
    extrapolation.  Where F does not increase (an unstable configuration) the offset is +inf
    if closing is favourable, -inf if opening is, 0 otherwise.
    """
    Fc, Fo = np.asarray(F_close, float), np.asarray(F_open, float)
    slope = Fc - Fo
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(slope > 0, -a0 * Fc / slope, np.nan)
    unstable = ~(slope > 0) & ~np.isnan(slope)  # -inf: a forced closing (whole gap)
    s = np.where(unstable & (Fc < 0), np.inf, s)
    s = np.where(unstable & (Fc >= 0) & (Fo > 0), -np.inf, s)
    s = np.where(unstable & (Fc >= 0) & (Fo <= 0), 0.0, s)
    return s


def sharp_crack_offset(F_close, F_open, a0: float):
    """Offset from x_b of the sharp-crack edge G = Δγ of an elastic scene, where a0 is only
    numerical (docs/theory.md, "the sharp-crack edge").

    In an elastic solid the closing work of a band is the integral of G = K²/(2E*) over it,
    and the stress-intensity factor K, not G, is the smooth near-linear function of the edge
    position: G ∝ K² is quadratic in it, and a linear fit of G over a0 leaves an
    O((a0/R)²) edge error with a large coefficient (a JKR disc at zero load: area −7 % at
    a0 = 0.2 a; with K linear −1.8 %).  With k = K/K_c = u + v s/a0 (s from x_b,
    K_c² = 2E*Δγ) the band means of k² are g_c = 1 + F_close = u² + uv + v²/3 over
    [0, a0] and g_o = 1 + F_open = u² − uv + v²/3 over [−a0, 0], so
    u² = (m + √(m² − 4d²/3))/2 with m = (g_c + g_o)/2, d = (g_c − g_o)/2, v = d/u, and the
    edge k = 1 lies at s = a0 (1 − u)/v.  Exact when K is linear with |v| ≤ √3 u (K may
    change sign inside the opening band; the larger root is the one taken); the
    discriminant is clipped at 0 where no linear K fits the two means.  Where the band
    means are not non-negative and increasing outward (no tensile crack tip to fit), the
    linear fit of G with its midpoint shift a0/2 is used (:func:`sub_cell_offset`)."""
    Fc, Fo = np.asarray(F_close, float), np.asarray(F_open, float)
    u, d, fit = _linear_k(Fc, Fo)
    with np.errstate(divide="ignore", invalid="ignore"):
        s_k = a0 * (1.0 - u) * u / d
    return np.where(fit, s_k, sub_cell_offset(Fc, Fo, a0) + 0.5 * a0)


def _linear_k(Fc, Fo):
    """(u, d = u v, fit): k = u + v s/a0 whose band means of k² are 1 + F_close over
    [0, a0] and 1 + F_open over [−a0, 0] (:func:`sharp_crack_offset`), and where such a
    field fits (band means non-negative and increasing outward)."""
    gc, go = 1.0 + Fc, 1.0 + Fo
    m, d = 0.5 * (gc + go), 0.5 * (gc - go)
    with np.errstate(invalid="ignore"):  # m < 0 only where no field fits (fit False)
        u = np.sqrt(0.5 * (m + np.sqrt(np.maximum(m * m - 4.0 * d * d / 3.0, 0.0))))
    return u, d, (gc > go) & (go >= 0.0)


def band_crack_offset(F_close, F_open, a0: float):
    """Offset from x_b of the seed's balanced edge l* (Eq. (3): the band [l*, l* + a0]
    releases Δγ a0) fitted by a square-root field: where a viscoelastic mask moves.

    The band means g = 1 + F of the closing band [0, a0] and the opening band [−a0, 0] are
    fitted, as in :func:`sharp_crack_offset`, by the mean of k² with k = u + v s/a0 linear in
    the position (the release rate is quadratic in a stress-intensity factor that varies
    smoothly with the edge); l* is where the band mean over [l*, l* + a0] is 1:
    k(l*)² + k(l*) v + v²/3 = 1, k(l*) = (√(4 − v²/3) − v)/2, l* = a0 (k(l*) − u)/v.  At
    the balance it agrees with the linear fit (:func:`sub_cell_offset`); away from it the
    two differ at first order in the offset.  On the rough viscoelastic case a mask dilated
    by one cell (0.89 cell by area over front length) gets a mean offset of −1.18 cells from
    the linear fit and −0.99 from this one (docs/theory.md, "Where a viscoelastic mask
    moves"), so the mask follows this edge (and the linear one where that lies beyond the
    acceptance band); the reported edge and the balance stay the linear fit's, which the
    sinusoid validates against the 1D method.  Where no such field fits (band means not
    non-negative and increasing outward, or a field so steep that no band has mean 1,
    |v| ≥ 2√3) the linear fit is used."""
    Fc, Fo = np.asarray(F_close, float), np.asarray(F_open, float)
    u, d, fit = _linear_k(Fc, Fo)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = d / u
        k_edge = 0.5 * (np.sqrt(np.maximum(4.0 - v * v / 3.0, 0.0)) - v)
        s_k = a0 * (k_edge - u) / v
    # a field as steep as |v| ≥ 2√3 has no band of mean 1 (its least band mean is v²/12)
    fit &= (v * v < 12.0) & np.isfinite(s_k)
    return np.where(fit, s_k, sub_cell_offset(Fc, Fo, a0))


def patch_labels(mask: np.ndarray, a0: float, spacing, d_in: np.ndarray | None = None):
    """(labels, resolved per label): 4-connected contact patches (periodic images not
    merged) and whether each can hold a band of width a0 — some cell of it lies at least a0
    from the outside (a disc of radius ≥ a0, a strip of half-width ≥ a0); label 0: outside.
    ``d_in``: the distance of each cell of the mask to the outside if the caller has it
    (criterion.Bands.inner_dist, exact up to the widest band and beyond a0)."""
    from scipy import ndimage

    from .bands import _wrap_edt

    lab, n = ndimage.label(mask)
    if n == 0:
        return lab, np.zeros(1, bool)
    hmin = min(spacing)
    if d_in is None:
        d_in, _, _ = _wrap_edt(mask, spacing, int(np.ceil(a0 / hmin)) + 2, indices=False)
    ok = np.zeros(n + 1, bool)
    ok[lab[d_in >= a0 * (1 - 1e-9)]] = True  # the labels of the cells a0 deep or more
    ok[0] = False
    return lab, ok


def unresolved_patches(mask: np.ndarray, a0: float, spacing) -> int:
    """Number of contact patches too thin for a band of width a0 (:func:`patch_labels`):
    the band tests cannot resolve them (reported, excluded from the front outputs)."""
    lab, ok = patch_labels(mask, a0, spacing)
    return int(ok.size - 1 - ok[1:].sum())


#: share of the resolved contact area that lies in the "small" patches (small_patch_diameter)
SMALL_PATCH_SHARE = 0.1


def small_patch_diameter(mask: np.ndarray, a0: float, spacing) -> float:
    """Size of the small resolved contact patches: the equivalent diameter 2√(A/π) below
    which ``SMALL_PATCH_SHARE`` of the resolved patches' area lies (patches sorted by size;
    the smallest patch itself is barely wider than the band whenever a0 is near the cell,
    so the area-weighted tenth is the size that matters).  nan without a resolved patch."""
    lab, ok = patch_labels(mask, a0, spacing)
    area = np.bincount(lab.ravel(), minlength=ok.size)[1:] * float(spacing[0] * spacing[1])
    area = area[ok[1:]]
    if area.size == 0:
        return float("nan")
    area = np.sort(area)
    k = int(np.searchsorted(np.cumsum(area), SMALL_PATCH_SHARE * area.sum()))
    return float(2.0 * np.sqrt(area[min(k, area.size - 1)] / np.pi))


def resolved_front(mask, outer, inner, a0: float, spacing, d_in=None):
    """(outer, inner) front cells that belong to resolved patches (an outer front cell
    belongs to each patch it touches; resolved if one of them is); ``d_in`` as in
    :func:`patch_labels`."""
    lab, ok = patch_labels(mask, a0, spacing, d_in)
    return touching(mask & ok[lab]) & outer, inner & ok[lab]


def thin_features(mask: np.ndarray, a0: float, spacing) -> np.ndarray:
    """Cells of the contact or of the gap that no disc of radius a0 lying inside it covers
    (the complement of the morphological opening by that disc, on each side; periodic):
    tongues of the contact and notches of the gap narrower than 2 a0, and corners tighter
    than a0.  There the bands of width a0 of the two sides of the feature overlap, so the
    band tests do not resolve its edges (docs/theory.md, "Features narrower than a0")."""
    from .bands import _wrap_edt

    hmin = min(spacing)
    pad = int(np.ceil(2.0 * a0 / hmin)) + 2
    out = np.zeros(mask.shape, bool)
    for side in (mask, ~mask):
        d, _, _ = _wrap_edt(side, spacing, pad, indices=False)  # to the other side
        core = d >= a0 * (1 - 1e-9)  # the centres of the discs of radius a0 inside it
        if not core.any():
            out |= side
            continue
        dc, _, _ = _wrap_edt(~core, spacing, pad, indices=False)
        out |= side & (dc > a0 * (1 + 1e-9))
    return out


def unbalanced_cells(s_out, s_in, res_out, res_in, free_in, hmin, tol) -> np.ndarray:
    """The tested front cells (bool, N²) whose residual of :func:`balance_residual` exceeds
    ``tol`` cells (an untested one included)."""
    with np.errstate(invalid="ignore"):
        r_out = np.maximum(0.0, s_out - 0.5 * hmin) / hmin
        r_in = np.maximum(0.0, -s_in - 0.5 * hmin) / hmin
    bad_out = res_out & ~(r_out <= tol)  # nan (untested): unbalanced
    bad_in = res_in & free_in & ~(r_in <= tol)
    return bad_out | bad_in


def touching(m: np.ndarray) -> np.ndarray:
    """Cells with a 4-neighbour (periodic) in ``m``."""
    out = np.zeros_like(m)
    for ax in (0, 1):
        for sh in (1, -1):
            out |= np.roll(m, sh, axis=ax)
    return out


def balance_residual(s_out, s_in, res_out, res_in, free_in, hmin):
    """Residual of the balance in position, in cells, on the resolved front cells: how far
    the balanced edge lies beyond the half cell the mask edge stands for,
    max(0, |s| − h/2)/h (outward on outer cells, inward on inner cells that may open:
    ``free_in``).  Returns (max residual, the residuals of the tested front cells)."""
    r_out = np.maximum(0.0, s_out[res_out] - 0.5 * hmin) / hmin
    r_in = np.maximum(0.0, -s_in[res_in & free_in] - 0.5 * hmin) / hmin
    r = np.concatenate([r_out, r_in])
    r = np.where(np.isnan(r), np.inf, r)  # an untested front cell is not balanced
    return (float(r.max()) if r.size else 0.0), r


def bracketed(tests, add, remove, last_change):
    """Front cells whose band cells flip back this iteration (a 2-cycle: one state closes the
    cell, the next opens it): their balanced edge lies inside the flipping cell, so its
    position is that cell's centre to ± h/2 (residual 0 by :func:`balance_residual`)."""
    b = tests.bands
    out = np.zeros(add.shape, bool)
    back_add = np.flatnonzero(add & last_change)
    back_rem = np.flatnonzero(remove & last_change)
    out.ravel()[b.outer_owner.ravel()[back_add]] = True
    out.ravel()[b.inner_owner.ravel()[back_rem]] = True
    return out
