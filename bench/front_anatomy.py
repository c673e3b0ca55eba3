"""Where an adhesive state's front iterations go (docs/performance.md, "Anatomy of the
front iteration").

Solves the rough SLS case of ``cases/rough_convergence.toml`` along its direct load path
(1e4 → 3e4 → 1e4 Pa) and records every outer iteration of each state's front iteration
(:class:`spectralbem.front_iteration.FrontIteration`): a *nucleation* iteration (cells outside
the mask interpenetrate at the state's Δ and join it; no band test) or an *exact* one (the
band tests and the mask's move): the cells in contact, the cells the move adds and removes,
the balanced fraction of the resolved front and its largest residual (cells), Δ, and for
every changed cell how often it changed before in this state (a cell that keeps moving
back and forth is churn, not progress).  A nucleated cell is *fresh* when it never changed
before in this state, *re-closed* when the criterion had opened it.

The instrumentation wraps two methods of the solver's outer iteration for the duration of
the run (:func:`recording`): a development bench, not an API.

Usage: python bench/front_anatomy.py [--sizes 256 512] [--front-tol F]
       python bench/front_anatomy.py --report
Rows go to bench/front_anatomy.json (one per N and front_tol), the figure to
docs/figures/front_anatomy.png; ``--report`` prints the summary table from the JSON.
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import rough_convergence as rc  # noqa: E402  (bench/, beside this script)

from spectralbem import front_iteration as fi  # noqa: E402
from spectralbem.bands import outward_normal  # noqa: E402
from spectralbem.io import write_text  # noqa: E402

OUT = Path(__file__).with_name("front_anatomy.json")
FIGURE = rc.ROOT / "docs" / "figures" / "front_anatomy.png"
NAMES = ("load 1e4", "load 3e4", "unload 1e4")
#: the tail of a state: its exact iterations from the first whose front is this balanced
NEAR = 0.99


def leading(mask: np.ndarray, cells: np.ndarray) -> int:
    """How many of ``cells`` lie on the leading side of the mask's front: v̂·n ≥ 0 with the
    solver's outward normal n (bands.outward_normal) and its split of the front
    (bands.colours); v̂ = x̂, the case's sliding direction."""
    if not cells.any():
        return 0
    nx, _ = outward_normal(mask, (1.0, 1.0))  # square cells: the direction needs no h
    return int(np.count_nonzero(nx[cells] >= 0))


class Recorder:
    """The iterations of each front iteration solved while installed, one list per state."""

    def __init__(self):
        self.states = []
        self._owner = None

    def _entries(self, it):
        if self._owner is not it:  # a new state's front iteration
            self._owner = it
            self.changes = np.zeros(it.mask.shape, np.int16)
            self.states.append([])
        return self.states[-1]

    def nucleation(self, it, before, opened):
        log = self._entries(it)
        new = it.mask & ~before
        log.append(dict(kind="nucleation", it=it.it, cells=int(it.mask.sum()),
                        new=int(new.sum()), fresh=int(np.count_nonzero(self.changes[new] == 0)),
                        reclosed=int(np.count_nonzero(new & opened)),
                        leading=leading(before, new), delta=float(it.delta)))
        self.changes[new] += 1

    def exact(self, it, before):
        log = self._entries(it)
        add, rem = it.mask & ~before, before & ~it.mask
        moved = add | rem
        log.append(dict(kind="exact", it=it.it, cells=int(it.mask.sum()), add=int(add.sum()),
                        remove=int(rem.sum()), remove_leading=leading(before, rem),
                        repeat=int(np.count_nonzero(self.changes[moved] > 0)),
                        frac=float(it.frac), rmax=float(it.rmax), delta=float(it.delta)))
        self.changes[moved] += 1


@contextlib.contextmanager
def recording(rec: Recorder):
    """Wrap FrontIteration._nucleate and _exact_step so that ``rec`` sees every iteration."""
    nucleate, exact = fi.FrontIteration._nucleate, fi.FrontIteration._exact_step

    def _nucleate(self, w):
        before, opened = self.mask.copy(), self.opened.copy()
        out = nucleate(self, w)
        if out:
            rec.nucleation(self, before, opened)
        return out

    def _exact_step(self, w, outer, inner):
        before = self.mask.copy()
        out = exact(self, w, outer, inner)
        rec.exact(self, before)
        return out

    fi.FrontIteration._nucleate, fi.FrontIteration._exact_step = _nucleate, _exact_step
    try:
        yield rec
    finally:
        fi.FrontIteration._nucleate, fi.FrontIteration._exact_step = nucleate, exact


def summary(log: list) -> dict:
    """One state's counts: iterations of each kind, the tail (exact iterations from the
    first with a balanced fraction ≥ NEAR), and the cells moved and nucleated in it."""
    ex = [e for e in log if e["kind"] == "exact"]
    nu = [e for e in log if e["kind"] == "nucleation"]
    start = next((e["it"] for e in ex if e["frac"] >= NEAR), None)
    tail = [] if start is None else [e for e in log if e["it"] >= start]
    tex = [e for e in tail if e["kind"] == "exact"]
    tnu = [e for e in tail if e["kind"] == "nucleation"]
    moved = sum(e["add"] + e["remove"] for e in tex)
    return dict(
        exact=len(ex), nucleation=len(nu), near_at=start, tail_exact=len(tex),
        tail_moved=moved, tail_repeat=(sum(e["repeat"] for e in tex) / moved) if moved else 0.0,
        tail_nucleated=sum(e["new"] for e in tnu), tail_fresh=sum(e["fresh"] for e in tnu),
        tail_reclosed=sum(e["reclosed"] for e in tnu),
        tail_nucleated_leading=sum(e["leading"] for e in tnu),
        tail_removed=sum(e["remove"] for e in tex),
        tail_removed_leading=sum(e["remove_leading"] for e in tex),
        # the cells in contact after the tail less those before its first test's move
        tail_net=(tail[-1]["cells"] - tail[0]["cells"] + tail[0]["add"] - tail[0]["remove"])
        if tail else 0,
        cells=log[-1]["cells"] if log else 0)


def run(n: int, front_tol: float | None) -> dict:
    rec = Recorder()
    with recording(rec):
        ds, cpu = rc._solve(n, "sls", rc.A0, None, loads=rc.PATHS["direct"],
                            front_tol=front_tol)
    its = [int(x) for x in np.atleast_1d(ds["iterations"].values)]
    if len(rec.states) != len(its):  # the wrapped methods were renamed or never called
        raise RuntimeError(f"recorded {len(rec.states)} front iterations for {len(its)} "
                           "states: the instrumentation no longer matches FrontIteration")
    return dict(N=n, front_tol=front_tol, cpu=cpu, iterations=its,
                states=[dict(name=name, log=log)
                        for name, log in zip(NAMES, rec.states, strict=True)],
                date=time.strftime("%Y-%m-%d"))


def _load() -> list:
    return json.loads(OUT.read_text())["rows"] if OUT.exists() else []


def _save(rows: list) -> None:
    write_text(OUT, json.dumps({"rows": rows}, indent=1))


def _share(part: int, whole: int) -> str:
    return f"{100 * part / whole:.0f} %" if whole else "—"


def table(rows: list) -> str:
    head = ("| N | front_tol | state | outer its | exact / nucleation | tail from | tail exact "
            "| cells moved in tail (repeats) | removed in tail (leading) "
            "| nucleated in tail: fresh / re-closed (leading) | net |")
    lines = [head, "|" + "---|" * 11]
    for r in sorted(rows, key=lambda r: (r["N"], r["front_tol"] or 0.5)):
        for k, st in enumerate(r["states"]):
            s = summary(st["log"])
            lines.append(
                f"| {r['N']}² | {r['front_tol'] or 0.5:g} | {st['name']} | {r['iterations'][k]}"
                f" | {s['exact']} / {s['nucleation']} | {s['near_at']} | {s['tail_exact']} "
                f"| {s['tail_moved']} ({100 * s['tail_repeat']:.0f} %) "
                f"| {s['tail_removed']} ({_share(s['tail_removed_leading'], s['tail_removed'])})"
                f" | {s['tail_nucleated']}: {s['tail_fresh']} / {s['tail_reclosed']} "
                f"({_share(s['tail_nucleated_leading'], s['tail_nucleated'])}) "
                f"| {s['tail_net']:+d} |")
    return "\n".join(lines)


def figure(rows: list, out: Path = FIGURE) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [r for r in rows if r["front_tol"] is None]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), sharey=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, ax in enumerate(axes):
        for c, r in zip(colours, sorted(rows, key=lambda r: r["N"]), strict=False):
            log = r["states"][k]["log"]
            ex = [e for e in log if e["kind"] == "exact"]
            nu = [e for e in log if e["kind"] == "nucleation"]
            ax.plot([e["it"] for e in ex], [max(e["add"] + e["remove"], 0.5) for e in ex],
                    "-", color=c, lw=1.2, label=f"{r['N']}²: moved by the balance")
            ax.plot([e["it"] for e in nu], [e["new"] for e in nu], ":", color=c, lw=1.2,
                    label=f"{r['N']}²: nucleated")
            near = summary(log)["near_at"]
            if near is not None:
                ax.axvline(near, color=c, lw=0.6, alpha=0.6)
        ax.set_yscale("log")
        ax.set_title(NAMES[k])
        ax.set_xlabel("outer iteration")
    axes[0].set_ylabel("cells per iteration")
    axes[-1].legend(fontsize=7, loc="upper right")
    fig.suptitle("Rough SLS case, direct path: cells moved per front iteration "
                 f"(vertical lines: the front first {100 * NEAR:.0f} % balanced)", fontsize=10)
    rc.save_figure(fig, out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    ap.add_argument("--front-tol", type=float, default=None)
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args(argv)
    rows = _load()
    if not a.report:
        for n in a.sizes:
            row = run(n, a.front_tol)
            rows = [r for r in rows if (r["N"], r["front_tol"]) != (n, a.front_tol)] + [row]
            _save(rows)  # each finished row kept
            print(f"{n}²: {row['iterations']} outer iterations, {row['cpu']:.0f} CPU-s",
                  flush=True)
        figure(rows)
    print(table(rows))


if __name__ == "__main__":
    main()
