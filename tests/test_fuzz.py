"""Property-based fuzz of the shipped scenes.

Hypothesis mutates the cases under ``cases/*.toml``, shrunk to tiny grids, by key and by the
type of the value (out-of-range numbers, wrong types, strings with units, huge and tiny
magnitudes, non-finite values, long strings and lists, deep nesting, unusable file paths,
other kinds, missing keys and sections, unknown ones) and runs each mutated scene, bounded in
time.  Every run must end in one of two ways:

* a clean :class:`~spectralbem.schema.SceneError` (what the command line prints as its
  one-line reasons), each problem naming its key, with values shortened; or
* a dataset whose status is one of the package's statuses, where no reported state
  (partial, full_contact, detached) carries a nan scalar, a detached state has a zero
  pressure field and a partial one a contact.

Never another exception (a traceback), never a hang.  Scenes that resolve to the 1D method
are validated and built as they are, then solved on the grid (``scene.model = "grid2d"``):
the 1D method's statuses have their own property test (tests/test_sinusoid1d_status.py),
and its solves take seconds each.  The iteration guards (``solver.max_outer``,
``max_iterations``, ``threads``) are not mutated: they bound the runs (their ranges are in
the bad-input catalogue), and the machine's memory is taken as 16 MB above the
interpreter's, so that a mutated grid that fits runs in well under a second and a larger
one is refused by the memory estimate.
"""

from __future__ import annotations

import copy
import math
import os
import signal
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import spectralbem as sb
from spectralbem import scenes
from spectralbem.schema import KINDS, SECTIONS, SceneError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent.parent
CASES = sorted((ROOT / "cases").glob("*.toml"))
#: bound of one run (load, build, solve): a tiny-grid solve takes well under a second
RUN_LIMIT = 20
#: mutated runs of the test (each applies one to three mutations)
EXAMPLES = 320
#: keys left alone: they bound the runs
GUARDS = {("solver", "max_outer"), ("solver", "max_iterations"), ("solver", "threads")}
REPORTED = ("partial", "full_contact", "detached")
STATUSES = REPORTED + ("unstable", "not_converged")


def tiny(raw: dict) -> dict:
    """A shipped case on a tiny grid, with its other keys as shipped (a0 two cells, the
    self-affine band on the grid, at most 40 front iterations)."""
    raw = copy.deepcopy(raw)
    if "sinusoid" in raw:
        s = raw["sinusoid"]
        s.update(cells_per_wavelength=32, ny=1, a0_tilde=0.2)
        return raw
    g = raw["grid"]
    line = raw["surface"]["kind"] == "sinusoid"
    g["Nx"], g["Ny"] = (32, 2) if line else (16, 16)
    if line:
        g["Ly"] = g["Lx"] / 16
    if "adhesion" in raw:
        raw["adhesion"]["a0"] = 2 * max(g["Lx"] / g["Nx"], g["Ly"] / g["Ny"])
    if raw["surface"]["kind"] == "self_affine":
        raw["surface"]["cutoff_wavelength"] = 4 * g["Lx"] / g["Nx"]
        raw["surface"]["rolloff_wavelength"] = 8 * g["Lx"] / g["Nx"]
    raw.setdefault("solver", {})["max_outer"] = 40
    return raw


BASES = {p.stem: tiny(tomllib.loads(p.read_text())) for p in CASES}
ALL_KINDS = sorted({k for kinds in KINDS.values() for k in kinds})

SPECIAL = [0.0, -0.0, 5e-324, -5e-324, 1e-300, 1e-30, 1e30, 1e308, -1e308, math.inf, -math.inf,
           math.nan, -1.0, 1.0, 0.5, 2.0, 1e-12, 1e12, 65536.0]
BAD_TYPES = st.one_of(
    st.booleans(),
    st.sampled_from(["2e6 Pa", "1 mm", "0.5e-3m", "1e3", "fast", "", "nan", "-inf", " 3 GPa",
                     "x" * 100_000, "é\u200b\x00"]),
    st.text(max_size=12),
    st.just([]), st.just([[1.0]]), st.just({"a": 1.0}), st.just([1.0, "x"]),
    st.just([1.0] * 10_001),  # longer than any path may be
    st.just([[[[[[[[1.0]]]]]]]]),
    st.integers(min_value=-(10**400), max_value=10**400),
)


def number(current) -> st.SearchStrategy:
    try:
        base = float(current) if isinstance(current, (int, float)) and not isinstance(
            current, bool) else 1.0
    except OverflowError:  # an earlier mutation's 10**400
        base = 1.0
    base = base if math.isfinite(base) and base != 0 else 1.0
    return st.one_of(
        st.sampled_from(SPECIAL),
        st.floats(allow_nan=True, allow_infinity=True),
        st.integers(min_value=-40, max_value=40).map(lambda k: base * 10.0**k),  # magnitude
        st.integers(min_value=-3, max_value=3).map(lambda k: -base * 2.0**k),  # sign
        st.lists(st.sampled_from(SPECIAL + [base]), min_size=1, max_size=3),
    )


def integer(current) -> st.SearchStrategy:
    return st.one_of(st.integers(min_value=-3, max_value=70), st.sampled_from(
        [0, -1, 7, 65536, 65537, 2**31, 2**70, 10**400, 1.5, 16.0, "16"]))


def spec_key(raw: dict, sec: str, key: str):
    """The schema's Key of ``sec.key`` in this scene (None when unknown)."""
    if sec in SECTIONS:
        return SECTIONS[sec].get(key)
    kind = raw.get(sec, {}).get("kind", "half_space" if sec == "layer" else None)
    return KINDS.get(sec, {}).get(kind, {}).get(key) if isinstance(kind, str) else None


def in_range(k) -> st.SearchStrategy:
    """Values inside a key's allowed range, log-uniform over its magnitudes and its ends:
    valid scenes at the extremes the solvers must survive."""
    lo = k.lo if k.lo is not None else -1e12
    hi = k.hi if k.hi is not None else 1e12
    small = max(k.tiny or 0.0, abs(lo) if lo > 0 else 0.0, 1e-12 * max(abs(lo), abs(hi)))
    top = max(abs(lo), abs(hi))
    mags = st.floats(min_value=math.log10(small), max_value=math.log10(top)).map(
        lambda e: 10.0**e)
    signed = mags if lo >= 0 else st.tuples(mags, st.booleans()).map(
        lambda t: -t[0] if t[1] else t[0])
    ends = [x for x in (lo, hi, k.tiny, 0.0) if x is not None and k.allows(float(x))
            and not (k.lo_open and x == k.lo)]
    vals = st.one_of(signed.filter(k.allows), st.sampled_from(ends or [hi]))
    if k.type == "integer":
        return st.integers(min_value=int(lo), max_value=min(int(hi), 64))
    return st.one_of(vals, st.lists(vals, min_size=1, max_size=3)) if k.type == (
        "number_or_numbers") else vals


def pick(*weighted) -> st.SearchStrategy:
    """One of the strategies, with the given weights (hypothesis flattens nested one_of into
    equal branches: a wide strategy of bad types would otherwise crowd out the others)."""
    options = [s for s, w in weighted for _ in range(w)]
    return st.integers(min_value=0, max_value=len(options) - 1).flatmap(lambda i: options[i])


def value_for(current, sec: str, key: str, files: dict, k=None) -> st.SearchStrategy:
    """A new value of ``sec.key``: mostly inside its allowed range (valid scenes at the
    extremes), else an out-of-range number or a value of a wrong type."""
    if k is not None and k.type in ("number", "number_or_numbers", "integer") and (
            k.lo is not None or k.hi is not None):
        other = integer(current) if k.type == "integer" else number(current)
        return pick((in_range(k), 5), (other, 2), (BAD_TYPES, 2))
    if key == "kind":
        return pick((st.sampled_from(ALL_KINDS), 3), (BAD_TYPES, 1))
    if key in ("path", "dgamma_map"):
        return pick((st.sampled_from(sorted(files.values())), 3), (BAD_TYPES, 1))
    if key == "model":
        return pick((st.sampled_from(["auto", "grid2d", "sinusoid1d", "fem"]), 3),
                    (BAD_TYPES, 1))
    if isinstance(current, bool):
        return pick((st.booleans(), 2), (BAD_TYPES, 1))
    if isinstance(current, int):
        return pick((integer(current), 2), (BAD_TYPES, 1))
    if isinstance(current, (float, list)):
        cur = current[0] if isinstance(current, list) and current else current
        return pick((number(cur), 2), (BAD_TYPES, 1))
    return pick((st.text(max_size=20), 2), (BAD_TYPES, 1))


NEW_KEYS = {"adhesion": {"dgamma": 0.01, "a0": 1e-4, "flaw_radius": 2e-4,
                         "dgamma_map": "/nonexistent.npy"},
            "motion": {"speed": 1e-3, "velocity": [1e-3, 0.0], "direction_deg": 30.0},
            "control": {"penetration": 1e-6, "mean_pressure": 1e3},
            "layer": {"kind": "glued", "thickness": 1e-5},
            "surface": {"kind": "file", "path": "h.npy", "scale": 1.0},
            "material": {"kind": "tabulated", "path": "e.csv", "nu": 0.5},
            "sinusoid": {"delta_tilde": 0.3, "direction_deg": 30.0, "ny": 2},
            "solver": {"tol": 1e-8, "front_tol": 0.25, "criterion": "hybrid"}}


@st.composite
def mutated(draw, files):
    name = draw(st.sampled_from(sorted(BASES)))
    raw = copy.deepcopy(BASES[name])
    done = []
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 3]))):
        op = draw(st.sampled_from(["set"] * 6 + ["delete", "drop_section", "add", "add",
                                                 "unknown"]))
        keys = [(s, k) for s, d in raw.items() if isinstance(d, dict) for k in d
                if (s, k) not in GUARDS]
        if op == "set" and keys:
            sec, key = draw(st.sampled_from(keys))
            raw[sec][key] = draw(value_for(raw[sec][key], sec, key, files,
                                           spec_key(raw, sec, key)))
            done.append(f"set {sec}.{key}")
        elif op == "delete" and keys:
            sec, key = draw(st.sampled_from(keys))
            del raw[sec][key]
            done.append(f"delete {sec}.{key}")
        elif op == "drop_section" and raw:
            sec = draw(st.sampled_from(sorted(raw)))
            del raw[sec]
            done.append(f"drop [{sec}]")
        elif op == "add":
            sec = draw(st.sampled_from(sorted(NEW_KEYS)))
            key = draw(st.sampled_from(sorted(NEW_KEYS[sec])))
            d = raw.setdefault(sec, {})
            if isinstance(d, dict):
                d[key] = NEW_KEYS[sec][key]
            done.append(f"add {sec}.{key}")
        elif op in ("unknown", "set", "delete", "drop_section"):
            where = draw(st.sampled_from(sorted(raw) + ["extra"]))
            d = raw.setdefault(where, {})
            if isinstance(d, dict):
                d[draw(st.sampled_from(["foo", "k" * 5000, "Nx ", "e"]))] = 1.0
            done.append(f"unknown key in [{where}]")
    return name, raw, done


class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang(f"no result within {RUN_LIMIT} s")


def check_rejection(exc: SceneError):
    assert exc.problems
    for line in exc.problems:
        assert len(line) <= 500, line[:200]  # long values are shortened
        assert ":" in line, line


def check_dataset(ds):
    status = [str(s) for s in np.ravel(ds["status"].values)]
    assert set(status) <= set(STATUSES), status
    for i, st_ in enumerate(status):
        if st_ not in REPORTED:
            continue
        one = ds.isel(step=i) if "step" in ds.dims else ds
        for k, v in one.data_vars.items():
            if v.ndim == 0 and v.dtype.kind == "f":
                assert not np.isnan(v.item()), (st_, k)
        p = one["pressure"] if "pressure" in one else one.get("pressure_tilde")
        if st_ == "detached" and p is not None:
            assert not np.any(p.values), "a detached state carries a pressure field"
        if st_ == "partial" and "contact" in one:
            assert one["contact"].values.any(), "a partial state without contact"


def run_one(raw, base_dir):
    """load → build → solve, as the command line does; the 1D method's scenes are built as
    they are, then solved on the grid."""
    scene = scenes.load_scene(raw, base_dir=base_dir)
    if scene.model == "sinusoid1d":
        raw = copy.deepcopy(raw)
        raw.setdefault("scene", {})["model"] = "grid2d"
        scene = scenes.load_scene(raw, base_dir=base_dir)
    return sb.solve(scene)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("fuzz_files")
    np.save(d / "h.npy", np.zeros((16, 16)))
    np.save(d / "spike.npy", np.where(np.arange(256).reshape(16, 16) == 136, 1e-6, 0.0))
    np.save(d / "huge.npy", np.full((16, 16), 1e300))
    np.save(d / "str.npy", np.array([["a"] * 16] * 16))
    np.savez(d / "map.npz", a=np.ones((16, 16)))
    (d / "e.csv").write_text("omega,storage,loss\n1,1e6,1e5\n1e3,2e6,3e5\n")
    (d / "bad.csv").write_bytes(b"\xff\xfe\x00garbage")
    os.mkfifo(d / "fifo")
    return {"h": str(d / "h.npy"), "spike": str(d / "spike.npy"),
            "huge": str(d / "huge.npy"), "str": str(d / "str.npy"),
            "npz": str(d / "map.npz"), "csv": str(d / "e.csv"), "bad": str(d / "bad.csv"),
            "fifo": str(d / "fifo"), "zero": "/dev/zero", "dir": str(d),
            "missing": str(d / "none.npy"), "scene": str(CASES[0])}


@pytest.mark.slow
def test_mutated_cases_fail_cleanly_or_give_a_verified_status(files, monkeypatch):
    """≥ 300 mutations of the shipped cases: a clean rejection or a verified status, never a
    traceback, a nan in a reported state or a hang (module docstring)."""
    monkeypatch.setattr(scenes, "machine_memory", lambda: scenes.BASE_BYTES + 16 * 2**20)
    outcomes = {"rejected": 0, "solved": 0}

    @settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(mutated(files))
    def run(case):
        name, raw, done = case
        old = signal.signal(signal.SIGALRM, _alarm)
        signal.alarm(RUN_LIMIT)
        try:
            ds = run_one(raw, ROOT / "cases")
        except SceneError as exc:
            check_rejection(exc)
            outcomes["rejected"] += 1
            return
        except Hang:
            pytest.fail(f"{name}: {done}: no result within {RUN_LIMIT} s")
        finally:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, old)
        check_dataset(ds)
        outcomes["solved"] += 1

    run()
    print(outcomes)
    assert sum(outcomes.values()) >= 300, outcomes
    assert outcomes["solved"] >= 30 and outcomes["rejected"] >= 100, outcomes
