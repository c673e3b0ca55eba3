"""Warm starts of the band solves of an adhesive solve
(:func:`spectralbem.adhesive.solve_adhesive`).

Each front test closes or opens bands along the front, one masked solve per (colour, side,
band) at fixed Δ (:func:`spectralbem.criterion.front_tests`), started from the state's
pressure p.  From one outer iteration to the next the front moves by a few cells, so the
correction a band solve adds to p (its solution minus p, local to the band and decaying
away from it) changes little: the next test of the same band starts from p plus the last
correction instead of p alone, and its first residual is that of the front's move instead
of the whole band's.  The answer is the solve's, to its tolerance; only the number of Krylov
products changes (measured on the rough cases of docs/rough_convergence.md: 29 % fewer band
products on the viscoelastic loading state at 512², 16 % on the elastic one, the same states;
docs/performance.md).

The corrections are kept in float32 (a start needs no more) on the cells of the mask and its
outer bands, where the band solves have unknowns: on a rough contact of 20-50 % of the
cells, one to two N² float64 arrays for the eight bands of a viscoelastic test.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BandStarts"]


class BandStarts:
    """The corrections of the last front test's band solves, by key (colour, side, band), and
    those of the test under way (:meth:`begin` makes the latter the former)."""

    def __init__(self):
        self._last_idx, self._last = None, {}
        self._idx, self._next = None, {}

    def begin(self, cells: np.ndarray) -> None:
        """A new front test whose band solves have unknowns on ``cells`` (bool, N²): the
        corrections of the test before become the starts."""
        if self._idx is not None:
            self._last_idx, self._last = self._idx, self._next
        self._idx, self._next = np.flatnonzero(cells), {}

    def start(self, key, p: np.ndarray) -> np.ndarray:
        """The start of the band solve ``key``: p plus that band's last correction (p itself
        when there is none)."""
        last = self._last.get(key)
        if last is None:
            return p
        x0 = p.copy()
        x0.ravel()[self._last_idx] += last
        return x0

    def keep(self, key, field: np.ndarray, p: np.ndarray) -> None:
        """Keep the correction ``field`` − p of the band solve ``key`` for the next test."""
        if self._idx is None:
            raise RuntimeError("BandStarts.keep before begin")
        self._next[key] = (field.ravel()[self._idx] - p.ravel()[self._idx]).astype(np.float32)
