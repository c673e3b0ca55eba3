"""Physics claims of docs/theory.md, docs/oned.md, docs/validation.md and README.md that no
other test checked (or checked far more loosely than the claim), each against an analytic or
independent result computed here.  The doc sentence each test checks is quoted in its
docstring with the measured error and the tolerance."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

import spectralbem as sb
from spectralbem import sinusoid1d as s1
from spectralbem.cell_average import delayed_kernel
from spectralbem.layers import GluedLayer
from spectralbem.materials import Elastic, StandardLinearSolid
from spectralbem.spectral import Cell, SpectralOperator

BETA, GAMMA = 10.0, 0.008


# -- the advance width a0 -------------------------------------------------------------------
@pytest.mark.parametrize("zeta", [0.1, 1.0, 10.0])
def test_infinitesimal_strip_releases_the_glassy_value_at_both_edges(zeta):
    """docs/theory.md, "The advance width a0": "in the limit of an infinitesimal strip
    δL/δA → K²/(2E∞*) at both edges for any v > 0"; docs/oned.md: "a0 ≪ vτ/β: glassy tips,
    δL/a0 → K²/(2E∞*)" (docs/derivations.md §4).

    On the converged seed state (β = 10, Γ = 0.008, ã0 = 0.01, p̃∞ = 0.15) the strip work of
    Eq. (8) (crack-closure quadrature of the gap before and the pressure after closure) is
    compared with Irwin's K²/(2E∞*), K from the Chebyshev coefficients of the pressure and
    E∞* = β E0* = 10 (units k = Λ = E0* = 1, ν = 0) written here, not taken from the code.
    The deviation is first order in a0 (ratio 9.94-10.04 between ã0 = 1e-4 and 1e-5, asserted
    8-12), so the two-point extrapolation to a0 = 0 removes it: measured |limit − 1| ≤ 3.1e-6
    over both edges and the three ζ, asserted 2e-5 (6×).  The relaxed value K²/(2E0*) would
    read 10."""
    pr = s1.dimensionless_problem(zeta, BETA, GAMMA, 0.01)
    st = pr.equilibrium(mean_pressure=0.15 * pr.p_star())
    assert st.info.converged
    e_inf_star = BETA / (1 - 0.0**2)
    for side in (1, 2):
        irwin = st.K[side - 1] ** 2 / (2 * e_inf_star)
        r = {a0: pr.edge_work(st, side, a0)[1].dL / a0 / irwin for a0 in (1e-5, 1e-4)}
        assert 8 < (r[1e-4] - 1) / (r[1e-5] - 1) < 12, (side, r)  # first order in a0
        limit = (10 * r[1e-5] - r[1e-4]) / 9
        assert limit == pytest.approx(1.0, abs=2e-5), (side, r)


def test_edge_shift_of_the_finite_advance_width_by_the_energy_route():
    """docs/theory.md, "Edge shift": "In the elastic limits a finite a0 moves each edge
    inward by c·a0 with c = 0.4598 (β = 10, Γ = 0.008, Δ̃ = 0.3), not exactly ½"; docs/oned.md:
    "a finite a0 moves each edge inward by 0.46 a0".  (tests/test_sinusoid1d.py asserts c
    within 10 % of ½, which does not tell 0.46 from 0.5.)

    Independent route: an elastic body's potential energy at fixed Δ is a function of the
    contact domain, so the work of closing the strip [l, l + a0] is ∫G ds with
    G = K²/(2E*) of the domain [−l, l + s] (docs/theory.md, "the sharp-crack edge").  The
    balance (1/a0)∫₀^{a0} K²(s)/(2E*) ds = Δγ is solved here for the symmetric edge by
    Gauss-Legendre in s and brentq (K of each domain from the 1D solver's SIF at a0 = 0,
    validated against Johnson), and compared with the 1D method's crack-closure strip
    (Eq. 8).  Measured: c = 0.459663, 0.459827 (energy) against 0.459663, 0.459827 (1D) at
    ã0 = 1e-4, 1e-3, differences ≤ 8e-8 (the root tolerance over a0), asserted 1e-6; c at
    1e-3 is the doc's 0.4598 to its four digits (asserted ±1e-4), 0.04 from ½."""
    delta, dgamma = 0.3, np.pi * GAMMA  # Δ̃ = 0.3; Δγ = πΓ in units k = Λ = E0* = 1
    pr = s1.dimensionless_problem(0.0, BETA, GAMMA, 0.0)
    xg, wg = np.polynomial.legendre.leggauss(12)

    def mean_release(l, a0):
        s = 0.5 * a0 * (xg + 1) if a0 > 0 else np.zeros(1)
        w = 0.5 * wg if a0 > 0 else np.ones(1)
        k2 = [pr.solve_domain(l, l + si, penetration=delta).K[1] ** 2 for si in s]
        return float(np.dot(w, k2)) / 2.0 - dgamma

    l0 = brentq(mean_release, 0.8, 1.0, args=(0.0,), xtol=1e-14)
    for a0 in (1e-4, 1e-3):
        energy = (l0 - brentq(mean_release, 0.8, 1.0, args=(a0,), xtol=1e-14)) / a0
        ds = s1.solve(0.0, BETA, GAMMA, delta_tilde=delta, a0_tilde=a0,
                      adhesiveless_reference=False)
        for key in ("l1_tilde", "l2_tilde"):
            assert (l0 - ds.attrs[key]) / a0 == pytest.approx(energy, abs=1e-6), (a0, key)
        if a0 == 1e-3:
            assert energy == pytest.approx(0.4598, abs=1e-4)
            assert abs(energy - 0.5) > 0.03


# -- the 1D method ---------------------------------------------------------------------------
def johnson_special_points(gamma, beta):
    """Johnson (1995) in the seed's variables (docs/derivations.md §7), written out here:
    p̃(ã) = β sin²(ã/2) − 2√(βΓ)√tan(ã/2), Δ̃ = sin²(ã/2) − 2(p̃/β) ln sin(ã/2)."""
    def p(a):
        return beta * np.sin(a / 2) ** 2 - 2 * np.sqrt(beta * gamma * np.tan(a / 2))

    def dp(a):  # dp̃/dã
        t = a / 2
        return (beta * np.sin(t) * np.cos(t)
                - np.sqrt(beta * gamma) / (2 * np.sqrt(np.tan(t)) * np.cos(t) ** 2))

    def d(a):
        return np.sin(a / 2) ** 2 - 2 * p(a) / beta * np.log(np.sin(a / 2))

    def dd(a):  # dΔ̃/dã
        t = a / 2
        return (np.sin(t) * np.cos(t) - 2 * dp(a) / beta * np.log(np.sin(t))
                - p(a) / beta * np.cos(t) / np.sin(t))

    a_pmin = brentq(dp, 1e-6, 1.5, xtol=1e-15)  # the extrema as roots of the derivatives
    a_pmax = brentq(dp, a_pmin + 1e-3, np.pi - 1e-3, xtol=1e-15)
    a0 = brentq(p, a_pmin, a_pmax, xtol=1e-15)
    a_dmin = brentq(dd, 1e-6, a_pmin, xtol=1e-15)
    T = 2 * np.pi * quad(lambda a: p(a) * dd(a), a0, a_dmin, epsabs=0, epsrel=1e-13)[0]
    return dict(p_min=p(a_pmin), a_pmin=a_pmin, p_max=p(a_pmax), a_pmax=a_pmax, a0=a0,
                delta_min=d(a_dmin), p_dmin=p(a_dmin), T=T)


@pytest.mark.parametrize("zeta, beta_eff", [(0.0, 1.0), (np.inf, BETA)])
def test_special_points_equal_johnson_to_the_stated_digits(zeta, beta_eff):
    """docs/oned.md, "Branch and special points": "In the elastic limits all agree with
    Johnson (1995) to 1e-7 (tests)"; "pull-off (load and fixed Δ), snap-in, zero-load contact
    and toughness (Eq. 24) to 1e-3 (measured ≤ 1e-7)".  tests/test_sinusoid1d.py asserts 1e-3.

    Johnson's closed form is evaluated here (extrema as roots of the derivatives, Eq. (24) by
    adaptive quadrature).  Measured with the defaults of special_points, relative: the
    values p_min, p_max, zero-load ã, Δ̃_min ≤ 2.5e-12 and T̃ ≤ 7.1e-10, asserted 5e-9 (7×;
    spectralbem.reference's 4001-point trapezoid T̃ is itself 3e-8 off); the extremum
    positions ã(p_min), ã(p_max) ≤ 8.1e-7 and the load at the fixed-grip pull-off
    p̃(Δ̃_min) ≤ 1.1e-6 (flat extrema: their positions are found to the square root of the
    values' accuracy), asserted 5e-6 (4.5×).  So the doc's "1e-7" holds for the values and
    the toughness, not for p̃ at the fixed-Δ pull-off (the |p̃_out| of docs/oned.md's table)
    or the positions of the extrema."""
    sp = s1.special_points(zeta, BETA, GAMMA, a0_tilde=0.0)
    rj = johnson_special_points(GAMMA, beta_eff)
    for key in ("p_min", "p_max", "a0", "delta_min", "T"):
        assert sp[key] == pytest.approx(rj[key], rel=5e-9), key
    for key in ("a_pmin", "a_pmax", "p_dmin"):
        assert sp[key] == pytest.approx(rj[key], rel=5e-6), key


def test_default_mesh_of_the_1d_method_meets_its_target():
    """docs/oned.md, "Mesh convergence at fixed a0": the largest relative change of ã, ẽ,
    G1, G2, μ̄ when M and Q are raised is "All below 5e-5, so the defaults meet the 1e-4
    target"; ζ = 3e-3 is where a rule with 10 % fewer modes fails it (1.1e-4).

    Reference: the same state on the doubled mesh (2M Chebyshev modes, 2Q kernel nodes),
    ẽ relative to max(|ẽ|, 0.01 ã) as in cases/oned_convergence.py.  Measured 4.6e-5 (G2),
    asserted at the documented 5e-5 bound times 2, 1e-4, the target itself.  (The table's
    column header reads "to (1.5M, 1.5Q), (2M, 2Q)"; cases/oned_convergence.py computes
    default → 2× and 1.5× → 2×: its first number is this one.)"""
    zeta = 3e-3
    pr = s1.dimensionless_problem(zeta, BETA, GAMMA, 0.01)
    keys = ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar")
    vals = []
    for f in (1, 2):
        ds = s1.solve(zeta, BETA, GAMMA, p_tilde=0.15, a0_tilde=0.01, modes=f * pr.M,
                      quad=f * pr.Q, adhesiveless_reference=False)
        assert ds.status.item() == "partial"
        vals.append(np.array([ds[k].item() for k in keys]))
    scale = np.maximum(np.abs(vals[1]), 1e-2 * abs(vals[1][0]))
    change = np.abs(vals[0] - vals[1]) / scale
    assert change.max() < 1e-4, dict(zip(keys, change, strict=True))


# -- the 2D grid against the 1D method and Johnson ----------------------------------------------
def test_adhesive_friction_at_two_cells_per_relaxation_length():
    """README.md, "Choosing the grid": "the adhesive friction μ_a is within 1 % of the 1D
    method from vτ/h = 2 on (a0 ≥ 2 cells; −7 % at one cell) on the sinusoid"; docs/theory.md:
    "μ̄_a within 1 % from 2 cells per vτ (−0.8 %, −0.06 %, −0.01 % at 2, 3, 4 cells,
    ζ = 0.005), where the sampled kernel is −6.6 %, −3.2 %, −1.6 % off".

    The y-invariant seed sinusoid (β = 10, Γ = 0.008, p̃∞ = 0.15, ã0 = 0.01 = 2 vτ) on the
    grid against the 1D method at the same a0.  Measured relative errors of μ̄_a with the
    default (cell-averaged) kernel: −0.80 % at vτ/h = 2 (asserted: the claim's 1 %, the
    margin being the doc's own), −0.06 % at 3 (asserted 0.25 %, 4×), −6.8 % at 1 (asserted
    −4 % to −10 %: the resolution the claim excludes); with the sampled kernel −6.6 % at 2
    (asserted −4 % to −10 %)."""
    zeta = 0.005
    one = s1.solve(zeta, BETA, GAMMA, p_tilde=0.15, a0_tilde=0.01, adhesiveless_reference=False)
    ref = one.mu_bar_adhesive.item()
    assert one.status.item() == "partial" and ref > 0

    def error(cells_per_vtau, kernel="cell"):
        n = int(np.ceil(cells_per_vtau * 2 * np.pi / zeta))
        ds = sb.solve(sb.Scene.sinusoid(zeta, BETA, GAMMA, p_tilde=0.15, a0_tilde=0.01,
                                        cells_per_wavelength=n, ny=2,
                                        solver={"delayed_kernel": kernel}))
        assert ds.status.item() == "partial"
        return ds.mu_bar_adhesive.item() / ref - 1

    assert abs(error(2)) < 0.01
    assert abs(error(3)) < 0.0025
    assert -0.10 < error(1) < -0.04
    assert -0.10 < error(2, "sampled") < -0.04


def test_oblique_adhesive_sliding_has_the_lateral_friction_of_the_1d_force():
    """docs/validation.md, "Oblique sliding": "Sliding at 40° to the wave vector at ζ = 0.3
    equals the 1D problem at ζ cos 40° ...; μ̄ along v is divided by cos 40° ...; lateral μ̄
    −0.45011 against −μ̄₁D sin 40°" (the adhesive seed scene; tests/test_adhesive2d.py checks
    μ̄ along v against the aligned grid, not the lateral force).

    The force on the profile is along the wave vector x: along v it is F cos φ, along
    v̂⊥ = ẑ × v̂ it is −F sin φ.  Reference: the 1D method at ζ cos 40°, same ã0 (4 cells at
    1024 cells per wavelength).  Measured 1.6e-4 relative for both, asserted 1e-3 (6×).
    The adhesive friction μ̄_a is along v too: the edges sweep the surface at v cos φ, so it
    is cos φ times the 1D value (it was the 1D value itself, along the wave vector: 0.2268
    against μ̄ along v at ζ = 0.5, 50°); measured 1.1e-5 relative, asserted 1e-3."""
    phi = np.radians(40.0)
    a0 = 4 * 2 * np.pi / 1024
    ds = sb.solve(sb.Scene.sinusoid(0.3, BETA, GAMMA, p_tilde=0.15, a0_tilde=a0,
                                    cells_per_wavelength=1024, ny=2, direction_deg=40.0))
    one = s1.solve(0.3 * np.cos(phi), BETA, GAMMA, p_tilde=0.15, a0_tilde=a0,
                   adhesiveless_reference=False)
    assert ds.status.item() == one.status.item() == "partial"
    mu1 = one.mu_bar.item()
    assert ds.mu_bar.item() == pytest.approx(mu1 * np.cos(phi), rel=1e-3)
    assert ds.mu_bar_lateral.item() == pytest.approx(-mu1 * np.sin(phi), rel=1e-3)
    mua1 = one.mu_bar_adhesive.item()
    assert ds.mu_bar_adhesive.item() == pytest.approx(mua1 * np.cos(phi), rel=1e-3)


def johnson_a(p_tilde, gamma):
    """Johnson's stable-branch ã at load p̃ (elastic E0): the root of
    p̃ = sin²(ã/2) − 2√Γ √tan(ã/2) between the pull-off and the snap-in."""
    def p(a):
        return np.sin(a / 2) ** 2 - 2 * np.sqrt(gamma * np.tan(a / 2))

    a_min = minimize_scalar(p, bounds=(1e-6, 1.5), method="bounded",
                            options={"xatol": 1e-12}).x
    return brentq(lambda a: p(a) - p_tilde, a_min, 3.0, xtol=1e-14)


def test_sharp_crack_edge_of_a_straight_elastic_front_against_johnson():
    """docs/theory.md, "Known limits": "On the y-invariant sinusoid at p̃ = 0.15 and 1024
    cells per wavelength the edge lies +0.103, +0.102, +0.097, +0.072 and −0.047 % from
    Johnson's ã at a0 = 1, 2, 4, 8 and 16 cells ... (these with the a0 tests' edge)";
    "Extrapolating the elastic edge": "K's curvature leaves an error of order a0² in the
    edge ... Richardson's combination (4 s(a0/2) − s(a0))/3 ... removes the a0² term".
    (Until now multi-cell a0 in an elastic scene was compared with an analytic edge only on
    the grid-free JKR disc of tests/test_front.py and at one cell on this sinusoid.)

    Johnson's ã is computed here.  Measured (a0 tests' edge): +0.102, +0.097, +0.072,
    −0.047 % at 2, 4, 8, 16 cells — all asserted within 0.3 % (3× the largest); their move
    from 8 to 16 cells is 4.8× that from 4 to 8 (second order in a0, asserted 3-7×).  The
    extrapolated edge (the default) reads +0.105, +0.107, +0.113, +0.126 %: its move from 2
    to 16 cells is 0.021 % against 0.149 % without, asserted below 0.3× of it, and every
    value within 0.3 %."""
    aj = johnson_a(0.15, GAMMA)

    def err(cells, extrapolate):
        ds = sb.solve(sb.Scene.sinusoid(0.0, BETA, GAMMA, p_tilde=0.15,
                                        a0_tilde=cells * 2 * np.pi / 1024,
                                        cells_per_wavelength=1024, ny=2,
                                        solver={"extrapolate_a0": extrapolate}))
        assert ds.status.item() == "partial"
        return ds.a_tilde.item() / aj - 1

    plain = {m: err(m, False) for m in (2, 4, 8, 16)}
    extra = {m: err(m, True) for m in (2, 16)}
    for e in list(plain.values()) + list(extra.values()):
        assert abs(e) < 3e-3
    assert 3 < (plain[16] - plain[8]) / (plain[8] - plain[4]) < 7
    assert abs(extra[16] - extra[2]) < 0.3 * abs(plain[16] - plain[2])


# -- the cell-averaged kernel --------------------------------------------------------------------
@pytest.mark.parametrize("layer", [None, GluedLayer(0.3)])
def test_a_mode_that_does_not_slide_keeps_the_relaxed_compliance_to_second_order(layer):
    """docs/theory.md, "The viscoelastic kernel on the grid": "A mode that does not slide
    (q·v = 0) keeps a cell-averaged relaxed compliance, which differs from the sampled one by
    O((qh)²) at long wavelengths"; and the cell kernel is "equal to the sampled kernel when
    D ≡ 0 (an elastic slab)".  (tests/test_spectral.py checks the second order on sliding
    modes only.)

    p = cos(q_y y) with v along x: the response against the continuum's relaxed
    2(1−ν²)S(q d)/(E0 q), written here, on 32² to 256² cells, and at vτ/h from 0.05 to 5e3
    (the mode must stay relaxed at every speed).  Measured error 1.1e-2, 2.8e-3, 7.1e-4,
    1.8e-4 (ratios 3.89-3.98; 0.07 (q h)²), identical at every speed: asserted ratios
    in 3.5-4.5, error below 0.2 (q h)², spread over speeds below 1e-9.  With E∞ = E0 (D ≡ 0)
    the cell kernel equals the sampled one exactly (measured 0; asserted 1e-14)."""
    sls = StandardLinearSolid(E0=1.0, Einf=10.0, tau=1.0, nu=0.4)
    errs = []
    for n in (32, 64, 128, 256):
        cell = Cell(1.3, 0.7, n, n)
        _, Y = cell.coordinates()
        qy = 2 * np.pi * 2 / cell.Ly
        S = 1.0 if layer is None else layer.factor(np.array([qy]), sls.nu)[0]
        relaxed = 2 * (1 - sls.nu**2) * S / (sls.E0 * qy)
        by_speed = []
        for vx in (0.003, 0.3, 30.0):
            u = SpectralOperator(cell, sls, layer, velocity=(vx, 0.0)).apply(np.cos(qy * Y))
            by_speed.append(np.abs(u - relaxed * np.cos(qy * Y)).max() / relaxed)
        assert np.ptp(by_speed) < 1e-9
        assert by_speed[0] < 0.2 * (qy * cell.hy) ** 2
        errs.append(by_speed[0])
    assert all(3.5 < a / b < 4.5 for a, b in zip(errs, errs[1:], strict=False)), errs
    # D ≡ 0: the image sum of the delayed part itself vanishes, and the operators agree
    cell, v = Cell(1.3, 0.7, 24, 20), (0.03, -0.02)
    no_delay = StandardLinearSolid(1.0, 1.0, 1.0, 0.4)
    sampled = SpectralOperator(cell, no_delay, layer, velocity=v, delayed="sampled").kernel
    scale = np.abs(sampled).max()
    assert np.abs(delayed_kernel(cell, no_delay, layer, v)).max() <= 1e-14 * scale
    for mat in (no_delay, Elastic(1.0, 0.4)):
        a = SpectralOperator(cell, mat, layer, velocity=v, delayed="cell").kernel
        np.testing.assert_allclose(a, sampled, rtol=0, atol=1e-14 * scale)


@pytest.mark.parametrize("extrapolate", [False, True])
def test_elastic_seed_scene_releases_dgamma_at_its_balanced_edges(extrapolate):
    """docs/theory.md, "Outputs": G at the balanced edge is Δγ − δL_P/δA, and δL_P ≡ 0 in an
    elastic scene: G1 = G2 = Δγ, as the 1D method reports and the grid's front outputs
    give.  The seed path read the band means' δU/δA interpolated linearly to the
    sharp-crack edge: 1.049 Δγ (1.058 with the extrapolated edge) at a0 = 16 cells of 1024
    per wavelength, an O(a0²) error of the interpolation, not of the edge.  Asserted to
    1e-12."""
    a0 = 16 * 2 * np.pi / 1024
    ds = sb.solve(sb.Scene.sinusoid(0.0, BETA, GAMMA, p_tilde=0.15, a0_tilde=a0,
                                    cells_per_wavelength=1024, ny=2,
                                    solver={"extrapolate_a0": extrapolate}))
    assert ds.status.item() == "partial"
    assert ds.G1_over_dgamma.item() == pytest.approx(1.0, abs=1e-12)
    assert ds.G2_over_dgamma.item() == pytest.approx(1.0, abs=1e-12)
