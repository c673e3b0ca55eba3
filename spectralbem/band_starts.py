"""Warm starts of the band solves of an adhesive solve
(:func:`spectralbem.adhesive.solve_adhesive`).

Each front test closes or opens bands along the front, one masked solve per (colour, side,
band) at fixed Δ (:func:`spectralbem.criterion.front_tests`), started from the state's
pressure p.  From one outer iteration to the next the front moves by a few cells, so the
correction a band solve adds to p (its solution minus p, local to the band and decaying
away from it) changes little: the next test of the same band starts from p plus the last
correction instead of p alone, and its first residual is that of the front's move instead
of the whole band's.  The answer is the solve's, to its tolerance; only the number of Krylov
products changes (measured on the rough cases of docs/rough_convergence.md: 33 % fewer band
products on the viscoelastic loading state at 512², 22 % on the elastic one, the same states;
docs/performance.md).

The corrections are kept in float32 (a start needs no more), the latest of each band, on the
cells of the mask and its outer bands (their indices in 32 bits), where the band solves
have unknowns (on a rough contact of 20-50 % of the cells, about one N² float64 array for
the eight bands of a viscoelastic test), and added to the start packed
(masked.solve_masked's ``x0_add``): no full-grid copy of a start is made.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BandStarts"]


class BandStarts:
    """The corrections of the band solves by key (colour, side, band): the latest of each
    key, packed on the cells of the front test that made it (one generation of cells per
    test, kept while a key refers to it)."""

    def __init__(self):
        self._cells = {}  # generation -> flat cells (sorted)
        self._values = {}  # key -> (generation, float32 corrections on its cells)
        self._gen = -1

    def begin(self, cells: np.ndarray) -> None:
        """A new front test whose band solves have unknowns on ``cells`` (bool, N²)."""
        self._gen += 1
        flat = np.flatnonzero(cells)  # 32-bit indices where they fit: half the memory
        self._cells[self._gen] = flat.astype(np.int32) if cells.size < 2**31 else flat
        self._drop()

    def start(self, key):
        """(flat cells, corrections) to add to the state's pressure for the start of the band
        solve ``key`` (masked.solve_masked's ``x0_add``), or None when there is none."""
        last = self._values.get(key)
        return None if last is None else (self._cells[last[0]], last[1])

    def keep(self, key, field: np.ndarray, p: np.ndarray) -> None:
        """Keep the correction ``field`` − p of the band solve ``key`` (the test under way's)."""
        if self._gen < 0:
            raise RuntimeError("BandStarts.keep before begin")
        cells = self._cells[self._gen]
        self._values[key] = (self._gen,
                             (field.ravel()[cells] - p.ravel()[cells]).astype(np.float32))
        self._drop()

    def keep_only(self, wanted) -> None:
        """Drop the corrections of the keys for which ``wanted(key)`` is false."""
        for key in [k for k in self._values if not wanted(k)]:
            del self._values[key]
        self._drop()

    def _drop(self) -> None:
        used = {g for g, _ in self._values.values()} | {self._gen}
        for g in [g for g in self._cells if g not in used]:
            del self._cells[g]
