"""Units, signs and dimensionless groups — stated once, here.

Units
    SI throughout: lengths in m, pressures and moduli in Pa, times in s, velocities in m/s,
    work of adhesion Δγ in J/m².  The solver is linear, so any consistent unit system works.

Signs (the seed's, checked in docs/derivations.md §1 and by tests/test_spectral.py)
    * Fourier transform ``f(q, ω) = ∫dt d²x f e^{-i(q·x - ωt)}`` (seed Eq. A.7): a passive
      material has ``Im E(ω) < 0`` for ω > 0 (conjugate of the engineering ``E' + iE''``).
    * Steady sliding ``f(x, t) = f(x - v t)``: the indenter moves along +v relative to the slab.
      The trailing (opening) edge is at the back (−v side), the leading (closing) edge at the
      front; a positive eccentricity ẽ means the contact is shifted toward the leading edge.
    * ``u`` is the surface displacement *into* the slab, ``p = -σ`` the pressure, positive in
      compression.  The rigid profile ``h`` is the height toward the slab; the prescribed
      displacement is ``w = h - max(h) + Δ``, ``u = w`` in contact and the gap ``g = u - w ≥ 0``
      elsewhere.
    * Friction: μ = -(1/(A0 p̄)) ∫ p v̂·∇h, the force on the indenter opposing v̂ over the
      normal force (> 0 for a dissipating contact); ``mu_lateral`` is the same along
      v̂⊥ = ẑ × v̂: the lateral force's component against v̂⊥.
    * Gauge: for a half-space the q = 0 displacement mode is dropped, so Δ is measured from the
      mean level of the deformed surface (the seed's log|2 sin(kx/2)| kernel).
    * Energies use the compressive pressure (docs/derivations.md §3): ``U = ½∫p u ≥ 0``.

Controls
    A state is prescribed by exactly one of ``mean_pressure`` (Pa, load control) and
    ``penetration`` (m, displacement control): the same two names in every solver, scene
    and dataset (:func:`control`).  The seed's dimensionless ``p_tilde`` and ``delta_tilde``
    appear only at its paper-level entry points (``Scene.sinusoid``, ``sinusoid1d.solve``).

Dimensionless groups of the sinusoid h = Λ cos(kx) (seed Section 4, with the corrected Γ of
docs/derivations.md §2)
    ã = k a, ẽ = k e, p̃ = p/p* with p* = E0 k Λ/(2(1-ν²)), Δ̃ = Δ/Λ, Λ̃ = kΛ, ζ = k v τ,
    β = E∞/E0, Γ = (1-ν²)Δγ/(π E0 k Λ²), ã0 = k a0.
"""

from __future__ import annotations

import numpy as np

__all__ = ["control", "p_star", "gamma_from_dgamma", "dgamma_from_gamma", "plain", "shown"]


def plain(value):
    """``value`` with numpy scalars as Python numbers (and arrays, tuples and lists of them as
    tuples and lists of Python numbers); anything else unchanged."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple)) and any(isinstance(x, (np.generic, np.ndarray, list,
                                                                   tuple)) for x in value):
        return type(value)(plain(x) for x in value) if type(value) in (list, tuple) else value
    return value


def shown(value) -> str:
    """A value as error messages quote it: its repr, numpy scalars as plain numbers (numpy 2
    writes ``np.float64(1.0)``; messages write ``1.0``)."""
    return repr(plain(value))


def control(mean_pressure=None, penetration=None, error=ValueError, allowed=None) -> tuple:
    """(name, value) of the one prescribed control: ``("mean_pressure", p̄)`` or
    ``("penetration", Δ)``; ``error`` (a ValueError subclass) when both or neither is given
    or the value is not a finite number (``allowed``: name -> the allowed range, for the
    message; finite numbers by default)."""
    if (mean_pressure is None) == (penetration is None):
        raise error("give exactly one of mean_pressure (load control) and penetration "
                    "(displacement control)")
    name, value = (("mean_pressure", mean_pressure) if mean_pressure is not None
                   else ("penetration", penetration))
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not np.isfinite(v):
        rng = (allowed or {}).get(name, "(-inf, inf)")
        raise error(f"{name} = {shown(value)} must be a finite number (allowed {rng})")
    return name, v


def p_star(E0: float, nu: float, k: float, amplitude: float) -> float:
    """Full-contact pressure scale p* = E0* k Λ/2 (Westergaard), so p̃ = p/p*."""
    return E0 / (1.0 - nu**2) * k * amplitude / 2.0


def gamma_from_dgamma(dgamma: float, E0: float, nu: float, k: float, amplitude: float) -> float:
    """Γ = (1-ν²)Δγ/(π E0 k Λ²)."""
    return (1.0 - nu**2) * dgamma / (np.pi * E0 * k * amplitude**2)


def dgamma_from_gamma(Gamma: float, E0: float, nu: float, k: float, amplitude: float) -> float:
    """Inverse of :func:`gamma_from_dgamma`."""
    return Gamma * np.pi * E0 * k * amplitude**2 / (1.0 - nu**2)
