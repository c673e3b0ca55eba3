"""Closed-form reference solutions (docs/derivations.md §6-§7), usable by users and by the tests.

Dimensionless sinusoid variables are the seed's (Section 4): ã = ka, p̃ = p/p* with
p* = E0* k Λ/2, Δ̃ = Δ/Λ (mean-level gauge), and the corrected adhesion parameter
Γ = (1-ν²)Δγ/(π E0 k Λ²) (docs/derivations.md §2).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, minimize_scalar

__all__ = ["westergaard_a", "westergaard_delta", "westergaard_pressure", "johnson_p",
           "johnson_delta", "johnson_a", "johnson_special_points", "johnson_G_asymmetric",
           "visco_full_contact_pressure", "visco_full_contact_mu", "sls_ratio", "hertz_radius",
           "hertz_penetration", "jkr_load", "jkr_penetration", "jkr_radius", "jkr_pulloff"]


# ---------------------------------------------------------------------------------------------
# Westergaard (1939): elastic adhesiveless sinusoid, docs/derivations.md §7

def westergaard_a(p_tilde):
    """ã = 2 arcsin √p̃ (0 ≤ p̃ ≤ 1)."""
    return 2.0 * np.arcsin(np.sqrt(np.clip(p_tilde, 0.0, 1.0)))


def westergaard_delta(p_tilde):
    """Δ̃ = S²(1 - ln S²) with S² = p̃ (mean-level gauge)."""
    s2 = np.clip(p_tilde, 1e-300, 1.0)
    return s2 * (1.0 - np.log(s2))


def westergaard_pressure(x, a, wavelength, p_star):
    """p(x) = 2 p* cos(kx/2) √(sin²(ka/2) - sin²(kx/2)) for |x| ≤ a, else 0."""
    k = 2 * np.pi / wavelength
    xm = (np.asarray(x) + wavelength / 2) % wavelength - wavelength / 2
    arg = np.sin(k * a / 2) ** 2 - np.sin(k * xm / 2) ** 2
    return np.where(arg > 0, 2 * p_star * np.cos(k * xm / 2) * np.sqrt(np.maximum(arg, 0)), 0.0)


# ---------------------------------------------------------------------------------------------
# Johnson (1995): adhesive elastic sinusoid, docs/derivations.md §7
# (β scales the modulus: the ζ → ∞ limit)


def johnson_p(a_tilde, Gamma, beta=1.0):
    """p̃(ã) = β sin²(ã/2) - 2√(βΓ) √tan(ã/2): Johnson's equilibrium G = Δγ in the seed's
    variables, with the modulus scaled by β (the ζ → ∞ limit; docs/derivations.md §7)."""
    t = np.asarray(a_tilde) / 2
    return beta * np.sin(t) ** 2 - 2.0 * np.sqrt(beta * Gamma) * np.sqrt(np.tan(t))


def johnson_delta(a_tilde, p_tilde, beta=1.0):
    """Δ̃ = sin²(ã/2) - 2(p̃/β) ln sin(ã/2)."""
    t = np.asarray(a_tilde) / 2
    return np.sin(t) ** 2 - 2.0 * (np.asarray(p_tilde) / beta) * np.log(np.sin(t))


def johnson_a(p_tilde, Gamma, beta=1.0):
    """Stable-branch ã at load p̃ (the branch between pull-off and jump to full contact).

    Returns nan when p̃ is below the pull-off load or above the jump to full contact.
    """
    sp = johnson_special_points(Gamma, beta)
    if not (sp["p_min"] <= p_tilde <= sp["p_max"]):
        return np.nan
    return brentq(lambda a: johnson_p(a, Gamma, beta) - p_tilde, sp["a_pmin"], sp["a_pmax"],
                  xtol=1e-15, rtol=1e-15)


def johnson_special_points(Gamma, beta=1.0):
    """Pull-off (load and fixed Δ), jump to full contact, zero-load radius and toughness.

    Keys: a_pmin, p_min (load-control pull-off); a_pmax, p_max (jump to full contact, nan when
    p̃(ã) has no local maximum); a0 (p̃ = 0); a_dmin, delta_min, p_dmin (fixed-Δ pull-off);
    T (Eq. 24 from p̃ = 0 to the fixed-Δ pull-off).
    """
    def f(a):
        return johnson_p(a, Gamma, beta)

    eps = 1e-12
    r = minimize_scalar(f, bounds=(eps, 1.5), method="bounded",
                        options={"xatol": 1e-14, "maxiter": 500})
    a_pmin = r.x
    r2 = minimize_scalar(lambda a: -f(a), bounds=(a_pmin, np.pi - 1e-9), method="bounded",
                         options={"xatol": 1e-14, "maxiter": 500})
    a_pmax, p_max = r2.x, f(r2.x)
    if a_pmax > np.pi - 1e-6:
        a_pmax, p_max = np.nan, np.nan
    hi = a_pmax if np.isfinite(a_pmax) else np.pi - 1e-9
    a0 = brentq(f, a_pmin, hi, xtol=1e-15) if f(a_pmin) < 0 < f(hi) else np.nan

    def d(a):
        return johnson_delta(a, f(a), beta)

    r3 = minimize_scalar(d, bounds=(eps, a_pmin if np.isfinite(a_pmin) else 1.0),
                         method="bounded", options={"xatol": 1e-14, "maxiter": 500})
    a_dmin = r3.x
    # toughness: T̃ = 2π ∫ p̃ dΔ̃ along the branch from ã0 down to the fixed-Δ pull-off
    a_grid = np.linspace(a0, a_dmin, 4001) if np.isfinite(a0) else np.array([a_dmin])
    pg = f(a_grid)
    dg = johnson_delta(a_grid, pg, beta)
    T = 2 * np.pi * np.trapezoid(pg, dg) if a_grid.size > 1 else np.nan
    return dict(a_pmin=a_pmin, p_min=f(a_pmin), a_pmax=a_pmax, p_max=p_max, a0=a0,
                a_dmin=a_dmin, delta_min=d(a_dmin), p_dmin=f(a_dmin), T=T)


def johnson_G_asymmetric(a_tilde, e_tilde, l1_tilde, l2_tilde, p_tilde, Gamma):
    """G_i/Δγ = cot(ã/2) B_i²/(16Γ), B_i = cos ẽ - cos(k l_i) - 2p̃ (docs/derivations.md §7)."""
    c = 1.0 / np.tan(a_tilde / 2)
    B1 = np.cos(e_tilde) - np.cos(l1_tilde) - 2 * p_tilde
    B2 = np.cos(e_tilde) - np.cos(l2_tilde) - 2 * p_tilde
    return c * B1**2 / (16 * Gamma), c * B2**2 / (16 * Gamma)


# ---------------------------------------------------------------------------------------------
# Adhesiveless viscoelastic sinusoid, docs/derivations.md §7




def visco_full_contact_pressure(kx, p_tilde, E_ratio):
    """p̃(x) = p̃∞ + Re[(E/E0) e^{ikx}] in full contact."""
    return p_tilde + np.real(E_ratio * np.exp(1j * np.asarray(kx)))


def visco_full_contact_mu(p_tilde, E_ratio):
    """μ/Λ̃ = -Im[E/E0]/(2 p̃∞) in full contact."""
    return -np.imag(E_ratio) / (2 * p_tilde)


def sls_ratio(zeta, beta):
    """E(ζ)/E0 = (1 - iζ)/(1 - iζ/β) for the standard linear solid at ω = kv."""
    return (1 - 1j * zeta) / (1 - 1j * zeta / beta)


# ---------------------------------------------------------------------------------------------
# Hertz and JKR sphere, docs/derivations.md §7; periodic correction §6

#: Δ_periodic = Δ_isolated - PERIODIC_LATTICE_CONSTANT · P/(E* L) on a square lattice of side L
PERIODIC_LATTICE_CONSTANT = 1.241493


def hertz_radius(P, R, Estar):
    """a = (3PR/(4E*))^{1/3}."""
    return (3 * P * R / (4 * Estar)) ** (1 / 3)


def hertz_penetration(P, R, Estar):
    return hertz_radius(P, R, Estar) ** 2 / R


def jkr_load(a, R, Estar, w):
    """P = 4E*a³/(3R) - √(8π w E* a³)."""
    return 4 * Estar * a**3 / (3 * R) - np.sqrt(8 * np.pi * w * Estar * a**3)


def jkr_penetration(a, R, Estar, w):
    """δ = a²/R - √(2π w a/E*)."""
    return a**2 / R - np.sqrt(2 * np.pi * w * a / Estar)


def jkr_radius(P, R, Estar, w):
    """Stable-branch JKR contact radius at load P (≥ the load-control pull-off)."""
    a_c = (9 * np.pi * w * R**2 / (8 * Estar)) ** (1 / 3)
    Pc = -1.5 * np.pi * w * R
    if P < Pc:
        return np.nan
    hi = a_c
    while jkr_load(hi, R, Estar, w) < P:
        hi *= 2
    return brentq(lambda a: jkr_load(a, R, Estar, w) - P, a_c, hi, xtol=1e-14 * hi)


def jkr_pulloff(R, w, control="load"):
    """Pull-off force: -(3/2)πwR (load control) or -(5/6)πwR (fixed grip)."""
    return -1.5 * np.pi * w * R if control == "load" else -5.0 / 6.0 * np.pi * w * R
