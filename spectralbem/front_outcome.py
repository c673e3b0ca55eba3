"""The end of the 2D adhesive front iteration (:class:`spectralbem.front_iteration.
FrontIteration`): the status its last front test earns, and the state it returns — the final
tests' release rates (the adjoint split of δL_P, Eq. (10)), the checks beyond the position
and the outputs of the balanced sub-cell front (docs/theory.md, "Convergence", "Checks beyond
the position")."""

from __future__ import annotations

import numpy as np

from .adjoint import complete_adjoint
from .friction import friction
from .front import unresolved_patches
from .moves import PIN_RELEASES, RELEASE_SLACK, crack_tips, release_out_of_bounds
from .state import AdhesiveState

__all__ = ["FrontOutcome"]


class FrontOutcome:
    """The status and result of a :class:`~spectralbem.front_iteration.FrontIteration`
    (a part of that class: it reads the iteration's state)."""

    def _converged(self, load_ok: bool = True) -> None:
        front_tol, rmax = self.front_tol, self.rmax
        self.converged = status_ok = rmax <= front_tol and not self.stale and load_ok
        self.status = "partial" if status_ok else "not_converged"
        self.message = (f"converged: every resolved front cell balanced within "
                        f"{front_tol:g} cells (largest residual {rmax:.3f})")
        if self.stale and rmax <= front_tol:
            self.message = (f"{self.stale} pinned cells would open (opening leaves a gap and "
                            f"the balance opens them; their pin was released {PIN_RELEASES} "
                            f"time(s) already) with more than √((1 + {RELEASE_SLACK:g}) β) "
                            f"times the tension of every free edge (a release rate beyond "
                            f"the glassy bound): the state is held by its pins, not "
                            f"verified; "
                            f"every other resolved front cell balanced within {front_tol:g} "
                            f"cells (largest residual {rmax:.3f})")
        if self.thin_unbalanced:
            self.message += (f"; {self.thin_unbalanced} front cells of oscillating features "
                             f"narrower than a0 (tongues of the contact, notches of the gap) "
                             f"unbalanced, held where they stood (unresolved)")
        if self.criterion == "predictor":  # one exact evaluation, no load correction
            carried = self._front_load()
            self.message = (f"predictor criterion; exact tests of the final mask: "
                            f"{100 * self.frac:.1f} % of the front balanced within "
                            f"{front_tol:g} cells (largest residual {rmax:.3f}); the front "
                            f"carries {carried:.6g} Pa of mean pressure"
                            + ("" if load_ok else
                               f", not the prescribed {self.mean_pressure:.6g} Pa (the "
                               f"predictor corrects no load: not verified)"))

    def _result(self, progress) -> AdhesiveState:
        op, cell, mask, p = self.op, self.op.cell, self.mask, self.p
        status, message, converged = self.status, self.message, self.converged
        # freed before the final adjoint solves (u is formed again for the outputs below);
        # the band starts' opening corrections are the final tests' own, the starts of the
        # adjoint's opening states (the closing ones are dropped)
        starts, self.moves_to, self.band_starts, self.u = self.band_starts, None, None, None
        if starts is not None:
            starts.keep_only(lambda key: key[1] == "open")
        if self.s_out is None:  # the last tests failed: no balanced edge
            self.s_out = self.s_in = np.full(cell.shape, np.nan)
        # the mean pressure carried by the sub-cell front (the predictor's, verified or not,
        # is the one its message names)
        pm = (self._front_load() if status == "partial" or self.criterion == "predictor"
              else float(p.mean()))
        tips = None
        if status == "partial" and self.tests is not None and self.tests.pending is not None:
            solves = self.tests.solves  # the release rates of the final state's tests
            complete_adjoint(self.tests, op, mask, p, self.test_kw["rtol"], starts)
            self.solves += self.tests.solves - solves
        del starts
        if status == "partial" and self.held is not None and self.res_out is not None:
            tips = crack_tips(self.res_out, self.held, self.outer)
            bad = release_out_of_bounds(op, self.tests, tips, self.dgamma, self.s_out,
                                        self.a0)
            if not tips.any() and self.res_out.any() and float(p.mean()) < 0:
                bad = ("no equilibrium: the contact carries a tensile mean pressure, but "
                       "every edge is held by contact (no crack tip: an adhesiveless contact "
                       "carries no tension)")
            if bad:
                status, converged = "not_converged", False
                message = (f"{bad}, although every resolved front cell lies within "
                           f"{self.front_tol:g} cells of its balanced edge")
        if status == "not_converged" and self.mean_pressure is not None \
                and self.mean_pressure < 0:
            message += ("; a tensile load beyond the pull-off has no equilibrium (penetration "
                        "control follows the branch through it)")
        if progress is not None:  # the final state's line
            progress(self.it, f"{status}, {self._line()}")
        nun = unresolved_patches(mask, self.a0, (cell.hx, cell.hy))
        if nun:
            message += f"; {nun} contact patches smaller than a disc of radius a0 (unresolved)"
        h, delta = self.h, self.delta
        u = op.apply(p)
        gap = u - (h - self.hmax + delta)
        gap[mask] = 0.0
        return AdhesiveState(
            pressure=p, displacement=u, gap=gap, contact=mask, penetration=float(delta),
            mean_pressure=pm, status=status, iterations=self.it, converged=converged,
            message=message, method="front-layer energy balance, sub-cell front",
            **friction(op, h, p, u), tests=self.tests, offset_out=self.s_out,
            offset_in=self.s_in, solves=self.solves, history=self.history, a0=self.a0,
            unresolved_patches=nun, unresolved_front=self.thin_unbalanced,
            edge_shift=self.shift, resolved=self.res_out,
            balanced_fraction=self.frac, residual=self.rmax, crack_tips=tips)
