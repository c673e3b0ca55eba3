"""The result contract of the grid solvers.

* :class:`Solution` — what an iterative contact solver returns (Polonsky–Keer, the active
  set, the semismooth Newton method): a named tuple, read by name.
* :class:`ContactState` — a verified state of the adhesiveless problem
  (:func:`spectralbem.contact.solve_contact`), its status set once by the solver.
* :class:`AdhesiveState` — the same for the adhesive problem
  (:func:`spectralbem.adhesive.solve_adhesive`), with its sub-cell front.

Names are those of the datasets (:mod:`spectralbem.io`): ``pressure`` p (Pa, compressive
positive), ``displacement`` u (m, into the slab), ``gap`` g (m), ``contact`` (the contact
mask), ``penetration`` Δ (m), ``mean_pressure`` p̄ (Pa), ``mu`` … (spectralbem.conventions).
Status: ``partial``, ``full_contact``, ``detached`` or ``not_converged``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from .criterion import FrontTest

__all__ = ["Solution", "ContactState", "AdhesiveState", "STATUSES"]

#: the statuses a state may carry
STATUSES = ("partial", "full_contact", "detached", "not_converged")


class Solution(NamedTuple):
    """An iterative contact solver's answer: ``iterations`` counts its inner iterations (PK
    steps, Krylov products), ``outer_iterations`` its contact-set updates (0 for PK),
    ``fft_pairs`` the transforms spent (nan where not counted)."""

    pressure: np.ndarray
    displacement: np.ndarray
    penetration: float
    contact: np.ndarray
    iterations: int
    converged: bool
    message: str
    outer_iterations: int = 0
    fft_pairs: float = float("nan")


def status_of(converged: bool, contact: np.ndarray) -> str:
    """The status of a solver's answer: ``not_converged`` unless it converged, then
    ``full_contact``, ``detached`` (no contact cell) or ``partial``."""
    if not converged:
        return "not_converged"
    if np.all(contact):
        return "full_contact"
    return "partial" if np.any(contact) else "detached"


@dataclass
class ContactState:
    """A contact state on the grid (SI units, the conventions of the package)."""

    pressure: np.ndarray
    displacement: np.ndarray
    gap: np.ndarray
    contact: np.ndarray
    penetration: float
    mean_pressure: float
    status: str
    iterations: int
    converged: bool
    message: str
    method: str = ""
    mu: float = float("nan")
    mu_lateral: float = float("nan")
    mu_profile: float = float("nan")
    mu_dissipation: float = float("nan")
    diagnostics: dict = field(default_factory=dict)

    @property
    def full_contact(self) -> bool:
        return bool(np.all(self.contact))

    @property
    def area_fraction(self) -> float:
        """Fraction of the cell in contact (the mask's; an adhesive state's sub-cell front
        gives :func:`spectralbem.front.front_outputs`)."""
        return float(np.mean(self.contact))


@dataclass
class AdhesiveState(ContactState):
    """An adhesive state: the contact mask is the history variable; the sub-cell front and
    the verdict on its balance (docs/theory.md, "The 2D criterion and the sub-cell front").

    ``mean_pressure`` is the load the sub-cell front carries (the mask state's under
    penetration control or when unverified); ``iterations`` counts the front's outer
    iterations, ``solves`` the masked solves.  ``mu``, ``mu_lateral``, ``mu_profile`` and
    ``mu_dissipation`` are the mask state's (its fields over its own normal force Σ p,
    which under load control is the front's load minus the load correction): a scene's
    dataset reports the force on the profile at the balanced sub-cell front over the
    front's load (:func:`spectralbem.results.front_friction`, from the band states'
    ``observables``), as it reports the front's area (:func:`spectralbem.front.front_outputs`)."""

    tests: FrontTest | None = None  # the band tests of the final state
    offset_out: np.ndarray | None = None  # balanced edge − mask edge on outer front cells (m)
    offset_in: np.ndarray | None = None  # the same on inner front cells (m)
    solves: int = 0
    history: list = field(default_factory=list)
    a0: float = 0.0  # the advance width used: the one asked for (m)
    unresolved_patches: int = 0  # contact patches too thin for a band of width a0
    #: front cells of oscillating features narrower than a0 left unbalanced, held
    #: (FrontIteration._hold_thin): unresolved, not in the status nor the front averages
    unresolved_front: int = 0
    # a0/2 in elastic scenes (the sharp-crack edge's nominal shift from the seed's l*:
    # front.sharp_crack_offset), 0 otherwise (m)
    edge_shift: float = 0.0
    resolved: np.ndarray | None = None  # outer front cells of resolved patches
    balanced_fraction: float = float("nan")  # resolved front cells balanced within front_tol
    residual: float = float("nan")  # largest balance residual in position (cells)
    crack_tips: np.ndarray | None = None  # resolved outer front cells not held by contact
