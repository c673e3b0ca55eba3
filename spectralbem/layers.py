"""Slab geometry: the thickness factor S(|q|d) of seed Eq. (A.3), Eqs. (A.4) and (A.5).

``G(q, ω) = -2(1-ν²) S(|q|d) / (E(ω)|q|)`` (A.3).  Three geometries:

* :class:`HalfSpace` — S = 1.  The q = 0 mode is dropped (zero-mean displacement gauge, as the
  seed's kernel log|2 sin(kx/2)|): the penetration Δ is measured from the mean level of the
  deformed surface and the mean pressure is imposed separately.
* :class:`GluedLayer` — layer of thickness d bonded to a rigid plate, Eq. (A.4).  The q = 0 mode
  is physical: a uniform pressure p compresses the layer by p d/M with the confined (P-wave)
  modulus M = E(1-ν)/((1+ν)(1-2ν)); for ν = 0.5 the layer is incompressible and the q = 0
  compliance is zero.  The relaxed modulus E(0) is used at q = 0 (ω = q·v = 0).
* :class:`PressureLayer` — free layer loaded by a uniform pressure on its far face, Eq. (A.5).
  S ~ 6/(qd)³ (plate bending) as q → 0; the q = 0 mode is dropped as for the half-space.

All S are evaluated in forms that neither overflow (cosh 2s for s ≳ 355) nor cancel
(the A.5 denominator for s ≲ 1e-2, the A.4 numerator as ν → 0.5): relative error below 1e-13
for s in [1e-8, 1e8] against a 50-digit reference (tests/test_layers.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .conventions import shown

__all__ = ["Layer", "HalfSpace", "GluedLayer", "PressureLayer", "s_glued", "s_pressure",
           "LayerError"]


class LayerError(ValueError):
    """Invalid layer parameter."""


_SWITCH = 2.0  # s above which the exp-scaled forms are used


def _sinh_minus_x(x: np.ndarray) -> np.ndarray:
    """sinh(x) - x without cancellation (x >= 0)."""
    x = np.asarray(x, dtype=float)
    out = np.sinh(x) - x
    small = x < 1.0
    if np.any(small):
        xs = x[small]
        x2 = xs * xs
        term = xs * x2 / 6.0
        acc = term.copy()
        for n in range(2, 14):  # x^(2n+1)/(2n+1)!, 13 terms: < 1e-27 relative at x = 1
            term = term * x2 / ((2 * n) * (2 * n + 1))
            acc += term
        out[small] = acc
    return out


def s_glued(s, nu: float) -> np.ndarray:
    """S(s) of Eq. (A.4) (layer glued to a rigid plate), s = |q| d > 0."""
    s = np.asarray(s, dtype=float)
    c = 3.0 - 4.0 * nu
    c0 = 5.0 - 12.0 * nu + 8.0 * nu**2  # = (1 + c²)/2
    out = np.empty_like(s)
    big = s > _SWITCH
    sb = s[big]
    e2 = np.exp(-2.0 * sb)
    den = c * (1.0 + e2 * e2) + (4.0 * sb**2 + 2.0 * c0) * e2
    out[big] = (c * (1.0 - e2 * e2) - 4.0 * sb * e2) / den
    ss = s[~big]
    num = 4.0 * (1.0 - 2.0 * nu) * ss + c * _sinh_minus_x(2.0 * ss)  # = c sinh 2s - 2s
    den = 2.0 * c * np.sinh(ss) ** 2 + 2.0 * ss**2 + 8.0 * (1.0 - nu) ** 2
    out[~big] = num / den
    return out


def s_pressure(s) -> np.ndarray:
    """S(s) of Eq. (A.5) (free layer, uniform pressure on the far face), s = |q| d > 0."""
    s = np.asarray(s, dtype=float)
    out = np.empty_like(s)
    big = s > _SWITCH
    sb = s[big]
    e2 = np.exp(-2.0 * sb)
    out[big] = (1.0 - e2 * e2 + 4.0 * sb * e2) / (1.0 + e2 * e2 - (4.0 * sb**2 + 2.0) * e2)
    ss = s[~big]
    sh = np.sinh(ss)
    num = np.sinh(2.0 * ss) + 2.0 * ss
    den = 2.0 * _sinh_minus_x(ss) * (sh + ss)  # = cosh 2s - 2s² - 1
    out[~big] = num / den
    return out


class Layer:
    """Base class: ``factor(qd)`` is S, ``q0_compliance(E0, nu)`` the q = 0 compliance or None."""

    kind = "layer"
    is_half_space = False

    def factor(self, q: np.ndarray, nu: float) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def q0_compliance(self, E0: float, nu: float):
        """Displacement per unit uniform pressure (m/Pa) at q = 0, or None (mode dropped)."""
        return None


@dataclass(frozen=True)
class HalfSpace(Layer):
    """Homogeneous half-space, S = 1 (never evaluated: the operator skips S entirely)."""

    kind = "half_space"
    is_half_space = True

    def factor(self, q, nu):
        return np.ones_like(np.asarray(q, dtype=float))


def _check_d(d) -> float:
    d = float(d)
    if not np.isfinite(d) or d <= 0:
        raise LayerError(f"d = {shown(d)} (layer thickness) must be a finite number > 0")
    return d


@dataclass(frozen=True)
class GluedLayer(Layer):
    """Layer of thickness ``d`` bonded to a rigid plate, Eq. (A.4)."""

    d: float
    kind = "glued"

    def __post_init__(self):
        object.__setattr__(self, "d", _check_d(self.d))

    def factor(self, q, nu):
        return s_glued(np.asarray(q, dtype=float) * self.d, nu)

    def q0_compliance(self, E0, nu):
        """lim_{q→0} 2(1-ν²)S(qd)/(E q) = d(1+ν)(1-2ν)/(E(1-ν)) = d/M."""
        return self.d * (1.0 + nu) * (1.0 - 2.0 * nu) / (E0 * (1.0 - nu))


@dataclass(frozen=True)
class PressureLayer(Layer):
    """Free layer of thickness ``d`` under uniform pressure on the far face, Eq. (A.5)."""

    d: float
    kind = "pressure"

    def __post_init__(self):
        object.__setattr__(self, "d", _check_d(self.d))

    def factor(self, q, nu):
        return s_pressure(np.asarray(q, dtype=float) * self.d)


# -- scene kinds ([layer] kind = ...): spectralbem.kinds --------------------------------------
def _register() -> None:
    from .keys import HEIGHT, key
    from .kinds import register

    register("layer", "half_space", {}, lambda spec, context: HalfSpace())
    register("layer", "glued",
             {"thickness": key("number", "layer thickness d, glued to a rigid plate (Eq. A.4)",
                               "m", *HEIGHT)},
             lambda spec, context: GluedLayer(spec["thickness"]))
    register("layer", "pressure",
             {"thickness": key("number", "layer thickness d under uniform pressure (Eq. A.5)",
                               "m", *HEIGHT)},
             lambda spec, context: PressureLayer(spec["thickness"]))


_register()
