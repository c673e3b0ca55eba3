"""Load paths: the steps of a scene's control solved one after another, the state carried
from step to step, and a step that fails, or holds front cells unbalanced, solved again in
sub-steps (docs/theory.md, "Load-path steps"); :class:`PathInterrupted` carries the
finished steps of a path stopped by Ctrl-C or SIGTERM."""

from __future__ import annotations

#: load-path sub-steps: a step of an adhesive grid path that ends not_converged or detached
#: from a verified partial state is solved again from that state by halving the step of the
#: control where it fails, at most this many times (steps down to 1/2**SUBSTEP_HALVINGS of
#: the jump; docs/theory.md, load-path steps).  A detachment is the path's once it happens
#: over the smallest step: a jump of the load can carry the front past a branch that a
#: quasi-static path follows (the JKR sphere at 256² from −150 to −230 Pa, above its pull-off
#: of −235.6 Pa, detached in one step; in two it stays in contact, tests/test_scenes.py)
SUBSTEP_HALVINGS = 3
# A partial step whose front holds cells of oscillating features narrower than a0
# unbalanced (``unresolved_front``, docs/theory.md, "Features narrower than a0") is solved
# again in sub-steps too, and such a state is accepted without them only over the smallest
# step or where the sub-steps fail: a quasi-static path may balance that front (the rough
# SLS case at 512² unloaded from 3e4 to 2.5e4 Pa: 35 cells held in one step, none in two)


def step_status(ds) -> str:
    """The status of a step's dataset ('' without one)."""
    return str(ds["status"].values) if "status" in ds else ""


def held_front(ds) -> int:
    """The front cells a step's state holds unbalanced (``unresolved_front``; 0 without)."""
    return int(ds["unresolved_front"].values) if "unresolved_front" in ds else 0


def needs_substeps(scene, ds, carried, prev, v) -> bool:
    """Whether the path step to ``v`` is to be retried in sub-steps: an adhesive grid scene
    whose step ended not_converged or detached from the verified partial state at ``prev``,
    or partial with front cells held unbalanced (:func:`held_front`)."""
    status = step_status(ds)
    return (scene.model == "grid2d" and scene.adhesive and carried is not None
            and prev is not None and prev != v
            and (status in ("not_converged", "detached")
                 or (status == "partial" and held_front(ds) > 0)))


def _accepted(ds, s, depth: int) -> bool:
    """A step's end that needs no sub-steps: partial with a state to carry and no front cell
    held unbalanced (held ones too over the smallest step), or detached over the smallest."""
    status = step_status(ds)
    if status == "partial" and s is not None:
        return depth == 0 or held_front(ds) == 0
    return status == "detached" and depth == 0


def _halved(solve_one, scene, v0, v1, state, depth: int, progress, first=None):
    """The states from the partial ``state`` at ``v0`` to the control ``v1``: the direct
    step (``first`` when already solved), else the two halves, each halved again where it
    fails (or holds front cells unbalanced), ``depth`` times at most.  Returns (dataset,
    carried state, number of steps); a direct step that holds front cells where its halves
    fail; the dataset of the last step tried when a step fails at the last depth.
    ``solve_one(scene, state, progress)`` solves one control value (solving._solve_one)."""
    ds, s = first or solve_one(scene.at_step(v1), state, progress)
    if _accepted(ds, s, depth):
        return ds, s, 1
    held = step_status(ds) == "partial" and s is not None  # kept if the halves fail
    if depth == 0:
        return ds, s, 0
    mid = 0.5 * (v0 + v1)
    dm, sm, km = _halved(solve_one, scene, v0, mid, state, depth - 1, progress)
    if km == 0:
        return (ds, s, 1) if held else (dm, sm, 0)
    # once a sub-step detached, the rest of the step starts afresh, in one step
    d1, s1, k1 = _halved(solve_one, scene, mid, v1, sm, depth - 1 if sm is not None else 0,
                         progress)
    if k1 == 0:
        return (ds, s, 1) if held else (d1, s1, 0)
    return d1, s1, km + k1


def substepped(solve_one, scene, ds, state, carried, prev, v, progress):
    """The path step prev → v, which ended not_converged or detached or held front cells
    unbalanced, solved again from the carried state by halving it where it fails
    (``SUBSTEP_HALVINGS``): (dataset, state, number of steps taken) of the last step, or the
    direct step's (``ds``, ``state``, 1) when some step fails at the smallest size."""
    direct = ds.attrs.get("solver_message", "")
    sub, s, k = _halved(solve_one, scene, prev, v, carried, SUBSTEP_HALVINGS, progress,
                        (ds, state))
    if sub is ds and k:  # partial, its held cells kept: the sub-steps failed
        ds.attrs["solver_message"] = (f"{direct}; steps from {prev:g} down to "
                                      f"1/{2 ** SUBSTEP_HALVINGS} of it did not end partial "
                                      f"without held front cells")
        return ds, state, 1
    if k:
        sub.attrs["solver_message"] = (
            f"{sub.attrs.get('solver_message', '')}; reached from {prev:g} in {k} steps of "
            f"the control (the direct step: {direct})")
        return sub, s, k
    failed = ("did not converge either" if step_status(ds) == "not_converged"
              else "failed (not converged) before the last one")
    ds.attrs["solver_message"] = (f"{direct}; steps from {prev:g} down to "
                                  f"1/{2 ** SUBSTEP_HALVINGS} of it {failed}")
    return ds, state, 1


class PathInterrupted(KeyboardInterrupt):
    """Ctrl-C during a load path after some steps finished: ``dataset`` holds those steps
    (a ``step`` dimension, as the whole path's), for the caller to keep."""

    def __init__(self, dataset, steps: int):
        super().__init__(f"{dataset.sizes.get('step', 1)} of {steps} path steps finished")
        self.dataset = dataset
