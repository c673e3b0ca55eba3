"""Bad-input catalogue: the Python API and the command line reject each input before
any heavy work, with an error naming the parameter, its value and the allowed range.  The
scene-file part of the catalogue is ``tests/test_scenes.py::MALFORMED`` (46 entries)."""

from pathlib import Path

import numpy as np
import pytest

from spectralbem import cli, fft, sinusoid1d
from spectralbem.adhesive import solve_adhesive
from spectralbem.contact import solve_contact
from spectralbem.io import write_dataset
from spectralbem.layers import GluedLayer, PressureLayer
from spectralbem.materials import Elastic, Prony, StandardLinearSolid, Tabulated
from spectralbem.scenes import Scene
from spectralbem.spectral import Cell, SpectralOperator
from spectralbem.surfaces import bisinusoid, paraboloid, read_heights, self_affine, sinusoid

CELL = Cell(1.0, 1.0, 16, 16)
OP = SpectralOperator(CELL, Elastic(1.0, 0.3))
H = bisinusoid(CELL, 0.01)


def with_bad(value, at=3):
    h = H.copy()
    h.flat[at] = value
    return h


API = [
    ("Cell Nx=0", lambda: Cell(1.0, 1.0, 0, 16), ["Nx = 0", "[4, 65536]"]),
    ("Cell 1x1", lambda: Cell(1.0, 1.0, 1, 1), ["Nx = 1", "[4, 65536]"]),
    ("Cell Lx nan", lambda: Cell(np.nan, 1.0, 16, 16), ["Lx = nan", "> 0"]),
    ("Cell Ly<0", lambda: Cell(1.0, -2.0, 16, 16), ["Ly = -2.0", "> 0"]),
    ("E = 0", lambda: Elastic(0.0, 0.3), ["E = 0.0", "> 0"]),
    ("E nan", lambda: Elastic(np.nan, 0.3), ["E = nan", "> 0"]),
    ("nu 0.7", lambda: Elastic(1.0, 0.7), ["nu = 0.7", "(-1, 0.5]"]),
    ("nu -1", lambda: Elastic(1.0, -1.0), ["nu = -1.0", "(-1, 0.5]"]),
    ("Einf<E0", lambda: StandardLinearSolid(2.0, 1.0, 1.0), ["Einf = 1.0", ">= E0 = 2.0"]),
    ("tau 0", lambda: StandardLinearSolid(1.0, 2.0, 0.0), ["tau = 0.0", "> 0"]),
    ("tau -1", lambda: StandardLinearSolid(1.0, 2.0, -1.0), ["tau = -1.0", "> 0"]),
    ("prony mismatch", lambda: Prony(1.0, (1.0, 2.0), (1.0,)), ["moduli has 2", "times has 1"]),
    ("prony E<0", lambda: Prony(1.0, (-1.0,), (1.0,)), ["moduli[0] = -1.0", "> 0"]),
    ("table omega", lambda: Tabulated((1.0, 0.5), (1.0, 2.0), (0.1, 0.1)),
     ["omega", "strictly increasing", "(1.0 -> 0.5)"]),
    ("table loss<0", lambda: Tabulated((1.0, 2.0), (1.0, 2.0), (-0.1, 0.1)),
     ["loss min = -0.1", ">= 0"]),
    ("table omega<=0", lambda: Tabulated(np.array([0.0, 1.0]), (1.0, 2.0), (0.1, 0.1)),
     ["omega min = 0.0", "> 0"]),
    ("table storage drop", lambda: Tabulated((1.0, 2.0, 3.0), (1.0, 2.0, 1.0), (0.1,) * 3),
     ["storage decreases at row 3 (1.0 after a maximum of 2.0"]),
    ("E numpy", lambda: Elastic(np.float64(0.0), 0.3), ["E = 0.0", "> 0"]),
    ("nu numpy", lambda: Elastic(1.0, np.float64(0.7)), ["nu = 0.7", "(-1, 0.5]"]),
    ("Cell Lx numpy", lambda: Cell(np.float64(-1.0), 1.0, 16, 16), ["Lx = -1.0", "> 0"]),
    ("load numpy < 0", lambda: solve_contact(OP, H, mean_pressure=np.float64(-0.1)),
     ["mean_pressure = -0.1", "(0, inf)"]),
    ("a0 numpy < cell", lambda: solve_adhesive(OP, H, 0.1, np.float64(0.01), mean_pressure=0.1),
     ["a0 = 0.01", "[0.0625, 0.5]"]),
    ("table file", lambda: Tabulated.from_csv("/nonexistent/e.csv"),
     ["/nonexistent/e.csv", "cannot read"]),
    ("glued d=0", lambda: GluedLayer(0.0), ["d = 0.0", "> 0"]),
    ("pressure d<0", lambda: PressureLayer(-1.0), ["d = -1.0", "> 0"]),
    ("velocity nan", lambda: SpectralOperator(CELL, Elastic(1.0), velocity=(np.nan, 0.0)),
     ["velocity = (nan, 0.0)", "finite"]),
    ("velocity 3d", lambda: SpectralOperator(CELL, Elastic(1.0), velocity=(1, 0, 0)),
     ["velocity = (1, 0, 0)", "(vx, vy)"]),
    ("heights shape", lambda: solve_contact(OP, np.zeros((8, 8)), mean_pressure=0.1),
     ["heights", "(8, 8)", "(16, 16)"]),
    ("heights nan", lambda: solve_contact(OP, with_bad(np.nan), mean_pressure=0.1),
     ["heights", "NaN"]),
    ("heights inf", lambda: solve_contact(OP, with_bad(np.inf), mean_pressure=0.1),
     ["heights", "inf"]),
    ("two controls", lambda: solve_contact(OP, H, mean_pressure=0.1, penetration=0.1),
     ["mean_pressure", "penetration", "exactly one"]),
    ("load < 0", lambda: solve_contact(OP, H, mean_pressure=-0.1),
     ["mean_pressure = -0.1", "(0, inf)"]),
    ("load nan", lambda: solve_contact(OP, H, mean_pressure=np.nan),
     ["mean_pressure = nan", "(0, inf)"]),
    ("penetration nan", lambda: solve_contact(OP, H, penetration=np.nan),
     ["penetration = nan", "finite"]),
    ("a0 < cell", lambda: solve_adhesive(OP, H, 0.1, 0.01, mean_pressure=0.1),
     ["a0 = 0.01", "[0.0625, 0.5]"]),
    ("a0 > cell/2", lambda: solve_adhesive(OP, H, 0.1, 0.9, mean_pressure=0.1),
     ["a0 = 0.9", "[0.0625, 0.5]"]),
    ("front_tol > a0/2", lambda: solve_adhesive(OP, H, 0.1, 0.25, mean_pressure=0.1,
                                                front_tol=3.0),
     ["front_tol = 3.0", "(0, 2]", "a0 = 4 cells"]),
    ("band_tol too loose", lambda: solve_adhesive(OP, H, 0.1, 0.25, mean_pressure=0.1,
                                                  band_tol=1e-3),
     ["band_tol = 0.001", "(0, 1e-05]"]),
    ("extrapolate a0 = 1 cell", lambda: solve_adhesive(OP, H, 0.1, 0.0625, mean_pressure=0.1,
                                                       extrapolate_a0=True),
     ["extrapolate_a0", "at least 2 cells", "a0 = 1 cells"]),
    ("extrapolate viscoelastic", lambda: solve_adhesive(
        SpectralOperator(CELL, StandardLinearSolid(1.0, 10.0, 1.0), velocity=(0.1, 0.0)), H,
        0.1, 0.125, mean_pressure=0.1, extrapolate_a0=True),
     ["extrapolate_a0", "elastic scene", "physical"]),
    ("dgamma < 0", lambda: solve_adhesive(OP, H, -0.1, 0.1, mean_pressure=0.1),
     ["dgamma", "-0.1", ">= 0"]),
    ("dgamma nan", lambda: solve_adhesive(OP, H, np.nan, 0.1, mean_pressure=0.1),
     ["dgamma", "nan", "finite"]),
    ("dgamma map", lambda: solve_adhesive(OP, H, np.ones((4, 4)), 0.1, mean_pressure=0.1),
     ["dgamma map", "(4, 4)", "(16, 16)"]),
    ("adhesive heights", lambda: solve_adhesive(OP, with_bad(np.nan), 0.1, 0.1,
                                                mean_pressure=0.1), ["heights", "non-finite"]),
    ("adhesive load inf", lambda: solve_adhesive(OP, H, 0.1, 0.1, mean_pressure=np.inf),
     ["mean_pressure = inf", "finite"]),
    ("1D zeta<0", lambda: sinusoid1d.solve(-1.0, 10, 0.01, p_tilde=0.1, a0_tilde=0.01),
     ["zeta = -1.0", "[0.0, inf]"]),
    ("1D beta<1", lambda: sinusoid1d.solve(1.0, 0.5, 0.01, p_tilde=0.1, a0_tilde=0.01),
     ["beta = 0.5", "[1.0, 1"]),
    ("1D a0<0", lambda: sinusoid1d.solve(1.0, 10, 0.01, p_tilde=0.1, a0_tilde=-0.01),
     ["a0_tilde = -0.01", "[0.0, 1.0]"]),
    ("1D Gamma nan", lambda: sinusoid1d.solve(1.0, 10, np.nan, p_tilde=0.1, a0_tilde=0.01),
     ["Gamma = nan", "[0.0, 10.0]"]),
    ("1D p inf", lambda: sinusoid1d.solve(1.0, 10, 0.01, p_tilde=np.inf, a0_tilde=0.01),
     ["p_tilde = inf", "finite"]),
    ("1D no control", lambda: sinusoid1d.solve(1.0, 10, 0.01, a0_tilde=0.01),
     ["p_tilde", "delta_tilde", "exactly one"]),
    ("2D a0 < cell", lambda: Scene.sinusoid(0.1, 10, 0.008, p_tilde=0.1, a0_tilde=1e-4,
                                            cells_per_wavelength=512),
     ["sinusoid.a0_tilde", "smaller than one cell", "[0.01227, 1]"]),
    ("hurst 1.5", lambda: self_affine(CELL, 1.5, rolloff=10, cutoff=40, rms_slope=0.1),
     ["hurst = 1.5", "(0, 1)"]),
    ("cutoff<rolloff", lambda: self_affine(CELL, 0.8, rolloff=40, cutoff=10, rms_slope=0.1),
     ["cutoff = 10", "rolloff = 40"]),
    ("amplitude<0", lambda: sinusoid(CELL, -1.0), ["amplitude = -1.0", "> 0"]),
    ("radius 0", lambda: paraboloid(CELL, 0.0), ["radius = 0.0", "> 0"]),
    ("threads 0", lambda: fft.set_threads(0), ["threads = 0", ">= 1"]),
    ("height file", lambda: read_heights("/nonexistent/h.npy"),
     ["/nonexistent/h.npy", "does not exist"]),
]


@pytest.mark.parametrize("name, call, words", API, ids=[a[0] for a in API])
def test_api_bad_input(name, call, words):
    with pytest.raises((ValueError, OSError)) as err:
        call()
    msg = str(err.value)
    for w in words:
        assert w in msg, (w, msg)
    # values print as plain numbers (numpy 2's repr of a numpy scalar is np.float64(1.0))
    assert "np.float" not in msg and "np.int" not in msg, msg


def test_unwritable_output():
    """/proc refuses new files even for root (a chmod-ed folder would not stop root)."""
    import xarray as xr

    with pytest.raises(OSError, match=r"'/proc/x.nc'.*not writable"):
        write_dataset(xr.Dataset({"a": ((), 1.0)}), "/proc/x.nc")


CASE = "cases/seed_sinusoid_1d.toml"
CLI = [
    (["run", CASE, "-o", "{tmp}/x.nc", "--set", "sinusoid.zeta=-2"],
     ["sinusoid.zeta", "-2.0", "0 or [1e-12, 1e+12]"]),
    (["run", CASE, "-o", "{tmp}/x.nc", "--set", "sinusoid.speed=1"],
     ["sinusoid.speed", "unknown key"]),
    (["run", CASE, "-o", "{tmp}/x.nc", "--set", "zeta=1"], ["zeta", "section.key"]),
    (["run", "{tmp}/bad.toml", "-o", "{tmp}/x.nc"], ["bad.toml", "not valid TOML"]),
    (["run", CASE, "-o", "{tmp}/missing/x.nc"], ["output folder", "does not exist"]),
    (["sweep", CASE, "--over", "zeta=1:2", "-o", "{tmp}/s.nc"], ["--over", "START:STOP:NUM"]),
    (["sweep", CASE, "--over", "speed=1,2", "-o", "{tmp}/s.nc"],
     ["speed", "not a key of this scene"]),
    (["sweep", CASE, "--over", "zeta=-1,1", "-o", "{tmp}/s.nc"],
     ["point 0", "sinusoid.zeta", "-1.0"]),
    (["plot", "{tmp}/none.nc"], ["none.nc", "does not exist"]),
    # refused before any point is built (1e8 points took 24 GB before being killed)
    (["sweep", CASE, "--over", "zeta=1:2:100000000", "-o", "{tmp}/s.nc"],
     ["NUM = 100000000", "[1, 100000]"]),
    (["sweep", CASE, "--over", "zeta=1:2:1000", "--over", "p_tilde=0:0.2:1000", "-o",
      "{tmp}/s.nc"], ["1e+06 points", "1000 × 1000", "100000"]),
    (["sweep", CASE, "--over", "zeta=0.1,1", "--over", "zeta=0.2,2", "-o", "{tmp}/s.nc"],
     ["sinusoid.zeta", "swept more than once"]),
    (["sweep", CASE, "--over", "zeta=0.1,1", "--workers", "-2", "-o", "{tmp}/s.nc"],
     ["--workers", "-2", ">= 1"]),
    (["sweep", "cases/rubber_rough.toml", "--over", "surface.seed=1.5,2", "-o", "{tmp}/s.nc"],
     ["surface.seed", "1.5 is not a whole number"]),
    (["run", CASE, "-o", "{tmp}"], ["is not a regular file"]),
    # run, sweep and refine write netCDF datasets: an image name is refused before any solve
    (["run", CASE, "-o", "{tmp}/x.png"], ["-o", "x.png", "'.png'", "allowed suffix: .nc"]),
    (["run", CASE, "-o", "{tmp}/x"], ["-o", "no suffix", "allowed suffix: .nc"]),
    (["sweep", CASE, "--over", "zeta=1,2", "-o", "{tmp}/s.png"],
     ["-o", "s.png", "allowed suffix: .nc"]),
    (["refine", "cases/rubber_rough.toml", "--sizes", "32", "64", "-o", "{tmp}/r.txt"],
     ["-o", "r.txt", "allowed suffix: .nc"]),
    (["run", "{tmp}/copy.toml", "-o", "{tmp}/copy.toml"], ["copy.toml", "is the input"]),
    # validate's -o is a folder (created when missing): a file there is refused before any solve
    (["validate", "--quick", "-o", "{tmp}/copy.toml"],
     ["copy.toml", "exists and is not a folder"]),
]


@pytest.mark.parametrize("argv, words", CLI, ids=[" ".join(c[0][:2] + c[0][-2:]) for c in CLI])
def test_cli_bad_input(argv, words, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(__import__("pathlib").Path(__file__).resolve().parent.parent)
    (tmp_path / "bad.toml").write_text("[sinusoid\nzeta = 1")
    (tmp_path / "copy.toml").write_text(open(CASE).read())
    args = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert cli.main(args) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"spectralbem {argv[0]}: error:")
    for w in words:
        assert w in err, (w, err)
    if "allowed suffix: .nc" in words:  # refused before anything is written
        assert not Path(args[args.index("-o") + 1]).exists()


@pytest.mark.parametrize("command", ["run", "sweep", "refine"])
def test_output_is_none_of_the_files_the_scene_reads(command, tmp_path, capsys):
    """``-o`` naming the scene's own height map is refused before any solve (``run`` replaced
    the user's height map by its result, and ``sweep`` did at its end); relative to the
    scene's folder, as the scene reads it."""
    import numpy as np
    import xarray as xr

    h = 1e-6 * np.random.default_rng(0).standard_normal((16, 16))
    xr.Dataset({"heights": (("x", "y"), h)}).to_netcdf(tmp_path / "h.nc")
    before = (tmp_path / "h.nc").read_bytes()
    (tmp_path / "file.toml").write_text(
        '[grid]\nLx = 1e-3\nLy = 1e-3\n[surface]\nkind = "file"\npath = "h.nc"\n'
        '[material]\nkind = "elastic"\nE = 2e6\n[control]\nmean_pressure = 1e4\n')
    extra = {"run": [], "sweep": ["--over", "E=1e6,2e6"], "refine": ["--sizes", "16", "32"]}
    argv = [command, str(tmp_path / "file.toml"), *extra[command], "-o", str(tmp_path / "h.nc")]
    assert cli.main(argv) == 1
    err = capsys.readouterr().err
    assert "is the input" in err and "h.nc" in err, err
    assert (tmp_path / "h.nc").read_bytes() == before


def test_plot_output_is_an_image(tmp_path, capsys):
    """``plot -o`` writes images (matplotlib's formats), refused otherwise before rendering;
    ``run -o x.png`` wrote a netCDF file named x.png (refused: test_cli_bad_input)."""
    import xarray as xr

    ds = tmp_path / "d.nc"
    xr.Dataset({"status": ((), "partial")}).to_netcdf(ds)
    assert cli.main(["plot", str(ds), "-o", str(tmp_path / "p.nc")]) == 1
    err = capsys.readouterr().err
    for w in ("spectralbem plot: error:", "-o", "p.nc", "allowed suffixes:", ".png", ".pdf"):
        assert w in err, (w, err)
    assert not (tmp_path / "p.nc").exists()


def test_validate_creates_its_output_folder_and_names_the_command(tmp_path, monkeypatch,
                                                                   canned_validate):
    """``validate -o out`` creates the folder (and its parents) when missing, and
    validation.md names the command that wrote it and, for --quick, that it was a quick run
    (the comparisons are replaced by canned rows: the real run takes minutes)."""
    v = canned_validate
    monkeypatch.setattr(v, "jkr_sphere", lambda: ())  # the full run's sections: left out
    monkeypatch.setattr(v, "rough_cycle", lambda: None)
    monkeypatch.chdir(tmp_path)
    assert cli.main(["validate", "--quick", "-o", "out/nested"]) == 0
    report = (tmp_path / "out" / "nested" / "validation.md").read_text()
    assert (tmp_path / "out" / "nested" / "figures" / "validation_sinusoid.png").is_file()
    head = report.split("\n\n", 2)[:2]
    assert head[0] == "# Validation of the 2D solver (quick run)"
    assert "Generated by `spectralbem validate --quick -o out/nested`" in head[1]
    assert "A quick run (`--quick`)" in head[1] and "make validate" not in head[0]
    v.main(["-o", "full"])  # python -m spectralbem.validate: the full run (canned here)
    head = (tmp_path / "full" / "validation.md").read_text().split("\n\n", 2)[:2]
    assert head[0] == "# Validation of the 2D solver"
    assert "Generated by `python -m spectralbem.validate -o full`" in head[1]
    assert "quick" not in head[1]


def _problems(raw, base_dir=None) -> list:
    from spectralbem.scenes import SceneError, load_scene

    with pytest.raises(SceneError) as err:
        load_scene(raw, base_dir=base_dir)
    return err.value.problems


ELASTIC = {"kind": "elastic", "E": 1e6}


@pytest.mark.parametrize("name, content, grid, words", [
    ("h.npy", None, {"Lx": 1e-3, "Ly": 1e-3}, ["does not exist", "grid.Nx, grid.Ny are"]),
    ("h.npy", b"garbage", {"Lx": 1e-3, "Ly": 1e-3},
     ["cannot read height map", "grid.Nx, grid.Ny are"]),
    ("h.nc", None, None, ["does not exist", "grid.Nx, grid.Ny, grid.Lx, grid.Ly are"]),
    ("h.nc", b"garbage", {"Lx": 1e-3, "Ly": 1e-3, "Ny": 16},
     ["not a readable netCDF file", "grid.Nx is left out"]),
])
def test_unreadable_height_map_with_the_grid_left_out(tmp_path, name, content, grid, words):
    """A height-map scene that leaves grid keys to the file: a file that cannot be read was
    reported as "grid.Nx: missing"; now the read failure, with the key and the path, alone."""
    if content is not None:
        (tmp_path / name).write_bytes(content)
    raw = {"surface": {"kind": "file", "path": name}, "material": ELASTIC,
           "control": {"mean_pressure": 1e3}}
    if grid is not None:
        raw["grid"] = grid
    problems = _problems(raw, tmp_path)
    assert len(problems) == 1, problems
    assert problems[0].startswith("surface.path: ") and str(tmp_path / name) in problems[0]
    for w in words:
        assert w in problems[0], (w, problems)
    # a .npy map states no size: a missing Lx is still missing
    problems = _problems({**raw, "grid": {"Ly": 1e-3}}, tmp_path)
    assert problems[0].startswith("surface.path: ")
    assert any(p.startswith("grid.Lx: missing") for p in problems) == name.endswith(".npy")


ADHESIVE = {"grid": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 32, "Ny": 32},
            "surface": {"kind": "bisinusoid", "amplitude": 1e-5}, "material": ELASTIC,
            "control": {"mean_pressure": 1e3}, "adhesion": {"dgamma": 0.05, "a0": 1e-4}}


@pytest.mark.parametrize("section, key, value, words", [
    ("adhesion", "a0", -1.0, ["adhesion.a0: -1.0 is outside the allowed range"]),
    ("adhesion", "a0", "x", ["adhesion.a0: expected a number in m, got str 'x'"]),
    ("adhesion", "a0", float("nan"), ["adhesion.a0: nan is not finite"]),
    ("adhesion", "a0", True, ["adhesion.a0: expected a number in m, got bool True"]),
    ("control", "mean_pressure", "abc", ["control.mean_pressure: expected a number in Pa"]),
])
def test_an_invalid_value_is_reported_once(section, key, value, words):
    """An invalid adhesion.a0 was reported twice: its own problem and a wrong "adhesion.a0:
    missing (required when Δγ > 0)"; an invalid mean_pressure also as "give exactly one"."""
    raw = {k: dict(v) for k, v in ADHESIVE.items()}
    raw[section][key] = value
    problems = _problems(raw)
    assert len(problems) == 1, problems
    for w in words:
        assert w in problems[0], (w, problems)


def test_an_invalid_dgamma_does_not_make_the_scene_adhesiveless():
    """Δγ that failed its check: whether the scene is adhesive is unknown, so a tensile
    load is not refused as "without adhesion" (and a0 is not asked for)."""
    raw = {k: dict(v) for k, v in ADHESIVE.items()}
    raw["adhesion"] = {"dgamma": "x"}
    raw["control"]["mean_pressure"] = -5.0
    problems = _problems(raw)
    assert problems == ["adhesion.dgamma: expected a number in J/m², got str 'x'"], problems


def test_cutoff_message_on_a_strip_states_a_range():
    """grid.Ny = 1 (a y-invariant strip) under a self-affine surface: the Nyquist message
    said "allowed (0.001, 0.00025) m", an empty interval; it now says why no cut-off fits
    and what would hold it (the scene file and the Python API)."""
    import re

    from spectralbem.scenes import read_scene_file
    from spectralbem.surfaces import SurfaceError

    raw = read_scene_file("cases/rubber_rough.toml")
    for ny, words in ((1, ["y-invariant strip", "grid.Ny = 1", "longer than grid.Ly = 0.001 m",
                           "allowed grid.Ny in [33, 65536] for this cutoff",
                           "or grid.Ly < 6.25e-05 m"]),
                      (8, ["grid.Ny = 8", "no cutoff fits", "allowed grid.Ny in [33, 65536]"]),
                      (16, ["allowed (0.000125, 0.00025) m", "grid.Ny in [33, 65536]"])):
        raw["grid"]["Ny"] = ny
        problems = _problems(raw)
        assert len(problems) == 1 and problems[0].startswith("surface.cutoff_wavelength: ")
        for w in words:
            assert w in problems[0], (w, problems)
        for lo, hi in re.findall(r"allowed \(([-+.e\d]+), ([-+.e\d]+)\)", problems[0]):
            assert float(lo) < float(hi), problems  # never an empty interval
    with pytest.raises(SurfaceError) as err:
        self_affine(Cell(1e-3, 1e-3, 64, 1), 0.8, rolloff=2 * np.pi / 2.5e-4,
                    cutoff=2 * np.pi / 6.25e-5, rms_slope=0.1)
    msg = str(err.value)
    for w in ("Ny = 1 is a y-invariant strip", "no cutoff fits", "Ny in [33, 65536]",
              "Ly < 2π/cutoff = 6.25e-05 m"):
        assert w in msg, (w, msg)
    raw["grid"].update(Ny=1, Ly=1e-5)  # a narrow strip holds the band: a 1D rough profile
    from spectralbem.scenes import load_scene

    assert load_scene(raw).heights.shape == (128, 1)


def test_catalogue_size():
    from tests.test_scenes import MALFORMED

    assert len(API) + len(CLI) + len(MALFORMED) >= 40 + 20


def test_swept_integer_keys_are_integers():
    """A swept integer key (``surface.seed``, ``grid.Nx``) takes whole numbers as integers
    (the schema refused the floats a range or list parses to); other keys keep floats."""
    from spectralbem.scenes import read_scene_file
    from spectralbem.sweep import _typed

    raw = read_scene_file("cases/rubber_rough.toml")
    seed = _typed(raw, "surface.seed", 2.0)
    assert seed == 2 and isinstance(seed, int)
    assert isinstance(_typed(raw, "grid.Nx", 64.0), int)
    assert isinstance(_typed(raw, "motion.speed", 1e-3), float)
