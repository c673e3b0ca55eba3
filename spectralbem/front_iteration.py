"""The outer iteration of the 2D adhesive solve (:func:`spectralbem.adhesive.solve_adhesive`):
the state between iterations and one method per part of an iteration — the masked solve at
the current Δ, nucleation, the band tests and the balanced sub-cell front they give, the
mask's moves, the load correction of the sub-cell front, the status and the result
(docs/theory.md, "The 2D criterion and the sub-cell front")."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from .band_starts import BandStarts
from .brackets import (
    across,
    bracket_offsets,
    far_ends,
    flip_memory,
    kept,
    place,
    snap_cells,
)
from .contact import full_contact
from .criterion import (
    front_cells,
    front_tests,
    loose_band_rtol,
    predictor_tests,
)
from .front import (
    at_front,
    balance_residual,
    resolved_front,
    thin_features,
    unbalanced_cells,
)
from .front_outcome import FrontOutcome
from .keys import LOAD_TOL
from .masked import TRUE_RESIDUAL_MARGIN, solve_masked, solve_packed
from .moves import (
    OSCILLATION_FLIPS,
    LoadCorrection,
    Oscillation,
    blocked,
    held_offsets,
    moves,
    offsets,
    overloaded_pins,
    predictor_moves,
    release_bound,
    release_pins,
    stale_pins,
    unverified_pins,
)
from .state import AdhesiveState

#: load control: the state's solve starts again from its answer at most this many times when
#: its true residual misses the tolerance its Krylov estimate met (round-off of an operator
#: spanning many decades: a 1 µm layer under pressure, Eq. (A.5), whose Ĉ spans 4e7, read
#: 6e-7 after 14 products and 1e-10 after one restart of 10)
REFINEMENTS = 3

__all__ = ["FrontIteration", "LOAD_TOL"]


def _nucleation_flaw(op, h, mean_pressure, penetration, a0):
    """The documented rule for leaving full contact: a flaw, the disc of radius a0 centred on
    the cell of largest tension of the full-contact solution (at the prescribed load; under
    penetration control of a half-space no full-contact solution exists at an arbitrary Δ).
    None when the full contact is nowhere tensile (it cannot open) or undefined."""
    full = full_contact(op, h, mean_pressure, penetration)
    if full is None:
        return None
    p = full[0]
    if p.min() >= 0:
        return None
    cell = op.cell
    i, j = np.unravel_index(int(np.argmin(p)), p.shape)
    X, Y = cell.coordinates()
    dx = (X - X[i, j] + cell.Lx / 2) % cell.Lx - cell.Lx / 2
    dy = (Y - Y[i, j] + cell.Ly / 2) % cell.Ly - cell.Ly / 2
    return np.hypot(dx, dy) <= a0 * (1 + 1e-9)


def _richardson(s, front, s_half):
    """The offsets ``s`` of the a0 tests on the ``front`` cells replaced by Richardson's
    combination (4 s(a0/2) − s(a0))/3 with the a0/2 tests' ``s_half`` (packed over
    ``front``): a stress-intensity factor taken as linear over the bands leaves an O(a0²)
    edge error (K's curvature), which this removes (docs/theory.md, "Extrapolating the
    elastic edge"); ``s`` kept where either offset is not finite (a forced move)."""
    out = s.copy()
    sf = s[front]
    with np.errstate(invalid="ignore"):
        r = (4.0 * s_half - sf) / 3.0
    out[front] = np.where(np.isfinite(r), r, sf)
    return out


_BREAK, _NEXT = "break", "next"


class FrontIteration(FrontOutcome):
    """The outer iteration of :func:`~spectralbem.adhesive.solve_adhesive` (that module's
    docstring): its state between iterations and one method per part of an iteration."""

    def __init__(self, op, h, dgamma, a0, penetration, mean_pressure, mask0, test_kw,
                 criterion, front_tol, flaw_radius, extrapolate_a0=False, band_tol=None):
        cell = op.cell
        self.op, self.h, self.dgamma, self.a0 = op, h, dgamma, a0
        self.penetration, self.mean_pressure = penetration, mean_pressure
        self.test_kw, self.criterion, self.front_tol = test_kw, criterion, front_tol
        self.flaw_radius = flaw_radius
        self.hmin = min(cell.hx, cell.hy)
        self.phase = "exact" if criterion == "exact" else "predictor"
        self.shift = 0.0 if op.viscoelastic else 0.5 * a0
        self.hmax = hmax = float(h.max())
        self.mask = ((h >= hmax - 1e-12 * max(1.0, abs(hmax))) if mask0 is None
                     else mask0.copy())
        self.delta = penetration
        self.p = np.zeros(cell.shape)
        self.u = None
        self.corr = 0.0  # load control: the front's mean pressure minus the mask's
        self.load_steps = LoadCorrection()  # the corrections of each balanced mask
        self.escaped = False  # the mask moved once off a jump of the front's load
        self.osc = Oscillation(cell.shape)
        self.wide = None  # the oscillating cells of a rescued front (moved only if unbalanced)
        # a rescued front: its oscillating cells in features narrower than a0, held where
        # they stand (_hold_thin), and the number of their front cells left unbalanced
        self.thin = None
        self.thin_unbalanced = 0
        self.snap_free = None  # band cells of the snaps this test bisects (brackets.snap_cells)
        self.opened = np.zeros(cell.shape, bool)  # cells the criterion opened in this solve
        self.last_change = np.zeros(cell.shape, bool)
        self.flip_prev = self.flip_next = None  # brackets.flip_memory of the last move
        self.flaw_tried = False
        self.stale = 0  # pinned cells that would open but may not be released again
        self.pinned = np.zeros(cell.shape, bool)  # opened, then closed by non-penetration
        self.released = np.zeros(cell.shape, np.int8)  # times each cell's pin was released
        self.solves = 0
        self.history = []
        self.status, self.message, self.converged = "not_converged", "", False
        self.tests = None
        self.band_starts = BandStarts()  # warm starts of the band solves, test to test
        # the band tests run at a loose tolerance until a state balances, which is then
        # tested again at the state's tolerance before it is accepted (_exact_step)
        self.band_tol = (loose_band_rtol(test_kw["rtol"]) if band_tol is None
                         else max(band_tol, test_kw["rtol"]))
        self.loose = self.band_tol > test_kw["rtol"]
        # the next state is solved on a balanced mask at a new load correction: at the state's
        # tolerance even while the band tests are loose (_solve_state)
        self.load_step = False
        self.s_out = self.s_in = np.full(cell.shape, np.nan)
        self.res_out = self.held = self.outer = None
        self.moves_to = None  # viscoelastic: (outer, inner) offsets the mask moves by
        self.frac, self.rmax = float("nan"), float("nan")
        self.it = 0
        # extrapolate_a0: the warm starts of the a0/2 tests (None: no extrapolation)
        self.half_starts = BandStarts() if extrapolate_a0 else None

    # -- the loop ----------------------------------------------------------------------------
    def solve(self, max_outer: int, progress) -> AdhesiveState:
        self.max_outer = max_outer
        for it in range(1, max_outer + 1):
            self.it = it
            if progress is not None:
                progress(it, f"{self.phase}, {self._line()}")
            if self._iteration() == _BREAK:
                break
        else:  # the guard ran out on a nucleation step
            self.message = f"not converged in {max_outer} outer iterations" + (
                f"; at the last front test {100 * self.frac:.1f} % of the resolved front "
                f"balanced within {self.front_tol:g} cells (largest residual "
                f"{self.rmax:.3f} cells)" if np.isfinite(self.frac) else "")
        return self._result(progress)

    def _line(self) -> str:
        return (f"{int(self.mask.sum())} cells in contact"
                + (f", balanced {self.frac:.3f}" if np.isfinite(self.frac) else ""))

    def _iteration(self) -> str:
        if not self.mask.any():
            self.status, self.message = "detached", "the contact vanished"
            self.p = np.zeros(self.op.cell.shape)
            return _BREAK
        if self.mask.all():
            return self._full_contact()
        if not self._solve_state():
            return _BREAK
        w = self.h - self.hmax + self.delta
        if self._nucleate(w):
            return _NEXT
        outer, inner = front_cells(self.mask)
        self.outer = outer
        if self.phase == "predictor" and self._predictor_step(w, outer):
            return _NEXT
        return self._exact_step(w, outer, inner)

    # -- the parts of an iteration -------------------------------------------------------------
    def _full_contact(self) -> str:
        """The mask covers the cell: open the nucleation flaw once, else report the
        full-contact state (:mod:`spectralbem.adhesive` docstring)."""
        op, h = self.op, self.h
        # the flaw's balanced edge has the flaw radius: its mask edge lies the sharp-crack
        # shift further out (elastic scenes)
        flaw = None if self.flaw_tried else _nucleation_flaw(
            op, h, self.mean_pressure, self.penetration,
            (self.flaw_radius or self.a0) + self.shift)
        if flaw is None:
            full = full_contact(op, h, self.mean_pressure, self.penetration)
            if full is not None:  # report the full-contact state itself
                self.p, self.delta = full
            self.status, self.message = "full_contact", "the contact covers the cell"
            if self.flaw_tried:
                self.message += " (the nucleation flaw at the peak tension closed)"
            return _BREAK
        self.flaw_tried = True  # nucleation rule: open it once, let the criterion decide
        self.mask = ~flaw
        # the flaw is no move of the balance: a criterion that closes it again is no 2-cycle
        # (a stale last move would bracket the flaw's edge and accept it as balanced)
        self.last_change = np.zeros_like(flaw)
        self.flip_prev = None
        return _NEXT

    def _solve_state(self) -> bool:
        """The pressure on the mask at the prescribed load (Δ its multiplier) or Δ; False
        (with the message) when the masked solve fails."""
        op, mask, h, hmax = self.op, self.mask, self.h, self.hmax
        # a state the moving front passes through, whose front is tested at the loose band
        # tolerance, is solved at that tolerance too; the state that balances is solved again
        # at its own before its exact retest (the next iteration, self.loose then false), and
        # so is each state of a load correction on a balanced mask, whose carried load must
        # converge to LOAD_TOL (at the loose tolerance its round-off kept the seed sinusoid
        # at ζ = 0.0178, 5027 cells, correcting the load for 500 iterations)
        loose = self.loose and not self.load_step
        rtol = self.band_tol if loose else self.test_kw["rtol"]
        if self.mean_pressure is not None:
            # Σ p fixed, Δ its multiplier: one projected solve (docs/derivations.md §8)
            guard = int(20 * np.sqrt(np.count_nonzero(mask)) + 500)
            p, used = self.p, 0
            rhs = (h - hmax)[mask]  # scale: the profile's variation or the displacement
            for _ in range(1 + REFINEMENTS):
                p, n, _pairs, rel = solve_packed(op, mask, p, h - hmax,
                                                 (self.mean_pressure - self.corr) * mask.size,
                                                 rtol, guard - used)
                used += n
                self.solves += 1
                u = op.apply(p)
                r = (u - (h - hmax))[mask]
                self.delta = float(r.mean())
                scale = max(float(np.linalg.norm(rhs - rhs.mean())),
                            float(np.linalg.norm(u[mask])), 1e-300)
                rel = float(np.linalg.norm(r - self.delta)) / scale
                if rel <= TRUE_RESIDUAL_MARGIN * rtol or used >= guard:
                    break
            self.p, self.u = p, u
            if rel > TRUE_RESIDUAL_MARGIN * rtol:  # the true residual
                self.message = (f"masked solve: not converged after {used} products (guard "
                                f"{guard}): relative residual {rel:.3e}")
                return False
            return True
        res = solve_masked(op, mask, h - hmax + self.delta, x0=self.p, rtol=rtol)
        self.solves += 1
        if not res.converged:
            self.message = "masked solve: " + res.message
            return False
        self.p = res.field
        self.u = op.apply(self.p)
        return True

    def _nucleate(self, w) -> bool:
        """Contact nucleation (JKR jump-in): the cells outside the mask where the surfaces
        interpenetrate join it; True when some did."""
        pen = ~self.mask & (self.u - w < -1e-12 * max(1.0, float(np.abs(w).max())))
        if not pen.any():
            return False
        # a cell the criterion opened that interpenetrates at a later Δ (load control)
        # cannot open: it stays closed (pinned) for the rest of this solve
        self.pinned |= pen & self.opened
        self.mask |= pen
        return True

    def _predictor_step(self, w, outer) -> bool:
        """One move of the zero-solve predictor; False once it stops (then the exact tests
        take over: 'hybrid', or only evaluate the outputs: 'predictor')."""
        mask = self.mask
        self.tests = predictor_tests(self.op, w, mask, self.p, self.dgamma, self.a0, u=self.u,
                                     front_smoothing=self.test_kw["front_smoothing"],
                                     smoothing_per_radius=self.test_kw["smoothing_per_radius"])
        add, remove = predictor_moves(self.tests, mask, outer, w, self.pinned, self.hmin)
        stop = self.osc.step(mask, add | remove) if (add.any() or remove.any()) else "stop"
        if not stop:
            self.history.append((self.it, int(mask.sum()), int(add.sum()), int(remove.sum()),
                                 float(self.delta)))
            self.mask = (mask | add) & ~remove
            self.opened |= remove
            return True
        self.phase = "exact"
        self.osc = Oscillation(self.op.cell.shape)
        return False

    def _balance(self, w, outer, inner):
        """The exact band tests of the mask and what they say: the sub-cell offsets, the
        cells that would move, and the residual of the balance of the resolved front.
        Returns (add, remove, res_out) or None when a test's solve failed."""
        op, mask, hmin, a0 = self.op, self.mask, self.hmin, self.a0
        # the last state's tests (kept on a balanced mask) and offsets: freed first
        self.tests = self.moves_to = None
        self.s_out = self.s_in = None
        # the adjoint split of δL_P serves only the outputs: the final state's (_result)
        band_rtol = self.band_tol if self.loose else None
        if self.thin is not None:  # cells that flip since they were held join them
            self._hold_thin()
        half = None  # extrapolate_a0: the a0/2 tests' offsets, packed (run first: one test
        if self.half_starts is not None:  # is held at a time, not both)
            half = self._half_offsets(w, outer, inner, band_rtol)
            if half is None:
                return None
        tests = front_tests(op, w, mask, self.p, self.dgamma, a0, u=self.u, adjoint=False,
                            band_rtol=band_rtol, starts=self.band_starts, **self.test_kw)
        self.tests = tests
        self.solves += tests.solves
        if not tests.converged:
            self.message = "layer test: " + tests.message
            return None
        # the joined closing/opening arrays: offsets reads the outer values on the outer
        # front and the inner values on the inner front
        widths = (tests.width, tests.width)
        s_out, s_in = offsets(tests.F, tests.F, outer, inner, a0, self.shift > 0, widths)
        if half is not None:  # the sharp-crack edge extrapolated to a0 → 0
            s_out, s_in = _richardson(s_out, outer, half[0]), _richardson(s_in, inner, half[1])
        pinned = self.pinned
        stale = None
        if self.criterion != "predictor" and self.p.mean() > 0 and pinned.any():
            # released pins move with the balance from now on; the rest are lattice binds
            stale = release_pins(stale_pins(tests, mask, s_out, s_in, w, pinned, hmin),
                                 pinned, self.released)
        blk = blocked(tests, w)
        held = self.held = pinned | blk
        # under a tensile load, pinned cells that could open now and whose balance lies
        # beyond the whole band are unbalanced where their patch has no free edge
        # (unverified_pins)
        stuck = pinned & ~blk & inner & (s_in == -np.inf)
        s_out, s_in = held_offsets(s_out, s_in, outer, inner & held)
        if self.shift == 0.0:  # viscoelastic: the mask moves by the square-root fit's edge
            to, to_in = held_offsets(*offsets(tests.F, tests.F, outer, inner, a0, False,
                                              widths, field=True), outer, inner & held)
            to[inner] = to_in[inner]  # one array: moves reads each side on its own front
            self.moves_to = to
            del to_in
        add, remove = self._moves(w, s_out, s_in)
        cell = op.cell
        res_out, res_in = resolved_front(mask, outer, inner, a0, (cell.hx, cell.hy),
                                         tests.bands.inner_dist)
        self.stale = overloaded_pins(stale, self.p, res_in & ~held,
                                     np.sqrt(release_bound(op)))
        # a 2-cycle brackets the edge between two masks (spectralbem.brackets): where the
        # last move went deeper than a cell, the secant through both masks' offsets places
        # it, and only the flipped cells beyond it move back
        bracket, deep = bracket_offsets(tests, add, remove, self.last_change, self.flip_prev,
                                        s_out, s_in, hmin)
        memory = flip_memory(tests, add, remove, s_out, s_in)  # this mask's own offsets
        self.snap_free = None
        if deep:
            place(deep, s_out, s_in)
            if self.moves_to is not None:
                place(deep, self.moves_to, self.moves_to)
            self.snap_free = snap_cells(tests, deep)
            add, remove = self._moves(w, s_out, s_in)
        self.flip_next = memory
        # a one-deep bracketed edge lies inside its flipping cell: its centre ± h/2
        s_out[bracket] = np.clip(s_out[bracket], -0.5 * hmin, 0.5 * hmin)  # in place
        s_in[bracket] = np.clip(s_in[bracket], -0.5 * hmin, 0.5 * hmin)
        if bracket.any() or deep:  # the cells across the front: the same edge
            across(s_out, s_in, outer, inner, bracket, deep, hmin)
        self.s_out, self.s_in = s_out, s_in
        if self.thin is not None:  # held thin features' unbalanced front cells: unresolved
            bad = self.thin & far_ends(deep, s_out, s_in, lambda: unbalanced_cells(
                s_out, s_in, res_out, res_in, ~held, hmin, self.front_tol))
            self.thin_unbalanced = int(np.count_nonzero(bad))
            res_out, res_in = res_out & ~bad, res_in & ~bad
        rmax, r = far_ends(deep, s_out, s_in, lambda: balance_residual(
            s_out, s_in, res_out, res_in, ~held, hmin))
        if self.mean_pressure is not None and self.mean_pressure < 0:
            stuck = unverified_pins(mask, stuck & res_in, res_in & ~held)
        else:
            stuck[:] = False
        if stuck.any():
            rmax, r = float("inf"), np.concatenate([r, np.full(int(stuck.sum()), np.inf)])
        self.frac = float(np.mean(r <= self.front_tol)) if r.size else 1.0
        self.rmax = rmax
        self.res_out = res_out
        return add, remove, res_out

    def _half_offsets(self, w, outer, inner, band_rtol):
        """``extrapolate_a0``: the sharp-crack offsets of tests at a0/2 on the mask (the band
        a0/2 wide at every orientation), packed over the outer and inner front cells; None
        when a test's solve failed (:func:`_richardson` combines them with the a0 tests')."""
        half = front_tests(self.op, w, self.mask, self.p, self.dgamma, 0.5 * self.a0,
                           u=self.u, adjoint=False, band_rtol=band_rtol,
                           starts=self.half_starts, exact=True, **self.test_kw)
        self.solves += half.solves
        if not half.converged:
            self.message = "layer test (a0/2): " + half.message
            return None
        h_out, h_in = offsets(half.F, half.F, outer, inner, 0.5 * self.a0, True,
                              (half.width, half.width))
        return h_out[outer], h_in[inner]

    def _moves(self, w, s_out, s_in):
        """The cells that join and leave the mask (moves.moves) by the balance's edge
        (``s_out``, ``s_in``); in a viscoelastic scene by the square-root fit's edge
        (``moves_to``, docs/theory.md), and by the balance's own wherever that lies beyond
        the acceptance band, so that no cell the balance calls unbalanced is left where it
        stands (the two fits disagree by a fraction of a cell)."""
        wide = self.wide
        if wide is not None and self.snap_free is not None:  # a bisection's step is made
            wide = wide & ~self.snap_free
        if self.moves_to is None:
            add, remove = moves(self.tests, self.mask, s_out, s_in, w, self.pinned,
                                self.hmin, wide, self.front_tol)
        else:
            add, remove = moves(self.tests, self.mask, self.moves_to, self.moves_to, w,
                                self.pinned, self.hmin, wide, self.front_tol)
            beyond = np.ones(self.mask.shape, bool)
            a_lin, r_lin = moves(self.tests, self.mask, s_out, s_in, w, self.pinned,
                                 self.hmin, beyond, self.front_tol)
            add, remove = add | (a_lin & ~remove), remove | (r_lin & ~add)
        if self.thin is not None:  # held where they stand
            add &= ~self.thin
            remove &= ~self.thin
        return add, remove

    def _hold_thin(self) -> None:
        """A rescued front (``wide`` set) that oscillates still: its cells that have
        flipped ``OSCILLATION_FLIPS`` times (before the rescue or since) and lie in a feature
        narrower than a0 (front.thin_features: a tongue of the contact or a notch of the gap
        whose two sides' bands overlap, so that closing them fills it and the filled mask's
        opening band empties it again) stand from now on (:meth:`_moves`); their front
        cells that stay unbalanced are unresolved, as a patch thinner than the band is
        (:meth:`_balance`; docs/theory.md, "Features narrower than a0")."""
        cell = self.op.cell
        flipped = self.wide | (self.osc.flips >= OSCILLATION_FLIPS)
        thin = thin_features(self.mask, self.a0, (cell.hx, cell.hy)) & flipped
        if self.thin is not None:  # once held, a cell stays held
            thin |= self.thin
        self.thin = thin if thin.any() else None

    def _exact_step(self, w, outer, inner) -> str:
        """Test the front, then: converged, a load correction on a balanced mask, the end
        of an oscillating front, or the mask's move."""
        out = self._balance(w, outer, inner)
        if out is None:
            return _BREAK
        add, remove, res_out = out
        mask, front_tol = self.mask, self.front_tol
        self.history.append((self.it, int(mask.sum()), int(add.sum()), int(remove.sum()),
                             float(self.delta)))
        load_ok, new_corr = True, self.corr
        if self.mean_pressure is not None:  # the load carried by the sub-cell front
            new_corr = self._front_load() - float(self.p.mean())
            load_ok = abs(new_corr - self.corr) <= LOAD_TOL * float(np.abs(self.p).mean())
        if not res_out.any():  # no resolved patch: nothing verifies a balance
            self.rmax, self.frac = float("inf"), 0.0
        rmax, frac = self.rmax, self.frac
        if (rmax <= front_tol and load_ok) or self.criterion == "predictor":
            if self.loose:  # test it again, band solves exact
                if self.it == self.max_outer:  # no iteration left to: not verified
                    self.message = (f"not converged in {self.max_outer} outer iterations: "
                                    f"the front balanced in the band tests at "
                                    f"{self.band_tol:g}, not yet tested at the state's "
                                    f"tolerance {self.test_kw['rtol']:g}")
                    return _BREAK
                self.loose = False
                self.tests = self.res_out = None
                return _NEXT
            self._converged(load_ok)
            return _BREAK
        moving = add.any() or remove.any()
        if not res_out.any() and not moving:
            self.message = ("every contact patch is too thin for a band of width a0: the "
                            "balance cannot be verified")
            return _BREAK
        if rmax <= front_tol or not moving:
            return self._correct_load(new_corr, add, remove)
        reason = self.osc.step(mask, add | remove)
        if (reason or self.osc.wandering) and self.wide is None and self.it < self.max_outer:
            # rescue, once: the cells that oscillate move from now on only when their front
            # cell is unbalanced (beyond the acceptance band), so a front that oscillates
            # inside it settles; the status rule is unchanged (every cell balanced); also for
            # a wandering front, whose moves are mostly such cells (moves.Oscillation)
            osc = self.osc
            self.wide = osc.flips >= min(OSCILLATION_FLIPS, int(osc.flips.max()))
            self.osc = Oscillation(self.op.cell.shape)
            add, remove = self._moves(w, self.s_out, self.s_in)
            reason = self.osc.step(mask, add | remove) if (add.any() or remove.any()) else ""
        elif reason and self.wide is not None and self.thin is None \
                and self.it < self.max_outer:
            # the rescued front oscillates still: its oscillating cells in features narrower
            # than a0 stand from now on (once; _hold_thin), the others move as before
            self._hold_thin()
            if self.thin is not None:
                self.osc = Oscillation(self.op.cell.shape)
                add, remove = self._moves(w, self.s_out, self.s_in)
                reason = self.osc.step(mask, add | remove) if (add.any() or remove.any()) else ""
        if reason or self.it == self.max_outer:
            reason = reason or f"not converged in {self.max_outer} outer iterations"
            self.message = (f"{reason}; {100 * frac:.1f} % of the resolved front balanced "
                            f"within {front_tol:g} cells (largest residual {rmax:.3f} cells)")
            return _BREAK
        return self._move(add, remove)

    def _move(self, add, remove, keep: bool = True) -> str:
        """The mask follows the balance: ``add`` cells join, ``remove`` cells leave, and the
        load correction becomes the one the move keeps (:meth:`_kept_correction`; none
        with ``keep`` false: off a jump of the front's load, which no correction carries)."""
        self.corr = self._kept_correction(add | remove) if keep else 0.0
        self.mask = (self.mask | add) & ~remove
        self.load_step = False
        self.last_change = add | remove
        self.flip_prev = kept(self.flip_next, self.last_change)
        # the tests and bands of the old mask: freed before the next state's solves
        self.tests = self.res_out = self.snap_free = None
        self.opened |= remove
        return _NEXT

    def _kept_correction(self, change) -> float:
        """The load correction a mask moved by ``change`` keeps: the load of the balanced
        offsets of the front cells the move leaves standing (not within one cell of a moved
        cell), measured on the state before it; the moved cells' new edges lie at the
        nearest cells of their balanced edge (offsets within half a cell: none).  Kept
        whole, a correction grown on one balanced mask (to 22 times the load on a 32² SLS
        sphere) was carried by the next masks, which receded under it to detachment;
        dropped on every move, each move of a few cells undid the last correction (the
        rough elastic loading state at 512² took 66 outer iterations instead of 34)."""
        if self.mean_pressure is None:
            return 0.0
        near = ndimage.maximum_filter(change.view(np.uint8), size=3, mode="wrap") > 0
        return self._front_load(~near) - float(self.p.mean())

    def _front_load(self, standing=None) -> float:
        """The mean pressure the balanced sub-cell front carries (the mask's where the last
        tests left no resolved front); with ``standing`` (bool, N²), of the resolved front
        cells there only, the others at the mask's edge."""
        pm = float(self.p.mean())
        if self.tests is None or self.res_out is None:
            return pm
        cells = self.res_out if standing is None else self.res_out & standing
        return at_front(self.tests, np.where(cells, self.s_out, np.nan),
                        {"mean_pressure": pm}, self.a0)["mean_pressure"]

    def _correct_load(self, new_corr, add, remove) -> str:
        """Balanced on this mask: the front's load correction moves Δ (updated only here,
        never with the mask moving: a correction that lags a moving mask makes the edges
        cycle; a mask that moves keeps the part of the front cells it leaves standing,
        :meth:`_kept_correction`); a new Δ makes new states.  Where the front's load jumps
        across the prescribed one on this mask (:class:`~spectralbem.moves.LoadCorrection`),
        the mask moves once to the nearest cell centres of the balanced edge (``add``,
        ``remove``: the moves without the acceptance band, from no correction), and a
        second jump ends the solve."""
        if self.it == self.max_outer:
            self.message = f"not converged in {self.max_outer} outer iterations (load)"
            return _BREAK
        # a bracket of the loose tests' loads is not one of the exact tests' (they differ by
        # the loose tolerance): the exact retest starts afresh
        nxt = self.load_steps.next((hash(self.mask.tobytes()), self.loose), self.corr,
                                   new_corr, LOAD_TOL * float(np.abs(self.p).mean()))
        if nxt is None and not self.escaped and (add.any() or remove.any()):
            self.escaped = True
            return self._move(add, remove, keep=False)
        if nxt is None:
            steps = self.load_steps
            (ca, _), (cb, _) = steps.ends[1], steps.ends[-1]
            pbar = self.mean_pressure
            self.message = (
                f"load control: the sub-cell front's mean pressure jumps across the "
                f"prescribed {pbar:.6g} Pa on this mask ({pbar + steps.missed[1]:.6g} and "
                f"{pbar + steps.missed[-1]:.6g} Pa at load corrections {abs(ca - cb):.2g} Pa "
                f"apart; typically a front cell's hold by non-penetration changes with Δ); a "
                f"smaller solver.front_tol or a finer grid moves the mask instead")
            return _BREAK
        self.corr = nxt
        self.load_step = True
        self.osc.seen.clear()
        self.tests = self.res_out = None  # freed before the next state's solves
        return _NEXT
