"""Observables of the adhesive band states (spectralbem.observables): the friction
observables are formed from the heights when a sum needs them, never held as fields, and
only the front tests at the state's tolerance (the final state's) record them."""

import numpy as np

from spectralbem.criterion import front_tests, loose_band_rtol
from spectralbem.materials import StandardLinearSolid
from spectralbem.observables import ProfileSlope, field_of, observe
from spectralbem.results import friction_observables
from spectralbem.spectral import Cell, SpectralOperator
from spectralbem.surfaces import self_affine

N = 32
CELL = Cell(1.0, 1.0, N, N)
H = self_affine(CELL, 0.8, rolloff=2 * np.pi * 2, cutoff=2 * np.pi * 8, rms_height=0.05,
                seed=5)
OP = SpectralOperator(CELL, StandardLinearSolid(1.0, 10.0, 1.0, 0.3), velocity=(0.3, 0.1))


def test_friction_observables_hold_the_heights_not_their_slopes():
    """force and lateral are the profile slopes −v̂·∇h and −v̂⊥·∇h (spectral derivative),
    formed on use from the caller's heights (no copy, no N² field held); their sums are
    Σ q f of those fields to round-off, and the unit observable is a scalar."""
    obs = friction_observables(OP, H)
    assert obs["load"] == 1.0
    v = np.array([0.3, 0.1]) / np.hypot(0.3, 0.1)
    for key, d in (("force", v), ("lateral", (-v[1], v[0]))):
        f = obs[key]
        assert isinstance(f, ProfileSlope) and f.heights is H
        assert np.array_equal(field_of(f), -CELL.derivative(H, d))
    q = np.random.default_rng(0).random(CELL.shape)
    sums = observe(obs, q)
    assert sums["load"] == float(q.sum())
    for key in ("force", "lateral"):
        ref = float(np.vdot(q, field_of(obs[key])))
        assert abs(sums[key] - ref) <= 1e-14 * np.sum(np.abs(q * field_of(obs[key])))
    # the slope along x of a sinusoid h = sin(2πx): −2π cos(2πx), exact on the grid
    X, _ = CELL.coordinates()
    s = ProfileSlope(CELL, np.sin(2 * np.pi * X), (1.0, 0.0)).field()
    assert np.allclose(s, -2 * np.pi * np.cos(2 * np.pi * X), atol=1e-12)


def test_only_the_tests_at_the_states_tolerance_record_the_observables():
    """An intermediate state's band tests (at the loose band tolerance) only move the front
    and record no observables; the tests at the state's tolerance, the only ones whose
    outputs are reported, record every observable for every band state."""
    mask = H > np.quantile(H, 0.7)
    w = H - H.max()
    from spectralbem.masked import solve_masked

    p = solve_masked(OP, mask, w, rtol=1e-10).field
    obs = friction_observables(OP, H)
    loose = front_tests(OP, w, mask, p, 0.01, 2.0 / N, adjoint=False, observables=obs,
                        band_rtol=loose_band_rtol(1e-10))
    exact = front_tests(OP, w, mask, p, 0.01, 2.0 / N, adjoint=False, observables=obs)
    for t in (loose.closing, loose.opening):
        assert t and all(set(lw.observables) == {"mean_pressure"} for lw in t.values())
    for t in (exact.closing, exact.opening):
        assert t and all(set(lw.observables) == {"mean_pressure", "load", "force", "lateral"}
                         for lw in t.values())
    # the band states' load is their mean pressure times the cells
    for lw in exact.closing.values():
        assert abs(lw.observables["load"] - lw.observables["mean_pressure"] * N * N) \
            <= 1e-12 * abs(lw.observables["load"])
