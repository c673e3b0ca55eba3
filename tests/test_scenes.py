"""Scene files: validation (every problem at once, key path and allowed range), the model the
scene decides, load paths, every case in cases/ at reduced resolution, unit conversions."""

import copy
from pathlib import Path

import numpy as np
import pytest

import spectralbem as sb
from spectralbem import reference as ref
from spectralbem.scenes import load_scene, read_scene_file
from spectralbem.schema import SceneError

CASES = Path(__file__).resolve().parent.parent / "cases"

BASE = {
    "grid": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 32, "Ny": 32},
    "surface": {"kind": "bisinusoid", "amplitude": 1e-5},
    "material": {"kind": "sls", "E0": 1e6, "Einf": 1e7, "tau": 1e-2, "nu": 0.5},
    "motion": {"speed": 0.05},
    "control": {"mean_pressure": 2e3},
}


def mutate(path, value, base=BASE):
    raw = copy.deepcopy(base)
    sec, _, key = path.partition(".")
    if value is DELETE:
        if key:
            del raw[sec][key]
        else:
            del raw[sec]
    elif key:
        raw.setdefault(sec, {})[key] = value
    else:
        raw[sec] = value
    return raw


class _Delete:
    def __repr__(self):
        return "<delete>"


DELETE = _Delete()

# (mutation path, value, words the message must contain: the key path and the allowed range)
MALFORMED = [
    ("grid.Nx", 4, ["grid.Nx", "[8, 65536]"]),
    ("grid.Nx", 1, ["grid.Nx", "[8, 65536]"]),
    ("grid.Ny", 0, ["grid.Ny", "[1, 65536]"]),
    ("grid.Nx", 32.5, ["grid.Nx", "integer"]),
    ("grid.Lx", -1e-3, ["grid.Lx", "[1e-09, 1000] in m"]),
    ("grid.Lx", "1 MPa", ["grid.Lx", "not a quantity in m", "[mass]"]),
    ("grid.Lx", DELETE, ["grid.Lx", "missing"]),
    ("grid.Lz", 1.0, ["grid.Lz", "unknown key", "Lx, Ly, Nx, Ny"]),
    ("grid", DELETE, ["grid", "missing section"]),
    ("material.kind", "rubber", ["material.kind", "'rubber'", "elastic, sls, prony, tabulated"]),
    ("material.E0", 0.0, ["material.E0", "[1, 1e+13] in Pa"]),
    ("material.E0", -2e6, ["material.E0", "[1, 1e+13] in Pa"]),
    ("material.Einf", 5e5, ["material.Einf", "below material.E0", "[E0, inf)"]),
    ("material.tau", 0.0, ["material.tau", "[1e-12, 1e+12] in s"]),
    ("material.nu", 0.6, ["material.nu", "(-1, 0.5]"]),
    ("material.nu", -1.0, ["material.nu", "(-1, 0.5]"]),
    ("material.E0", "2e6", ["material.E0", "expected a number in Pa", "without quotes"]),
    ("material.E0", float("nan"), ["material.E0", "not finite"]),
    ("material.E0", float("inf"), ["material.E0", "not finite"]),
    ("layer", {"kind": "glued", "thickness": 0.0}, ["layer.thickness", "[1e-12, 1000] in m"]),
    ("layer", {"kind": "glued"}, ["layer.thickness", "missing"]),
    ("layer", {"kind": "slab", "thickness": 1e-3}, ["layer.kind", "half_space, glued, pressure"]),
    ("surface.kind", "fractal", ["surface.kind", "sinusoid, bisinusoid"]),
    ("surface.amplitude", DELETE, ["surface.amplitude", "missing"]),
    ("surface", {"kind": "self_affine", "hurst": 1.2, "rolloff_wavelength": 2e-4,
                 "rms_slope": 0.1}, ["surface.hurst", "(0, 1)"]),
    ("surface", {"kind": "self_affine", "hurst": 1.0, "rolloff_wavelength": 2e-4,
                 "rms_slope": 0.1}, ["surface.hurst", "1.0 is outside", "(0, 1)"]),
    ("surface", {"kind": "self_affine", "hurst": 0.8, "rolloff_wavelength": 2e-4},
     ["rms_height / surface.rms_slope", "exactly one"]),
    ("surface", {"kind": "self_affine", "hurst": 0.8, "rolloff_wavelength": 2e-4,
                 "cutoff_wavelength": 3e-4, "rms_slope": 0.1},
     ["surface.cutoff_wavelength", "shorter"]),
    ("surface", {"kind": "sinusoid", "amplitude": 1e-5, "wavelength": 3e-4},
     ["surface.wavelength", "divide"]),
    ("control", {}, ["control.mean_pressure / control.penetration", "exactly one"]),
    ("control", {"mean_pressure": 1e3, "penetration": 1e-6}, ["exactly one"]),
    ("control.mean_pressure", -5.0, ["control.mean_pressure", "without adhesion", "(0, 1e12]"]),
    # a half-space's mean displacement is 0: Δ < max h − mean h = 1e-5 m for this bisinusoid
    ("control", {"penetration": [5e-6, 2e-5, 3e-5]},
     ["control.penetration = 2e-05", "1 more", "max(h) - mean(h) = 1e-05",
      "allowed (-inf, 1e-05)"]),
    ("control.mean_pressure", [1e3, "x"], ["control.mean_pressure[1]", "expected a number"]),
    ("motion.speed", -1.0, ["motion.speed", "[0, 1e+06]"]),
    ("motion.velocity", [0.1, float("nan")], ["motion.velocity[1]", "not finite"]),
    ("motion.velocity", [0.1, 0.0, 0.0], ["motion.velocity", "two entries"]),
    ("adhesion", {"dgamma": -0.1, "a0": 1e-4}, ["adhesion.dgamma", "[0, 1e+06]"]),
    ("adhesion", {"dgamma": 0.05}, ["adhesion.a0", "missing", "at least one cell"]),
    ("adhesion", {"dgamma": 0.05, "a0": 1e-6}, ["adhesion.a0", "smaller than one cell"]),
    ("adhesion", {"dgamma": 0.05, "a0": 0.9e-3}, ["adhesion.a0", "larger than half the cell"]),
    ("adhesion", {"dgamma": 0.05, "a0": -1e-4}, ["adhesion.a0", "(0, inf]"]),
    ("solver.tol", 0.5, ["solver.tol", "[1e-14, 0.01]"]),
    ("solver.threads", 0, ["solver.threads", "[1, 256]"]),
    ("solver.band_tol", 1e-3, ["solver.band_tol", "[1e-14, 1e-05]"]),
    ("solver.extrapolate_a0", True, ["solver.extrapolate_a0", "adhesive elastic 2D scene",
                                     "viscoelastic True, adhesive False"]),
    ("output.fields", "yes", ["output.fields", "true or false"]),
    ("scene.model", "fem", ["scene.model", "auto, grid2d, sinusoid1d"]),
    ("sinusoid", {"zeta": 0.1}, ["grid, surface", "not allowed with [sinusoid]"]),
    ("extra", {"a": 1}, ["extra", "unknown section"]),
]


@pytest.mark.parametrize("path, value, words", MALFORMED,
                         ids=[f"{i}-{m[0]}={m[1]!r}"[:40] for i, m in enumerate(MALFORMED)])
def test_malformed_scene_rejected(path, value, words):
    with pytest.raises(SceneError) as err:
        load_scene(mutate(path, value))
    msg = str(err.value)
    for w in words:
        assert w in msg, (w, msg)


def test_every_problem_reported_at_once():
    raw = mutate("grid.Nx", 2)
    raw["material"]["nu"] = 0.7
    raw["motion"]["speed"] = "fast"
    raw["output"] = {"plot": True}
    with pytest.raises(SceneError) as err:
        load_scene(raw)
    assert len(err.value.problems) == 4, err.value.problems
    assert "(4 problems)" in str(err.value)


def test_seed_scene_errors():
    for kw, word in ((dict(zeta=-1.0), "sinusoid.zeta"), (dict(beta=0.5), "sinusoid.beta"),
                     (dict(Gamma=20.0), "sinusoid.Gamma"), (dict(a0_tilde=2.0), "a0_tilde")):
        raw = {"sinusoid": {"zeta": 0.1, "beta": 10, "Gamma": 0.008, "p_tilde": 0.1,
                            "a0_tilde": 0.01, **kw}}
        with pytest.raises(SceneError, match=word):
            load_scene(raw)
    with pytest.raises(SceneError, match="exactly one"):
        load_scene({"sinusoid": {"zeta": 0.1, "beta": 10, "Gamma": 0.0, "a0_tilde": 0.0}})


def test_valid_base_and_model_choice(monkeypatch):
    """The scene decides the model: an elastic scene runs Polonsky–Keer (CG, no E(ω)); a
    half-space never evaluates S; an adhesiveless scene never runs the energy balance; a
    y-invariant sinusoid on an SLS half-space runs as 1D (recorded in the dataset)."""
    import spectralbem.front_iteration as adh
    import spectralbem.layers as layers
    from spectralbem.materials import StandardLinearSolid

    def boom(*a, **k):
        raise AssertionError("must not be called")

    monkeypatch.setattr(layers, "s_glued", boom)
    monkeypatch.setattr(layers, "s_pressure", boom)
    monkeypatch.setattr(adh, "front_tests", boom)
    monkeypatch.setattr(StandardLinearSolid, "compliance", boom)
    el = mutate("material", {"kind": "elastic", "E": 1e6})
    ds = sb.solve(load_scene(el))
    assert ds.attrs["model"] == "grid2d" and ds.status.item() == "partial"
    assert '"method": "polonsky-keer"' in ds.attrs["solver_diagnostics"]
    monkeypatch.undo()
    sc = load_scene({**BASE, "surface": {"kind": "sinusoid", "amplitude": 1e-5}})
    assert sc.model == "sinusoid1d"
    sc = load_scene({**BASE, "surface": {"kind": "sinusoid", "amplitude": 1e-5},
                     "scene": {"model": "grid2d"}})
    assert sc.model == "grid2d"
    with pytest.raises(SceneError, match="'sinusoid1d' is not possible"):
        load_scene({**BASE, "scene": {"model": "sinusoid1d"}})


def test_physical_sinusoid_units_against_westergaard():
    """An elastic adhesiveless physical sinusoid, run by the 1D method (model auto) and on
    the grid: contact half-width against Westergaard in SI units.  1D: the method's own
    accuracy (1e-5); grid: one cell (the mask resolution)."""
    E, nu, lam, amp, p = 1e6, 0.5, 1e-4, 2e-6, 1.2e4
    raw = {"grid": {"Lx": lam, "Ly": lam / 512 * 4, "Nx": 512, "Ny": 4},
           "surface": {"kind": "sinusoid", "amplitude": amp},
           "material": {"kind": "elastic", "E": E, "nu": nu},
           "control": {"mean_pressure": p}}
    pstar = E / (1 - nu**2) * np.pi * amp / lam
    a_ref = ref.westergaard_a(p / pstar) / (2 * np.pi / lam)
    one = sb.solve(load_scene(raw))
    assert one.attrs["model"] == "sinusoid1d"
    assert one.contact_half_width.item() == pytest.approx(a_ref, rel=1e-5)
    assert one.mean_pressure.item() == pytest.approx(p, rel=1e-9)
    grid = sb.solve(load_scene({**raw, "scene": {"model": "grid2d"}}))
    assert grid.attrs["model"] == "grid2d"
    a_grid = grid.area_fraction.item() * lam / 2
    assert abs(a_grid - a_ref) <= lam / 512


def test_load_path_jkr_sphere():
    """JKR sphere along a load/unload path (the mask carried from step to step): contact
    radius against JKR at every step within 1.5 cells (128², a ≈ 11 cells: the staircase
    front and lattice trapping are of order one cell; the periodic images change a by < 1 %
    at a/L < 0.1, docs/derivations.md §6)."""
    R, E, w, L, n = 1e-3, 1e6, 0.05, 1e-3, 128
    raw = {"grid": {"Lx": L, "Ly": L, "Nx": n, "Ny": n},
           "surface": {"kind": "paraboloid", "radius": R},
           "material": {"kind": "elastic", "E": E},
           "adhesion": {"dgamma": w, "a0": 2 * L / n},
           "control": {"mean_pressure": [500.0, 3000.0, 500.0, -100.0]}}
    ds = sb.solve(load_scene(raw))
    assert ds.sizes["step"] == 4
    assert list(ds.control_value.values) == [500.0, 3000.0, 500.0, -100.0]
    assert all(s == "partial" for s in ds.status.values), ds.status.values
    a = np.sqrt(ds.area_fraction.values * L * L / np.pi)
    a_jkr = [ref.jkr_radius(P * L * L, R, E / 0.75, w) for P in ds.control_value.values]
    np.testing.assert_allclose(a, a_jkr, atol=1.5 * L / n)


def test_extrapolate_a0_default_where_a0_is_numerical():
    """solver.extrapolate_a0 unset: on in an adhesive elastic 2D scene whose a0 spans two
    cells or more (a0 is numerical there, docs/theory.md), off at one cell, in a sliding
    viscoelastic scene (a0 physical) and without adhesion; a value given wins; the
    dataset's scene records the edge the solve used."""
    import json

    L, n = 1e-3, 128
    raw = {"grid": {"Lx": L, "Ly": L, "Nx": n, "Ny": n},
           "surface": {"kind": "paraboloid", "radius": 1e-3},
           "material": {"kind": "elastic", "E": 1e6},
           "adhesion": {"dgamma": 0.05, "a0": 2 * L / n},
           "control": {"mean_pressure": 500.0}}
    assert load_scene(raw).extrapolate_a0
    assert not load_scene(raw, overrides={"adhesion.a0": L / n}).extrapolate_a0
    assert not load_scene(raw, overrides={"solver.extrapolate_a0": False}).extrapolate_a0
    assert not load_scene(raw, overrides={"adhesion.dgamma": 0.0}).extrapolate_a0
    sls = dict(raw, material={"kind": "sls", "E0": 1e6, "Einf": 1e7, "tau": 1e-2})
    assert not load_scene(dict(sls, motion={"speed": 1e-3})).extrapolate_a0
    assert load_scene(sls).extrapolate_a0  # at rest the solid responds elastically
    ds = sb.solve(load_scene(raw))
    assert ds.status.item() == "partial", ds.attrs["solver_message"]
    assert json.loads(ds.attrs["scene"])["solver"]["extrapolate_a0"] is True
    ds = sb.solve(load_scene(raw, overrides={"adhesion.a0": L / n}))
    assert json.loads(ds.attrs["scene"])["solver"]["extrapolate_a0"] is False


def _fake_path_scene(loads) -> dict:
    """A small adhesive grid scene along ``loads`` (Pa), for the stand-in step solvers."""
    return {"grid": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 16, "Ny": 16},
            "surface": {"kind": "paraboloid", "radius": 1e-3},
            "material": {"kind": "elastic", "E": 1e6},
            "adhesion": {"dgamma": 0.05, "a0": 1e-4},
            "control": {"mean_pressure": list(loads)}}


def test_path_step_that_fails_is_retried_in_sub_steps(monkeypatch):
    """A path step of an adhesive grid scene that ends not_converged from a partial state is
    solved again from that state, each failing step halved (load_path.SUBSTEP_HALVINGS = 3
    times at most); the state reached is marked with the number of steps, a failure at the
    smallest step keeps the direct step's state and says so.  The step solver is a stand-in
    that converges only for load changes of at most ``limit`` and records its calls."""
    import xarray as xr

    from spectralbem import solving

    calls = []

    def fake(scene, state, progress=None):
        p = scene.mean_pressure
        ok = state is None or abs(p - state) <= limit
        calls.append(p)
        ds = xr.Dataset({"status": ((), "partial" if ok else "not_converged"),
                         "mean_pressure": ((), p)})
        ds.attrs["solver_message"] = "fake"
        return ds, p

    monkeypatch.setattr(solving, "_solve_one", fake)
    raw = _fake_path_scene([1e4, 3e4, 1e4])
    limit = 6e3  # halves of 1e4 fail, quarters of 5e3 converge
    ds = sb.solve(load_scene(raw))
    assert list(ds.status.values) == ["partial"] * 3
    assert list(ds.substeps.values) == [1, 4, 4]
    assert calls == [1e4,
                     3e4, 2e4, 1.5e4, 2e4, 3e4, 2.5e4, 3e4,  # direct, 1st half, 2nd half
                     1e4, 2e4, 2.5e4, 2e4, 1e4, 1.5e4, 1e4]
    assert "in 4 steps of the control" in str(ds.solver_message.values[2])
    limit = 3e3  # eighths of 2.5e3 converge
    assert list(sb.solve(load_scene(raw)).substeps.values) == [1, 8, 8]
    calls.clear()
    limit = 1e3  # nothing converges: the direct steps are kept, marked as such
    ds = sb.solve(load_scene(raw))
    assert list(ds.status.values) == ["partial", "not_converged", "not_converged"]
    assert list(ds.substeps.values) == [1, 1, 1]
    assert "1/8 of it did not converge either" in str(ds.solver_message.values[1])
    assert calls == [1e4, 3e4, 2e4, 1.5e4, 1.25e4, 1e4]  # no retry after a failed step



def test_path_step_that_holds_front_cells_is_retried_in_sub_steps(monkeypatch):
    """A partial path step whose front holds cells unbalanced (``unresolved_front`` > 0:
    oscillating features narrower than a0, docs/theory.md) is solved again in sub-steps;
    the sub-steps' state is taken where they end partial without held cells (or with held
    cells over the smallest step), the direct state, marked, where they fail.  Stand-in
    solver: a step of more than ``limit`` holds 5 cells; with ``only_direct`` a step that
    does not end at 3e4 Pa does not converge."""
    import xarray as xr

    from spectralbem import solving

    calls = []

    def fake(scene, state, progress=None):
        p = scene.mean_pressure
        calls.append(p)
        jump = 0.0 if state is None else abs(p - state)
        ok = state is None or not only_direct or p == 3e4
        ds = xr.Dataset({"status": ((), "partial" if ok else "not_converged"),
                         "mean_pressure": ((), p),
                         "unresolved_front": ((), 5 if jump > limit else 0)})
        ds.attrs["solver_message"] = "fake"
        return ds, p

    monkeypatch.setattr(solving, "_solve_one", fake)
    raw = _fake_path_scene([1e4, 3e4])
    limit, only_direct = 1.5e4, False  # the direct step holds cells, its halves do not
    ds = sb.solve(load_scene(raw))
    assert list(ds.status.values) == ["partial", "partial"]
    assert list(ds.substeps.values) == [1, 2]
    assert list(ds.unresolved_front.values) == [0, 0]
    assert calls == [1e4, 3e4, 2e4, 3e4]
    assert "in 2 steps of the control" in str(ds.solver_message.values[1])
    calls.clear()
    limit = 1e3  # every step holds cells: the eighths' state is taken
    ds = sb.solve(load_scene(raw))
    assert list(ds.substeps.values) == [1, 8]
    assert list(ds.unresolved_front.values) == [0, 5]
    calls.clear()
    only_direct = True  # the sub-steps fail: the direct state is kept, marked
    ds = sb.solve(load_scene(raw))
    assert list(ds.status.values) == ["partial", "partial"]
    assert list(ds.substeps.values) == [1, 1]
    assert list(ds.unresolved_front.values) == [0, 5]
    assert "did not end partial without held front cells" in str(ds.solver_message.values[1])
    assert calls == [1e4, 3e4, 2e4, 1.5e4, 1.25e4]


def test_path_step_that_detaches_is_retried_in_sub_steps(monkeypatch):
    """A path step of an adhesive grid scene that ends detached from a partial state is solved
    again in sub-steps like a failed one; a detachment is accepted over the smallest step (the
    path's pull-off), and the rest of the step then starts afresh in one step.  Stand-in
    solver: a step of more than ``limit`` detaches, and every state beyond the pull-off
    ``-250`` is detached."""
    import xarray as xr

    from spectralbem import solving

    calls = []

    def fake(scene, state, progress=None):
        p = scene.mean_pressure
        calls.append(p)
        ok = p >= -250.0 and (state is None or abs(p - state) <= 30.0)
        ds = xr.Dataset({"status": ((), "partial" if ok else "detached"),
                         "mean_pressure": ((), p)})
        ds.attrs["solver_message"] = "fake"
        return ds, (p if ok else None)

    monkeypatch.setattr(solving, "_solve_one", fake)
    raw = _fake_path_scene([-150.0, -230.0])
    ds = sb.solve(load_scene(raw))
    assert list(ds.status.values) == ["partial", "partial"]  # halves of 80 Pa: 40 Pa detach
    assert list(ds.substeps.values) == [1, 4]
    calls.clear()
    raw["control"]["mean_pressure"] = [-150.0, -310.0]  # beyond the pull-off
    ds = sb.solve(load_scene(raw))
    assert list(ds.status.values) == ["partial", "detached"]
    assert list(ds.substeps.values) == [1, 7]
    # the direct step; the first half (-230) in four eighths; the second half, its quarter
    # (-270) in eighths until the eighth past -250 detaches (accepted), and the rest
    # (-270 → -310) from the detached state in one step
    assert calls == [-150.0, -310.0,
                     -230.0, -190.0, -170.0, -190.0, -230.0, -210.0, -230.0,
                     -310.0, -270.0, -250.0, -270.0, -310.0]
    assert "reached from -150" in str(ds.solver_message.values[1])


def test_unloading_toward_the_pull_off_stays_on_the_branch(monkeypatch):
    """JKR sphere (cases/jkr_sphere.toml at 256²: a0 = 2 cells, JKR pull-off −235.6 Pa): one
    step from the partial state at −150 Pa to −232 Pa (1.5 % above the pull-off) stays on the
    branch without sub-steps, radius within 5 % of JKR's 55.1 µm (measured +3.6 %: JKR's
    radius at −227.6 Pa, 1.9 % of the load away, where da/dP → ∞ at the pull-off; reached via
    −200 Pa +5.8 %, via −225 Pa +3.6 %).  It detached, even in three sub-step halvings, while
    the load correction of one balanced mask was carried by the masks that followed it."""
    from pathlib import Path

    from spectralbem import load_path
    from spectralbem import reference as ref

    monkeypatch.setattr(load_path, "SUBSTEP_HALVINGS", 0)
    case = Path(__file__).parents[1] / "cases" / "jkr_sphere.toml"
    scene = load_scene(case, overrides={"control.mean_pressure": [-150.0, -232.0]})
    a_jkr = ref.jkr_radius(-232.0 * 1e-6, 1e-3, 1e6 / (1 - 0.5**2), 0.05)
    ds = sb.solve(scene)
    assert list(ds.status.values) == ["partial", "partial"]
    assert list(ds.substeps.values) == [1, 1]
    radius = np.sqrt(float(ds.area_fraction.values[1]) * 1e-6 / np.pi)
    assert radius == pytest.approx(a_jkr, rel=0.05)


# reduced resolution for each case: (overrides)
REDUCED = {
    "rubber_rough": {"grid.Nx": 32, "grid.Ny": 32, "surface.cutoff_wavelength": 1.25e-4},
    "seed_sinusoid_1d": {},
    "seed_sinusoid_2d": {"sinusoid.cells_per_wavelength": 2513, "sinusoid.ny": 1},
    "oblique_sliding": {"sinusoid.cells_per_wavelength": 1257, "sinusoid.ny": 1,
                        "sinusoid.a0_tilde": 0.02},
    "finite_thickness_glued": {"grid.Nx": 64, "grid.Ny": 1},
    "finite_thickness_pressure": {"grid.Nx": 64, "grid.Ny": 1},
    "prony_rubber": {"grid.Nx": 32, "grid.Ny": 32},
    "jkr_sphere": {"grid.Nx": 128, "grid.Ny": 128, "adhesion.a0": 1.5625e-5,
                   "control.mean_pressure": [1e3, 0.0]},
    # the rough paths at 128² (the cases' a0 of 7.8 µm, one cell; the cut-off 8 cells).  At
    # a0 two cells (15.6 µm) the state at 3e4 Pa holds a notch of the gap no wider than 2 a0
    # that fills and empties in turn (docs/theory.md, "Features narrower than a0";
    # tests/test_adhesive2d.py runs it); at 64² (a0 two cells of 15.6 µm) the step to 3e4
    # Pa ends not_converged, two tensile pins held where no free edge of the front carries
    # tension (moves.overloaded_pins)
    "rough_load_unload": {"grid.Nx": 128, "grid.Ny": 128,
                          "surface.cutoff_wavelength": 6.25e-5,
                          "control.mean_pressure": [1e4, 3e4, 1e4]},
    "sinusoid_physical": {},
    "rough_convergence": {"grid.Nx": 128, "grid.Ny": 128,
                          "surface.cutoff_wavelength": 6.25e-5},
}


def test_reduced_table_covers_every_case():
    assert sorted(p.stem for p in CASES.glob("*.toml")) == sorted(REDUCED)


@pytest.mark.parametrize("name", sorted(REDUCED))
def test_every_case_runs(name):
    ds = sb.solve(load_scene(CASES / f"{name}.toml", overrides=REDUCED[name]))
    status = np.atleast_1d(ds.status.values)
    assert all(s in ("partial", "full_contact", "detached", "not_converged") for s in status)
    for v in ds.data_vars.values():  # NaN only where the status explains it
        if v.dtype.kind == "f" and v.dims == ():
            assert not np.isinf(v.values)
    assert ds.attrs["model"] in ("grid2d", "sinusoid1d")
    assert all(s in ("partial", "full_contact") for s in status), (name, status)
    if name == "rough_load_unload":  # adhesion hysteresis: unloading keeps more contact
        af = ds.area_fraction.values
        assert af[2] > af[0], af


def test_user_guide_reference_is_current():
    """docs/user_guide.md embeds the schema reference that docs/generate_reference.py
    generates from the code (make docs)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "generate_reference", CASES.parent / "docs" / "generate_reference.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    guide = (CASES.parent / "docs" / "user_guide.md").read_text()
    assert gen.reference_markdown() in guide


def test_api_page_is_current():
    """docs/api.md is the public API that docs/generate_reference.py generates from the
    modules' ``__all__`` (make docs): every listed name exists, and the page is current."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "generate_reference", CASES.parent / "docs" / "generate_reference.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    assert (CASES.parent / "docs" / "api.md").read_text() == gen.api_markdown() + "\n"


def test_command_line_values_comma_lists_and_words():
    """``--set key=1e3,2e3`` is a list of numbers (a load path), as ``[1e3, 2e3]`` is; words
    and mixed items stay text, so the schema names them."""
    from spectralbem.scenes import parse_value

    assert parse_value("1e3,2e3") == [1e3, 2e3] == parse_value("[1e3, 2e3]")
    assert parse_value("1e3") == 1e3 and parse_value("true") is True
    for text in ("a,b", "1,a", "true,false", "x"):
        assert parse_value(text) == text



@pytest.mark.parametrize("key, text, si", [
    ("material.E0", "2 MPa", 2e6), ("material.Einf", "20 MPa", 2e7),
    ("motion.speed", "4 mm/s", 4e-3), ("surface.cutoff_wavelength", "125 um", 1.25e-4),
    ("surface.cutoff_wavelength", "125 µm", 1.25e-4), ("material.tau", "10 ms", 1e-2),
])
def test_quantities_with_units_are_converted_to_si(key, text, si):
    """A value written with a unit (a TOML string, or --set key="2 MPa") is read by pint
    and stored in the key's SI unit: the dataset's scene records the SI number."""
    raw = read_scene_file(CASES / "rubber_rough.toml")
    sc = load_scene(raw, overrides={"grid.Nx": 32, "grid.Ny": 32,
                                    "surface.cutoff_wavelength": 1.25e-4, key: text})
    section, name = key.split(".")
    assert sc.spec[section][name] == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize("key, text, words", [
    ("material.E0", "2 mm", ["material.E0", "'2 mm' is not a quantity in Pa", "[length]"]),
    ("material.E0", "20 TPa", ["material.E0 = '20 TPa'", "2e+13 Pa is outside",
                               "[1, 1e+13] in Pa"]),
    ("grid.Nx", "32 m", ["grid.Nx", "expected an integer"]),
    ("material.nu", "0.5 m", ["material.nu", "carries a unit; this key takes a plain number"]),
    ("material.E0", "2 bananas", ["material.E0", "not a quantity pint can read"]),
])
def test_quantities_that_do_not_fit_are_named(key, text, words):
    raw = read_scene_file(CASES / "rubber_rough.toml")
    with pytest.raises(SceneError) as e:
        load_scene(raw, overrides={key: text})
    msg = str(e.value)
    assert all(w in msg for w in words), msg


@pytest.mark.parametrize("case, ov", [
    ("rubber_rough.toml", {"grid.Nx": 32, "grid.Ny": 32, "surface.cutoff_wavelength": 1.25e-4}),
    ("seed_sinusoid_1d.toml", {}),
])
def test_the_recorded_scene_reruns(case, ov):
    """A dataset's ``scene`` attribute is everything needed to rerun it: ``load_scene`` of the
    recorded mapping gives the same answer (the keys left unset were recorded as null, which
    ``load_scene`` refuses: nine problems for the rough rubber)."""
    import json

    ds = sb.solve(load_scene(CASES / case, overrides=ov))
    again = sb.solve(load_scene(json.loads(ds.attrs["scene"]), base_dir=CASES))
    for v in ("status", "area_fraction", "a_tilde", "mu", "mu_bar"):
        if v in ds:
            assert again[v].values.tolist() == ds[v].values.tolist(), v


def _guide() -> str:
    return (CASES.parent / "docs" / "user_guide.md").read_text()


def test_user_guide_api_snippet_works_only_under_the_main_guard(tmp_path, monkeypatch):
    """The user guide's Python API example does all its work under ``if __name__ ==
    "__main__":``: dask's worker processes run the script's top level again, so at top level
    there are only imports and definitions.  Run as a worker would (``__mp_main__``), the
    snippet imports its names and writes nothing."""
    import ast

    block = _guide().split("## Python API", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    tree = ast.parse(block)
    guarded = []
    for node in tree.body:
        if isinstance(node, ast.If):
            assert ast.unparse(node.test) == "__name__ == '__main__'", ast.unparse(node.test)
            guarded.append(node)
        else:
            assert isinstance(node, (ast.Import, ast.ImportFrom, ast.FunctionDef)), \
                ast.unparse(node)
    assert len(guarded) == 1
    work = " ".join(ast.unparse(n) for n in tree.body if not isinstance(n, ast.If))
    for call in ("load_scene(", "sb.solve(", "to_netcdf(", "plot_dataset(", "run_sweep("):
        assert call in block and call in work  # in the function the guard calls
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__mp_main__"}
    exec(compile(block, "user_guide.md", "exec"), namespace)
    assert callable(namespace["main"]) and list(tmp_path.iterdir()) == []


def test_every_case_is_listed_in_the_user_guide():
    """The user guide's Cases section names every scene of cases/."""
    cases = _guide().split("\n## Cases", 1)[1].split("\n## ", 1)[0]
    for p in sorted(CASES.glob("*.toml")):
        assert f"`{p.stem}`" in cases, p.stem


def test_path_dataset_has_each_steps_solver_diagnostics():
    """A load path of a physical grid scene keeps ``solver_diagnostics`` as a single state
    does: a JSON list, one object per step (it was dropped, the steps' attributes
    differing); the documented outputs include ``mu_profile``."""
    import json

    ds = sb.solve(load_scene(CASES / "jkr_sphere.toml", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "adhesion.a0": 3.2e-5,
        "control.mean_pressure": [1e3, 0.0]}))
    diag = json.loads(ds.attrs["solver_diagnostics"])
    assert isinstance(diag, list) and len(diag) == ds.sizes["step"] == 2
    assert all("front-layer" in d["method"] and "a0" in d for d in diag)
    single = sb.solve(load_scene(mutate("control.mean_pressure", [2e3, 3e3])))
    diag = json.loads(single.attrs["solver_diagnostics"])
    assert [d["method"] for d in diag] == [json.loads(sb.solve(load_scene(
        mutate("control.mean_pressure", p))).attrs["solver_diagnostics"])["method"]
        for p in (2e3, 3e3)]
    assert "mu_profile" in ds and "`mu_profile`" in _guide()


def test_progress_in_a_notebook_is_a_bar(monkeypatch):
    """A notebook's stderr is no terminal, but it shows bars: with an IPython kernel loaded
    progress_bar gives tqdm's (tqdm.auto), elsewhere off a terminal plain lines."""
    import sys
    import types

    from tqdm.std import tqdm

    from spectralbem import progress

    assert isinstance(progress.progress_bar(total=2), progress._LineProgress)
    monkeypatch.setitem(sys.modules, "ipykernel", types.ModuleType("ipykernel"))
    bar = progress.progress_bar(total=2, desc="x", disable=True)
    assert isinstance(bar, tqdm)
    bar.close()


def test_progress_on_a_stderr_that_is_no_terminal_is_plain_lines(capsys, monkeypatch):
    """``progress=True`` draws tqdm bars on a terminal only; on a log or a pipe (here
    pytest's capture) it writes plain lines, at most one per LOG_INTERVAL seconds and each
    bar's last count and text (on close or reset), with no carriage return or escape
    code."""
    from spectralbem import progress

    assert not progress._terminal(__import__("sys").stderr)
    sb.solve(load_scene(CASES / "jkr_sphere.toml", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "adhesion.a0": 3.2e-5,
        "control.mean_pressure": [1e3, 0.0]}), progress=True)
    err = capsys.readouterr().err
    assert "\r" not in err and "\x1b" not in err, repr(err)
    lines = [ln for ln in err.splitlines() if ln.startswith(("path:", "front:"))]
    assert sum(ln.startswith("path:") for ln in lines) == 2  # the first and the last step
    assert lines[-2].startswith("path: 2/2 step"), err
    # each state's front ends with its final line: the outcome and the balanced fraction
    assert lines[-1].startswith("front:") and "balanced 1.000" in lines[-1], err
    monkeypatch.setattr(progress, "LOG_INTERVAL", 3600.0)
    bar = progress.progress_bar(total=5, desc="sweep", unit="point")
    for _ in range(5):
        bar.update(1)
    bar.close()
    assert capsys.readouterr().err.splitlines() == ["sweep: 1/5 point (0 s)",
                                                    "sweep: 5/5 point (0 s)"]


@pytest.mark.parametrize("terminal", [False, True])
def test_a_new_solve_on_the_same_bar_counts_from_its_own_start(capsys, monkeypatch, terminal):
    """A load path's sub-steps solve again on the step's bar: their outer iterations count
    from 1 (a step that took 462 iterations showed '462 it' through the sub-steps'
    iterations, whose counts never passed it).  Both bars: plain lines and tqdm."""
    from spectralbem import progress, solving

    monkeypatch.setattr(progress, "_terminal", lambda stream: terminal)
    monkeypatch.setattr(progress, "LOG_INTERVAL", 0.0)
    bar = progress.progress_bar(desc="front", unit="it")
    show = solving._bar_progress(bar)
    for k in (1, 2, 3):
        show(k, f"direct {k}")
    show(1, "sub-step 1")
    assert bar.n == 1
    show(2, "sub-step 2")
    assert bar.n == 2
    bar.close()
    if not terminal:
        assert capsys.readouterr().err.splitlines()[-2:] == [
            "front: 1 it, sub-step 1 (0 s)", "front: 2 it, sub-step 2 (0 s)"]


@pytest.mark.parametrize("scene, words", [
    ({"grid": {"Lx": 1e-3, "Ly": 1e-5, "Nx": 100, "Ny": 1},
      "surface": {"kind": "sinusoid", "amplitude": 2e-6},
      "material": {"kind": "elastic", "E": 2e6}, "control": {"penetration": 2e-6}},
     ["control.penetration = 2e-06", "admits no equilibrium", "allowed (-inf, 2e-06)"]),
    ({"scene": {"name": "s", "model": "sinusoid1d"},
      "sinusoid": {"zeta": 0.1, "beta": 10, "Gamma": 0.008, "delta_tilde": 1.0,
                   "a0_tilde": 0.01}},
     ["sinusoid.delta_tilde = 1", "admits no equilibrium", "allowed (-inf, 1"])])
def test_a_penetration_beyond_full_contact_is_named_by_its_key_for_the_1d_method(scene,
                                                                                words):
    """A y-invariant scene that the 1D method solves ('auto' picks it) refused Δ at the
    full-contact bound in the seed's units ("delta_tilde = 1.0 is outside the allowed
    range", for a physical control.penetration of 2 µm); the bound is checked while the
    scene is built, for either model, and names the scene's own key."""
    from spectralbem.scenes import load_scene

    with pytest.raises(SceneError) as err:
        load_scene(scene)
    assert all(w in str(err.value) for w in words), str(err.value)


def test_reversed_sliding_mirrors_the_1d_fields_and_keeps_the_eccentricity():
    """Conventions (spectralbem.conventions): ẽ > 0 toward the leading edge, whichever way v
    points.  Sliding along −x mirrors the fields in x and changes no scalar: the physical
    1D scene returned the +x fields unmirrored (its pressure peak stayed at +1.48e-5 m
    while the grid model puts it at −1.48e-5 m), and the seed's grid scene read ẽ = +0.333
    at 180° against −0.333 at 0° (its edges were taken as −x and +x, not trailing and
    leading).  Mirror exact to round-off; ẽ at 180° equal to 0° to 1e-10."""
    import numpy as np

    a = sb.solve(load_scene(CASES / "sinusoid_physical.toml"))
    b = sb.solve(load_scene(CASES / "sinusoid_physical.toml",
                            overrides={"motion.direction_deg": 180.0}))
    assert b.attrs["model"] == "sinusoid1d"
    np.testing.assert_array_equal(b.pressure.values, a.pressure.values[::-1])
    np.testing.assert_array_equal(b.position.values, -a.position.values[::-1])
    assert float(b.eccentricity) == float(a.eccentricity) < 0
    e = [sb.solve(load_scene(CASES / "seed_sinusoid_2d.toml", overrides={
        "sinusoid.cells_per_wavelength": 1024, "sinusoid.direction_deg": d})).e_tilde.item()
        for d in (0.0, 180.0)]
    assert e[0] < 0 and e[1] == pytest.approx(e[0], abs=1e-10)


def test_max_iterations_guards_the_adhesiveless_start_of_an_adhesive_scene(monkeypatch):
    """``solver.max_iterations`` of an adhesive scene is the guard of its adhesiveless start
    (it had no effect at all there); the front iteration's is ``max_outer``."""
    import spectralbem.contact as contact

    seen, real = [], contact.solve_contact

    def spy(*a, **kw):
        seen.append(kw.get("maxiter"))
        return real(*a, **kw)

    monkeypatch.setattr(contact, "solve_contact", spy)
    sb.solve(load_scene(CASES / "jkr_sphere.toml", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "adhesion.a0": 6.25e-5, "solver.max_iterations": 7}))
    assert seen and set(seen) == {7}


def test_a0_is_checked_against_the_cells_of_the_grid_model_only():
    """A scene that the 1D method solves has no cells: its a0 is not refused for being
    smaller than a grid cell it never uses (cases/sinusoid_physical.toml with
    grid.Nx = 128, a0 0.32 of a cell, was); where 'auto' chooses the grid, or grid2d is
    given, a0 below one cell is refused before any solve, naming the key."""
    case = CASES / "sinusoid_physical.toml"
    sc = load_scene(case, overrides={"grid.Nx": 128})
    assert sc.model == "sinusoid1d"
    with pytest.raises(SceneError, match=r"adhesion.a0: .* smaller than one cell .* grid"):
        load_scene(case, overrides={"grid.Nx": 128, "scene.model": "grid2d"})
    with pytest.raises(SceneError, match=r"adhesion.a0: .* smaller than one cell .* grid"):
        load_scene(CASES / "jkr_sphere.toml", overrides={"grid.Nx": 32, "grid.Ny": 32})


def test_a_seed_scene_records_the_edge_rule_it_chose():
    """A seed grid scene without [solver] records the ``solver.extrapolate_a0`` it decided
    (on, an elastic sinusoid with a0 of two cells or more; it recorded no solver at all, so
    that its dataset did not say which edge ran), and reruns to the same state from it."""
    import json

    ds = sb.solve(load_scene(CASES / "seed_sinusoid_2d.toml", overrides={"sinusoid.zeta": 0.0}))
    spec = json.loads(ds.attrs["scene"])
    assert spec["solver"] == {"extrapolate_a0": True}
    assert float(sb.solve(load_scene(spec)).a_tilde) == float(ds.a_tilde)


@pytest.mark.parametrize("overrides", [{}, {"sinusoid.zeta": 0.0, "sinusoid.a0_tilde": 0.004}])
def test_a_seed_scene_refuses_an_extrapolated_edge_it_cannot_have(overrides):
    """``solver.extrapolate_a0 = true`` on a seed grid scene that cannot have it (sliding
    viscoelastic: a0 is physical; elastic with a0 under two cells) is a scene error naming the
    key, before any solve (the solve's ValueError was the message)."""
    with pytest.raises(SceneError, match=r"solver.extrapolate_a0: true needs"):
        load_scene(CASES / "seed_sinusoid_2d.toml",
                   overrides={**overrides, "solver.extrapolate_a0": True})
