"""Warm starts of the band solves (spectralbem.band_starts): the front tests of a moved mask
started from the last test's band corrections give the same balance in fewer Krylov
products."""

import numpy as np
import pytest

from spectralbem import criterion
from spectralbem.band_starts import BandStarts


def test_start_is_p_plus_the_last_correction_on_the_kept_cells():
    rng = np.random.default_rng(1)
    p, field = rng.normal(size=(8, 8)), rng.normal(size=(8, 8))
    cells = rng.random((8, 8)) < 0.5
    st = BandStarts()
    with pytest.raises(RuntimeError):
        st.keep("k", field, p)
    st.begin(cells)
    assert st.start("k", p) is p  # nothing kept yet: the state's pressure itself
    st.keep("k", field, p)
    st.begin(cells)  # the next test: the corrections kept become the starts
    x0 = st.start("k", p)
    # the correction in float32: p + (field − p) to float32's rounding of the correction
    np.testing.assert_allclose(x0[cells], field[cells], rtol=0, atol=1e-6)
    assert np.array_equal(x0[~cells], p[~cells])
    assert st.start("other", p) is p


@pytest.mark.parametrize("viscoelastic", [False, True])
def test_front_tests_of_a_moved_mask_same_balance_fewer_products(monkeypatch, viscoelastic):
    """JKR disc at 256² (25.6 cells of radius, a0 = 2 cells), the tests of the mask
    r < a_JKR, then of the same mask with a bump of 13 cells on its front (a local move, as
    the late outer iterations of a rough contact make): with the first test's band
    corrections as starts the second test's balance F is the same to 1e-7 (the band solves'
    tolerance is 1e-10); the viscoelastic band solves (GMRES) take fewer products, the
    elastic ones (CG, a decade per product here) about as many.  The saving grows with the
    front: 29 % (viscoelastic) and 16 % (elastic) on the 512² rough states of
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
