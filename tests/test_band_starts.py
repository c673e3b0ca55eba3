"""Warm starts of the band solves (spectralbem.band_starts): the front tests of a moved mask
started from the last test's band corrections give the same balance in fewer Krylov
products."""

import numpy as np
import pytest

from spectralbem import criterion
from spectralbem.band_starts import BandStarts


def test_start_is_the_last_correction_of_each_band_on_its_cells():
    """BandStarts keeps the latest correction of each key in float32 on the cells of the
    test that made it, and masked.solve_masked adds it to the start on the mask's cells."""
    from spectralbem.masked import solve_masked
    from spectralbem.materials import Elastic
    from spectralbem.spectral import Cell, SpectralOperator

    rng = np.random.default_rng(1)
    p, field, field2 = (rng.normal(size=(16, 16)) for _ in range(3))
    cells = rng.random((16, 16)) < 0.5
    st = BandStarts()
    with pytest.raises(RuntimeError):
        st.keep("k", field, p)
    st.begin(cells)
    assert st.start("k") is None  # nothing kept yet: the state's pressure alone
    st.keep("k", field, p)
    idx, vals = st.start("k")
    assert np.array_equal(idx, np.flatnonzero(cells)) and vals.dtype == np.float32
    # float32: the correction to its rounding (|field − p| < 10 here)
    np.testing.assert_allclose(vals, (field - p)[cells], rtol=0, atol=1e-5)
    st.begin(~cells)  # the next test: another set of cells; "k" still refers to the old one
    assert np.array_equal(st.start("k")[0], np.flatnonzero(cells))
    st.keep("k", field2, p)  # replaced: the old cells are dropped
    assert np.array_equal(st.start("k")[0], np.flatnonzero(~cells))
    assert len(st._cells) == 1
    # the start of a masked solve is x0 plus the correction on the mask's cells: from the
    # exact solution minus a correction, with the correction added, the start is exact
    op = SpectralOperator(Cell(1.0, 1.0, 16, 16), Elastic(1.0, 0.0))
    mask = rng.random((16, 16)) < 0.6
    w = rng.normal(size=(16, 16))
    exact = solve_masked(op, mask, w, rtol=1e-13).field
    cidx = np.flatnonzero(~cells)
    cval = rng.normal(size=cidx.size).astype(np.float32)
    x0 = exact.copy()
    x0.ravel()[cidx] -= cval
    res = solve_masked(op, mask, w, x0=x0, rtol=1e-10, x0_add=(cidx, cval))
    assert res.converged and res.iterations <= 2, res.iterations  # the checks of the start
    assert solve_masked(op, mask, w, x0=x0, rtol=1e-10).iterations > 5  # without it


@pytest.mark.parametrize("viscoelastic", [False, True])
def test_front_tests_of_a_moved_mask_same_balance_fewer_products(monkeypatch, viscoelastic):
    """JKR disc at 256² (25.6 cells of radius, a0 = 2 cells), the tests of the mask
    r < a_JKR, then of the same mask with a bump of 13 cells on its front (a local move, as
    the late outer iterations of a rough contact make): with the first test's band
    corrections as starts the second test's balance F is the same to 1e-7 (the band solves'
    tolerance is 1e-10); the viscoelastic band solves (GMRES) take fewer products, the
    elastic ones (CG, a decade per product here) about as many.  The saving grows with the
    front: 33 % (viscoelastic) and 22 % (elastic) on the 512² rough states of
    docs/rough_convergence.md (docs/performance.md).  (A whole front moved by half a cell
    gains nothing: every band's correction changes.)"""
    from spectralbem import reference as ref
    from spectralbem.masked import solve_masked
    from spectralbem.materials import StandardLinearSolid
    from spectralbem.spectral import SpectralOperator
    from spectralbem.validate import W_JKR, jkr_cell

    cell, op, h, r, w = jkr_cell(256, W_JKR)
    if viscoelastic:
        op = SpectralOperator(cell, StandardLinearSolid(1.0, 10.0, 1.0, 0.0),
                              velocity=(0.02 * cell.Lx, 0.0))
    aJ = ref.jkr_radius(0.0, 1.0, 1.0, w)
    wv = h - h.max() + ref.jkr_penetration(aJ, 1.0, 1.0, w)
    products = []
    real = criterion.solve_masked

    def counted(*a, **k):
        res = real(*a, **k)
        products.append(res.iterations)
        return res

    monkeypatch.setattr(criterion, "solve_masked", counted)
    out = {}
    for warm in (False, True):
        st = BandStarts() if warm else None
        X, Y = cell.coordinates()
        bump = np.hypot(X - (0.5 * cell.Lx + aJ), Y - 0.5 * cell.Ly) < 2.1 * cell.hx
        for mask in (r < aJ, (r < aJ) | bump):
            p = solve_masked(op, mask, wv, rtol=1e-10).field
            products.clear()
            t = criterion.front_tests(op, wv, mask, p, w, 2 * cell.hx, starts=st,
                                      adjoint=False)
        out[warm] = (t.F, sum(products))
    (F0, n0), (F1, n1) = out[False], out[True]
    ok = np.isfinite(F0)
    assert np.array_equal(ok, np.isfinite(F1)) and ok.any()
    np.testing.assert_allclose(F1[ok], F0[ok], rtol=0, atol=1e-7)
    if viscoelastic:  # GMRES: measured 148 products against 164
        assert n1 < 0.95 * n0, (n1, n0)
    else:  # CG gains less than a product per solve on this small front (51 against 50)
        assert n1 <= n0 + 2, (n1, n0)
