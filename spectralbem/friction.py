"""The friction coefficients of a pressure field on a sliding slab: seed Eq. (19) generalised
to 2D (the force opposing the sliding and the lateral force, per unit normal force), with
the profile and spectral-dissipation forms that check it (docs/derivations.md §5); and the
sliding direction v̂ they are taken along."""

from __future__ import annotations

import numpy as np

from .spectral import SpectralOperator

__all__ = ["friction", "sliding_direction"]


def sliding_direction(op: SpectralOperator) -> np.ndarray:
    """Unit vector of the sliding velocity (x̂ when v = 0)."""
    v = op.velocity
    n = np.hypot(*v)
    return np.array([1.0, 0.0]) if n == 0 else v / n


def friction(op: SpectralOperator, heights: np.ndarray, p: np.ndarray, u: np.ndarray) -> dict:
    """Friction coefficients of a pressure field (dimensionless, per unit mean pressure; nan
    when the net normal force vanishes).

    * ``mu`` — seed Eq. (19) generalised to 2D, μ = -(1/(A0 p̄)) ∫ p (v̂·∇u) d²x, with the exact
      spectral derivative of the surface displacement u;
    * ``mu_lateral`` — the same along v̂⊥ = ẑ × v̂ (lateral force / normal force);
    * ``mu_profile`` — the force on the rigid indenter, -(1/(A0 p̄)) ∫ p (v̂·∇h) d²x; equal to
      ``mu`` in the continuum (u = w on the contact), they differ by the edge discretisation;
    * ``mu_dissipation`` — the spectral dissipation form (docs/derivations.md §5), equal to ``mu``
      by Parseval (a check of the Fourier conventions).
    """
    cell = op.cell
    vhat = sliding_direction(op)
    vperp = np.array([-vhat[1], vhat[0]])
    total = float(np.sum(p))
    if abs(total) <= 1e-9 * float(np.sum(np.abs(p))) or total == 0.0:
        # no net normal force (e.g. an adhesive contact at zero load): the ratios are undefined
        return dict(mu=np.nan, mu_lateral=np.nan, mu_profile=np.nan, mu_dissipation=np.nan)
    area = cell.cell_area
    return dict(
        mu=-float(np.sum(p * cell.derivative(u, vhat))) / total,
        mu_lateral=-float(np.sum(p * cell.derivative(u, vperp))) / total,
        mu_profile=-float(np.sum(p * cell.derivative(heights, vhat))) / total,
        mu_dissipation=op.dissipation_friction_force(p, vhat) / (total * area),
    )
