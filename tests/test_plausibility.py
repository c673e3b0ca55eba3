"""Plausibility warnings: valid scenes that look like mistakes are named before the solve."""

import warnings
from pathlib import Path

import numpy as np
import pytest

from spectralbem import cli
from spectralbem.plausibility import PlausibilityWarning, scene_warnings
from spectralbem.scenes import load_scene, read_scene_file

CASES = Path(__file__).resolve().parent.parent / "cases"
SMALL = {"grid.Nx": 32, "grid.Ny": 32, "surface.cutoff_wavelength": 1.25e-4}


def rough(**over):
    return load_scene(CASES / "rubber_rough.toml", overrides={**SMALL, **over})


def test_the_shipped_rough_rubber_case_is_plausible():
    assert scene_warnings(rough()) == []


@pytest.mark.parametrize("over, words", [
    # a modulus meant in MPa written as a number of pascals: p̄ = 10.7 kPa on E0 = 2 Pa
    ({"material.E0": 2.0, "material.Einf": 20.0},
     ["control.mean_pressure", "1.067e+04 Pa", "of the relaxed contact modulus", "MPa"]),
    # the same surface 20 times steeper: rms slope 2
    ({"surface.rms_slope": 2.0}, ["surface", "rms slope is 2", "above 0.5"]),
])
def test_implausible_inputs_are_named(over, words):
    msgs = scene_warnings(rough(**over))
    assert len(msgs) == 1 and all(w in msgs[0] for w in words), msgs


def test_a_forgotten_height_scale_is_named(tmp_path):
    """A height map in µm read as metres: rms height 1 m in a 1 mm cell (and slopes of
    order 1e3)."""
    rng = np.random.default_rng(0)
    np.save(tmp_path / "h.npy", rng.normal(size=(32, 32)))
    sc = load_scene({"grid": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 32, "Ny": 32},
                     "surface": {"kind": "file", "path": str(tmp_path / "h.npy")},
                     "material": {"kind": "elastic", "E": 1e6, "nu": 0.5},
                     "control": {"penetration": 0.5}})
    msgs = " | ".join(scene_warnings(sc))
    assert "rms height" in msgs and "of the cell's side" in msgs and "surface.scale" in msgs


def test_a_modulus_table_short_of_the_excited_frequencies_is_named(tmp_path):
    """An SLS tabulated over ω in [1, 1e3] rad/s.  On a 1 mm cell of 32², sliding excites
    q·v from v·2π/L to v·π√2/h: 25 to 569 rad/s at 4 mm/s (covered), 251 to 5.7e3 rad/s at
    40 mm/s (not covered above 1e3)."""
    w = np.logspace(0, 3, 31)
    E = 2e6 * (1 - 1j * w * 1e-2) / (1 - 1j * w * 1e-3)
    np.savetxt(tmp_path / "e.csv", np.c_[w, E.real, -E.imag], delimiter=",")
    table = {"kind": "tabulated", "path": str(tmp_path / "e.csv"), "nu": 0.5}

    def msgs(speed):
        raw = read_scene_file(CASES / "rubber_rough.toml")
        sc = load_scene({**raw, "material": table, "motion": {"speed": speed}},
                        overrides=SMALL)
        return scene_warnings(sc)

    assert msgs(4e-3) == []
    out = msgs(4e-2)
    assert len(out) == 1 and "modulus table covers ω in [1, 1e+03]" in out[0]
    assert "extrapolated" in out[0]


def test_a0_large_against_the_cut_off_is_named():
    """rough_load_unload: a0 = 7.8 µm against a cut-off of 31 µm (0.25 > 0.1).  Its slab is
    viscoelastic and sliding, where a0 is a physical length: the advice says so (it gave the
    elastic one, "a0 is numerical, one cell is the most accurate"); an elastic slab gets the
    elastic advice."""
    def cut_off(material=None):
        raw = read_scene_file(CASES / "rough_load_unload.toml")
        sc = load_scene({**raw, "material": material or raw["material"]}, base_dir=CASES)
        return [m for m in scene_warnings(sc) if "surface's cut-off" in m]

    visco = cut_off()
    assert len(visco) == 1 and "adhesion.a0" in visco[0] and "0.25 of the surface's" in visco[0]
    assert "physical process-zone length" in visco[0] and "numerical" not in visco[0]
    elastic = cut_off({"kind": "elastic", "E": 1e6, "nu": 0.5})
    assert len(elastic) == 1 and "a0 is numerical" in elastic[0]


def test_a0_of_many_cells_in_an_elastic_scene_is_named():
    """An elastic scene with a0 of 8 cells (numerical there; its answer moves with a0 and
    wide bands take many front iterations, docs/theory.md) is warned, whatever the
    smoothing; with a0 of 4 cells or a viscoelastic slab it is not."""
    raw = read_scene_file(CASES / "rough_convergence.toml")
    raw["material"] = {"kind": "elastic", "E": 1e6, "nu": 0.5}

    def msgs(**over):
        return [m for m in scene_warnings(load_scene(raw, overrides={
            "grid.Nx": 256, "grid.Ny": 256, **over}, base_dir=CASES)) if "spans" in m]

    out = msgs(**{"adhesion.a0": 3.125e-05})
    assert len(out) == 1 and "spans 8 cells in an elastic scene" in out[0]
    assert msgs(**{"adhesion.a0": 1.5625e-05}) == []
    assert len(msgs(**{"adhesion.a0": 3.125e-05, "solver.front_smoothing": 1.5})) == 1
    raw["material"] = read_scene_file(CASES / "rough_convergence.toml")["material"]
    assert msgs(**{"adhesion.a0": 3.125e-05}) == []


def test_relaxation_length_of_few_cells_is_named():
    """rough_convergence: vτ = 3.98e-4 m/s × 10 ms = 3.98 µm is 1.02 cells at 256² (warned:
    below 2, where the sinusoid's μ_a is 1 % off the 1D method's with the default kernel,
    bench/relaxation_length.py) and 2.04 at 512² (not); with the sampled kernel 512² is warned
    (below 2.5: 5 % off) and 1024² (4.08) not; adhesiveless or at rest it is not checked."""
    def msgs(n, **over):
        return [m for m in scene_warnings(load_scene(CASES / "rough_convergence.toml",
                                                     overrides={"grid.Nx": n, "grid.Ny": n,
                                                                **over}))
                if "relaxation length" in m]

    out = msgs(256)
    assert len(out) == 1 and "vτ = 3.98e-06 m is 1.02 cells long (warned below 2)" in out[0]
    assert msgs(512) == []
    assert msgs(256, **{"adhesion.dgamma": 0.0}) == []
    sampled = {"solver.delayed_kernel": "sampled"}
    out = msgs(512, **sampled)
    assert len(out) == 1 and "2.04 cells long (warned below 2.5)" in out[0], out
    assert msgs(1024, **sampled) == []


def test_small_patch_diameter_is_the_area_weighted_tenth():
    """Discs of radius 3, 6 and 12 cells (areas 9 : 36 : 144): the smallest holds 4.8 % of
    the area, the two smaller 24 %, so the diameter below which a tenth lies is the middle
    disc's (12 cells, to its pixel count); a patch thinner than a0 is not counted."""
    from spectralbem.front import small_patch_diameter

    i, j = np.meshgrid(np.arange(128), np.arange(128), indexing="ij")
    mask = np.zeros((128, 128), bool)
    for (ci, cj), r in (((20, 20), 3), ((60, 20), 6), ((64, 80), 12)):
        mask |= (i - ci) ** 2 + (j - cj) ** 2 <= r * r
    d = small_patch_diameter(mask, 1.0, (1.0, 1.0))
    assert d == pytest.approx(12.0, rel=0.03)
    mask[100:102, 90:127] = True  # a strip 2 cells wide: unresolved for a0 = 2 cells
    assert small_patch_diameter(mask, 2.0, (1.0, 1.0)) == pytest.approx(d, rel=1e-12)
    assert np.isnan(small_patch_diameter(np.zeros((8, 8), bool), 1.0, (1.0, 1.0)))


@pytest.mark.parametrize("a0, warned", [(3.2e-5, True), (1.6e-5, False)])
def test_a0_large_against_the_patches_found_is_named(a0, warned, tmp_path, capsys):
    """After the solve: the JKR sphere at 64² holds one disc (the mask) of diameter 0.20-0.30
    mm, a0 = 32 µm (two cells: the band a0 wide at every orientation; the edge extrapolated
    to a0 → 0 by default) is 0.15 of it on the unloading step (warned, named, printed by
    ``run``; the mask of 146 cells there, radius 106.5 µm, lies 0.2 cell outside the
    estimated sub-cell front, 103.4 µm against JKR's 100.5 µm: a patch 3.2 a0 in radius, the
    coarse end of the band rule, docs/theory.md); a0 = 16 µm (0.08) is not warned."""
    import spectralbem as sb
    from spectralbem.plausibility import state_warnings

    over = {"grid.Nx": 64, "grid.Ny": 64, "adhesion.a0": a0,
            "control.mean_pressure": [2e3, 500.0]}
    sc = load_scene(CASES / "jkr_sphere.toml", overrides=over)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ds = sb.solve(sc)
    d = ds["small_patch_diameter"].values
    assert np.all((d > 2.0e-4) & (d < 3.2e-4)), d
    msgs = state_warnings(sc, ds)
    assert [str(w.message) for w in rec if w.category is PlausibilityWarning] == msgs
    assert bool(msgs) is warned
    if warned:
        assert "adhesion.a0: 3.2e-05 m is 0.15 of the small contact patches" in msgs[0]
        assert cli.main(["run", str(CASES / "jkr_sphere.toml"), "-o", str(tmp_path / "j.nc"),
                         "-q"] + [f"--set={k}={v}" for k, v in over.items()]) == 0
        assert "warning: adhesion.a0: 3.2e-05 m is 0.15 " in capsys.readouterr().err
        out = tmp_path / "s.nc"
        assert cli.main(["run", str(CASES / "jkr_sphere.toml"), "-o", str(out), "-q",
                         "--strict"] + [f"--set={k}={v}" for k, v in over.items()]) == 1
        assert (f"implausible (--strict, dataset written to {out}): adhesion.a0: 3.2e-05 m "
                "is 0.15 ") in capsys.readouterr().err and out.exists()


def test_seed_scenes_are_not_checked():
    assert scene_warnings(load_scene(CASES / "seed_sinusoid_1d.toml")) == []


def test_solve_warns_and_the_command_line_prints_or_stops(tmp_path, capsys):
    import spectralbem as sb

    sc = rough(**{"material.E0": 2.0, "material.Einf": 20.0})
    with pytest.warns(PlausibilityWarning, match="control.mean_pressure"):
        sb.solve(sc)
    args = ["run", str(CASES / "rubber_rough.toml"), "-o", str(tmp_path / "x.nc"), "-q",
            "--set", "material.E0=2", "--set", "material.Einf=20"]
    args += [f"--set={k}={v}" for k, v in SMALL.items()]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the command line prints, it does not warn twice
        assert cli.main(args) == 0
    assert "warning: control.mean_pressure" in capsys.readouterr().err
    assert cli.main(args + ["--strict"]) == 1
    err = capsys.readouterr().err
    assert "implausible (--strict): control.mean_pressure" in err
    assert not (tmp_path / "y.nc").exists()
