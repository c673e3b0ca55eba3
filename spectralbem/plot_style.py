"""What every figure of :mod:`spectralbem.plotting` and :mod:`spectralbem.plot_maps` shares:
pyplot with a non-interactive backend unless ``MPLBACKEND`` says otherwise, the round-off
level of a friction coefficient, and the title of a state whose values are not verified."""

from __future__ import annotations

import os

import matplotlib

if not os.environ.get("MPLBACKEND"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = ["plt", "ROUND_OFF", "VERIFIED"]

#: statuses of verified states; points of the others are crossed out in red
VERIFIED = ("partial", "full_contact", "detached")

#: a friction coefficient below this is zero to round-off (an elastic or resting scene)
ROUND_OFF = 1e-12


def _verified(status) -> bool:
    return str(status) in VERIFIED


def _banner(status) -> str:
    """The warning line of a state whose values the solver did not verify."""
    head = ("NOT CONVERGED" if str(status) == "not_converged"
            else f"STATUS {str(status).upper().replace('_', ' ')}")
    return f"{head} — values unverified"


def _suptitle(fig, text: str, status, **kw) -> None:
    """The figure's title; for a state not verified, a red banner above it and a red frame
    round the figure so its values cannot pass for a result."""
    if _verified(status):
        fig.suptitle(text, **kw)
        return
    kw["fontsize"] = kw.get("fontsize", 10) + 2
    fig.suptitle("\n".join(filter(None, (_banner(status), text))), color="C3",
                 fontweight="bold", **kw)
    fig.patch.set_edgecolor("C3")
    fig.patch.set_linewidth(8)  # half of it inside the figure: a wider margin for it
    engine = fig.get_layout_engine()
    if engine is not None and hasattr(engine, "set"):
        engine.set(w_pad=0.12, h_pad=0.12)
