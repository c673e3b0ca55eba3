"""The detection of an oscillating or wandering front (spectralbem.moves.Oscillation)."""

import numpy as np

from spectralbem.moves import (
    OSCILLATING_SHARE,
    OSCILLATION_FLIPS,
    OSCILLATION_RUN,
    Oscillation,
)

SHAPE = (32, 32)


def _run(changes):
    """Feed the masks and changes of a front to a detector: (reasons, wandering) per step."""
    osc, mask, out = Oscillation(SHAPE), np.zeros(SHAPE, bool), []
    for k, change in enumerate(changes):
        mask = mask.copy()
        mask.ravel()[1000 + k % 20] ^= True  # every mask distinct: no exact cycle
        reason = osc.step(mask, change)
        out.append((reason, osc.wandering))
        mask ^= change
    return out


def _cells(flat):
    c = np.zeros(SHAPE, bool)
    c.ravel()[list(flat)] = True
    return c


def test_wandering_front_is_seen_where_new_cells_break_the_strict_run():
    """Ten cells flip at every step and one new cell joins each step (the rough 256² front's
    wander: a new cell now and then): the strict run (only oscillating cells) never forms,
    so the solve would run to its guard; the share of oscillating cells (10/11 ≥
    OSCILLATING_SHARE) makes it a wandering front once the ten have flipped
    OSCILLATION_FLIPS times and OSCILLATION_RUN steps have passed."""
    flip = list(range(10))
    changes = [_cells(flip + [100 + k]) for k in range(20)]
    out = _run(changes)
    assert all(reason == "" for reason, _ in out)
    first = next(k for k, (_, w) in enumerate(out) if w)
    # steps 0..FLIPS-1 flip the ten cells for the first FLIPS times; the run counts from then
    assert first == OSCILLATION_FLIPS + OSCILLATION_RUN - 1
    assert 10 / 11 >= OSCILLATING_SHARE


def test_drifting_front_of_new_cells_is_not_wandering():
    """A front that advances (new cells at every step, a few old ones flipping with them at
    a share below OSCILLATING_SHARE) is neither oscillating nor wandering."""
    flip = list(range(3))
    changes = [_cells(flip + list(range(100 + 10 * k, 110 + 10 * k))) for k in range(20)]
    assert not any(reason or w for reason, w in _run(changes))


def test_strict_oscillation_still_ends_the_solve():
    """Only oscillating cells moved OSCILLATION_RUN times in a row: the reason to stop."""
    changes = [_cells(range(10)) for _ in range(OSCILLATION_FLIPS + OSCILLATION_RUN)]
    out = _run(changes)
    assert out[-1][0].startswith("the front oscillates")
    assert out[-1][1]  # and it is wandering too
