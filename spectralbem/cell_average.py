"""The delayed part of a viscoelastic kernel, averaged over the cells (docs/theory.md, "The
viscoelastic kernel on the grid").

The sliding kernel Ĉ(q) = 2(1-ν²) S(|q|d) C(q·v) / |q| (A.3, A.8) splits into its glassy
part, C∞ = 1/E∞ (the instantaneous response), and its delayed part D(ω) = C(ω) − C∞ (the
creep, A.7/Eq. 14).  The glassy part is sampled at the grid's wavevectors, as the elastic
kernel is.  The delayed part changes with q on the scale 1/(vτ), and vτ may be shorter than a
cell: sampled, the kernel of a grid with h > vτ sees only the relaxed slab at every resolved
wavevector although the response of a cell to its own pressure is partly glassy.  It is
therefore taken as the exact response of cell-constant pressures, averaged over each cell
(the Galerkin operator of piecewise-constant pressures), which sums the aliased images
q_m = q + 2π (mx/hx, my/hy):

    Ĉ_D(q) = Σ_m W(q_m) 2(1-ν²) S(|q_m| d) D(q_m·v) / |q_m|,
    W(Q) = sinc²(Qx hx/2) sinc²(Qy hy/2).

The images kept are those whose bound b(mx) b(my) / max(1, 2 max(|mx|, |my|) − 1) on the
term relative to Ĉ(q) is at least ``IMAGE_TOL`` (b(0) = 1, b(m) = 1/(π(|m| − ½))² bounds
W's factor; |q|/|q_m| ≤ 1/(2|m| − 1) at the zone edge; |D(q_m·v)| ≤ |C(q·v)| for the
materials of :mod:`spectralbem.materials`, whose |D| falls with |ω|).  The sum is a function
of q·v only through D, so an elastic material (D ≡ 0) gives back the sampled elastic kernel
exactly, and so does the glassy limit v → ∞.
"""

from __future__ import annotations

import functools

import numpy as np

#: smallest bound (relative to the kernel) of an image term that is summed
IMAGE_TOL = 2e-4


def _b(m: int) -> float:
    return 1.0 if m == 0 else 1.0 / (np.pi * (abs(m) - 0.5)) ** 2


@functools.lru_cache(maxsize=8)
def images(tol: float = IMAGE_TOL) -> tuple:
    """The image offsets (mx, my) summed at tolerance ``tol`` (symmetric under m → −m)."""
    if not 0.0 < tol < 1.0:
        raise ValueError(f"tol = {tol!r} must lie in (0, 1)")
    reach = int(np.ceil(0.5 + (1.0 / (np.pi**2 * tol)) ** (1 / 3))) + 1
    out = []
    for mx in range(-reach, reach + 1):
        for my in range(-reach, reach + 1):
            bound = _b(mx) * _b(my) / max(1, 2 * max(abs(mx), abs(my)) - 1)
            if bound >= tol:
                out.append((mx, my))
    return tuple(out)


def delayed_kernel(cell, material, layer, velocity, tol: float = IMAGE_TOL) -> np.ndarray:
    """Ĉ_D on the full spectrum (m/Pa, unscaled), 0 at q = 0 (the caller sets the mean mode).

    ``layer`` None or a half-space: S is never evaluated.
    """
    qx, qy = cell.wavevectors(half=False)
    hx, hy = cell.hx, cell.hy
    vx, vy = float(velocity[0]), float(velocity[1])
    c_inf = 1.0 / material.Einf
    nu = material.nu
    out = np.zeros((cell.Nx, cell.Ny), dtype=complex)
    for mx, my in images(tol):
        Qx = qx + 2 * np.pi * mx / hx
        Qy = qy + 2 * np.pi * my / hy
        w = np.sinc(Qx * hx / (2 * np.pi)) ** 2 * np.sinc(Qy * hy / (2 * np.pi)) ** 2
        if vy == 0.0:  # the frequency of a sliding along an axis is a 1D array
            d = material.compliance(Qx * vx) - c_inf
        elif vx == 0.0:
            d = material.compliance(Qy * vy) - c_inf
        else:
            d = material.compliance(Qx * vx + Qy * vy) - c_inf
        Q = np.hypot(Qx, Qy)
        k = np.divide(2.0 * (1.0 - nu**2) * w, Q, out=np.zeros(Q.shape), where=Q > 0)
        if layer is not None and not layer.is_half_space:
            k = k * layer.factor(np.where(Q > 0, Q, 1.0), nu)
        out += k * d
    return out
