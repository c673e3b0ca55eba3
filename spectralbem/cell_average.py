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

from .conventions import shown

#: smallest bound (relative to the kernel) of an image term that is summed
IMAGE_TOL = 2e-4


def _b(m: int) -> float:
    return 1.0 if m == 0 else 1.0 / (np.pi * (abs(m) - 0.5)) ** 2


@functools.lru_cache(maxsize=8)
def images(tol: float = IMAGE_TOL) -> tuple:
    """The image offsets (mx, my) summed at tolerance ``tol`` (symmetric under m → −m)."""
    if not 0.0 < tol < 1.0:
        raise ValueError(f"tol = {shown(tol)} must lie in (0, 1)")
    reach = int(np.ceil(0.5 + (1.0 / (np.pi**2 * tol)) ** (1 / 3))) + 1
    out = []
    for mx in range(-reach, reach + 1):
        for my in range(-reach, reach + 1):
            bound = _b(mx) * _b(my) / max(1, 2 * max(abs(mx), abs(my)) - 1)
            if bound >= tol:
                out.append((mx, my))
    return tuple(out)


def delayed_kernel(cell, material, layer, velocity, tol: float = IMAGE_TOL) -> np.ndarray:
    """Ĉ_D on the rfft half spectrum (m/Pa, unscaled), hermitian, 0 at q = 0 (the caller sets
    the mean mode).  ``layer`` None or a half-space: S is never evaluated.

    The images come in pairs ±m, so Ĉ_D(−q) = conj Ĉ_D(q) and the half spectrum holds the
    whole kernel, except where a wavevector and its negative are the same grid mode (the
    Nyquist row and column, q = 0 column): there the two representatives ±π/h are averaged,
    which makes C an exact real matrix.
    """
    qx = 2 * np.pi * np.fft.fftfreq(cell.Nx, cell.hx)
    qy = 2 * np.pi * np.fft.rfftfreq(cell.Ny, cell.hy)
    args = (cell.hx, cell.hy, material, layer, velocity, images(tol))
    out = _image_sum(qx, qy, *args)
    if cell.Nx % 2 == 0:  # the Nyquist row −π/hx and its other representative +π/hx
        r = cell.Nx // 2
        out[r] = 0.5 * (out[r] + _image_sum(np.array([np.pi / cell.hx]), qy, *args)[0])
    flip = (-np.arange(cell.Nx)) % cell.Nx  # row of −qx
    for j in {0, qy.size - 1} if cell.Ny % 2 == 0 else {0}:  # columns that hold ±q
        out[:, j] = 0.5 * (out[:, j] + np.conj(out[flip, j]))
    out[0, 0] = 0.0  # the images' sinc² vanish there only to round-off
    return out


def _image_sum(qx, qy, hx, hy, material, layer, velocity, image_set) -> np.ndarray:
    """Σ_m W(q_m) 2(1-ν²) S(|q_m|d) D(q_m·v)/|q_m| on the grid qx ⊗ qy (1D arrays).

    D and the sinc² factor along the velocity are 1D when the sliding is along an axis: the
    images are then grouped by their index along it, and each group's real 2D sum is
    multiplied by its complex 1D factor once (three real passes over the grid per image).
    """
    vx, vy = float(velocity[0]), float(velocity[1])
    c_inf, c2 = 1.0 / material.Einf, 2.0 * (1.0 - material.nu**2)
    qx, qy = qx[:, None], qy[None, :]
    shape = (qx.shape[0], qy.shape[1])
    layered = layer is not None and not layer.is_half_space
    along = 0 if vy == 0.0 else 1 if vx == 0.0 else None
    groups: dict = {}
    for m in image_set:
        groups.setdefault(m if along is None else m[along], []).append(m)
    out = np.zeros(shape, dtype=complex)
    acc, buf = np.empty(shape), np.empty(shape)
    for members in groups.values():
        acc[:] = 0.0
        for mx, my in members:
            Qx, Qy = qx + 2 * np.pi * mx / hx, qy + 2 * np.pi * my / hy
            wx = np.sinc(Qx * hx / (2 * np.pi)) ** 2
            wy = np.sinc(Qy * hy / (2 * np.pi)) ** 2
            np.hypot(Qx, Qy, out=buf)
            zero = buf[0, 0] == 0.0  # q = 0, m = 0: left to the caller
            if zero:
                buf[0, 0] = 1.0
            if layered:
                s = layer.factor(buf, material.nu)
            np.divide(wy if along == 0 else wx if along == 1 else wx * wy, buf, out=buf)
            if layered:
                buf *= s
            if zero:
                buf[0, 0] = 0.0
            if along is None:
                buf *= c2
                out += buf * (material.compliance(Qx * vx + Qy * vy) - c_inf)
            else:
                acc += buf
        if along is not None:  # the group's factor along the velocity, 1D
            Q, w, v = (Qx, wx, vx) if along == 0 else (Qy, wy, vy)
            out += acc * (c2 * w * (material.compliance(Q * v) - c_inf))
    return out
