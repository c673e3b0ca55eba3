"""The seed's 1D method (Section 3): adhesive viscoelastic sliding of a rigid sinusoid
h = Λ cos(kx) on a half-plane, with continuous contact edges.

Discretisation (spectral, on the contact domain [-l1, l2] only)
    The pressure is ``p(x) = Σ_m c_m T_m(ξ)/√(1-ξ²)``, x = c + aξ, c = (l2-l1)/2,
    a = (l1+l2)/2: the square-root edge singularity of adhesive contact is built in, and the
    stress-intensity factors follow from the coefficients.  Eq. (15) is collocated at the
    Chebyshev roots.

Kernel (seed Eq. (13) / (A.18), with p = -σ so that u = ∫ C p)
    ``C(x) = -(2(1-ν²)/(π E_ref)) log|2 sin(kx/2)| + R(x)`` with E_ref = E∞ for a viscoelastic
    material (the glassy log singularity of Eq. 13: J(0) = 1/E∞) and E_ref = E for an elastic
    one (R = 0).  ``log|2 sin(θ/2)| = log|θ| + log sinc(θ/2π)``: the first term is integrated
    exactly against the basis (∫ log|ξ-σ| T_m(σ)/√(1-σ²) dσ = -(π/m) T_m(ξ)), the rest is
    smooth.  R has Fourier coefficients ``2(1-ν²)(1/E(nkv) - 1/E∞)/(|n|k)``: its 1/n² and
    1/n³ tails are summed in closed form (Clausen functions Cl2, Cl3), the rest is tabulated by
    FFT and interpolated, with the Clausen kinks at the origin evaluated exactly.  The
    smooth part is integrated against all basis functions at once by a DCT in φ (σ = cos φ).

Edge energy balance (Eqs. 3, 7-10, 16-17, 20-21) with an explicit advance width a0
    δL_i is the work of Eq. (8) of closing the strip of width a0 just outside edge i at fixed Δ
    (the other edge fixed): ``δL = ½∫_strip g₋ t₊ dx`` with the gap g₋ before and the tensile
    stress t₊ = -p₊ after closure (docs/derivations.md §3), integrated by Gauss-Jacobi
    quadrature that carries the √ end behaviours.  Equilibrium: δL_i/a0 = Δγ at both edges.
    δU (Eq. 9) and δL_P (Eq. 10) are computed on the same perturbation; G_i = δU_i/a0, which
    at equilibrium is Eq. (20)/(21).  a0 = 0 selects the strict limit through the SIF:
    δL/δl = K²/(2 E_tip*) with E_tip = E∞ (glassy tip) for a viscoelastic material.

Units follow :mod:`spectralbem.conventions`; :func:`solve` is the dimensionless entry point.

Modules: ``special`` (Clausen functions, interpolation), ``kernel`` (Kernel1D), ``domain``
(Domain, the Chebyshev basis), ``problem`` (Sinusoid1D: states, edge law, equilibrium,
friction), ``branches`` (dimensionless problems, traced branches, verified statuses),
``api`` (solve, sweep, special_points).
"""

from .api import SCALARS, solve, special_points, sweep
from .branches import (
    A0_MIN,
    NXI,
    STATUSES,
    Verdict,
    branch_point,
    branch_slope,
    dimensionless_material,
    dimensionless_problem,
)
from .domain import Q_ANALYTIC, Domain
from .kernel import Kernel1D
from .problem import EdgeWork, Sinusoid1D, State
from .special import clausen2, clausen3, log_sinc

__all__ = ["A0_MIN", "NXI", "Q_ANALYTIC", "SCALARS", "STATUSES", "Domain", "EdgeWork",
           "Kernel1D", "Sinusoid1D", "State", "Verdict", "branch_point", "branch_slope",
           "clausen2", "clausen3", "dimensionless_material", "dimensionless_problem",
           "log_sinc", "solve", "special_points", "sweep"]

