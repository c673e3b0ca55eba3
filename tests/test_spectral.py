"""Periodic cell and spectral operator: Ĉ(q) = 2(1-ν²)S(|q|d)/(E(q·v)|q|), exact real matrix."""

import numpy as np
import pytest
from scipy.integrate import quad

from spectralbem import fft
from spectralbem.layers import GluedLayer, PressureLayer
from spectralbem.materials import Elastic, StandardLinearSolid
from spectralbem.spectral import Cell, GridError, SpectralOperator

SLS = StandardLinearSolid(E0=1.0, Einf=10.0, tau=1.0, nu=0.4)


def cos_mode(cell, mx, my):
    X, Y = cell.coordinates()
    qx, qy = 2 * np.pi * mx / cell.Lx, 2 * np.pi * my / cell.Ly
    return qx, qy, qx * X + qy * Y


@pytest.mark.parametrize("shape", [(48, 30), (45, 7), (64, 64)])
@pytest.mark.parametrize("layer", [None, GluedLayer(0.3), PressureLayer(0.2)])
def test_single_mode_response_matches_formula(shape, layer):
    """p = cos(q·x) gives u = Re[Ĉ(q) e^{iq·x}], Ĉ from (A.3)/(A.8), any grid and v direction
    (the sampled kernel)."""
    cell = Cell(1.3, 0.7, *shape)
    v = (0.4, -0.25)
    op = SpectralOperator(cell, SLS, layer, velocity=v, delayed="sampled")
    for mx, my in [(1, 0), (3, 2), (-2, 1), (5, -3)]:
        qx, qy, phase = cos_mode(cell, mx, my)
        q = np.hypot(qx, qy)
        S = 1.0 if layer is None else layer.factor(np.array([q]), SLS.nu)[0]
        C = 2 * (1 - SLS.nu**2) * S * SLS.compliance(qx * v[0] + qy * v[1]) / q
        u = op.apply(np.cos(phase))
        np.testing.assert_allclose(u, np.real(C * np.exp(1j * phase)), atol=1e-13 * abs(C))


@pytest.mark.parametrize("layer", [None, GluedLayer(0.3), PressureLayer(0.2)])
@pytest.mark.parametrize("v", [(0.4, -0.25), (0.3, 0.0)])
def test_cell_kernel_single_mode_converges_at_second_order(layer, v):
    """The cell-averaged kernel's response to cos(q·x) tends to Re[Ĉ(q) e^{iq·x}] as
    O((qh)²) (the cell average of the delayed part; its images are O((qh)²) too): the error
    falls by 3.5-4.5× per halving of h, and stays below (|q| h)² |Ĉ(q)|."""
    errs = []
    for n in (32, 64, 128):
        cell = Cell(1.3, 0.7, n, n)
        op = SpectralOperator(cell, SLS, layer, velocity=v)
        qx, qy, phase = cos_mode(cell, 3, 2)
        q = np.hypot(qx, qy)
        S = 1.0 if layer is None else layer.factor(np.array([q]), SLS.nu)[0]
        C = 2 * (1 - SLS.nu**2) * S * SLS.compliance(qx * v[0] + qy * v[1]) / q
        err = np.abs(op.apply(np.cos(phase)) - np.real(C * np.exp(1j * phase))).max() / abs(C)
        assert err < (q * max(cell.hx, cell.hy)) ** 2
        errs.append(err)
    assert all(3.5 < a / b < 4.5 for a, b in zip(errs, errs[1:], strict=False)), errs


def test_seed_eq13_time_domain_kernel_sign():
    """The 1D kernel of seed Eq. (13) (x + vt, creep of Eq. 14), by quadrature, equals the operator.

    For σ = -cos(kx): u(x) = (2(1-ν²)/k)[J(0) cos kx + ∫₀^∞ J̇(t) cos(k(x+vt)) dt].
    """
    cell = Cell(2 * np.pi, 1.0, 64, 1)
    k, v = 1.0, 0.7
    op = SpectralOperator(cell, SLS, velocity=(v, 0.0), delayed="sampled")
    x = cell.x
    u = op.apply(np.cos(k * x)[:, None])[:, 0]
    a = (1 / SLS.E0 - 1 / SLS.Einf) / SLS.tau
    c = quad(lambda t: a * np.exp(-t / SLS.tau), 0, np.inf, weight="cos", wvar=k * v)[0]
    s = quad(lambda t: a * np.exp(-t / SLS.tau), 0, np.inf, weight="sin", wvar=k * v)[0]
    # cos(kx + kvt) = cos kx cos kvt - sin kx sin kvt
    expected = 2 * (1 - SLS.nu**2) / k * ((1 / SLS.Einf + c) * np.cos(k * x) - s * np.sin(k * x))
    np.testing.assert_allclose(u, expected, atol=1e-12)  # quadrature ~1e-14


@pytest.mark.parametrize("shape", [(16, 8), (15, 9), (32, 1), (10, 6)])
def test_exact_real_matrix_and_even_odd_split(shape, rng):
    """Adjointness, C = C^E + C^O, C^E symmetric, C^O antisymmetric (Eq. 2), incl. Nyquist bins."""
    cell = Cell(1.0, 0.8, *shape)
    op = SpectralOperator(cell, SLS, velocity=(0.3, 0.2))
    n = cell.Nx * cell.Ny
    M = np.array([op.apply(e.reshape(cell.shape)).ravel() for e in np.eye(n)]).T
    MT = np.array([op.apply_transpose(e.reshape(cell.shape)).ravel() for e in np.eye(n)]).T
    ME = np.array([op.apply_even(e.reshape(cell.shape)).ravel() for e in np.eye(n)]).T
    MO = np.array([op.apply_odd(e.reshape(cell.shape)).ravel() for e in np.eye(n)]).T
    scale = np.abs(M).max()
    np.testing.assert_allclose(MT, M.T, atol=1e-14 * scale)
    np.testing.assert_allclose(ME + MO, M, atol=1e-14 * scale)
    np.testing.assert_allclose(ME, ME.T, atol=1e-14 * scale)
    np.testing.assert_allclose(MO, -MO.T, atol=1e-14 * scale)
    assert np.abs(MO).max() > 1e-3 * scale  # the odd part is really there


def test_elastic_operator_is_symmetric_and_never_evaluates_modulus(monkeypatch):
    cell = Cell(1.0, 1.0, 16, 16)
    mat = Elastic(2.0, 0.3)
    monkeypatch.setattr(Elastic, "modulus", lambda *a: (_ for _ in ()).throw(AssertionError))
    op = SpectralOperator(cell, mat, velocity=(1.0, 0.0))
    assert op.symmetric and op.kernel.dtype == np.float64
    sls_static = SpectralOperator(cell, SLS, velocity=(0.0, 0.0))
    assert sls_static.symmetric


def test_half_space_never_evaluates_S(monkeypatch):
    from spectralbem.layers import HalfSpace

    monkeypatch.setattr(HalfSpace, "factor", lambda *a: (_ for _ in ()).throw(AssertionError))
    SpectralOperator(Cell(1.0, 1.0, 8, 8), SLS, velocity=(1.0, 0.0))


def test_q0_mode_gauges():
    cell = Cell(1.0, 1.0, 8, 8)
    ones = np.ones(cell.shape)
    assert np.abs(SpectralOperator(cell, SLS).apply(ones)).max() < 1e-15  # zero-mean gauge
    assert np.abs(SpectralOperator(cell, SLS, PressureLayer(0.5)).apply(ones)).max() < 1e-15
    lay = GluedLayer(0.5)
    u = SpectralOperator(cell, SLS, lay, velocity=(1.0, 0.0)).apply(ones)
    np.testing.assert_allclose(u, lay.q0_compliance(SLS.E0, SLS.nu), rtol=1e-14)


def test_numpy_fallback_equals_fftw(rng):
    x = rng.standard_normal((24, 10))
    a = fft.RealFFT2(x.shape, use_fftw=False)
    X = a.forward(x).copy()
    np.testing.assert_allclose(a.inverse(X), x * x.size, atol=1e-12)
    if fft.backend() == "pyfftw":
        b = fft.RealFFT2(x.shape, use_fftw=True)
        np.testing.assert_allclose(b.forward(x), X, atol=1e-12)
        np.testing.assert_allclose(b.inverse(X), x * x.size, atol=1e-11)


@pytest.mark.parametrize("use_fftw", [False, True])
def test_forward_of_input_buffer_preserves_it(rng, use_fftw):
    """The PK loop keeps a sparse search direction in the r2c input: the transform must equal
    rfft2 and leave the input untouched (FFTW r2c without DESTROY_INPUT)."""
    if use_fftw and fft.backend() != "pyfftw":
        pytest.skip("pyFFTW not installed")
    x = rng.standard_normal((24, 10))
    a = fft.RealFFT2(x.shape, use_fftw=use_fftw)
    a.input_buffer[...] = x
    np.testing.assert_allclose(a.forward_buffer(), np.fft.rfft2(x), atol=1e-12)
    assert np.array_equal(a.input_buffer, x)


@pytest.mark.parametrize("shape", [(1, 1), (7, 9), (6, 10), (64, 48), (512, 512)])
@pytest.mark.parametrize("k", [1, 5, 16])
def test_add_sparse_equals_the_transform(rng, shape, k):
    """X += r2c of a field with k nonzero cells, by the direct sum: equal to the transform
    to rounding — the phases are exact table entries at (m·q) mod N, so the error is a few
    ulps of the largest term (|values| ≤ 1 → 1e-14 absolute; a phase computed as 2π·m·q/N
    directly would be off by ~N·1e-16, 5e-14 at 512)."""
    k = min(k, shape[0] * shape[1])
    a = fft.RealFFT2(shape, use_fftw=False)
    idx = rng.choice(shape[0] * shape[1], size=k, replace=False)
    vals = rng.uniform(-1, 1, size=k)
    x = np.zeros(shape)
    x.flat[idx] = vals
    X0 = np.ascontiguousarray(rng.standard_normal(a.hshape) + 1j * rng.standard_normal(a.hshape))
    X = X0.copy()
    a.add_sparse(X, idx, vals)
    np.testing.assert_allclose(X, X0 + np.fft.rfft2(x), rtol=0, atol=1e-14 * k)
    with pytest.raises(ValueError, match="C-contiguous"):  # a wrong shape
        a.add_sparse(np.zeros((shape[0] + 1, shape[1] // 2 + 1), complex), idx, vals)
    if X.shape[1] > 1:
        with pytest.raises(ValueError, match="C-contiguous"):  # a transposed buffer
            a.add_sparse(np.zeros(X.shape[::-1], complex).T, idx, vals)


def test_one_fft_pair_per_application(monkeypatch):
    cell = Cell(1.0, 1.0, 16, 16)
    op = SpectralOperator(cell, SLS, velocity=(1.0, 0.0))
    calls = {"f": 0, "i": 0}
    pl = op.plan
    f0, i0 = pl.forward, pl.inverse_buffer
    monkeypatch.setattr(pl, "forward", lambda x: (calls.__setitem__("f", calls["f"] + 1), f0(x))[1])
    monkeypatch.setattr(pl, "inverse_buffer",
                        lambda: (calls.__setitem__("i", calls["i"] + 1), i0())[1])
    op.apply(np.ones(cell.shape))
    assert calls == {"f": 1, "i": 1}


@pytest.mark.parametrize(
    "args, word",
    [((0.0, 1.0, 8, 8), "Lx"), ((1.0, -1.0, 8, 8), "Ly"), ((1.0, 1.0, 1, 1), "Nx"),
     ((1.0, 1.0, 8, 0), "Ny"), ((1.0, 1.0, 8.5, 8), "Nx"), ((np.nan, 1.0, 8, 8), "Lx")],
)
def test_bad_cell(args, word):
    with pytest.raises(GridError, match=word):
        Cell(*args)


def test_bad_velocity():
    with pytest.raises(GridError, match="velocity"):
        SpectralOperator(Cell(1.0, 1.0, 8, 8), SLS, velocity=(np.nan, 0.0))
