"""The seed's 1D method (Section 3) against Westergaard, Johnson (1995), the viscoelastic
closed forms and the energy identities (the seed's qualitative claims:
tests/test_seed_claims.py)."""

import numpy as np
import pytest

from spectralbem import reference as ref
from spectralbem import sinusoid1d as s1
from spectralbem.materials import Elastic, StandardLinearSolid
from spectralbem.oned import problem

GAMMA, BETA = 0.008, 10.0


def test_clausen_functions():
    import mpmath as mp

    th = np.linspace(-7, 7, 41)
    np.testing.assert_allclose(s1.clausen2(th), [float(mp.clsin(2, t)) for t in th], atol=1e-13)
    np.testing.assert_allclose(s1.clausen3(th), [float(mp.clcos(3, t)) for t in th], atol=1e-13)


def test_viscoelastic_kernel_against_direct_fourier_sum():
    """R(x) from the table + Clausen tails equals the brute-force series (truncation < 1e-7)."""
    mat = StandardLinearSolid(1.0, BETA, 1.0, 0.0)
    kern = s1.Kernel1D(mat, 1.0, 0.1)
    d = np.array([1e-3, 0.01, 0.3, 2.5, -0.5])
    n = np.arange(1, 2_000_001)
    Rn = 2 * (mat.compliance(0.1 * n) - 1 / BETA) / n
    direct = [np.sum((Rn * np.exp(1j * n * x)).real) / np.pi for x in d]
    # the direct sum's own truncation error is ~ α/(π ζ N) ≈ 1.4e-6 near the origin
    np.testing.assert_allclose(kern.remainder(d), direct, atol=3e-6)


def test_remainder_matrix_equals_elementwise_remainder():
    """The compiled M × Q pass equals R at each distance (the numpy path, including the
    distances beyond a period and the exact near-origin correction) to rounding."""
    kern = s1.Kernel1D(StandardLinearSolid(1.0, BETA, 1.0, 0.0), 1.0, 0.01)
    x = np.array([-7.0, -0.3, 0.0, 1e-4, 0.2, 3.0, 6.5])
    y = np.linspace(-1.2, 1.3, 301)
    F = kern.remainder_matrix(x, y)
    from spectralbem import kernels

    args = (kern._cubic, x, y, kern.lam, 1 / kern.dx, 16.0)
    G, near_g = np.empty_like(F), np.empty(F.size, dtype=np.intp)
    H, near_h = np.empty_like(F), np.empty(F.size, dtype=np.intp)
    ng = kernels.periodic_cubic_numpy(*args, G, near_g)
    nh = kernels.periodic_cubic(*args, H, near_h)
    assert nh == ng > 0  # the near-origin entries are exercised, the same ones
    np.testing.assert_array_equal(near_h[:nh], near_g[:ng])
    # the same cubic at positions that may differ by the rounding of the modulo
    tol = 1e-13 * np.abs(F).max()
    np.testing.assert_allclose(H, G, atol=tol)
    for j, xj in enumerate(x):
        np.testing.assert_allclose(F[j], kern.remainder(xj - y), atol=tol)


@pytest.mark.parametrize("l1, l2", [(0.3, 0.2), (1.15, 1.12), (3.0, 3.05)])
def test_response_with_adaptive_analytic_nodes(monkeypatch, l1, l2):
    """The log-sinc part on the adaptive number of nodes (analytic_nodes) equals the one on
    Q_ANALYTIC nodes to 1e-12 relative, for points inside, beside and far from the contact
    (small, medium and nearly full contact: 2π − (l1 + l2) = 5.8, 4.0, 0.23)."""
    kern = s1.Kernel1D(StandardLinearSolid(1.0, BETA, 1.0, 0.0), 1.0, 0.1)
    dom = s1.Domain(l1, l2, 64, 2048)
    x = np.concatenate([dom.x, [-l1 - 0.01, l2 + 0.01, l2 + 1.0, np.pi]])
    A = dom.response(kern, x)
    assert dom.analytic_nodes(x, kern.lam) < s1.Q_ANALYTIC or l1 + l2 > 6
    monkeypatch.setattr(s1.Domain, "analytic_nodes", lambda self, x, lam: s1.Q_ANALYTIC)
    B = dom.response(kern, x)
    np.testing.assert_allclose(A, B, rtol=0, atol=1e-12 * np.abs(B).max())


@pytest.mark.parametrize("p_tilde", [0.05, 0.15, 0.5])
def test_westergaard(p_tilde):
    ds = s1.solve(0.0, BETA, 0.0, p_tilde=p_tilde, a0_tilde=0.0, adhesiveless_reference=False)
    # the spectral method is exact for Westergaard's pressure up to round-off
    assert ds.a_tilde.item() == pytest.approx(ref.westergaard_a(p_tilde), rel=1e-10)
    assert ds.delta_tilde.item() == pytest.approx(ref.westergaard_delta(p_tilde), rel=1e-10)
    assert abs(ds.e_tilde.item()) < 1e-10


@pytest.mark.parametrize("zeta, beta_eff", [(0.0, 1.0), (np.inf, BETA)])
@pytest.mark.parametrize("a0", [0.0, 1e-6])
@pytest.mark.parametrize("p_tilde", [0.15, -0.02])
def test_johnson_elastic_limits(zeta, beta_eff, a0, p_tilde):
    ds = s1.solve(zeta, BETA, GAMMA, p_tilde=p_tilde, a0_tilde=a0, adhesiveless_reference=False)
    a_ref = ref.johnson_a(p_tilde, GAMMA, beta_eff)
    # acceptance: ã within 1e-5 (a finite a0 moves the edges in by a0/2 ~ 5e-7)
    assert ds.a_tilde.item() == pytest.approx(a_ref, rel=1e-5)
    if a0 == 0:
        assert ds.delta_tilde.item() == pytest.approx(
            ref.johnson_delta(a_ref, p_tilde, beta_eff), rel=1e-6)
    # G1 = G2 = Δγ within 1e-4 (exact in the elastic limit: δL_P = 0)
    assert ds.G1_over_dgamma.item() == pytest.approx(1.0, abs=1e-4)
    assert ds.G2_over_dgamma.item() == pytest.approx(1.0, abs=1e-4)


@pytest.mark.parametrize("zeta, beta_eff", [(0.0, 1.0), (np.inf, BETA)])
def test_special_points_elastic_limits(zeta, beta_eff):
    sp = s1.special_points(zeta, BETA, GAMMA, a0_tilde=0.0, n=30, cheb=16)
    rj = ref.johnson_special_points(GAMMA, beta_eff)
    for key in ("p_min", "a_pmin", "p_max", "a_pmax", "a0", "delta_min", "p_dmin", "T"):
        assert sp[key] == pytest.approx(rj[key], rel=1e-3), key  # acceptance: 1e-3
    # and the closed forms' values tabulated independently to 6 digits
    table = {0.0: (-0.047881, 0.591038, 0.06566), np.inf: (-0.102716, 8.354, 0.03382)}[zeta]
    assert sp["p_min"] == pytest.approx(table[0], rel=1e-3)
    assert sp["p_max"] == pytest.approx(table[1], rel=1e-3)
    assert sp["T"] == pytest.approx(table[2], rel=1e-3)


def test_finite_a0_moves_edges_inward_linearly():
    """Elastic, fixed Δ: l_i(a0) = l_i(0) - c a0 + O(a0²).

    The singular tip terms alone (Irwin: δL/a0 = K₋K₊/(2E*)) give c = ½; the next terms of the
    tip expansion enter at the same order, and for this state c = 0.4598, robust to modes and
    strip nodes (checked at M = 64/128, 48/96 nodes).  Asserted: c within 10 % of ½, the
    same at both edges, and the remainder quadratic.
    """
    base = s1.solve(0.0, BETA, GAMMA, delta_tilde=0.3, a0_tilde=0.0,
                    adhesiveless_reference=False)
    c = {}
    for a0 in (1e-4, 1e-3, 4e-3):
        ds = s1.solve(0.0, BETA, GAMMA, delta_tilde=0.3, a0_tilde=a0,
                      adhesiveless_reference=False)
        c[a0] = [(base.attrs[k] - ds.attrs[k]) / a0 for k in ("l1_tilde", "l2_tilde")]
    assert c[1e-3][0] == pytest.approx(c[1e-3][1], rel=1e-6)  # symmetric elastic contact
    assert c[1e-4][0] == pytest.approx(0.5, rel=0.1)
    # shift = c0 a0 + c1 a0²: the slope of c(a0) is the same on both intervals (10 %)
    s1_ = (c[1e-3][0] - c[1e-4][0]) / 0.9e-3
    s2_ = (c[4e-3][0] - c[1e-3][0]) / 3e-3
    assert s2_ == pytest.approx(s1_, rel=0.1)


@pytest.fixture(scope="module")
def visco_state():
    pr = s1.dimensionless_problem(0.1, BETA, GAMMA, 0.01)
    st = pr.equilibrium(mean_pressure=0.15 * pr.p_star())
    assert st.info.converged
    return pr, st


def test_energy_identities(visco_state):
    pr, st = visco_state
    for ew in st.work:
        # Eq. (6): δL = δU + δL_P, each from its own quadrature (acceptance 1e-10)
        assert ew.dL == pytest.approx(ew.dU + ew.dLP, rel=1e-10)
        assert abs(ew.dLP) > 1e-3 * abs(ew.dL)  # the viscoelastic term is really there
    el = s1.Sinusoid1D(Elastic(1.0, 0.0), 1.0, 1.0, dgamma=np.pi * GAMMA, a0=0.01)
    est = el.equilibrium(mean_pressure=0.075)
    for ew in est.work:  # Betti reciprocity: δL_P = 0 for an elastic material
        assert abs(ew.dLP) < 1e-10 * abs(ew.dL)


def test_friction_energy_balance(visco_state):
    """μ (Eq. 19) = bulk dissipation (docs/derivations.md §5) + the sharp-tip energy exchange
    (K1² - K2²)/(2E∞* λ p∞), which vanishes in the strict limit a0 = 0 and without adhesion."""
    pr, st = visco_state
    K1, K2 = st.K
    tip = (K1**2 - K2**2) / (2 * pr.Estar_tip * pr.lam * st.mean_pressure)
    # the dissipation series is summed to 2e4 terms with an asymptotic tail: ~1e-6 accurate
    assert pr.friction(st) == pytest.approx(pr.friction_dissipation(st, 20000) + tip, rel=1e-5)
    plain = s1.dimensionless_problem(0.3, BETA, 0.0)
    s0 = plain.equilibrium(mean_pressure=0.075)
    assert plain.friction(s0) == pytest.approx(plain.friction_dissipation(s0, 20000), rel=1e-6)


# an independent Fourier-series solver of the same problem (±1e-3 in ã and ẽ, 4-5 digits in μ)
@pytest.mark.parametrize("zeta, a_ref, e_ref, mu_ref", [(0.1, 0.7497, 0.0445, 0.07807),
                                                        (1.0, 0.4068, 0.2681, 0.34400),
                                                        (10.0, 0.2472, 0.0572, 0.06297)])
def test_adhesiveless_viscoelastic_table(zeta, a_ref, e_ref, mu_ref):
    ds = s1.solve(zeta, BETA, 0.0, p_tilde=0.15, a0_tilde=0.0, adhesiveless_reference=False)
    assert ds.a_tilde.item() == pytest.approx(a_ref, abs=1e-3)
    assert ds.e_tilde.item() == pytest.approx(e_ref, abs=1e-3)
    assert ds.mu_bar.item() == pytest.approx(mu_ref, rel=2e-4)


def test_adhesiveless_asymptotes_and_full_contact():
    # low speed: μ/Λ̃ ≈ (ζ/2)(1-1/β)(2-p̃); O(ζ) corrections: 1 % at ζ = 3e-3
    ds = s1.solve(3e-3, BETA, 0.0, p_tilde=0.15, a0_tilde=0.0, adhesiveless_reference=False)
    assert ds.mu_bar.item() == pytest.approx(1.5e-3 * 0.9 * 1.85, rel=1e-2)
    # high speed: μ/Λ̃ ≈ ((β-1)/(βζ)) p̃ (½ - ln(p̃/β)); O(1/ζ) corrections: 1e-3 at ζ = 1e3
    ds = s1.solve(1e3, BETA, 0.0, p_tilde=0.15, a0_tilde=0.0, adhesiveless_reference=False)
    assert ds.mu_bar.item() == pytest.approx(0.9 / 1e3 * 0.15 * (0.5 - np.log(0.015)),
                                             rel=1e-3)
    # full contact above p̃ = |E(ζ)|/E0, closed form
    ratio = ref.sls_ratio(1.0, BETA)
    ds = s1.solve(1.0, BETA, 0.0, p_tilde=1.01 * abs(ratio), a0_tilde=0.0)
    assert ds.status.item() == "full_contact"
    assert ds.mu_bar.item() == pytest.approx(ref.visco_full_contact_mu(1.01 * abs(ratio), ratio),
                                             rel=1e-12)
    below = s1.solve(1.0, BETA, 0.0, p_tilde=0.9 * abs(ratio), a0_tilde=0.0,
                     adhesiveless_reference=False)
    assert below.status.item() == "partial" and below.a_tilde.item() < np.pi


def test_equilibrium_rejects_a_state_that_interpenetrates(monkeypatch):
    """Balanced edges are not enough: a contact on the flank ([0.4, 1.6], the crest x = 0
    outside it) at the Δ of the crest contact crosses the rigid profile near the crest, and
    equilibrium() must report it as not converged (the root finder is made to return it)."""
    from types import SimpleNamespace

    pr = s1.dimensionless_problem(0.0, 10.0, 0.008, 0.01)
    good = pr.equilibrium(mean_pressure=0.15 * pr.p_star())
    assert good.info.converged and good.info.interpenetration == 0.0
    # the root finder's unknowns are the half-width and centre (a, c) = (0.6, 1.0)
    flank = SimpleNamespace(x=np.array([0.6, 1.0]), fun=np.zeros(2), message="forced",
                            nfev=1)
    monkeypatch.setattr(problem, "root", lambda *a, **k: flank)
    bad = pr.equilibrium(penetration=good.penetration)
    assert not bad.info.converged
    assert bad.info.interpenetration > 1e-3 and "inadmissible" in bad.info.message


def test_special_points_retrace_a_branch_lost_near_snap_in():
    """ζ = 0.1, ã0 = 1e-3: on the coarse ã grid the branch solver loses the branch after
    ã = 1.93 while the load still rises, so the snap-in maximum used to be nan; the gap is
    now traced again in smaller steps and the maximum is interior (the largest load on the
    traced branch, within the refine's xatol: values are flat there, 1e-8)."""
    sp = s1.special_points(0.1, 10.0, 0.008, a0_tilde=1e-3, n=16, cheb=8)
    br = sp["branch"]
    assert np.isfinite(sp["p_max"]) and np.isfinite(sp["a_pmax"])
    assert sp["p_max"] >= np.max(br["p_tilde"]) - 1e-8
    assert br["a_tilde"][0] < sp["a_pmax"] < br["a_tilde"][-1]
    assert np.isfinite(sp["T"]) and sp["p_min"] < 0


def test_bad_inputs():
    with pytest.raises(ValueError, match="beta"):
        s1.solve(0.1, 0.5, GAMMA, p_tilde=0.1, a0_tilde=0.01)
    with pytest.raises(ValueError, match="a0_tilde"):
        s1.solve(0.1, BETA, GAMMA, p_tilde=0.1, a0_tilde=-1.0)
    with pytest.raises(ValueError, match="exactly one"):
        s1.solve(0.1, BETA, GAMMA, a0_tilde=0.01)
    with pytest.raises(ValueError, match="zeta"):
        s1.solve(np.nan, BETA, GAMMA, p_tilde=0.1, a0_tilde=0.01)


def test_robust_equilibrium_prefers_the_rising_branch():
    """ζ = 1, p̃∞ = 0.15 (β = 10, Γ = 0.008, ã0 = 0.01) has two partial equilibria: ã = 0.898
    on the rising branch and ã = 2.194 beyond the snap-in maximum, where the load falls
    (unstable under load control; a ζ sweep continued from ζ = 0.3 reached it).  The slope
    sign and size are checked against a central difference of two independent branch points
    (± 2e-3 in ã: the load changes by ~5e-3, far above the 1e-10 balance; the one-sided step
    of 6e-4 differs by O(step) curvature, measured 0.3 %, so 1 %), and the robust solver
    started on the falling state must return the rising one."""
    pr = s1.dimensionless_problem(1.0, BETA, 0.008, 0.01)
    p = 0.15 * pr.p_star()
    fall = pr.equilibrium(mean_pressure=p, guess=(2.194 + 0.495, 2.194 - 0.495))
    assert fall.info.converged and abs(fall.domain.a - 2.1943) < 1e-3
    slope = s1.branch_slope(pr, fall, "mean_pressure")
    lo, hi = (s1.branch_point(pr, fall.domain.a + s, (fall.domain.c, fall.penetration))
              for s in (-2e-3, 2e-3))
    central = (hi.mean_pressure - lo.mean_pressure) / 4e-3
    assert slope < 0 and central < 0 and abs(slope / central - 1) < 0.01
    st = pr.robust_equilibrium(mean_pressure=p, guess=(fall.l1, fall.l2))
    assert st.info.converged and st.info.branch_slope > 0
    assert abs(st.domain.a - 0.8975705620) < 1e-8  # the cold-start state, same to 1e-8


@pytest.mark.parametrize("l1, l2", [(0.3, 0.2), (1.15, 0.9), (0.4, 2.6)])
def test_pair_from_the_half_width_equals_a_direct_solve(l1, l2):
    """Translation invariance (Sinusoid1D.shape): the coefficients combined from the three
    centre-free right-hand sides equal a direct solve of Eq. (15) on [-l1, l2] (response
    matrix built at the domain's own points, right-hand side Λ(cos kx − 1)), viscoelastic
    kernel.  Both are one LU solve of the same matrix up to rounding of the translated points:
    1e-10 relative to the largest coefficient (measured ≤ 1e-12)."""
    pr = s1.dimensionless_problem(0.1, BETA, 0.008, 0.01)
    dom = s1.Domain(l1, l2, pr.M, pr.Q)
    A = dom.response(pr.kernel, dom.x)
    direct = np.linalg.solve(A, np.column_stack([np.cos(dom.x) - 1.0, np.ones(pr.M)]))
    _, cw, c1 = pr.domain_pair(l1, l2)
    for got, want in ((cw, direct[:, 0]), (c1, direct[:, 1])):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max())
