"""Materials: E(ω) in the seed's Fourier convention (docs/theory.md, units and signs)."""

import numpy as np
import pytest
from scipy.integrate import quad

from spectralbem.materials import (
    Elastic,
    MaterialError,
    Prony,
    StandardLinearSolid,
    Tabulated,
)

SLS = StandardLinearSolid(E0=2.0e6, Einf=2.0e7, tau=0.3, nu=0.45)
W = np.logspace(-4, 4, 41) / SLS.tau


def test_sls_limits_and_sign():
    E = SLS.modulus(np.array([0.0, 1e12]))
    assert E[0] == pytest.approx(SLS.E0, rel=1e-14)
    assert E[1].real == pytest.approx(SLS.Einf, rel=1e-6)  # 1/(ωτ)² tail at ωτ = 3e11
    # seed convention (e^{+iωt} kernel): passive material has Im E < 0, Im 1/E > 0 for ω > 0
    assert np.all(SLS.modulus(W).imag < 0)
    assert np.all(SLS.compliance(W).imag > 0)
    np.testing.assert_allclose(SLS.modulus(-W), np.conj(SLS.modulus(W)), rtol=1e-15)
    np.testing.assert_allclose(SLS.compliance(W) * SLS.modulus(W), 1.0, rtol=1e-14)


def test_sls_compliance_is_fourier_transform_of_creep_eq14():
    """1/E(ω) = J(0+) + ∫₀^∞ J̇(t) e^{iωt} dt, with J from seed Eq. (14) (independent quadrature)."""
    a = (1 / SLS.E0 - 1 / SLS.Einf) / SLS.tau  # J̇(t) = a e^{-t/τ} for t > 0, from Eq. (14)
    for w in (0.1, 1.0, 3.0, 30.0):
        re = quad(lambda t: a * np.exp(-t / SLS.tau), 0, np.inf, weight="cos", wvar=w)[0]
        im = quad(lambda t: a * np.exp(-t / SLS.tau), 0, np.inf, weight="sin", wvar=w)[0]
        expected = SLS.creep(0.0) + re + 1j * im
        # QAWF quadrature is accurate to ~1e-12 here; 1e-9 leaves margin
        np.testing.assert_allclose(SLS.compliance(w), expected, rtol=1e-9)


def test_sls_tan_delta_peak_physics_md():
    """tan δ = -Im E/Re E peaks at ωτ = √β with (β-1)/(2√β) (1.42302 for β = 10)."""
    m = StandardLinearSolid(1.0, 10.0, 1.0)
    w = np.logspace(-2, 3, 200001)
    E = m.modulus(w)
    tand = -E.imag / E.real
    i = np.argmax(tand)
    assert w[i] == pytest.approx(np.sqrt(10.0), rel=1e-3)  # grid spacing 6e-5 in log ω
    assert tand[i] == pytest.approx(1.42302, abs=1e-5)  # the closed form to 6 digits


def test_kramers_kronig_sum_rule():
    """(2/π) ∫₀^∞ Im(1/E(ω))/ω dω = 1/E0 - 1/E∞ (a Kramers–Kronig identity of a causal modulus)."""
    val = quad(lambda lw: np.imag(SLS.compliance(np.exp(lw))), -40, 40, limit=400)[0]
    assert 2 / np.pi * val == pytest.approx(1 / SLS.E0 - 1 / SLS.Einf, rel=1e-8)


def test_prony_one_branch_equals_sls():
    p = Prony(E_eq=SLS.E0, moduli=(SLS.Einf - SLS.E0,), times=(SLS.tau / SLS.beta,), nu=SLS.nu)
    np.testing.assert_allclose(p.modulus(W), SLS.modulus(W), rtol=1e-13)
    assert p.E0 == SLS.E0 and p.Einf == pytest.approx(SLS.Einf)


def test_prony_many_branches_passive():
    p = Prony(1e6, moduli=(1e6, 3e6, 1e7), times=(1e-3, 1e-1, 10.0))
    E = p.modulus(np.logspace(-5, 5, 50))
    assert np.all(E.imag < 0) and np.all(np.diff(E.real) > 0)
    assert p.Einf == pytest.approx(1.5e7)


def test_tabulated_reproduces_sls_loglog(tmp_path):
    w = np.logspace(-3, 3, 241) / SLS.tau
    E = SLS.modulus(w)
    path = tmp_path / "sls.csv"
    np.savetxt(path, np.c_[w, E.real, -E.imag], delimiter=",", header="omega,storage,loss",
               comments="")
    t = Tabulated.from_csv(path, nu=SLS.nu)
    wq = np.logspace(-2.5, 2.5, 37) / SLS.tau
    # log-log linear interpolation error of a smooth curve at 40 points/decade: < 1e-3 relative
    np.testing.assert_allclose(t.modulus(wq), SLS.modulus(wq), rtol=1e-3)
    assert t.modulus(np.array([0.0]))[0].imag == 0.0
    np.testing.assert_allclose(t.modulus(-wq), np.conj(t.modulus(wq)))
    # ω = 0, every mode that does not slide (q·v = 0), is the relaxed plateau: E0 of the SLS
    # to the table's 1e-3 (it was E' at 1 rad/s, 5 times E0 on a table spanning 1 rad/s)
    e0 = t.modulus(np.array([0.0]))[0]
    assert e0 == pytest.approx(t.storage[0], rel=1e-12) and e0.imag == 0.0
    assert e0 == pytest.approx(t.modulus(np.array([1e-9]))[0].real, rel=1e-12)
    assert abs(e0 / SLS.E0 - 1) < 1e-3


def test_tabulated_accepts_measurement_scatter(tmp_path):
    """A DMA table of the SLS with 0.5 % multiplicative noise on E' and E'' (its storage
    then dips by up to ~1.4 % between neighbouring rows) is read, and its modulus is the
    SLS's to within the noise (2 % at 40 points a decade)."""
    rng = np.random.default_rng(1)
    w = np.logspace(-3, 3, 241) / SLS.tau
    E = SLS.modulus(w)
    noise = 1 + 0.005 * rng.standard_normal((2, w.size))
    s, loss = E.real * noise[0], -E.imag * noise[1]
    assert np.any(np.diff(s) < 0)  # the strict test would have refused it
    t = Tabulated(tuple(w), tuple(s), tuple(loss), nu=SLS.nu)
    np.testing.assert_allclose(t.modulus(w[1:-1]), E[1:-1], rtol=0.02)


@pytest.mark.parametrize(
    "make, words",
    [
        (lambda: Elastic(E=-1.0), ["E", "-1.0", "> 0"]),
        (lambda: Elastic(E=1.0, nu=0.6), ["nu", "0.6", "(-1, 0.5]"]),
        (lambda: Elastic(E=1.0, nu=-1.0), ["nu", "-1.0"]),
        (lambda: StandardLinearSolid(E0=2.0, Einf=1.0, tau=1.0), ["Einf", "E0"]),
        (lambda: StandardLinearSolid(E0=1.0, Einf=2.0, tau=0.0), ["tau", "0.0"]),
        (lambda: StandardLinearSolid(E0=np.nan, Einf=2.0, tau=1.0), ["E0", "nan"]),
        (lambda: Prony(1.0, moduli=(1.0, 2.0), times=(1.0,)), ["moduli", "times"]),
        (lambda: Tabulated((1.0, 0.5, 2.0), (1, 2, 3), (0, 0, 0)), ["omega", "increasing"]),
        (lambda: Tabulated((1.0, 2.0, 3.0), (3, 2, 4), (0, 0, 0)),
         ["storage", "decreases at row 2", "33.3% lower", "up to 2% is accepted"]),
        (lambda: Tabulated((1.0, 2.0, 3.0), (1, 2, 3), (0, -1, 0)), ["loss", "causal"]),
    ],
)
def test_invalid_parameters_are_named(make, words):
    with pytest.raises(MaterialError) as exc:
        make()
    for w in words:
        assert w in str(exc.value)
