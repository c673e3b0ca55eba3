"""Result datasets (xarray) and atomic netCDF files.

Every variable carries ``units`` and ``long_name`` (the tables below, used by
:mod:`spectralbem.scenes`); a dataset carries the package version, a UTC timestamp, the solver
diagnostics and the scene description (JSON) as attributes.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import xarray as xr

#: the one table of result variables: name -> (units, long name)
SCALARS = {
    "mean_pressure": ("Pa", "mean (nominal) pressure, compressive positive"),
    "penetration": ("m", "penetration Δ, mean-level gauge"),
    "area_fraction": ("1", "contact area fraction (adhesive: inside the sub-cell front)"),
    "mu": ("1", "friction coefficient: force opposing v over normal force, Eq. (19) in 2D"),
    "mu_lateral": ("1", "lateral force (along z × v) over normal force"),
    "mu_profile": ("1", "friction coefficient from the rigid-profile force on the mask"),
    "mu_dissipation": ("1", "friction coefficient from the spectral dissipation"),
    "mu_adhesive": ("1", "adhesive friction -∮ G (n·v̂) ds / W, Eq. (23) in 2D"),
    "G1": ("J/m²", "energy release rate at the trailing (opening) front, Eq. (20)"),
    "G2": ("J/m²", "energy release rate at the leading (closing) front, Eq. (21)"),
    "contact_half_width": ("m", "contact semi-width a of the sinusoid"),
    "eccentricity": ("m", "contact eccentricity e (> 0: toward the leading edge)"),
    "iterations": ("1", "solver iterations (adhesive: outer front iterations)"),
    "solves": ("1", "masked linear solves"),
    "unresolved_patches": ("1", "contact patches smaller than a disc of radius a0 (the band "
                                "tests cannot resolve them)"),
    "balanced_fraction": ("1", "fraction of the resolved front balanced within front_tol"),
    "front_residual": ("1", "largest balance residual of the front in position (cells)"),
    "front_length": ("m", "length of the balanced front of the resolved patches"),
}
FIELDS = {
    "heights": ("m", "rigid profile height toward the slab"),
    "pressure": ("Pa", "contact pressure (compressive positive)"),
    "displacement": ("m", "surface displacement into the slab"),
    "gap": ("m", "gap between slab and indenter"),
    "contact": ("1", "contact mask (1 in contact)"),
    "G_front": ("1", "local conservative energy release rate G/Δγ on outer front cells"),
}
STATUS = ("1", "partial | full_contact | detached | not_converged")


def attrs(entry) -> dict:
    """``{"units", "long_name"}`` of a table entry (units, long name)."""
    return {"units": entry[0], "long_name": entry[1]}


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
