"""Where the balanced edge lies when the mask of an adhesive solve flips back and forth
between two states (a 2-cycle): the bracket of the edge between the two masks
(docs/theory.md, "Convergence").

A front cell whose band cells flip back (the last move closed them, this test opens them,
or the other way round) has its balanced edge between the two masks.  Where the last move
was one cell deep there, the edge lies inside the flipping cell (:func:`front.bracketed`:
its offset clipped to ± h/2, residual 0).  Where it went deeper (D cells along the normal:
the viscoelastic mask moves by the square-root fit's edge, several cells at a time at a
wide a0), a clip would accept an edge up to D − ½ cells away; instead the two masks' own
linear offsets s_p (the last mask's, from its edge) and s_c (this mask's) place the edge by
the secant through them: a fraction |s_c| / (|s_p| + |s_c|) of D back from this mask's
edge, exact when the offset is linear in the mask's position, whatever its slope (a slope
below −1, each mask's estimate over-responding to its own position, is what makes the
mask flip).  That edge is the one the residual measures and the outputs read, and the
mask moves to it: only the flipped cells beyond it move back.  Where one of the two offsets
lies beyond the whole band (±inf, a snap: no position to draw a secant through) the
bracket is bisected: the edge is placed half way, D/2 back from this mask's edge, the mask
moves back to it, and until a bracket one cell deep is left the cell is not balanced (its
residual is that of the bracket's far end, D − ½ cells: where inside the bracket the edge
lies is not known).  Where the two offsets do not change sign the one-cell clip stays
(such a flip comes from the viscoelastic mover's square-root fit; the linear offset of this
mask then says balanced or beyond its edge, where the residual does not read an inner
cell's offset).
"""

from __future__ import annotations

import numpy as np

from .front import bracketed

__all__ = ["flip_memory", "kept", "bracket_offsets", "place", "far_ends", "snap_cells",
           "across", "DEEP_MOVE"]

#: a flipping cell's last move counts as deeper than one cell beyond this many cells along
#: the normal (one layer at a staircase corner is √2 cells)
DEEP_MOVE = 1.5


def flip_memory(tests, add, remove, s_out, s_in):
    """What the next test needs of this move to place a bracketed edge: the moved cells
    (flat, sorted), their front cell's offset in this test (m) and their distance from this
    mask (m: the bands' distance, h for the first layer)."""
    b = tests.bands
    ca, cr = np.flatnonzero(add), np.flatnonzero(remove)
    cells = np.concatenate([ca, cr])
    s = np.concatenate([s_out.ravel()[b.outer_owner.ravel()[ca]],
                        s_in.ravel()[b.inner_owner.ravel()[cr]]])
    d = np.concatenate([b.outer_dist.ravel()[ca], b.inner_dist.ravel()[cr]])
    order = np.argsort(cells, kind="stable")
    return cells[order], s[order], d[order]


def kept(memory, moved):
    """``memory`` (:func:`flip_memory`) restricted to the cells that did move (``moved``:
    bool, N²); None without memory."""
    if memory is None:
        return None
    cells, s, d = memory
    on = moved.ravel()[cells]
    return cells[on], s[on], d[on]


def _secant(s_p, s_c, depth):
    """The edge's offset from this mask (m) by the secant through the two masks' offsets
    (module docstring), half way (``depth``/2, toward the last mask) where they change sign
    and one is not finite (a snap); nan where they do not change sign.  Returns (offsets,
    snap: bool)."""
    a_p, a_c = np.abs(s_p), np.abs(s_c)
    change = np.sign(s_p) * np.sign(s_c) < 0
    finite = np.isfinite(s_p) & np.isfinite(s_c)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(finite, a_c / (a_p + a_c), 0.5)
    x = np.sign(s_c) * t * depth
    return np.where(change, x, np.nan), change & ~finite


def bracket_offsets(tests, add, remove, last_change, memory, s_out, s_in, hmin):
    """The bracketed front cells of this test (``add``, ``remove``: its moves; ``memory``:
    :func:`flip_memory` of the last move, None if unknown): (one-deep, deep) where
    ``one-deep`` (bool, N²) marks the front cells whose edge is taken inside their flipping
    cell (clipped to ± h/2 by the caller: a last move one cell deep, or a deeper one whose
    offsets do not change sign) and ``deep`` lists [(outer side, front cells, offsets (m),
    snap: bool)] of the cells whose last move went deeper, their edge placed by the secant,
    or half way where it bisects a snap (:func:`far_ends`)."""
    one = bracketed(tests, add, remove, last_change)
    if memory is None or memory[0].size == 0:
        return one, []
    cells, s_p, d_p = memory
    b = tests.bands
    deep = []
    for outer, back, owner, dist, s in (
            (True, add & last_change, b.outer_owner, b.outer_dist, s_out),
            (False, remove & last_change, b.inner_owner, b.inner_dist, s_in)):
        c = np.flatnonzero(back)
        pos = np.minimum(np.searchsorted(cells, c), cells.size - 1)
        c, pos = c[cells[pos] == c], pos[cells[pos] == c]
        depth = d_p[pos] + dist.ravel()[c] - hmin  # the last move's depth along the normal
        far = depth > DEEP_MOVE * hmin
        if not far.any():
            continue
        c, pos, depth = c[far], pos[far], depth[far]
        own = owner.ravel()[c]
        x, snap = _secant(s_p[pos], s.ravel()[own], depth)
        owners, slot = np.unique(own, return_inverse=True)
        # the deepest flipping cell of each front cell places its edge
        best = np.full(owners.size, -1.0)
        np.maximum.at(best, slot, depth)
        pick = depth >= best[slot] * (1 - 1e-12)
        n = np.bincount(slot[pick], minlength=owners.size)
        xs = np.bincount(slot[pick], weights=np.nan_to_num(x[pick]), minlength=owners.size)
        bad = np.bincount(slot[pick], weights=np.isnan(x[pick]), minlength=owners.size) > 0
        snapped = np.bincount(slot[pick], weights=snap[pick], minlength=owners.size) > 0
        vals = np.where(bad, np.nan, xs / np.maximum(n, 1))
        placed = np.isfinite(vals)  # the others keep the one-cell clip
        one.ravel()[owners[placed]] = False
        deep.append((outer, owners[placed], vals[placed], snapped[placed]))
    return one, deep


def place(deep, s_out, s_in) -> None:
    """Set the secant offsets of ``deep`` (:func:`bracket_offsets`) on ``s_out``, ``s_in``
    in place."""
    for outer, owners, x, _ in deep:
        (s_out if outer else s_in).ravel()[owners] = x


def far_ends(deep, s_out, s_in, residual):
    """``residual()`` evaluated with the bisected snaps of ``deep`` at their bracket's far
    end (twice the half-way offset: the last mask's edge), their placed offsets restored
    after it: where inside a snap's bracket the edge lies is not known, so the residual
    takes the farthest it may be."""
    snaps = [(s_out if outer else s_in, owners[snap], x[snap])
             for outer, owners, x, snap in deep if snap.any()]
    for arr, owners, x in snaps:
        arr.ravel()[owners] = 2.0 * x
    try:
        return residual()
    finally:
        for arr, owners, x in snaps:
            arr.ravel()[owners] = x


def snap_cells(tests, deep):
    """The band cells (bool, N²) whose front cell's snap ``deep`` bisects, or None: the
    move back to the half-way edge is the bisection's step, made whatever the rescue of an
    oscillating front holds back (``moves``' ``wide``: a half-way edge on a cell boundary
    lies within its extra reach, and the bracket would never shrink)."""
    snaps = [(outer, owners[snap]) for outer, owners, _, snap in deep if snap.any()]
    if not snaps:
        return None
    b = tests.bands
    out = np.zeros(b.outer_owner.shape, bool)
    for outer, owners in snaps:
        owner = b.outer_owner if outer else b.inner_owner
        out |= np.isin(owner, owners)
    return out


def _neighbours(cells: np.ndarray, shape) -> tuple:
    """The 4-neighbours (periodic) of the flat ``cells``: (neighbour, index into ``cells``)."""
    i, j = np.divmod(cells, shape[1])
    nb = [((i + di) % shape[0]) * shape[1] + (j + dj) % shape[1]
          for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))]
    return np.concatenate(nb), np.tile(np.arange(cells.size), 4)


def across(s_out, s_in, outer, inner, one, deep, hmin) -> None:
    """The front cells across the front from a bracketed one (the outer front cells next to
    a bracketed inner cell, and the other way round) stand for the same edge, in place: an
    offset of theirs that puts the edge beyond the bracket, on the bracketed cell's side, is
    brought to its bound (the secant's edge of a deep bracket, the mean over the bracketed
    cells they touch; the far side of the flipping cell, h, of a one-deep one).  Only
    offsets the residual does not count are bounded (inward ones on outer cells, outward
    ones on inner cells): the outputs' edge, never the balance's verdict.  Packed: no N²
    array."""
    shape = one.shape
    for outer_side, arr, front in ((True, s_out, outer), (False, s_in, inner)):
        other = inner if outer_side else outer
        sign = -1.0 if outer_side else 1.0  # the bracketed side's direction
        cells = [np.flatnonzero(one & other)]
        vals = [np.full(cells[0].size, sign * hmin)]
        for side, owners, x, _ in deep:
            if side != outer_side:
                cells.append(owners)
                vals.append(x)
        cells, vals = np.concatenate(cells), np.concatenate(vals)
        if not cells.size:
            continue
        nb, k = _neighbours(cells, shape)
        on = front.ravel()[nb]
        nb, v = nb[on], vals[k[on]]
        if not nb.size:
            continue
        at, slot = np.unique(nb, return_inverse=True)
        bound = (np.bincount(slot, weights=v, minlength=at.size)
                 / np.bincount(slot, minlength=at.size))
        cur = arr.ravel()[at]
        hit = sign * (cur - bound) > 0
        arr.ravel()[at[hit]] = bound[hit]
