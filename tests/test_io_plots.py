"""Datasets (round trip, units, atomic writes), plots and the command line."""

import numpy as np
import pytest
import xarray as xr

from spectralbem import cli
from spectralbem.io import read_dataset, write_dataset
from spectralbem.plotting import plot_contact


@pytest.fixture(scope="module")
def dataset():
    """An adhesiveless viscoelastic bi-sinusoid state through the scene path."""
    import spectralbem as sb
    from spectralbem.scenes import load_scene

    ds = sb.solve(load_scene({
        "grid": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 32, "Ny": 32},
        "surface": {"kind": "bisinusoid", "amplitude": 1e-5},
        "material": {"kind": "sls", "E0": 1e6, "Einf": 1e7, "tau": 0.01},
        "motion": {"velocity": [0.05, 0.0]}, "control": {"mean_pressure": 2e3}}))
    assert ds.status.item() == "partial"
    return ds


def test_units_and_round_trip(dataset, tmp_path):
    for name, var in {**dataset.data_vars, **dataset.coords}.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    for key in ("spectralbem_version", "created_utc", "scene", "solver_diagnostics"):
        assert key in dataset.attrs
    path = write_dataset(dataset, tmp_path / "r.nc")
    back = read_dataset(path)
    xr.testing.assert_identical(back, dataset)
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def test_heights_in_surface_topographys_layout(dataset, tmp_path):
    """The dataset's heights carry SurfaceTopography's netCDF layout (``heights(x, y)``
    with ``unit``; ``length``, ``unit``, ``periodic`` on x and y), and io.write_heights
    writes them alone as the classic file its reader takes: our reader takes them back with
    their size, and so does SurfaceTopography's when that optional package is installed
    (the same heights, sizes, unit and periodicity)."""
    from spectralbem.io import write_heights
    from spectralbem.surfaces import read_heights

    path = write_heights(dataset, tmp_path / "h.nc")
    assert path.read_bytes()[:3] == b"CDF"  # classic netCDF
    with pytest.raises(ValueError, match="no heights"):
        write_heights(dataset.drop_vars("heights"), tmp_path / "none.nc")
    for name in ("x", "y"):
        a = dataset[name].attrs
        assert a["unit"] == "m" and a["periodic"] == 1
        assert a["length"] == pytest.approx(1e-3, rel=1e-12)
    assert dataset["heights"].attrs["unit"] == "m"
    h, size = read_heights(path)
    np.testing.assert_array_equal(h, dataset["heights"].values)
    assert size == pytest.approx((1e-3, 1e-3), rel=1e-12)
    st = pytest.importorskip("SurfaceTopography")
    topo = st.read_topography(str(path))
    np.testing.assert_array_equal(np.asarray(topo.heights()), dataset["heights"].values)
    assert tuple(topo.physical_sizes) == pytest.approx((1e-3, 1e-3), rel=1e-12)
    assert topo.unit == "m" and topo.is_periodic


def test_unwritable_output(dataset, tmp_path):
    with pytest.raises(OSError, match="does not exist"):
        write_dataset(dataset, tmp_path / "missing" / "r.nc")


def test_plot_contact_png(dataset, tmp_path):
    """A bi-sinusoid state sliding along x: the pressure scale, clipped at its 99th
    percentile, says so (an extend arrow, the peak in the bar's label); the power spectrum
    of a single mode is a line of text, not a dot on empty axes; the velocity arrow is
    drawn from a point (no text attached), exactly along x, its label apart."""
    from spectralbem.plot_maps import _pressure_text

    fig = plot_contact(dataset, tmp_path / "c.png")
    labels = [ax.get_xlabel() for ax in fig.axes[:3]]
    assert labels == ["x (mm)"] * 3
    (image,) = fig.axes[1].get_images()
    bar = image.colorbar
    p = dataset.pressure.values[dataset.contact.values.astype(bool)]
    assert p.max() * 1e-3 > image.norm.vmax and bar.extend == "max"
    assert bar.ax.get_ylabel() == ("pressure (kPa)\nscale clipped: peak "
                                   f"{_pressure_text(p.max())}")
    (spectrum,) = [ax for ax in fig.axes if ax.get_title() == "surface power spectrum"]
    assert not spectrum.get_lines() and not spectrum.axison
    assert spectrum.texts[0].get_text().startswith("single mode\n|q| = 8.89e+03 1/m")
    arrows = [a for a in fig.axes[0].texts if getattr(a, "arrow_patch", None) is not None]
    assert len(arrows) == 1 and arrows[0].get_text() == ""
    assert arrows[0].xy[1] == arrows[0].xyann[1] and arrows[0].xy[0] > arrows[0].xyann[0]
    assert "v" in [t.get_text() for t in fig.axes[0].texts]
    assert fig.axes[3].get_xlabel() == "distance along v (mm)"  # the profile cut
    assert (tmp_path / "c.png").stat().st_size > 10_000


def test_cli_plot_and_info(dataset, tmp_path, capsys):
    write_dataset(dataset, tmp_path / "r.nc")
    assert cli.main(["plot", str(tmp_path / "r.nc")]) == 0
    assert (tmp_path / "r.png").exists()
    assert cli.main(["info"]) == 0
    info = capsys.readouterr().out
    assert "FFT backend" in info and "compiled loops: " in info
    assert all(f"{d} " in info for d in ("xarray", "netCDF4", "dask", "numba"))
    assert cli.main(["plot", str(tmp_path / "nope.nc")]) == 1
    assert "does not exist" in capsys.readouterr().err


# -- datasets of every kind: round trip, units, plots, command line ----------------------------
from pathlib import Path  # noqa: E402

import spectralbem as sb  # noqa: E402
from spectralbem.plotting import plot_dataset  # noqa: E402
from spectralbem.scenes import load_scene  # noqa: E402

CASES = Path(__file__).resolve().parent.parent / "cases"
KINDS = {
    "grid": ("rubber_rough", {"grid.Nx": 32, "grid.Ny": 32,
                              "surface.cutoff_wavelength": 1.25e-4}),
    "adhesive_grid": ("jkr_sphere", {"grid.Nx": 128, "grid.Ny": 128, "adhesion.a0": 1.6e-5,
                                     "control.mean_pressure": 1e3}),
    "oned": ("sinusoid_physical", {}),
    "path": ("jkr_sphere", {"grid.Nx": 64, "grid.Ny": 64, "adhesion.a0": 3.2e-5,
                            "control.mean_pressure": [2e3, 500.0]}),
}
LABELS = {"grid": ("x (mm)", "distance along v (mm)"), "adhesive_grid": ("x (mm)",),
          "oned": ("k x (sliding along +x)",), "path": ("p̄ (Pa)",)}


@pytest.fixture(scope="module")
def results():
    return {k: sb.solve(load_scene(CASES / f"{c}.toml", overrides=o))
            for k, (c, o) in KINDS.items()}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_scene_datasets_round_trip_and_plot(results, kind, tmp_path):
    ds = results[kind]
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert var.attrs.get("units") is not None and var.attrs.get("long_name"), name
    for key in ("model", "scene", "spectralbem_version", "created_utc", "fft_backend"):
        assert key in ds.attrs, key
    back = read_dataset(write_dataset(ds, tmp_path / "r.nc"))
    xr.testing.assert_identical(back, ds)
    fig = plot_dataset(back, tmp_path / "r.png")
    assert (tmp_path / "r.png").stat().st_size > 10_000
    xl = {ax.get_xlabel() for ax in fig.axes}
    for label in LABELS[kind]:
        assert label in xl, (label, xl)
    if kind == "adhesive_grid":
        assert "G_front" in ds and np.isfinite(ds.G_front.values).any()
        assert "local G/Δγ on the front" in {ax.get_ylabel() for ax in fig.axes}
    if kind == "path":  # a contact map per step under the curves, titled with its load
        titles = [ax.get_title() for ax in fig.axes if ax.get_title().startswith("step")]
        assert [t.split(":")[0] for t in titles] == ["step 0", "step 1"], titles
        assert "2000" in titles[0] and str(ds.status.values[1]) in titles[1]


def test_plot_step_of_a_path(results, tmp_path, capsys):
    """``spectralbem plot --step K`` draws step K of a path as a state; a step outside the
    path or a dataset without steps is refused naming --step and the allowed range."""
    path = write_dataset(results["path"], tmp_path / "p.nc")
    assert cli.main(["plot", str(path), "--step", "-1", "-o", str(tmp_path / "s.png")]) == 0
    assert (tmp_path / "s.png").stat().st_size > 10_000
    assert cli.main(["plot", str(path), "--step", "2"]) == 1
    assert "--step: 2 is outside the path's steps [0, 1]" in capsys.readouterr().err
    grid = write_dataset(results["grid"], tmp_path / "g.nc")
    assert cli.main(["plot", str(grid), "--step", "0"]) == 1
    assert "not a path" in capsys.readouterr().err


def test_sweep_plot(tmp_path):
    """The sweep plot kind, on a dataset assembled as run_sweep does (two swept keys)."""
    ds = xr.Dataset({k: (("zeta", "p_tilde"), np.random.default_rng(0).random((4, 2)) + 0.1,
                         {"units": "1", "long_name": k})
                     for k in ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma",
                               "mu_bar")},
                    coords={"zeta": ("zeta", [1e-3, 1e-2, 1e-1, 1.0], {"units": "1"}),
                            "p_tilde": ("p_tilde", [0.05, 0.15], {"units": "1"})},
                    attrs={"sweep_keys": '["sinusoid.zeta", "sinusoid.p_tilde"]'})
    fig = plot_dataset(ds, tmp_path / "s.png")
    assert fig.axes[0].get_xscale() == "log" and fig.axes[0].get_xlabel() == "sinusoid.zeta"
    assert {ax.get_ylabel() for ax in fig.axes} >= {"ã", "ẽ", "G1/Δγ", "G2/Δγ", "μ/Λ̃"}
    assert fig.axes[0].get_legend() is not None
    assert (tmp_path / "s.png").stat().st_size > 10_000
    # swept values given out of order (a sweep keeps the order given) are drawn in order,
    # each value with its own point (the curves zigzagged)
    shuffled = ds.isel(zeta=[3, 0, 2, 1], p_tilde=[1, 0])
    fig = plot_dataset(shuffled, tmp_path / "u.png")
    for line, p in zip(fig.axes[0].get_lines()[:2], [0.05, 0.15], strict=True):
        x, y = line.get_data()
        assert list(x) == [1e-3, 1e-2, 1e-1, 1.0]
        np.testing.assert_array_equal(y, ds["a_tilde"].sel(p_tilde=p).values)


def test_cli_run_plot_help_and_errors(tmp_path, capsys):
    out = tmp_path / "x.nc"
    assert cli.main(["run", str(CASES / "rubber_rough.toml"), "-o", str(out), "-q",
                     "--set", "grid.Nx=32", "--set", "grid.Ny=32",
                     "--set", "surface.cutoff_wavelength=1.25e-4"]) == 0
    assert cli.main(["plot", str(out)]) == 0 and out.with_suffix(".png").exists()
    capsys.readouterr()
    for cmd in ("run", "sweep", "refine", "plot", "validate", "info"):
        with pytest.raises(SystemExit) as e:
            cli.main([cmd, "--help"])
        assert e.value.code == 0
        assert "example" in capsys.readouterr().out
    # failures: non-zero exit and a reason naming the problem
    assert cli.main(["run", str(CASES / "rubber_rough.toml"), "-o", str(out), "--set",
                     "grid.Nx=3"]) == 1
    err = capsys.readouterr().err
    assert "grid.Nx" in err and "[8, 65536]" in err
    assert cli.main(["run", str(tmp_path / "none.toml"), "-o", str(out)]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert cli.main(["run", str(CASES / "rubber_rough.toml"), "-o",
                     str(tmp_path / "no" / "x.nc")]) == 1
    assert "output folder" in capsys.readouterr().err


def test_height_map_readers(tmp_path):
    from spectralbem.scenes import SceneError
    from spectralbem.surfaces import SurfaceError, read_heights

    h = np.random.default_rng(1).standard_normal((16, 8)) * 1e-6
    np.save(tmp_path / "h.npy", h)
    np.savetxt(tmp_path / "h.txt", h)
    np.savetxt(tmp_path / "h.csv", h * 1e6, delimiter=",")
    x = (np.arange(16) + 0.5) * 1e-4
    y = (np.arange(8) + 0.5) * 1e-4
    xr.Dataset({"heights": (("x", "y"), h)}, coords={"x": x, "y": y}).to_netcdf(
        tmp_path / "h.nc")
    for name, scale in (("h.npy", 1.0), ("h.txt", 1.0), ("h.csv", 1e-6), ("h.nc", 1.0)):
        got, size = read_heights(tmp_path / name, scale=scale)
        np.testing.assert_allclose(got, h, rtol=1e-12, atol=1e-22)
    assert read_heights(tmp_path / "h.nc")[1] == pytest.approx((1.6e-3, 0.8e-3))
    raw = {"grid": {"Lx": 1.6e-3, "Ly": 0.8e-3, "Nx": 16, "Ny": 8},
           "surface": {"kind": "file", "path": "h.nc"},
           "material": {"kind": "elastic", "E": 1e6}, "control": {"mean_pressure": 1e3}}
    sc = load_scene(raw, base_dir=tmp_path)
    np.testing.assert_array_equal(sc.heights, h)
    with pytest.raises(SceneError, match="grid.Lx.*physical size"):
        load_scene({**raw, "grid": {**raw["grid"], "Lx": 2e-3}}, base_dir=tmp_path)
    with pytest.raises(SceneError, match=r"surface.path.*shape \(16, 8\).*\(8, 8\)"):
        load_scene({**raw, "grid": {**raw["grid"], "Nx": 8, "Lx": 0.8e-3},
                    "surface": {"kind": "file", "path": "h.npy"}}, base_dir=tmp_path)
    data = (tmp_path / "h.npy").read_bytes()
    (tmp_path / "t.npy").write_bytes(data[: len(data) // 2])
    with pytest.raises(SurfaceError, match="cannot read height map"):
        read_heights(tmp_path / "t.npy")
    with pytest.raises(SurfaceError, match="unknown format"):
        (tmp_path / "h.xyz").write_text("1 2")
        read_heights(tmp_path / "h.xyz")


def test_import_and_help_load_no_numerical_stack():
    """``import spectralbem`` and ``spectralbem --help`` import neither numpy nor the FFT,
    compiled-kernel or parallel libraries (checked in a fresh interpreter; the numerical
    stack costs ~1 s to import); ``spectralbem.solve`` still resolves on first use."""
    import subprocess
    import sys

    heavy = ("numpy", "scipy", "xarray", "dask", "numba", "pyfftw", "matplotlib")
    code = ("import sys, spectralbem; from spectralbem import cli\n"
            "try:\n    cli.main(['--help'])\nexcept SystemExit:\n    pass\n"
            f"print(sorted(m for m in sys.modules if m.split('.')[0] in {heavy!r}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip().splitlines()[-1] == "[]"
    import spectralbem

    assert callable(spectralbem.solve) and spectralbem.Scene.__name__ == "Scene"
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        spectralbem.nothing  # noqa: B018


def test_datasets_follow_cf_conventions(tmp_path, capsys):
    """Every solve's dataset carries CF-1.10 attributes (axis on x and y, flag values and
    meanings on the contact mask, counts as integers, the solver's message under one name
    for every model), and a file written by ``spectralbem run`` records the command in
    ``history``; the printed status says what it means."""
    import spectralbem as sb
    from spectralbem.scenes import load_scene

    for case, over in (("jkr_sphere", {"grid.Nx": 32, "grid.Ny": 32, "adhesion.a0": 3.2e-5}),
                       ("seed_sinusoid_1d", {}),
                       ("seed_sinusoid_2d", {"sinusoid.cells_per_wavelength": 256,
                                            "sinusoid.a0_tilde": 0.025})):
        ds = sb.solve(load_scene(CASES / f"{case}.toml", overrides=over))
        assert ds.attrs["Conventions"] == "CF-1.10", case
        # a path keeps each step's message as a variable
        assert "message" not in ds.attrs and "message" not in ds, case
        assert "solver_message" in ds.attrs or "solver_message" in ds, case
        if "contact" in ds:
            assert ds.x.attrs["axis"] == "X" and ds.y.attrs["axis"] == "Y", case
            assert list(ds.contact.attrs["flag_values"]) == [0, 1]
            assert ds.contact.attrs["flag_meanings"] == "no_contact contact"
        if "iterations" in ds:
            assert ds.iterations.dtype.kind == "i", case
        if case == "seed_sinusoid_2d":  # the local G/Δγ on the seed grid's front, too
            G = ds.G_front.values
            assert np.isfinite(G).sum() == 2 * ds.sizes["y"]  # both edges of each row
            # the closing band's value at the mask edge; G1 is interpolated to the balanced
            # edge, within a0 of it (measured 4.56 against 4.48)
            assert np.nanmax(G) == pytest.approx(ds.G1_over_dgamma.item(), rel=0.05)
    out = tmp_path / "j.nc"
    assert cli.main(["run", str(CASES / "jkr_sphere.toml"), "-o", str(out), "-q", "--set",
                     "grid.Nx=32", "--set", "grid.Ny=32", "--set", "adhesion.a0=3.2e-5"]) == 0
    assert "(a converged state in partial contact)" in capsys.readouterr().out
    ds = read_dataset(out)
    assert "spectralbem run" in ds.attrs["history"] and "grid.Nx=32" in ds.attrs["history"]


def test_a_single_adhesive_solve_shows_its_front_iterations(tmp_path, capsys):
    """Without -q a single adhesive state shows a progress line per outer iteration (the
    phase, the cells in contact and the balanced fraction of the front)."""
    assert cli.main(["run", str(CASES / "jkr_sphere.toml"), "-o", str(tmp_path / "j.nc"),
                     "--set", "grid.Nx=32", "--set", "grid.Ny=32", "--set",
                     "adhesion.a0=3.2e-5", "--set", "control.mean_pressure=0"]) == 0
    err = capsys.readouterr().err
    assert "front:" in err and "cells in contact" in err and "balanced 1.000" in err


@pytest.mark.parametrize("material", ["elastic", "sls"])
def test_a_large_adhesiveless_solve_shows_its_iterations(tmp_path, capsys, monkeypatch,
                                                        material):
    """From solving.PROGRESS_CELLS cells (lowered here to 64²) an adhesiveless solve shows
    its iterations on a "contact" bar: every PROGRESS_EVERY Polonsky–Keer iterations with
    the error (elastic), every Newton step with the contact's size (viscoelastic); below
    that size, no bar."""
    from spectralbem import solving
    from spectralbem.scenes import load_scene, read_scene_file

    raw = read_scene_file(CASES / "rubber_rough.toml")
    if material == "elastic":
        raw["material"] = {"kind": "elastic", "E": 1e6, "nu": 0.5}
        raw.pop("motion", None)
    scene = load_scene(raw, overrides={"grid.Nx": 64, "grid.Ny": 64,
                                       "surface.cutoff_wavelength": 1.25e-4},
                       base_dir=CASES)
    shown = []
    real = solving._bar_progress

    def spy(bar):
        show = real(bar)
        return lambda k, text: shown.append(text) or show(k, text)

    monkeypatch.setattr(solving, "_bar_progress", spy)
    solving.solve(scene, progress=True)
    assert "contact:" not in capsys.readouterr().err and not shown
    monkeypatch.setattr(solving, "PROGRESS_CELLS", 64 * 64)
    solving.solve(scene, progress=True)
    assert "contact:" in capsys.readouterr().err
    word = "error " if material == "elastic" else "Newton step"
    assert shown and all(t.startswith(word) for t in shown), shown


def test_no_panel_of_round_off_friction():
    """An elastic path has μ and μ_a zero to round-off (|μ| ~ 1e-17): no panel plots that
    noise; a viscoelastic state's μ keeps its panel."""
    import matplotlib.pyplot as plt

    import spectralbem as sb
    from spectralbem.plotting import plot_dataset
    from spectralbem.scenes import load_scene

    ds = sb.solve(load_scene(CASES / "jkr_sphere.toml", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "adhesion.a0": 3.2e-5}))
    assert float(abs(ds.mu).max()) < 1e-12
    fig = plot_dataset(ds)
    labels = [ax.get_ylabel() for ax in fig.axes if ax.get_visible()]
    plt.close(fig)
    assert "area fraction" in labels and not any(lb.startswith("μ") for lb in labels)
    ds = sb.solve(load_scene(CASES / "rubber_rough.toml", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "surface.cutoff_wavelength": 1.25e-4,
        "control.mean_pressure": [1e4, 2e4]}))
    fig = plot_dataset(ds)
    labels = [ax.get_ylabel() for ax in fig.axes if ax.get_visible()]
    plt.close(fig)
    assert "μ" in labels


def test_validate_writes_where_output_says(tmp_path, monkeypatch, canned_validate):
    """``validate -o DIR`` writes DIR/validation.md and DIR/figures/, never the source tree
    (the comparisons are replaced by canned rows here: the real run takes minutes)."""
    v = canned_validate
    docs = Path(v.__file__).resolve().parent.parent / "docs"
    before = (docs / "validation.md").read_bytes() if (docs / "validation.md").exists() else b""
    monkeypatch.chdir(tmp_path)
    assert cli.main(["validate", "--quick"]) == 0
    assert (tmp_path / "validation.md").exists()
    assert (tmp_path / "figures" / "validation_sinusoid.png").exists()
    other = tmp_path / "o"
    other.mkdir()
    assert cli.main(["validate", "--quick", "-o", str(other)]) == 0
    assert (other / "validation.md").exists()
    after = (docs / "validation.md").read_bytes() if (docs / "validation.md").exists() else b""
    assert after == before


def test_state_figure_has_title_block_diverging_pressure_and_cut():
    """The state figure of an adhesive scene: a title block naming the scene, material, v,
    p̄, μ and area; the contact map's title the crack tips' share of the front (a JKR disc:
    all of it, no front cell held by contact); the pressure diverging around p = 0 with
    non-contact masked; the gap on a log scale; the profile cut drawn (dashed) on each
    map."""
    import matplotlib.pyplot as plt
    from matplotlib import colors

    import spectralbem as sb
    from spectralbem.plotting import plot_contact
    from spectralbem.scenes import load_scene

    ds = sb.solve(load_scene(CASES / "jkr_sphere.toml", overrides={
        "grid.Nx": 64, "grid.Ny": 64, "adhesion.a0": 1.6e-5, "control.mean_pressure": 0.0}))
    fig = plot_contact(ds)
    title = fig._suptitle.get_text()
    for word in ("jkr_sphere", "elastic", "v = 0 m/s", "p̄ =", "μ = 0", "contact area",
                 "partial"):
        assert word in title, (word, title)
    maps = fig.axes[:3]  # contact, pressure, gap (the colour bars come after the panels)
    pressure = [im for ax in fig.axes for im in ax.get_images()
                if isinstance(im.norm, colors.TwoSlopeNorm)]
    assert len(pressure) == 1 and pressure[0].norm.vcenter == 0.0
    assert np.ma.is_masked(pressure[0].get_array())  # non-contact masked
    assert any(isinstance(im.norm, colors.LogNorm) for ax in fig.axes for im in ax.get_images())
    assert all(any(ln.get_linestyle() == "--" for ln in ax.get_lines()) for ax in maps)
    titles = {ax.get_title() for ax in fig.axes}
    assert {"pressure distribution", "surface power spectrum (radial mean)",
            "release rate along the front"} <= titles
    # a JKR disc is a crack tip all round: no front cell is marked as held by contact
    assert "crack tips 100 % of front" in maps[0].get_title()
    assert not maps[0].get_legend()
    # tension and compression both readable: ticks at the scale's ends and at 0; the
    # tensile spikes at the front clipped, with an arrow and the value that was cut off
    norm, bar = pressure[0].norm, pressure[0].colorbar
    ticks = list(bar.get_ticks())
    assert ticks[0] == norm.vmin < 0.0 < norm.vmax == ticks[-1] and 0.0 in ticks
    p = ds.pressure.values[ds.contact.values.astype(bool)] * 1e-3
    low, high = p.min() < norm.vmin, p.max() > norm.vmax
    assert bar.extend == {(True, True): "both", (True, False): "min",
                          (False, True): "max", (False, False): "neither"}[(low, high)]
    # the clipped extremes are named exactly when they are clipped (on this symmetric disc
    # the 8 equal tensile minima of its 89 contact cells are the 1st percentile itself, so
    # whether anything is clipped is round-off: the spike below decides it for certain)
    label = bar.ax.get_ylabel()
    assert ("min -" in label) == bool(low) and ("scale clipped" in label) == bool(low or high)
    # at rest: no velocity arrow, and the cut is along x
    assert not [a for a in maps[0].texts if getattr(a, "arrow_patch", None) is not None]
    assert fig.axes[3].get_xlabel() == "distance along x (at rest) (mm)"
    plt.close(fig)
    # an isolated tensile spike (one front cell at 10 times the largest tension) is clipped:
    # the scale stays at the 1st percentile, with the arrow and the cut-off value named
    spiked = ds.copy(deep=True)
    pv = spiked.pressure.values
    cell = np.unravel_index(np.argmin(np.where(spiked.contact.values > 0, pv, np.inf)), pv.shape)
    pv[cell] = 10.0 * pv[cell]
    fig = plot_contact(spiked)
    (im,) = [im for ax in fig.axes for im in ax.get_images()
             if isinstance(im.norm, colors.TwoSlopeNorm)]
    label = im.colorbar.ax.get_ylabel()
    assert im.norm.vmin > 1e-3 * pv[cell] and im.colorbar.extend in ("min", "both")
    assert "scale clipped" in label and f"min -{abs(pv[cell]) / 1e3:.3g} kPa" in label, label
    plt.close(fig)


def test_oblique_sliding_is_shown():
    """A direction of sliding other than x is in the title, on an arrow (the seed's strip:
    at its angle on screen, since its y is not to scale) and in the cut's axis label."""
    import matplotlib.pyplot as plt

    ds = sb.solve(load_scene(CASES / "oblique_sliding.toml", overrides={
        "sinusoid.cells_per_wavelength": 512, "sinusoid.a0_tilde": 0.025}))
    fig = plot_contact(ds)
    assert "v at 40° to the wave vector x" in fig._suptitle.get_text()
    arrows = [a for a in fig.axes[0].texts if getattr(a, "arrow_patch", None) is not None]
    assert len(arrows) == 1
    fig.canvas.draw()
    (x0, y0), (x1, y1) = arrows[0].arrow_patch.get_path().vertices[[0, 1]]
    assert np.degrees(np.arctan2(y1 - y0, x1 - x0)) == pytest.approx(40.0, abs=1.0)
    assert "v (40° to x; y not to scale)" in [t.get_text() for t in fig.axes[0].texts]
    assert fig.axes[2].get_xlabel() == "distance along x, the wave vector (v at 40° to x) (k⁻¹)"
    plt.close(fig)
    ds = sb.solve(load_scene(CASES / "rubber_rough.toml", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "surface.cutoff_wavelength": 1.25e-4,
        "motion.direction_deg": 30.0}))
    fig = plot_contact(ds)
    assert "v = 0.004 m/s at 30° to x" in fig._suptitle.get_text()
    (arrow,) = [a for a in fig.axes[0].texts if getattr(a, "arrow_patch", None) is not None]
    (x0, y0), (x1, y1) = arrow.xyann, arrow.xy  # in the map's coordinates
    assert np.degrees(np.arctan2(y1 - y0, x1 - x0)) == pytest.approx(30.0, abs=1e-9)
    assert fig.axes[3].get_xlabel() == "distance along v, at 30° to x (mm)"
    plt.close(fig)


def test_unverified_states_are_unmistakable(dataset, results):
    """A state whose status is not a verified one (solving.REPORTED) gets a red banner above
    its title ("NOT CONVERGED — values unverified") and a red frame; a verified one
    neither. The same for the 1D state figure and for a path's step maps."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import same_color

    from spectralbem.plotting import VERIFIED
    from spectralbem.solving import REPORTED

    assert set(VERIFIED) == set(REPORTED)
    fig = plot_contact(dataset)
    assert "unverified" not in fig._suptitle.get_text()
    assert not same_color(fig.get_edgecolor(), "C3")
    plt.close(fig)
    for status, head in (("not_converged", "NOT CONVERGED"), ("unstable", "STATUS UNSTABLE")):
        for ds in (dataset.copy(), results["oned"].copy()):
            ds["status"] = ((), status)
            fig = plot_dataset(ds)
            title = fig._suptitle
            assert title.get_text().startswith(f"{head} — values unverified"), status
            assert same_color(title.get_color(), "C3")
            assert same_color(fig.get_edgecolor(), "C3") and fig.patch.get_linewidth() > 0
            plt.close(fig)
    ds = results["path"].copy(deep=True)
    ds["status"] = ds["status"].astype(object)
    ds["status"].values[1] = "not_converged"
    fig = plot_dataset(ds)
    titles = [ax.title for ax in fig.axes if ax.get_title().startswith("step")]
    assert "NOT CONVERGED — values unverified" in titles[1].get_text()
    assert same_color(titles[1].get_color(), "C3") and same_color(titles[0].get_color(), "k")
    plt.close(fig)


def test_path_maps_have_a_scale_and_the_load_with_its_unit(results):
    """Each step map of a path has ticks and an x label in mm as the single state's map
    (y only on the first), and its title names the load with its symbol and unit."""
    import matplotlib.pyplot as plt

    fig = plot_dataset(results["path"])
    maps = [ax for ax in fig.axes if ax.get_title().startswith("step")]
    assert [ax.get_xlabel() for ax in maps] == ["x (mm)"] * len(maps)
    assert maps[0].get_ylabel() == "y (mm)"
    assert all(len(ax.get_xticks()) >= 2 for ax in maps)
    assert maps[0].get_title().startswith("step 0: p̄ = 2000 Pa, area ")
    plt.close(fig)


def test_refinement_and_sweep_legends_carry_units(tmp_path):
    """The refinement figure names each curve by its load with the unit ("p̄ = 1000 Pa", not
    "step 0") and each panel as a percentage difference without the quantity's unit; a
    sweep's legend gives the other swept value's unit."""
    import matplotlib.pyplot as plt

    from spectralbem.refinement import refine

    ds = refine(CASES / "rubber_rough.toml", [32, 64], tmp_path / "r.nc", overrides={
        "grid.Nx": 32, "grid.Ny": 32, "surface.cutoff_wavelength": 1.25e-4,
        "control.mean_pressure": [1e4, 2e4]})
    fig = plot_dataset(ds)
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts == ["p̄ = 10000 Pa", "p̄ = 20000 Pa"]
    ylabels = {ax.get_ylabel() for ax in fig.axes if ax.get_visible()}
    assert "Δ: % difference from N = 64" in ylabels and not any("(m)" in y for y in ylabels)
    plt.close(fig)
    sweep = xr.Dataset({"area_fraction": (("speed", "mean_pressure"), [[0.1, 0.2], [0.05, 0.1]],
                                          {"units": "1"})},
                       coords={"speed": ("speed", [1e-4, 1e-2], {"units": "m/s"}),
                               "mean_pressure": ("mean_pressure", [5e3, 2e4], {"units": "Pa"})},
                       attrs={"sweep_keys": '["motion.speed", "control.mean_pressure"]'})
    fig = plot_dataset(sweep)
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts == ["mean_pressure = 5000 Pa", "mean_pressure = 20000 Pa"]
    assert fig.axes[0].get_xlabel() == "motion.speed (m/s)"
    plt.close(fig)


def test_ctrl_c_during_a_single_solve(tmp_path):
    """Ctrl-C (SIGINT to the process group, as a terminal sends it) while the adhesive front
    of a single path step iterates: the progress bars are closed first, then one line and
    exit code 130 within a few seconds; no traceback, no output file."""
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "c.nc"
    cmd = [sys.executable, "-m", "spectralbem.cli", "run", str(CASES / "jkr_sphere.toml"),
           "--set", "grid.Nx=256", "--set", "grid.Ny=256", "--set", "adhesion.a0=4e-6",
           "--set", "control.mean_pressure=[2e3, 1e3, 500.0]", "-o", str(out)]
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env={**os.environ, "COLUMNS": "120"})
    seen, t0 = b"", time.time()
    while b"front:" not in seen and time.time() - t0 < 120:  # the solve is running
        chunk = os.read(proc.stderr.fileno(), 4096)
        assert chunk, "the run ended before its front iterations showed: " + seen.decode()
        seen += chunk
    os.killpg(proc.pid, signal.SIGINT)
    t = time.time()
    _, err = proc.communicate(timeout=60)
    err = (seen + err).decode()
    assert proc.returncode == 130, err[-2000:]
    assert time.time() - t < 10.0  # a prompt exit (measured 0.2-0.5 s)
    assert err.endswith("spectralbem run: interrupted\n") and "Traceback" not in err
    assert not out.exists()


def test_unverified_points_are_crossed_out(results):
    """A path or sweep point whose state was not verified (status not partial,
    full_contact or detached) is crossed out in red, with a legend entry saying so."""
    from spectralbem.plotting import NOT_VERIFIED

    ds = results["path"].copy(deep=True)
    fig = plot_dataset(ds)
    assert all(ax.get_legend() is None for ax in fig.axes)
    ds["status"].values[1] = "not_converged"
    fig = plot_dataset(ds)
    first = fig.axes[0]
    assert [t.get_text() for t in first.get_legend().get_texts()] == [NOT_VERIFIED]
    crosses = [ln for ln in first.get_lines() if ln.get_marker() == "x"]
    assert len(crosses) == 1 and list(crosses[0].get_xdata()) == [500.0]


def test_sweep_counts_the_states_it_could_not_verify(tmp_path):
    """`spectralbem sweep` exits 2 and says how many states are not verified (as `run` does
    for one), counting every point and step of the written dataset."""
    import xarray as xr

    from spectralbem.cli import _unverified

    path = tmp_path / "s.nc"
    xr.Dataset({"status": (("point", "step"), [["partial", "not_converged"],
                                               ["detached", "full_contact"]])}).to_netcdf(path)
    assert _unverified(path) == (1, 4)
    xr.Dataset({"a": ((), 1.0)}).to_netcdf(tmp_path / "n.nc")
    assert _unverified(tmp_path / "n.nc") == (0, 0)


def test_interrupted_path_keeps_its_finished_steps(tmp_path, monkeypatch, capsys):
    """Ctrl-C during the third step of a load path: `run` writes the two finished steps (a
    `step` dimension, their control values) and exits 130, as a sweep keeps its points."""
    import xarray as xr

    from spectralbem import solving
    from spectralbem.io import read_dataset

    def fake(scene, state, progress=None):
        p = scene.mean_pressure
        if p == 5e2:
            raise KeyboardInterrupt
        ds = xr.Dataset({"status": ((), "partial"), "mean_pressure": ((), p)})
        ds.attrs["solver_message"] = "fake"
        return ds, None

    monkeypatch.setattr(solving, "_solve_one", fake)
    case = Path(__file__).resolve().parent.parent / "cases" / "jkr_sphere.toml"
    out = tmp_path / "path.nc"
    assert cli.main(["run", str(case), "-o", str(out), "-q"]) == 130  # loads 1e3, 2e3, 5e2 ...
    assert "2 of 5 path steps finished" in capsys.readouterr().err
    ds = read_dataset(out)
    assert list(ds.control_value.values) == [1e3, 2e3]
    assert list(ds.status.values) == ["partial", "partial"]
    assert "history" in ds.attrs


def test_sigterm_on_a_path_keeps_its_finished_steps(tmp_path, monkeypatch, capsys):
    """SIGTERM (a batch system's time limit) during the third step of a load path: `run`
    writes the two finished steps as on Ctrl-C and exits 143 (it died with nothing written),
    and the process's own SIGTERM handler is back afterwards."""
    import os
    import signal

    from spectralbem import solving
    from spectralbem.io import read_dataset

    def fake(scene, state, progress=None):
        p = scene.mean_pressure
        if p == 5e2:
            os.kill(os.getpid(), signal.SIGTERM)
        ds = xr.Dataset({"status": ((), "partial"), "mean_pressure": ((), p)})
        ds.attrs["solver_message"] = "fake"
        return ds, None

    monkeypatch.setattr(solving, "_solve_one", fake)
    before = signal.getsignal(signal.SIGTERM)
    case = Path(__file__).resolve().parent.parent / "cases" / "jkr_sphere.toml"
    out = tmp_path / "path.nc"
    assert cli.main(["run", str(case), "-o", str(out), "-q"]) == 143
    assert "2 of 5 path steps finished" in capsys.readouterr().err
    assert list(read_dataset(out).control_value.values) == [1e3, 2e3]
    assert signal.getsignal(signal.SIGTERM) is before


def test_the_figure_power_spectrum_has_persson_normalisation():
    """The state figure's C(q) integrates to the surface's mean square height, ∫C d²q = ⟨h²⟩
    (Persson's normalisation, the one tribology papers plot; it was (2π)² times that):
    Σ C (2π)²/A over the wavevectors equals ⟨(h − h̄)²⟩ to round-off, and a single mode of
    amplitude Λ puts Λ²A/(4(2π)²) at ±q."""
    from spectralbem.plot_maps import _spectrum

    rng = np.random.default_rng(1)
    nx, ny, hx, hy = 32, 16, 2e-6, 3e-6
    h = rng.normal(size=(nx, ny)) * 1e-6
    q, C = _spectrum(h, hx, hy)
    area = nx * hx * ny * hy
    assert np.sum(C) * (2 * np.pi) ** 2 / area == pytest.approx(np.var(h), rel=1e-12)
    lam = 1e-6
    x = np.arange(nx) * hx
    q1, C1 = _spectrum(lam * np.cos(2 * np.pi * 3 * x / (nx * hx))[:, None] * np.ones(ny),
                       hx, hy)
    assert C1.max() == pytest.approx(lam**2 * area / (4 * (2 * np.pi) ** 2), rel=1e-12)


def test_a_height_map_run_reruns_from_its_dataset(tmp_path, monkeypatch):
    """The dataset of a scene that reads a height map names it by absolute path, with its
    SHA-256 (``scene_inputs``): a rerun from the dataset's ``scene`` attribute alone, from
    another folder, gives the same data (the relative path did not resolve there)."""
    import hashlib
    import json

    from spectralbem.io import read_dataset

    h = 1e-6 * np.random.default_rng(3).standard_normal((16, 16))
    folder = tmp_path / "scene"
    folder.mkdir()
    np.save(folder / "h.npy", h)
    (folder / "s.toml").write_text(
        '[grid]\nLx = 1e-3\nLy = 1e-3\n[surface]\nkind = "file"\npath = "h.npy"\n'
        '[material]\nkind = "elastic"\nE = 1e6\n[control]\nmean_pressure = 1e3\n')
    out = tmp_path / "r.nc"
    assert cli.main(["run", str(folder / "s.toml"), "-o", str(out), "-q"]) == 0
    ds = read_dataset(out)
    spec = json.loads(ds.attrs["scene"])
    assert spec["surface"]["path"] == str(folder / "h.npy")
    sha = hashlib.sha256((folder / "h.npy").read_bytes()).hexdigest()
    assert json.loads(ds.attrs["scene_inputs"]) == {"surface.path": sha}
    monkeypatch.chdir(tmp_path)
    again = sb.solve(load_scene(spec, base_dir=tmp_path / "elsewhere"))
    for v in ("area_fraction", "mean_pressure", "penetration"):
        np.testing.assert_array_equal(again[v].values, ds[v].values)


def test_a_ctrl_c_swallowed_by_a_finalizer_still_stops_the_command(tmp_path):
    """A Ctrl-C that lands in a finalizer ("Exception ignored in __del__": numba's compiler
    objects while a fresh checkout's first solve compiles its kernels) was lost and the run
    went on to its end; the command raises it again once out of the finalizer: one line,
    exit 130 (a command whose finalizer swallows a KeyboardInterrupt, then works on)."""
    import subprocess
    import sys

    script = tmp_path / "swallow.py"
    script.write_text(
        "import sys, time\n"
        "from spectralbem import cli\n"
        "def fake(args):\n"
        "    class D:\n"
        "        def __del__(self):\n"
        "            raise KeyboardInterrupt\n"
        "    D()\n"
        "    for _ in range(100):\n"
        "        time.sleep(0.01)\n"
        "    print('finished', file=sys.stderr)\n"
        "    return 0\n"
        "cli._run = fake\n"
        "sys.exit(cli.main(['run', sys.argv[1], '-o', sys.argv[2]]))\n")
    proc = subprocess.run([sys.executable, str(script), str(CASES / "jkr_sphere.toml"),
                           str(tmp_path / "x.nc")], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 130, proc.stderr
    assert proc.stderr == "spectralbem run: interrupted\n"
