"""Thickness factors S(qd) of seed Eqs. (A.4), (A.5) against a 50-digit reference."""

import mpmath as mp
import numpy as np
import pytest

from spectralbem.layers import GluedLayer, LayerError, PressureLayer, s_glued, s_pressure

mp.mp.dps = 50
S_GRID = np.logspace(-8, 8, 97)


def ref_glued(s, nu):
    s, nu = mp.mpf(s), mp.mpf(nu)
    c = 3 - 4 * nu
    den = c * mp.cosh(2 * s) + 2 * s**2 - 4 * nu * (3 - 2 * nu) + 5
    return (c * mp.sinh(2 * s) - 2 * s) / den


def ref_pressure(s):
    s = mp.mpf(s)
    return (mp.sinh(2 * s) + 2 * s) / (mp.cosh(2 * s) - 2 * s**2 - 1)


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49, 0.5])
def test_glued_matches_high_precision(nu):
    got = s_glued(S_GRID, nu)
    ref = np.array([float(ref_glued(s, nu)) for s in S_GRID])
    # acceptance: relative error <= 1e-12 over qd in [1e-8, 1e8] (float64 forms reach ~1e-15)
    np.testing.assert_allclose(got, ref, rtol=1e-12)


def test_pressure_matches_high_precision():
    got = s_pressure(S_GRID)
    ref = np.array([float(ref_pressure(s)) for s in S_GRID])
    np.testing.assert_allclose(got, ref, rtol=1e-12)
    assert np.all(np.isfinite(got))


def test_limits_physics_md_section5():
    nu = 0.3
    s = np.array([1e-6])
    # A.4: S ≈ s(1-2ν)/(2(1-ν)²) — confined compression; q0 compliance d/M
    assert s_glued(s, nu)[0] == pytest.approx(s[0] * (1 - 2 * nu) / (2 * (1 - nu) ** 2), rel=1e-6)
    lay = GluedLayer(d=2.0)
    E = 3.0
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    assert lay.q0_compliance(E, nu) == pytest.approx(2.0 / M, rel=1e-14)
    assert GluedLayer(1.0).q0_compliance(E, 0.5) == 0.0  # incompressible confined layer
    # A.5: S = 6/s³ + 6/(5s) + O(s): plate bending
    assert s_pressure(s)[0] == pytest.approx(6 / s[0] ** 3 + 6 / (5 * s[0]), rel=1e-9)
    assert PressureLayer(1.0).q0_compliance(E, nu) is None
    # thick layers: S → 1 exponentially
    np.testing.assert_allclose(s_glued(np.array([40.0]), nu), 1.0, rtol=1e-14)
    np.testing.assert_allclose(s_pressure(np.array([40.0])), 1.0, rtol=1e-14)


@pytest.mark.parametrize("d", [0.0, -1.0, np.inf, np.nan])
def test_bad_thickness(d):
    with pytest.raises(LayerError, match="d = "):
        GluedLayer(d)
