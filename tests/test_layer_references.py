"""Finite-thickness layers (seed Eqs. A.3-A.5) against references computed here by independent
code: the plane-strain layer equations integrated as a state vector (scipy.linalg.expm), an
axisymmetric Fredholm equation for a sphere on a glued layer, the thin incompressible and
compressible glued-layer asymptotics, Kirchhoff plate (beam) theory for the free layer of
Eq. (A.5), and the closed-form full-contact friction of a viscoelastic layer.  No reference
value below comes from spectralbem.layers."""

import functools
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

import spectralbem as sb
from spectralbem.contact import solve_contact
from spectralbem.layers import GluedLayer, PressureLayer
from spectralbem.materials import Elastic, StandardLinearSolid
from spectralbem.plausibility import PlausibilityWarning
from spectralbem.scenes import load_scene
from spectralbem.spectral import Cell, SpectralOperator
from spectralbem.surfaces import paraboloid, sinusoid

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

CASES = Path(__file__).resolve().parents[1] / "cases"
BOTTOM = {"glued": "glued", "pressure": "free"}


def make_layer(kind, d):
    return GluedLayer(d) if kind == "glued" else PressureLayer(d)


# -- reference 1: the plane-strain layer equations -------------------------------------------
def layer_compliance(q, d, E, nu, bottom):
    """u_z(0)/p of a layer 0 < z < d (z into the layer) under a frictionless surface pressure
    p e^{iqx}; ``bottom`` "glued" (u = 0 at z = d, Eq. A.4) or "free" (no traction at z = d:
    the q ≠ 0 part of a uniform pressure on the far face, Eq. A.5).  E may be complex
    (correspondence principle, ν constant).

    State X = (u_x, u_z, σ_xz, σ_zz) of the mode e^{iqx}; with G = E/(2(1+ν)),
    1/M = (1+ν)(1-2ν)/(E(1-ν)) and r = ν/(1-ν) (finite at ν = 0.5):
    u_x' = σ_xz/G - iq u_z,  u_z' = σ_zz/M - r iq u_x  (Hooke),
    σ_xz' = -iq σ_xx = q² E/(1-ν²) u_x - r iq σ_zz,  σ_zz' = -iq σ_xz  (equilibrium).
    X(d) = expm(A d) X(0) with X(0) = (a, b, 0, -1) (σ_zz = -p, p = 1): two conditions at
    z = d fix (a, b) and u_z(0) = b."""
    E = complex(E)
    iq = 1j * q
    r = nu / (1 - nu)
    a = np.array([[0, -iq, 2 * (1 + nu) / E, 0],
                  [-r * iq, 0, 0, (1 + nu) * (1 - 2 * nu) / (E * (1 - nu))],
                  [q * q * E / (1 - nu**2), 0, 0, -r * iq],
                  [0, 0, -iq, 0]], dtype=complex)
    phi = expm(a * d)
    rows = [0, 1] if bottom == "glued" else [2, 3]
    _, b = np.linalg.solve(phi[rows][:, :2], phi[rows, 3])
    return b


def ode_kernel(cell, d, E_of_q, nu, bottom):
    """The reference Ĉ on the operator's half spectrum; E_of_q(qx, qy) the modulus of a mode."""
    qx, qy = cell.wavevectors()
    qx, qy = np.broadcast_arrays(qx, qy)
    out = np.zeros(qx.shape, dtype=complex)
    for i, j in np.ndindex(qx.shape):
        q = np.hypot(qx[i, j], qy[i, j])
        if q > 0 or bottom == "glued":  # A.5 drops the q = 0 mode (no reference there)
            out[i, j] = layer_compliance(q, d, E_of_q(qx[i, j], qy[i, j]), nu, bottom)
    return out


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
@pytest.mark.parametrize("kind", ["glued", "pressure"])
def test_elastic_kernel_is_the_plane_strain_layer(kind, nu):
    """Ĉ(q) = 2(1-ν²)S(|q|d)/(E|q|), Eqs. (A.3)-(A.5), on every mode of a 32 × 16 grid (and
    the glued layer's q = 0 mode, d/M) against the state-vector solution.  |q|d spans 0.06-1.4
    (d = 0.01) and 0.6-14 (d = 0.1).  Measured max relative difference 2.3e-13 (expm's and
    the 2 × 2 solve's round-off grow with e^{|q|d}); asserted 1e-10.  Fails with A.4 and A.5
    swapped, ν - 0.005 in S of A.4, |q|d scaled by 1.02, or d/M scaled by 1.1."""
    cell, E = Cell(1.0, 0.5, 32, 16), 2.5
    for d in (0.01, 0.1):
        op = SpectralOperator(cell, Elastic(E, nu), make_layer(kind, d))
        ref = ode_kernel(cell, d, lambda qx, qy: E, nu, BOTTOM[kind])
        assert np.abs(ref.imag).max() <= 1e-12 * np.abs(ref).max()  # elastic: real
        got = op.kernel
        assert got.shape == ref.shape
        if kind == "pressure":
            assert got[0, 0] == 0.0  # the dropped mode (zero-mean gauge, as the half-space)
            got, ref = got.ravel()[1:], ref.ravel()[1:]
        if kind == "glued" and nu == 0.5:
            assert got[0, 0] == ref[0, 0] == 0.0  # incompressible: no q = 0 compliance
            got, ref = got.ravel()[1:], ref.ravel()[1:]
        np.testing.assert_allclose(got, ref.real, rtol=1e-10, atol=0)


@pytest.mark.parametrize("kind", ["glued", "pressure"])
def test_viscoelastic_sampled_kernel_is_the_layer_with_complex_modulus(kind):
    """Sliding at v = (0.3, -0.2) on an SLS layer (Eq. 14: 1/E(ω) = 1/E∞ + (1/E0 - 1/E∞)/(1 -
    iωτ), ω = q·v), the sampled kernel: Ĉ(q) = 2(1-ν²)S/(E(q·v)|q|) against the state vector
    with the complex modulus, the glued q = 0 mode with E0.  The Nyquist row and column are
    left out (the hermitian symmetrisation makes them real there).  Measured 1.7e-14
    relative; asserted 1e-10.  Fails if the glued q = 0 mode used E∞ instead of E0."""
    E0, Einf, tau, nu, d = 1.0, 10.0, 1.0, 0.45, 0.1
    v = (0.3, -0.2)
    cell = Cell(1.0, 1.0, 16, 16)
    op = SpectralOperator(cell, StandardLinearSolid(E0, Einf, tau, nu), make_layer(kind, d),
                          velocity=v, delayed="sampled")

    def modulus(qx, qy):
        w = qx * v[0] + qy * v[1]
        return 1.0 / (1.0 / Einf + (1.0 / E0 - 1.0 / Einf) / (1.0 - 1j * w * tau))

    ref = ode_kernel(cell, d, modulus, nu, BOTTOM[kind])
    got = op.kernel
    keep = np.ones(got.shape, bool)
    keep[cell.Nx // 2, :] = keep[:, -1] = False
    if kind == "pressure":
        keep[0, 0] = False
    assert np.abs(ref[keep].imag).max() > 0.1 * np.abs(ref[keep]).max()  # truly complex
    np.testing.assert_allclose(got[keep], ref[keep], rtol=1e-10, atol=0)


# -- reference 2: a sphere on a glued layer, axisymmetric Fredholm equation -----------------
@functools.lru_cache(maxsize=None)
def _s_minus_one(nu):
    """Nodes σ, weights and S(σ) - 1 of the glued layer (state vector) on [0, 20] (S - 1 ~
    σ² e^{-2σ}: < 1e-14 beyond), 40 Gauss-Legendre panels of 16 nodes."""
    x, w = np.polynomial.legendre.leggauss(16)
    edges = np.linspace(0.0, 20.0, 41)
    half = np.diff(edges)[0] / 2
    sig = (edges[:-1, None] + half * (x[None, :] + 1)).ravel()
    s = np.array([layer_compliance(1.0, t, 1.0, nu, "glued").real for t in sig]) / (2 * (1 - nu**2))
    return sig, np.tile(w * half, 40) * (s - 1.0)


def fredholm_sphere(a, d, R, E, nu, nq=32):
    """Penetration Δ and load P of a rigid paraboloid (radius R) pressed into a layer of
    thickness d glued to a rigid plate, frictionless, at contact radius a (no adhesion).

    With p̂(k) = ∫_0^a φ(t) cos(kt) dt (Hankel transform of p) and u(r) = (2/E*)∫ S(kd) p̂ J0(kr)
    dk, Abel's reduction of u = Δ - r²/(2R) on r < a gives
    φ(t) + (2/π)∫_0^a K(s, t) φ(s) ds = (E*/π)(Δ - t²/R),  K = [H(s-t) + H(s+t)]/2,
    H(x) = ∫_0^∞ (S(kd) - 1) cos(kx) dk,  P = 2π∫_0^a φ,  p ~ φ(a)/√(a² - r²) at the edge.
    Hertz (no edge singularity): φ(a) = 0 fixes Δ.  K = 0 gives Hertz exactly.  Nyström on
    nq Gauss nodes: nq = 16 and 64 agree to 1e-14 for d/a ≥ 0.5 (80 panels in σ: likewise)."""
    es = E / (1 - nu**2)
    sig, wf = _s_minus_one(nu)

    def big_h(x):
        return np.cos(np.multiply.outer(np.abs(x) / d, sig)) @ wf / d

    t, w = np.polynomial.legendre.leggauss(nq)
    t, w = a * (t + 1) / 2, a * w / 2
    k = 0.5 * (big_h(t[None, :] - t[:, None]) + big_h(t[None, :] + t[:, None]))
    lhs = np.eye(nq) + (2 / np.pi) * k * w[None, :]
    rhs = np.stack([np.full(nq, es / np.pi), -es * t**2 / (np.pi * R)], axis=1)
    phi = np.linalg.solve(lhs, rhs)  # the Δ = 1 and the curvature parts
    # φ(a) by the Nyström interpolation formula
    ka = 0.5 * (big_h(t - a) + big_h(t + a))
    phi_a = np.array([es / np.pi, -es * a**2 / (np.pi * R)]) - (2 / np.pi) * (ka * w) @ phi
    delta = -phi_a[1] / phi_a[0]
    load = 2 * np.pi * (w @ phi) @ [delta, 1.0]
    return delta, load


@pytest.mark.parametrize("d_over_a", [2.0, 1.0, 0.5])
@pytest.mark.parametrize("nu", [0.5, 0.3])
def test_sphere_on_glued_layer_against_axisymmetric_fredholm(nu, d_over_a):
    """Eq. (A.4): a paraboloid R = L on a glued layer at contact radius a = L/16 (16 cells of
    a 256² grid), d/a = 2, 1, 0.5, against the Fredholm solution above (Δ and P exact to
    1e-14).  Load control at P_ref: Δ; penetration control at Δ_ref: P.  Measured |ΔΔ|/Δ
    ≤ 2.9e-4 and |ΔP|/P ≤ 5.5e-4 (largest at ν = 0.5, d/a = 2, d = L/8, where the periodic
    images are felt: 1.3e-2 with d = L/4 on a 128² grid), asserted 1e-3 and 1.5e-3;
    the contact radius √(A/π) within 0.09 cells, asserted half a cell.  The layer matters:
    Δ and P differ from Hertz by 24-160 %; every point fails with ν - 0.005 in S of A.4,
    with |q|d scaled by 1.02 or with A.5 in place of A.4 (and the ν = 0.3 points with d/M
    scaled by 1.1)."""
    L = R = E = 1.0
    n, a = 256, 1.0 / 16
    d = d_over_a * a
    delta, load = fredholm_sphere(a, d, R, E, nu)
    cell = Cell(L, L, n, n)
    h = paraboloid(cell, R)
    op = SpectralOperator(cell, Elastic(E, nu), GluedLayer(d))
    by_load = solve_contact(op, h, mean_pressure=load / L**2)
    assert by_load.converged, by_load.message
    assert by_load.penetration == pytest.approx(delta, rel=1e-3)
    radius = np.sqrt(by_load.contact.sum() * cell.cell_area / np.pi)
    assert abs(radius - a) <= 0.5 * cell.hx
    by_pen = solve_contact(op, h, penetration=delta)
    assert by_pen.converged, by_pen.message
    assert by_pen.pressure.sum() * cell.cell_area == pytest.approx(load, rel=1.5e-3)


# -- reference 3: thin glued layers -----------------------------------------------------------
@pytest.mark.parametrize("nu", [0.5, 0.3])
def test_thin_glued_layer_asymptotics(nu):
    """A paraboloid on a glued layer much thinner than the contact (128² grid, R = L = E = 1),
    penetration control.  Small-|q|d limits of Eq. (A.4):
    ν = 0.5: u = -(d³/E)∇²p (lubrication-like squeeze of an incompressible layer), with
    u = Δ - r²/(2R), p = p' = 0 at r = a: p = E a⁴(1 - r²/a²)²/(32 R d³), Δ = a²/(4R),
    P = 2π E R² Δ³/(3 d³) (= π E a⁶/(96 R d³)); at d/a = 0.0125 (d = h/4).
    ν = 0.3: Winkler foundation p = M(Δ - r²/(2R))/d, M = E(1-ν)/((1+ν)(1-2ν)),
    P = π M R Δ²/d; at d/a = 0.025.
    Measured: ν = 0.5, P +3.8e-3 and the pressure field 4.0e-3 (L2, relative): mostly the
    asymptotics' own next term, second order in d/a (the Fredholm solution above at the same
    Δ, 384 nodes, gives +3.3e-3; the grid P +4.8e-2, +1.3e-2 at d/a = 0.05, 0.025, Fredholm
    +4.9e-2, +1.3e-2); asserted 1e-2.  ν = 0.3: P -3.9e-4, field 4.3e-4 (the edge boundary
    layer of width ~d: P -2.4e-3, -8.3e-4 at d/a = 0.1, 0.05), asserted 2e-3."""
    n, a = 128, 0.15
    cell = Cell(1.0, 1.0, n, n)
    x, y = cell.coordinates(centred=True)
    r = np.hypot(x, y)
    if nu == 0.5:
        d = 0.0125 * a
        delta = a**2 / 4
        p_ref = np.where(r < a, a**4 / (32 * d**3) * (1 - r**2 / a**2) ** 2, 0.0)
        load_ref, tol = 2 * np.pi * delta**3 / (3 * d**3), 1e-2
    else:
        d = 0.025 * a
        m = (1 - nu) / ((1 + nu) * (1 - 2 * nu))
        delta = a**2 / 2
        p_ref = np.maximum(m * (delta - r**2 / 2) / d, 0.0)
        load_ref, tol = np.pi * m * delta**2 / d, 2e-3
    res = solve_contact(SpectralOperator(cell, Elastic(1.0, nu), GluedLayer(d)),
                        paraboloid(cell, 1.0), penetration=delta)
    assert res.converged, res.message
    assert res.pressure.sum() * cell.cell_area == pytest.approx(load_ref, rel=tol)
    assert np.linalg.norm(res.pressure - p_ref) <= tol * np.linalg.norm(p_ref)


# -- reference 4: the layer of Eq. (A.5) is a free plate on a uniform back pressure ------------
def test_pressure_layer_is_a_plate_on_back_pressure():
    """Eq. (A.5) behaves as S ~ 6/(qd)³, a Kirchhoff plate D w'''' = p - p̄ with
    D = E d³/(12(1-ν²)).  A periodic rigid cylinder h = -x²/(2R) (period L) pressed into it:
    in contact w'''' = 0, so p = p̄ exactly, and line forces p̄b at the edges x = ±a, where
    the free span b = L/2 - a obeys b³ = 3 D L/(2 R p̄) (beam theory).  With p̄ chosen so that
    b = L/4, at Nx = 1024 (ν = 0.3, R = L = E = 1), d = 0.01 and 0.005:
    (i) the pressure over |x| < a/2 is p̄ (measured max deviation 7.9e-5, 2.1e-4: the
    solver's tolerance on a kernel spanning 1e7-1e8; asserted 1e-3; a half-space or a glued
    layer of the same d deviates by more than 100 p̄ there);
    (ii) the contact half-width a = a_ref + c d + O(d²) (c ≈ 0.7: the edge forces spread over
    ~d): the extrapolation 2a(d/2) - a(d) is within 0.5 cells of a_ref (the half-width is
    counted in half cells), asserted 1.5 cells — S of A.5 scaled by 1.03 (b³ ∝ D: b - 1 %,
    2.6 cells) moves it by 4 cells."""
    E, nu, R, L, n = 1.0, 0.3, 1.0, 1.0, 1024
    cell = Cell(L, L / n, n, 1)
    x = cell.coordinates(centred=True)[0]
    b = L / 4
    a_ref = L / 2 - b
    widths = []
    for d in (0.01, 0.005):
        stiff = E * d**3 / (12 * (1 - nu**2))
        pbar = 3 * stiff * L / (2 * R * b**3)
        op = SpectralOperator(cell, Elastic(E, nu), PressureLayer(d))
        res = solve_contact(op, -x**2 / (2 * R), mean_pressure=pbar, maxiter=100_000)
        assert res.converged, res.message
        centre = np.abs(x) < a_ref / 2
        assert np.abs(res.pressure[centre] / pbar - 1).max() <= 1e-3
        widths.append(res.contact.sum() * cell.hx / 2)
    assert abs(2 * widths[1] - widths[0] - a_ref) <= 1.5 * cell.hx


# -- reference 5: full contact on a sliding viscoelastic layer ---------------------------------
E0, EINF, TAU, NU = 1.0, 10.0, 1.0, 0.45


def sls_modulus(omega):
    """Seed Eq. (14) in the package's e^{iωt} convention (docs/theory.md)."""
    return 1.0 / (1.0 / EINF + (1.0 / E0 - 1.0 / EINF) / (1.0 - 1j * omega * TAU))


def full_contact_reference(x, k, amp, pbar, compliance):
    """h = Λ cos kx in full contact: u = h + const, so p = p̄ + Λ Re[e^{ikx}/Ĉ(k)] and the
    friction μ = |<p ∂h/∂x>|/p̄ = kΛ²|Im(1/Ĉ(k))|/(2p̄)."""
    p = pbar + amp * np.real(np.exp(1j * k * x) / compliance)
    return p, k * amp**2 * abs(np.imag(1 / compliance)) / (2 * pbar)


@pytest.mark.parametrize("zeta", [0.3, 5.0])
@pytest.mark.parametrize("kind", ["glued", "pressure"])
def test_full_contact_friction_on_viscoelastic_layers(kind, zeta):
    """A sinusoid λ = 1, Λ = 0.01, on an SLS layer d = 0.2λ (kd = 1.26) sliding at ζ = kvτ,
    p̄ = 1.05 of the full-contact threshold; Ĉ(k) from the state vector with E(kv).  Sampled
    kernel (64 cells): measured 7e-16 (μ) and 1.4e-12 (pressure) relative, asserted 1e-9.
    Default cell-averaged kernel: O((kh)²) — measured μ errors 1.60e-4, 4.01e-5 (ζ = 0.3)
    and 8.8e-5, 2.2e-5 (ζ = 5) at 128, 256 cells, ratio 3.99; asserted ratio in [3.5, 4.5]
    and error ≤ 0.2 (kh)² (measured 0.067 (kh)²).  The cell kernel fails without the layer
    factor in its delayed part."""
    lam, amp, d = 1.0, 0.01, 0.2
    k = 2 * np.pi / lam
    v = zeta / (k * TAU)
    c_k = layer_compliance(k, d, sls_modulus(k * v), NU, BOTTOM[kind])
    pbar = 1.05 * amp / abs(c_k)
    mat = StandardLinearSolid(E0, EINF, TAU, NU)
    errs = []
    for n, delayed in ((64, "sampled"), (128, "cell"), (256, "cell")):
        cell = Cell(lam, lam / n, n, 1)
        op = SpectralOperator(cell, mat, make_layer(kind, d), velocity=(v, 0.0), delayed=delayed)
        res = solve_contact(op, sinusoid(cell, amp), mean_pressure=pbar)
        assert res.converged and res.status == "full_contact", res.message
        p_ref, mu_ref = full_contact_reference(cell.x, k, amp, pbar, c_k)
        err = abs(res.mu / mu_ref - 1)
        if delayed == "sampled":
            assert err <= 1e-9
            np.testing.assert_allclose(res.pressure[:, 0], p_ref, rtol=1e-9)
        else:
            errs.append(err)
            assert err <= 0.2 * (k * cell.hx) ** 2
    assert 3.5 < errs[0] / errs[1] < 4.5


@pytest.mark.parametrize("case, bottom", [("finite_thickness_glued", "glued"),
                                          ("finite_thickness_pressure", "free")])
def test_layer_scenes_full_contact(case, bottom):
    """The shipped scenes cases/finite_thickness_*.toml (SI units: λ = 100 µm, d = 20 µm,
    SLS E0 = 1 MPa, E∞ = 10 MPa, τ = 10 ms, ν = 0.45, v = 1 mm/s) with the amplitude
    lowered to 0.5 µm, p̄ at 1.05 of the full-contact threshold and the sampled kernel: the
    scene's layer kind and thickness reach the operator.  Reference as above with the
    scene's own parameters read from the file; measured 7e-16 (μ) and 6.7e-12 (pressure)
    relative, asserted 1e-9."""
    path = CASES / f"{case}.toml"
    spec = tomllib.loads(path.read_text())
    mat, amp = spec["material"], 5e-7
    lam, d, v = spec["grid"]["Lx"], spec["layer"]["thickness"], spec["motion"]["speed"]
    e0, einf, tau, nu = mat["E0"], mat["Einf"], mat["tau"], mat["nu"]
    k = 2 * np.pi / lam
    w = k * v
    modulus = 1.0 / (1.0 / einf + (1.0 / e0 - 1.0 / einf) / (1.0 - 1j * w * tau))
    c_k = layer_compliance(k, d, modulus, nu, bottom)
    pbar = 1.05 * amp / abs(c_k)
    n = 128
    scene = load_scene(path, overrides={"grid.Nx": n, "grid.Ny": 1, "grid.Ly": lam / n,
                                        "surface.amplitude": amp, "control.mean_pressure": pbar,
                                        "solver.delayed_kernel": "sampled"})
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)  # p̄ < 0.1 E*: small strains
        ds = sb.solve(scene)
    assert str(ds.status.values) == "full_contact"
    p_ref, mu_ref = full_contact_reference(ds.x.values, k, amp, pbar, c_k)
    assert float(ds.mu) == pytest.approx(mu_ref, rel=1e-9)
    np.testing.assert_allclose(ds.pressure.values[:, 0], p_ref, rtol=1e-9)


def test_the_validation_page_states_these_tests():
    """docs/validation.md ends with the section ``spectralbem.validate`` writes for these
    tests (LAYER_CHECKS: a regeneration keeps it), and every test it names exists here."""
    import re

    from spectralbem import validate

    here = Path(__file__).read_text()
    page = (Path(__file__).resolve().parents[1] / "docs" / "validation.md").read_text()
    assert page.endswith(validate.LAYER_CHECKS)
    named = set(re.findall(r"`(test_\w+)`", validate.LAYER_CHECKS))
    assert len(named) >= 6
    for name in named:
        assert f"def {name}(" in here, name
