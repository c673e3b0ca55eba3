"""The bands of the front tests (docs/theory.md, "The 2D criterion and the sub-cell
front"): the front cells of a contact mask, the cells within a reach of the other side
(periodic Euclidean distances), each owned by its nearest front cell, the whole-layer
split of a0, and the trailing/leading colours of a sliding front.  Used by
:mod:`spectralbem.criterion`, :mod:`spectralbem.moves` and :mod:`spectralbem.front`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

__all__ = ["Bands", "bands", "bands_reach", "band_split", "band_weights", "colours",
           "front_cells", "outward_normal"]


def _wrap_edt(free: np.ndarray, sampling, pad: int, indices: bool = True):
    """Periodic Euclidean distance (and nearest-target indices, None without ``indices``)
    to the cells where free is False: ndimage's EDT on a wrap-padded copy."""
    nx, ny = free.shape
    px, py = min(pad, nx), min(pad, ny)
    big = np.pad(free, ((px, px), (py, py)), mode="wrap")
    sl = (slice(px, px + nx), slice(py, py + ny))
    if not indices:
        return ndimage.distance_transform_edt(big, sampling=sampling)[sl].copy(), None, None
    dist, (ix, iy) = ndimage.distance_transform_edt(big, sampling=sampling, return_indices=True)
    # copies, so that the padded arrays are freed (views would keep them alive)
    return dist[sl].copy(), (ix[sl] - px) % nx, (iy[sl] - py) % ny


def front_cells(mask: np.ndarray):
    """(outer, inner): cells outside A 4-adjacent to A, and cells of A 4-adjacent to the
    outside (periodic)."""
    grow = np.zeros_like(mask)
    for ax in (0, 1):
        for s in (1, -1):
            grow |= np.roll(mask, s, axis=ax)
    shrink = np.ones_like(mask)
    for ax in (0, 1):
        for s in (1, -1):
            shrink &= np.roll(mask, s, axis=ax)
    return grow & ~mask, mask & ~shrink


@dataclass
class Bands:
    """Bands of width a0 outside/inside the front, each cell assigned to a front cell."""

    outer_band: np.ndarray  # bool, cells outside A within a0
    outer_owner: np.ndarray  # flat index of the owning outer front cell (-1 elsewhere)
    inner_band: np.ndarray
    inner_owner: np.ndarray
    outer_front: np.ndarray
    inner_front: np.ndarray
    outer_dist: np.ndarray  # distance of an outside cell centre to A (m)
    inner_dist: np.ndarray  # distance of a cell of A to the outside (m)
    mask: np.ndarray  # the contact mask A the bands belong to
    spacing: tuple  # (hx, hy)
    #: (nx, ny) of :attr:`normal` on the outer front cells (flat order), kept when known
    outer_normal_: tuple | None = None
    #: the reach (m) of the cells the mask may take or give in one step: ⌈a0/h⌉ h
    #: (moves.moves), the whole layers of a0 even where the tests reach one layer further
    step_reach: float = np.inf

    def outer_normal(self, normal=None) -> tuple:
        """(nx, ny) of the outward normal on the outer front cells, in flat order (packed:
        no N² array is kept; ``normal``: :attr:`normal` if the caller has it)."""
        if self.outer_normal_ is None:
            nx, ny = self.normal if normal is None else normal
            self.outer_normal_ = (nx[self.outer_front], ny[self.outer_front])
        return self.outer_normal_

    @property
    def normal(self) -> tuple:
        """Outward unit normal (nx, ny) of A (:func:`outward_normal`), on the whole grid
        (meaningful on the front cells), computed on demand (two N² arrays)."""
        return outward_normal(self.mask, self.spacing)


def outward_normal(mask: np.ndarray, spacing: tuple) -> tuple:
    """Outward unit normal (nx, ny) of the contact mask: minus the gradient of its indicator
    smoothed by a Gaussian of σ = 2 cells, as the convolution with the Gaussian's derivative
    (no bias in angle: on straight digital fronts at 0-79° to the grid the front cells'
    mean angle is within 0.06° of the normal's, where centred differences of the smoothed
    indicator turned it by up to 0.6° towards the nearer axis); on the whole grid
    (meaningful on the front cells).  ``spacing``: (hx, hy)."""
    hx, hy = spacing
    gx = ndimage.gaussian_filter(mask, sigma=2.0, order=(1, 0), mode="wrap",
                                 output=np.float64)
    gy = ndimage.gaussian_filter(mask, sigma=2.0, order=(0, 1), mode="wrap",
                                 output=np.float64)
    gx /= hx
    gy /= hy
    nrm = np.hypot(gx, gy)
    nrm[nrm == 0] = 1.0
    gx /= -nrm
    gy /= -nrm
    return gx, gy


def band_split(a0: float, hx: float, hy: float) -> tuple:
    """(m, θ) with a0 = (m + θ) h, h = min(hx, hy), m ≥ 1 whole layers and 0 ≤ θ < 1.

    A band exactly a0 wide is tested as the interpolation of the works of m and m + 1 whole
    layers with weights (1 − θ, θ) (:func:`front_tests`): the closing work W(a) of a band of
    width a is smooth in a, so the interpolation is second order in h (docs/theory.md).
    θ within 1e-9 of a whole number counts as whole (one band, one solve)."""
    x = a0 / min(hx, hy)
    m = int(np.floor(x + 1e-9))
    theta = x - m
    if theta < 1e-9:
        theta = 0.0
    return max(m, 1), float(theta)


def band_weights(a0: float, hx: float, hy: float) -> list:
    """[(layers, weight), ...] of the whole-layer bands whose interpolation is the band of
    width a0 (one entry when a0/h is whole)."""
    m, theta = band_split(a0, hx, hy)
    return [(m, 1.0)] if theta == 0.0 else [(m, 1.0 - theta), (m + 1, theta)]


def bands_reach(a0: float, hx: float, hy: float, shape, levels: int = 1) -> float:
    """The reach (m) of the bands of a test whose band is exactly a0 wide (the cells within
    a0 and ``levels`` digital layers more, along_front.band_levels): a0 and ``levels``
    cells of the coarser axis that has more than one cell, so that the widest band holds
    the next layers along either axis."""
    return a0 + levels * max(h for h, n in ((hx, shape[0]), (hy, shape[1]),
                                            (min(hx, hy), 2)) if n > 1)


def bands(mask: np.ndarray, hx: float, hy: float, a0: float, reach: float | None = None
          ) -> Bands:
    """Bands of the cells whose centre lies within ``reach`` (m) of the other side's centres
    (default ⌈a0/h⌉ h, the widest band :func:`band_weights` tests); narrower ones are
    selected by distance."""
    outer_front, inner_front = front_cells(mask)
    step = band_weights(a0, hx, hy)[-1][0] * min(hx, hy)
    reach = reach or step
    pad = int(np.ceil(reach / min(hx, hy))) + 2
    tol = 1e-9 * min(hx, hy)
    # outside: distance from each outside cell to the nearest cell of A
    d_out, _, _ = _wrap_edt(~mask, (hx, hy), pad, indices=False)
    outer_band = ~mask & (d_out <= reach + tol)
    _, ox, oy = _wrap_edt(~outer_front, (hx, hy), pad)
    itype = np.int32 if mask.size < 2**31 else np.int64  # owner indices: half the memory
    outer_owner = np.where(outer_band, np.ravel_multi_index((ox, oy), mask.shape), -1
                           ).astype(itype)
    d_in, _, _ = _wrap_edt(mask, (hx, hy), pad, indices=False)
    inner_band = mask & (d_in <= reach + tol)
    _, ix, iy = _wrap_edt(~inner_front, (hx, hy), pad)
    inner_owner = np.where(inner_band, np.ravel_multi_index((ix, iy), mask.shape), -1
                           ).astype(itype)
    return Bands(outer_band, outer_owner, inner_band, inner_owner, outer_front, inner_front,
                 d_out, d_in, mask.copy(), (hx, hy), step_reach=step)


def colours(b: Bands, vhat, viscoelastic: bool, normal=None):
    """Front colours: one for elastic scenes, trailing/leading (v̂·n < 0 / ≥ 0) otherwise
    (``normal``: the bands' normal if the caller has it)."""
    if not viscoelastic:
        return [np.ones(b.outer_front.shape, bool)]
    nx, ny = b.normal if normal is None else normal
    vn = nx * vhat[0] + ny * vhat[1]
    return [vn < 0, vn >= 0]
