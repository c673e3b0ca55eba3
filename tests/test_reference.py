"""Reference solutions and helpers: internal consistency against independent relations."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from spectralbem import conventions
from spectralbem import reference as ref
from spectralbem.materials import Elastic
from spectralbem.spectral import Cell, SpectralOperator
from spectralbem.surfaces import SurfaceError, from_npy


def test_westergaard_pressure_integrates_to_the_mean_load():
    lam, pstar = 2.0, 1.3
    for pt in (0.1, 0.5):
        a = ref.westergaard_a(pt) * lam / (2 * np.pi)
        mean = quad(ref.westergaard_pressure, -a, a, args=(a, lam, pstar), limit=200)[0] / lam
        assert mean == pytest.approx(pt * pstar, rel=1e-8)  # p̄ = p* sin²(ka/2)


def test_asymmetric_release_rate_at_johnson_equilibrium():
    G, pt = 0.008, 0.15
    a = ref.johnson_a(pt, G)
    G1, G2 = ref.johnson_G_asymmetric(a, 0.0, a, a, pt, G)
    assert G1 == pytest.approx(1.0, rel=1e-10) and G2 == pytest.approx(1.0, rel=1e-10)


def test_jkr_pulloff_and_penetration():
    R, Es, w = 1.0, 1.0, 1e-3
    r = minimize_scalar(lambda a: ref.jkr_load(a, R, Es, w), bounds=(1e-6, 1.0),
                        method="bounded", options={"xatol": 1e-12})
    assert r.fun == pytest.approx(ref.jkr_pulloff(R, w, "load"), rel=1e-8)
    # fixed grip: the load at the minimum of δ(a)
    r2 = minimize_scalar(lambda a: ref.jkr_penetration(a, R, Es, w), bounds=(1e-6, 1.0),
                         method="bounded", options={"xatol": 1e-12})
    assert ref.jkr_load(r2.x, R, Es, w) == pytest.approx(ref.jkr_pulloff(R, w, "grip"), rel=1e-6)
    assert ref.jkr_radius(0.0, R, Es, w) == pytest.approx((9 * np.pi * w * R**2 / 2) ** (1 / 3))


def test_elastic_energy_parseval(rng):
    cell = Cell(1.0, 0.7, 32, 24)
    op = SpectralOperator(cell, Elastic(2.0, 0.3))
    p = rng.standard_normal(cell.shape)
    direct = 0.5 * cell.cell_area * np.sum(p * op.apply(p))
    assert op.elastic_energy(p) == pytest.approx(direct, rel=1e-12)


def test_gamma_conversion_round_trip():
    g = conventions.gamma_from_dgamma(0.05, 2e6, 0.5, 1e4, 1e-5)
    assert conventions.dgamma_from_gamma(g, 2e6, 0.5, 1e4, 1e-5) == pytest.approx(0.05)
    assert conventions.p_star(2e6, 0.5, 1e4, 1e-5) == pytest.approx(2e6 / 0.75 * 1e4 * 1e-5 / 2)


def test_height_map_from_npy(tmp_path, rng):
    cell = Cell(1.0, 1.0, 16, 8)
    h = rng.standard_normal(cell.shape)
    np.save(tmp_path / "h.npy", h)
    np.testing.assert_array_equal(from_npy(tmp_path / "h.npy", cell), h)
    np.save(tmp_path / "bad.npy", h[:, :4])
    with pytest.raises(SurfaceError, match="shape"):
        from_npy(tmp_path / "bad.npy", cell)
    h[3, 2] = np.nan
    np.save(tmp_path / "nan.npy", h)
    with pytest.raises(SurfaceError, match="non-finite"):
        from_npy(tmp_path / "nan.npy", cell)
    (tmp_path / "trunc.npy").write_bytes(b"\x93NUMPY")
    with pytest.raises(SurfaceError, match="cannot read"):
        from_npy(tmp_path / "trunc.npy", cell)
