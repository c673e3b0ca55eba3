"""The edge of a 2-cycle between two masks (spectralbem.brackets): the secant through both
masks' offsets, and an adhesive state that ends on a cycle deeper than one cell."""

from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from spectralbem.bands import bands
from spectralbem.brackets import (
    _secant,
    bracket_offsets,
    far_ends,
    flip_memory,
    place,
    snap_cells,
)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.05, 0.95), st.floats(0.2, 5.0), st.integers(2, 6), st.booleans())
def test_secant_is_the_root_of_an_offset_linear_in_the_mask_position(frac, k, depth, out):
    """Offsets s(x) = k (x* − x) of masks whose edge stands at x, any slope k (an estimate
    that over-responds, k > 1, is what makes a mask cycle): from the last mask at x_p and
    this one at x_c = x_p ± D, the secant gives x* − x_c exactly (to round-off)."""
    xp = 0.0
    xc = depth if out else -depth
    xs = xp + frac * (xc - xp)  # the root lies between the two masks
    s_p, s_c = k * (xs - xp), k * (xs - xc)
    x, snap = _secant(np.array([s_p]), np.array([s_c]), float(depth))
    assert np.isclose(x[0], xs - xc, rtol=1e-12, atol=1e-12) and not snap[0]


def test_secant_of_offsets_that_bracket_nothing_or_lie_beyond_the_band():
    """No change of sign: nan (the caller keeps the one-cell bracket's clip); an offset
    beyond the whole band (±inf, a snap: no position to draw a secant through) with a change
    of sign: half way, toward the last mask, flagged as a snap to bisect."""
    got, snap = _secant(np.array([1.0, np.inf, 2.0, np.inf, -3.0, np.inf]),
                        np.array([0.5, -1.0, -np.inf, -np.inf, 1.0, np.inf]), 2.0)
    assert np.isnan(got[[0, 5]]).all()
    np.testing.assert_array_equal(got[1:4], [-1.0, -1.0, -1.0])
    assert got[4] == 2.0 * 1.0 / 4.0
    np.testing.assert_array_equal(snap, [False, True, True, True, False, False])


def _strip(edge: int, n: int = 40):
    """A y-invariant contact strip of cells 10 … edge on an n × 2 grid (h = 1)."""
    m = np.zeros((n, 2), bool)
    m[10:edge + 1] = True
    return m


def test_a_two_cell_cycle_places_the_edge_by_both_masks():
    """The last mask ends at cell 21 and its offset there says +2.87 h, its move added cells
    22 and 23; this mask (ending at 23) says −1.62 h and opens cell 23 again.  The edge is
    the secant's, 2 × 1.62/(2.87 + 1.62) = 0.72 h inside this mask's edge, on the inner
    front cell of the cycle only: a one-cell bracket is not reported as deep."""
    h, a0 = 1.0, 2.0
    last, this = _strip(21), _strip(23)
    b_last = bands(last, h, h, a0)
    s_out = np.where(b_last.outer_front, 2.874, np.nan)
    s_in = np.full(last.shape, np.nan)
    add = this & ~last
    memory = flip_memory(SimpleNamespace(bands=b_last), add, np.zeros_like(add), s_out, s_in)
    b = bands(this, h, h, a0)
    s_out = np.full(this.shape, np.nan)
    s_in = np.where(b.inner_front, -1.62, np.nan)
    remove = np.zeros_like(this)
    remove[23] = True
    one, deep = bracket_offsets(SimpleNamespace(bands=b), np.zeros_like(this), remove, add,
                                memory, s_out, s_in, h)
    assert not one.any()
    (outer, owners, x, snap), = deep
    assert not outer and not snap.any()
    np.testing.assert_array_equal(np.sort(owners), np.flatnonzero(b.inner_front & (
        np.arange(40)[:, None] == 23)))
    np.testing.assert_allclose(x, -2 * 1.62 / (2.874 + 1.62), rtol=1e-12)
    # the same flip after a move of one cell is the one-deep bracket (its cell's centre)
    last1 = _strip(22)
    b1 = bands(last1, h, h, a0)
    add1 = this & ~last1
    memory1 = flip_memory(SimpleNamespace(bands=b1), add1, np.zeros_like(add1),
                          np.where(b1.outer_front, 0.8, np.nan), np.full(this.shape, np.nan))
    one, deep = bracket_offsets(SimpleNamespace(bands=b), np.zeros_like(this), remove, add1,
                                memory1, s_out, s_in, h)
    assert deep == [] and one[23].all() and one.sum() == 2


def test_a_two_cell_snap_is_bisected_and_not_balanced_until_resolved():
    """The last mask (ending at cell 21) sent its edge beyond the whole band (+inf) and
    added cells 22 and 23; this mask's test sends it back beyond its band (−inf) and opens
    both.  No secant exists: the edge is placed half way, one cell inside this mask's edge
    (so that the move back opens cell 23 only, the nearest-centre rule), and the residual
    reads the bracket's far end, the last mask's edge two cells inside: 1.5 cells, beyond
    the default tolerance (a clip into the flipping cell read 0)."""
    from spectralbem.front import balance_residual
    from spectralbem.moves import moves

    h, a0 = 1.0, 2.0
    last, this = _strip(21), _strip(23)
    b_last = bands(last, h, h, a0)
    add = this & ~last
    memory = flip_memory(SimpleNamespace(bands=b_last), add, np.zeros_like(add),
                         np.where(b_last.outer_front, np.inf, np.nan),
                         np.full(last.shape, np.nan))
    b = bands(this, h, h, a0)
    tests = SimpleNamespace(bands=b, F=np.zeros(this.shape),  # every opened cell leaves a gap
                            g_band=np.ones(int(b.inner_band.sum())))
    s_out = np.full(this.shape, np.nan)
    s_in = np.where(b.inner_front, 0.0, np.nan)  # the strip's other edge balanced
    s_in[20:][b.inner_front[20:]] = -np.inf
    remove = this & ~last
    one, deep = bracket_offsets(tests, np.zeros_like(this), remove, add, memory, s_out, s_in,
                                h)
    (outer, owners, x, snap), = deep
    assert not outer and snap.all() and not one[22:24].any()
    np.testing.assert_allclose(x, -1.0)
    place(deep, s_out, s_in)
    top = b.inner_front & (np.arange(40)[:, None] == 23)
    res = np.zeros_like(this)
    rmax, r = far_ends(deep, s_out, s_in, lambda: balance_residual(
        s_out, s_in, res, top, np.ones_like(this), h))
    assert rmax == 1.5 and r.size == 2
    np.testing.assert_allclose(s_in[top], -1.0)  # the placed edge restored after it
    _, rem = moves(tests, this, s_out, s_in, np.zeros(this.shape), np.zeros_like(this), h)
    np.testing.assert_array_equal(np.flatnonzero(rem.any(axis=1)), [23])
    # after the rescue of an oscillating front (every cell ``wide``: it moves only beyond
    # the tolerance, 0.5 cells more) the half-way edge on the cell boundary would move
    # nothing; the bisection's step is made all the same
    wide = np.ones_like(this)
    held = moves(tests, this, s_out, s_in, np.zeros(this.shape), np.zeros_like(this), h,
                 wide, 0.5)[1]
    assert not held.any()
    free = snap_cells(tests, deep)
    np.testing.assert_array_equal(np.flatnonzero(free.any(axis=1)), [22, 23])
    _, rem = moves(tests, this, s_out, s_in, np.zeros(this.shape), np.zeros_like(this), h,
                   wide & ~free, 0.5)
    np.testing.assert_array_equal(np.flatnonzero(rem.any(axis=1)), [23])


def test_a_wide_band_state_reports_an_edge_within_its_tolerance():
    """The y-invariant seed sinusoid at ã0 = 0.2 with a0 = 16 cells (503 × 2, ζ = 0.256,
    β = 10): its leading edge ends on a 2-cycle between masks two cells apart (the mover's
    square-root fit steps 2 cells, the linear fits of the two masks disagree by 2 cells).
    The state is accepted only if the edge the two masks place lies within the tolerance:
    every resolved front cell's reported offset within (front_tol + ½) h of the mask edge
    (the former one-cell clip accepted it with the outer cell's offset at −1.52 h)."""
    import spectralbem.adhesive as ad
    from spectralbem.oned.branches import dimensionless_material
    from spectralbem.spectral import Cell, SpectralOperator

    mat, v = dimensionless_material(0.256, 10.0)
    nx = 503
    cell = Cell(2 * np.pi, 2 * np.pi * 2 / nx, nx, 2)
    X, _ = cell.coordinates()
    op = SpectralOperator(cell, mat, velocity=(v, 0.0))
    r = ad.solve_adhesive(op, np.cos(X), np.pi * 0.008, 0.2, mean_pressure=0.075)
    assert r.status == "partial"
    h = cell.hx
    for s, where in ((r.offset_out, r.resolved), (r.offset_in, None)):
        vals = s[np.isfinite(s)] if where is None else s[where & np.isfinite(s)]
        assert vals.size and np.abs(vals).max() <= (0.5 + 0.5) * h * (1 + 1e-9)
