"""Datasets (round trip, units, atomic writes), plots and the command line."""

import numpy as np
import pytest
import xarray as xr

from spectralbem import cli
from spectralbem.contact import solve_contact
from spectralbem.io import contact_dataset, read_dataset, write_dataset
from spectralbem.materials import StandardLinearSolid
from spectralbem.plotting import plot_contact
from spectralbem.spectral import Cell, SpectralOperator
from spectralbem.surfaces import bisinusoid


@pytest.fixture(scope="module")
def dataset():
    cell = Cell(1e-3, 1e-3, 32, 32)
    h = bisinusoid(cell, 1e-5)
    op = SpectralOperator(cell, StandardLinearSolid(1e6, 1e7, 0.01), velocity=(0.05, 0.0))
    res = solve_contact(op, h, mean_pressure=2e3)
    assert res.converged
    return contact_dataset(res, cell, h, scene={"note": "test"})


def test_units_and_round_trip(dataset, tmp_path):
    for name, var in {**dataset.data_vars, **dataset.coords}.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    for key in ("spectralbem_version", "created_utc", "scene", "solver_diagnostics"):
        assert key in dataset.attrs
    path = write_dataset(dataset, tmp_path / "r.nc")
    back = read_dataset(path)
    xr.testing.assert_identical(back, dataset)
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def test_unwritable_output(dataset, tmp_path):
    with pytest.raises(OSError, match="does not exist"):
        write_dataset(dataset, tmp_path / "missing" / "r.nc")


def test_plot_contact_png(dataset, tmp_path):
    fig = plot_contact(dataset, tmp_path / "c.png")
    labels = [ax.get_xlabel() for ax in fig.axes[:3]]
    assert labels == ["x (mm)"] * 3
    assert "pressure (kPa)" in [ax.get_ylabel() for ax in fig.axes]
    assert (tmp_path / "c.png").stat().st_size > 10_000


def test_cli_plot_and_info(dataset, tmp_path, capsys):
    write_dataset(dataset, tmp_path / "r.nc")
    assert cli.main(["plot", str(tmp_path / "r.nc")]) == 0
    assert (tmp_path / "r.png").exists()
    assert cli.main(["info"]) == 0
    assert "FFT backend" in capsys.readouterr().out
    assert cli.main(["plot", str(tmp_path / "nope.nc")]) == 1
    assert "does not exist" in capsys.readouterr().err


def test_demo_runs(tmp_path):
    from spectralbem.demo import run

    nc = run(tmp_path)
    ds = read_dataset(nc)
    assert int(ds["converged"]) == 1 and 0 < float(ds["area_fraction"]) < 0.2
    assert np.isfinite(float(ds["mu"])) and float(ds["mu"]) > 0
