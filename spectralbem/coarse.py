"""The coarse-grid start of the adhesive solve (:func:`spectralbem.adhesive.solve_adhesive`).

The front iteration moves the mask by at most the band width a0 per outer iteration, and a
start far from the balanced front (the adhesiveless contact, or the mask of the previous
load step) costs many iterations.  The same scene on the grid of half the cells per side
(same cell, material, layer and velocity; heights and Δγ sampled at every other cell, a0
unchanged in metres) is solved first — recursively, down to ``COARSE_MIN`` cells per side
or to one coarse cell per a0 — and its balanced sub-cell front, sampled at the fine cell
centres, is the fine solve's start.  The fine solve then decides the state: the start
changes which iterations are run, not the criterion or the status rule
(docs/theory.md, "Coarse-grid start"; costs in docs/performance.md).
"""

from __future__ import annotations

import numpy as np

from .bands import _wrap_edt
from .spectral import Cell, SpectralOperator

__all__ = ["COARSE_MIN", "eligible", "restrict", "prolong", "coarse_operator"]

#: the coarsest grid of the recursion has at least this many cells per side
COARSE_MIN = 64


def eligible(cell: Cell, a0: float) -> bool:
    """True when the grid halves into one of at least ``COARSE_MIN`` cells per side whose
    cells are no wider than a0 (the band test needs one whole layer)."""
    if cell.Nx % 2 or cell.Ny % 2 or min(cell.Nx, cell.Ny) < 2 * COARSE_MIN:
        return False
    return a0 >= 2.0 * min(cell.hx, cell.hy) * (1 - 1e-9)


def restrict(field):
    """A field on the coarse grid: the values at every other cell (cell centres x = 2i·h
    are the coarse centres); scalars pass through."""
    a = np.asarray(field)
    return a if a.ndim == 0 else np.ascontiguousarray(a[::2, ::2])


def coarse_operator(op: SpectralOperator) -> SpectralOperator:
    """The operator of the same scene on the grid of half the cells per side."""
    c = op.cell
    return SpectralOperator(Cell(c.Lx, c.Ly, c.Nx // 2, c.Ny // 2), op.material, op.layer,
                            op.velocity, op.threads, op.backend, op.delayed)


def _level_set(state, spacing) -> np.ndarray:
    """Signed distance (m) of each cell centre to the balanced sub-cell front, positive
    inside: the distance to the mask edge (the cell boundary, half a cell beyond the last
    centre) plus the front cell's offset of its balanced edge (``offset_out`` on outer,
    ``offset_in`` on inner front cells, clipped to one cell)."""
    mask = state.contact
    h = min(spacing)
    pad = 4
    d_in, _, _ = _wrap_edt(mask, spacing, pad, indices=False)  # inside: to the nearest outside
    d_out, _, _ = _wrap_edt(~mask, spacing, pad, indices=False)
    phi = np.where(mask, d_in - 0.5 * h, -(d_out - 0.5 * h))
    for s in (state.offset_out, state.offset_in):
        if s is not None:
            phi += np.clip(np.nan_to_num(s, nan=0.0, posinf=h, neginf=-h), -h, h)
    return phi


def prolong(state, cell: Cell) -> np.ndarray:
    """The fine mask (``cell``: the fine grid) whose cell centres lie inside the coarse
    state's balanced front: its level set (:func:`_level_set`) interpolated bilinearly
    (periodic) to the fine centres, which lie on and halfway between the coarse ones."""
    if not state.contact.any():
        return np.zeros(cell.shape, bool)
    phi = _level_set(state, (2 * cell.hx, 2 * cell.hy))
    fine = np.empty(cell.shape)
    fine[::2, ::2] = phi
    fine[1::2, ::2] = 0.5 * (phi + np.roll(phi, -1, 0))
    fine[:, 1::2] = 0.5 * (fine[:, ::2] + np.roll(fine[:, ::2], -1, 1))
    return fine > 0.0
