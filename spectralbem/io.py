"""Result datasets (xarray) and atomic netCDF files.

Every variable carries ``units`` and ``long_name``; the dataset carries the package version, a
UTC timestamp, the solver diagnostics and the scene description (JSON) as attributes.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

from . import __version__

FIELD_META = {
    "heights": ("m", "rigid profile height toward the slab"),
    "pressure": ("Pa", "contact pressure (compressive positive)"),
    "displacement": ("m", "surface displacement into the slab"),
    "gap": ("m", "gap between slab and indenter"),
    "contact": ("1", "contact mask (1 in contact)"),
}
SCALAR_META = {
    "mean_pressure": ("Pa", "mean (nominal) pressure"),
    "penetration": ("m", "penetration, mean-level gauge"),
    "area_fraction": ("1", "contact area fraction"),
    "mu": ("1", "friction coefficient, seed Eq. (19) in 2D"),
    "mu_lateral": ("1", "lateral force over normal force"),
    "mu_profile": ("1", "friction coefficient from the rigid-profile force"),
    "mu_dissipation": ("1", "friction coefficient from the spectral dissipation"),
    "iterations": ("1", "solver iterations"),
    "converged": ("1", "solver converged (1) or not (0)"),
}


def contact_dataset(result, cell, heights, scene: dict | None = None) -> xr.Dataset:
    """Dataset of an adhesiveless :class:`~spectralbem.contact.ContactResult`."""
    coords = {
        "x": ("x", cell.x, {"units": "m", "long_name": "position along x"}),
        "y": ("y", cell.y, {"units": "m", "long_name": "position along y"}),
    }
    fields = {
        "heights": heights, "pressure": result.pressure, "displacement": result.displacement,
        "gap": result.gap, "contact": result.mask.astype(np.int8),
    }
    data = {k: (("x", "y"), v, dict(zip(("units", "long_name"), FIELD_META[k], strict=True)))
            for k, v in fields.items()}
    for k in SCALAR_META:
        val = getattr(result, k)
        val = int(val) if isinstance(val, (bool, np.bool_)) else val
        data[k] = ((), val, dict(zip(("units", "long_name"), SCALAR_META[k], strict=True)))
    attrs = {
        "title": "spectralbem contact result",
        "spectralbem_version": __version__,
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "solver_method": result.method,
        "solver_message": result.message,
        "solver_diagnostics": json.dumps(result.diagnostics, default=float),
        "scene": json.dumps(scene or {}, default=str),
        "conventions": "see spectralbem.conventions: u into the slab, p compressive positive",
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_dataset(ds: xr.Dataset, path) -> Path:
    """Write netCDF4 atomically: a temporary file in the target folder, then rename."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OSError(f"output folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK):
        raise OSError(f"output folder {str(folder)!r} is not writable")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise OSError(f"output path {str(path)!r} is not writable: {exc.strerror}") from exc
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def read_dataset(path) -> xr.Dataset:
    """Read a dataset fully into memory (the file is closed on return)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()
