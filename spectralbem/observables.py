"""Observables of an adhesive solve: linear functionals Σ q f of a pressure field q that the
front tests record for each band state, so that integrated quantities (the load, the
friction force on the rigid profile) can be interpolated to the balanced sub-cell front
(:func:`spectralbem.front.at_front`).

An observable ``f`` is a scalar (Σ q f = f Σ q), a field of the grid's shape, or a
:class:`ProfileSlope`: the slope of the rigid profile along a direction, formed from the
heights each time a sum needs it and never held, so that a viscoelastic solve does not
carry two N² arrays of slopes through all its iterations (docs/performance.md, memory).
"""

from __future__ import annotations

import numpy as np

__all__ = ["ProfileSlope", "observe", "field_of"]


class ProfileSlope:
    """−d̂·∇h, the rigid profile's slope along the unit vector d̂ (spectral derivative,
    :meth:`spectralbem.spectral.Cell.derivative`): the friction force per unit pressure on
    the contact (Eq. (19) in 2D, −v̂·∇u = −v̂·∇h on the contact).  Holds a reference to the
    heights, not a copy: each :meth:`field` call is one FFT pair."""

    def __init__(self, cell, heights: np.ndarray, direction):
        self.cell, self.heights = cell, heights
        self.direction = (float(direction[0]), float(direction[1]))

    def field(self) -> np.ndarray:
        """The slope field −d̂·∇h (a new N² array)."""
        return -self.cell.derivative(self.heights, self.direction)


def field_of(f):
    """The field (or scalar) of an observable."""
    return f.field() if isinstance(f, ProfileSlope) else f


def observe(observables: dict, q: np.ndarray) -> dict:
    """Σ q f of each observable (name -> scalar, field or :class:`ProfileSlope`)."""
    out = {}
    for k, f in observables.items():
        f = field_of(f)
        out[k] = float(f) * float(q.sum()) if np.ndim(f) == 0 else float(np.vdot(q, f))
    return out
