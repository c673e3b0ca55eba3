"""Result datasets (xarray) and atomic netCDF files.

Files are written through a temporary file in the target folder (created exclusively, never
through a symlink) and renamed, with the permissions of a plain new file (0o666 minus the
umask); a full disk is reported as such, naming the file.  A netCDF file of unknown origin is
opened in a child process first (:func:`check_netcdf`): a corrupted file can crash netCDF-C.

Every variable carries ``units`` and ``long_name`` (the tables below, used by
:mod:`spectralbem.scenes`); a dataset carries the package version, a UTC timestamp, the solver
diagnostics and the scene description (JSON) as attributes.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import tempfile
from pathlib import Path

import xarray as xr

#: the one table of result variables: name -> (units, long name, comment); the long name
#: is short (plot axis labels), the comment says the rest
SCALARS = {
    "mean_pressure": ("Pa", "mean pressure", "nominal, compressive positive"),
    "penetration": ("m", "penetration Δ", "mean-level gauge"),
    "area_fraction": ("1", "contact area fraction",
                      "adhesive: the area inside the balanced sub-cell front"),
    "mu": ("1", "friction coefficient μ",
           "force opposing v over the normal force, Eq. (19) in 2D; adhesive viscoelastic: the "
           "force on the rigid profile at the balanced sub-cell front"),
    "mu_lateral": ("1", "lateral friction coefficient",
                   "the force on the indenter against z × v over the normal force (as mu is "
                   "against v)"),
    "mu_profile": ("1", "μ from the profile force",
                   "friction coefficient from the rigid-profile force on the mask"),
    "mu_dissipation": ("1", "μ from the dissipation",
                       "friction coefficient from the spectral dissipation (Eq. (19) with "
                       "the spectral derivative of u, on the mask)"),
    "mu_adhesive": ("1", "adhesive friction μ_a", "-∮ G (n·v̂) ds / W, Eq. (23) in 2D"),
    "G1": ("J/m²", "G1 (trailing front)",
           "energy release rate at the trailing (opening) front, Eq. (20)"),
    "G2": ("J/m²", "G2 (leading front)",
           "energy release rate at the leading (closing) front, Eq. (21)"),
    "contact_half_width": ("m", "contact half-width a", "of the sinusoid"),
    "eccentricity": ("m", "contact eccentricity e", "> 0: toward the leading edge"),
    "iterations": ("1", "iterations", "solver iterations (adhesive: outer front iterations)"),
    "solves": ("1", "masked solves", "masked linear solves"),
    "unresolved_patches": ("1", "unresolved patches",
                           "contact patches smaller than a disc of radius a0 (the band "
                           "tests cannot resolve them)"),
    "unresolved_front": ("1", "unresolved front cells",
                         "front cells of features narrower than a0 (tongues of the contact, "
                         "notches of the gap) that oscillated and stay unbalanced: held, "
                         "left out of the status and the front averages"),
    "small_patch_diameter": ("m", "small-patch diameter",
                             "equivalent diameter of the resolved contact patches below "
                             "which a tenth of their area lies (a0 should be under a tenth "
                             "of it); 0 when detached"),
    "balanced_fraction": ("1", "balanced fraction",
                          "fraction of the resolved front balanced within front_tol"),
    "front_residual": ("1", "front residual (cells)",
                       "largest balance residual of the front in position; inf where a "
                       "resolved front cell has no balanced edge in its band (not converged)"),
    "front_length": ("m", "front length", "of the balanced front of the resolved patches"),
    "crack_tip_length": ("m", "crack-tip length",
                         "the part of front_length that is a crack tip (the rest is held by "
                         "contact): G1, G2 and mu_adhesive are taken over it"),
    "substeps": ("1", "path sub-steps",
                 "equal steps of the control from the previous path state that reached this "
                 "one (1: the direct step; more after a direct step did not converge)"),
}
FIELDS = {
    "heights": ("m", "height h", "rigid profile height toward the slab"),
    "pressure": ("Pa", "pressure p", "contact pressure, compressive positive"),
    "displacement": ("m", "displacement u", "surface displacement into the slab"),
    "gap": ("m", "gap g", "gap between slab and indenter"),
    "contact": ("1", "contact mask", "1 in contact"),
    "G_front": ("1", "G/Δγ on the front",
                "local conservative energy release rate over Δγ on outer front cells"),
}
STATUS = ("1", "status", "partial | full_contact | detached | unstable | not_converged")

__all__ = ["read_dataset", "write_dataset", "write_heights", "cf_attributes", "DiskFullError"]


def attrs(entry) -> dict:
    """``{"units", "long_name", "comment"}`` of a table entry (units, long name, comment)."""
    out = {"units": entry[0], "long_name": entry[1]}
    if len(entry) > 2:
        out["comment"] = entry[2]
    return out


#: what each status means, for people reading a printed status
STATUS_MEANING = {
    "partial": "a converged state in partial contact",
    "full_contact": "a converged state in full contact",
    "detached": "no contact",
    "unstable": "an equilibrium on an unstable branch",
    "not_converged": "no verified state; see the dataset's message",
}


#: result variables that count things: stored as integers where every value is finite
COUNTS = ("iterations", "solves", "unresolved_patches", "unresolved_front", "substeps")


def cf_attributes(ds: xr.Dataset, history: str | None = None) -> xr.Dataset:
    """The CF-1.10 conventions of a result dataset, in place: ``Conventions``, ``axis`` on
    the x and y coordinates, ``flag_values``/``flag_meanings`` on the contact mask, counts
    as integers, one name for the solver's message (``solver_message``) and ``history``
    (a line prepended: the command that made the file).  Returns ``ds``."""
    import numpy as np

    ds.attrs["Conventions"] = "CF-1.10"
    for name, axis in (("x", "X"), ("y", "Y")):
        if name in ds.coords:
            ds[name].attrs["axis"] = axis
    if "heights" in ds and ds["heights"].dims == ("x", "y"):
        # SurfaceTopography's netCDF layout: the size as ``length``, ``unit``, ``periodic``
        ds["heights"].attrs["unit"] = "m"
        for name in ("x", "y"):
            c = np.asarray(ds[name].values, float)
            step = float(c[1] - c[0]) if c.size > 1 else float("nan")
            ds[name].attrs.update(length=step * c.size, unit="m", periodic=np.int8(1))
    if "contact" in ds:
        ds["contact"].attrs.update(flag_values=np.array([0, 1], np.int8),
                                   flag_meanings="no_contact contact")
    for k in COUNTS:
        if k in ds and ds[k].dtype.kind == "f" and bool(np.isfinite(ds[k].values).all()):
            ds[k] = ds[k].astype(np.int64)
    if "message" in ds.attrs:
        ds.attrs.setdefault("solver_message", ds.attrs["message"])
        del ds.attrs["message"]
    if history:
        old = ds.attrs.get("history", "")
        ds.attrs["history"] = history + ("\n" + old if old else "")
    return ds


#: a write that fails while the file system has less free space than the data plus this margin
#: is reported as a full disk (netCDF-C reports ENOSPC as "Permission denied" or "NetCDF: HDF
#: error")
FULL_MARGIN = 1 << 20


class DiskFullError(OSError):
    """No space left on the device (or quota) while writing a file; the message names the
    path (see :func:`disk_full`)."""

    def __init__(self, message: str, err: int = errno.ENOSPC):
        super().__init__(message)  # one argument: pickles (dask workers) as it was
        self.errno = err


def disk_full(path, free: int | None = None, err: int = errno.ENOSPC) -> DiskFullError:
    where = f" ({free} bytes free)" if free is not None else ""
    return DiskFullError(f"cannot write {str(path)!r}: {os.strerror(err).lower()}{where}", err)


def umask() -> int:
    """The process umask, read without changing it where the system allows (Linux)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    old = os.umask(0o022)
    os.umask(old)
    return old


def _free_bytes(folder) -> int | None:
    """Bytes available to this user in ``folder``'s file system (None: not a disk, /proc)."""
    try:
        st = os.statvfs(folder)
    except (OSError, AttributeError):
        return None
    return st.f_bavail * st.f_frsize if st.f_blocks > 0 else None


def _full_disk(exc: BaseException, path: Path, need: int,
               guess: bool = True) -> DiskFullError | None:
    """A DiskFullError when ``exc`` (raised while writing ``need`` bytes to ``path``) comes
    from a full file system, else None.  ``guess``: an error without ENOSPC counts when the
    disk has no room left (netCDF-C reports ENOSPC as "Permission denied" or "NetCDF: HDF
    error"); off for errors of plain system calls, whose errno is right."""
    if not isinstance(exc, Exception):
        return None
    err = getattr(exc, "errno", None)
    if err in (errno.ENOSPC, errno.EDQUOT):
        return disk_full(path, _free_bytes(path.parent), err)
    free = _free_bytes(path.parent) if guess else None
    if free is not None and free < need + FULL_MARGIN:
        return disk_full(path, free)
    return None


def _temporary(path: Path):
    """A new temporary file next to ``path`` (O_EXCL: never an existing file or symlink),
    with the permissions of a plain new file (0o666 & ~umask); returns (fd, name)."""
    folder = path.parent
    if not folder.is_dir():
        raise OSError(f"output folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK):
        raise OSError(f"output folder {str(folder)!r} is not writable")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        full = _full_disk(exc, path, 0, guess=False)
        if full is not None:
            raise full from exc
        raise OSError(f"output path {str(path)!r} is not writable: {exc.strerror}") from exc
    try:
        os.fchmod(fd, 0o666 & ~umask())
    except OSError:
        pass
    return fd, tmp


def _discard(tmp) -> None:
    try:
        os.unlink(tmp)
    except OSError:
        pass


def write_dataset(ds: xr.Dataset, path, *, format: str = "NETCDF4") -> Path:
    """Write netCDF4 atomically: a temporary file in the target folder, then rename.  The file
    gets the permissions of a plain new file (0o666 minus the umask); a full disk raises
    :class:`DiskFullError` naming the path, and no temporary file is left behind.
    ``format``: netCDF-C's file format (``NETCDF3_64BIT`` for readers of classic files)."""
    path = Path(path)
    if not str(path.parent):
        path = Path(".") / path
    fd, tmp = _temporary(path)
    os.close(fd)
    try:
        # coordinates carry no fill value (CF: a coordinate has none missing)
        coords = {c: {"_FillValue": None} for c in ds.coords
                  if ds[c].dtype.kind == "f" and "_FillValue" not in ds[c].encoding}
        ds.to_netcdf(tmp, engine="netcdf4", format=format, encoding=coords)
        os.replace(tmp, path)
    except BaseException as exc:
        full = _full_disk(exc, path, int(ds.nbytes))
        _discard(tmp)
        if full is not None:
            raise full from exc
        raise
    return path


def write_heights(ds: xr.Dataset, path) -> Path:
    """The heights of a result dataset alone, as a classic (netCDF-3) file in
    SurfaceTopography's layout — ``heights(x, y)`` and the coordinates, with ``unit``, and
    ``length`` and ``periodic`` on x and y — which its reader and
    :func:`spectralbem.surfaces.read_heights` both read (a surface for another tool, or
    for a later scene of ``surface.kind = "file"``)."""
    if "heights" not in ds or ds["heights"].dims != ("x", "y"):
        raise ValueError("the dataset has no heights(x, y) to write (a 2D state's dataset "
                         "with output.fields = true has)")
    out = xr.Dataset({"heights": ds["heights"]})
    cf_attributes(out)
    return write_dataset(out, path, format="NETCDF3_64BIT")


def write_text(path, text: str) -> Path:
    """Write a small text file atomically (temporary file, fsync, rename), as write_dataset."""
    path = Path(path)
    fd, tmp = _temporary(path)
    data = text.encode()
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        full = _full_disk(exc, path, len(data), guess=False)
        _discard(tmp)
        if full is not None:
            raise full from exc
        raise
    return path


def sha256_file(path) -> str:
    """Hex SHA-256 of a file's contents."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


# A netCDF file is opened in a child process first: netCDF-C/HDF5 can crash the process
# (segmentation fault) on a corrupted file, which no exception handler catches.  The child
# reads every variable and the global attributes of each file in turn and reports
# "BEGIN i", then "OK i <json attributes and variable names>" or "ERR i <message>".
_CHILD = r"""
import json, sys
import netCDF4
for i, p in enumerate(sys.argv[1:]):
    print("BEGIN", i, flush=True)
    try:
        with netCDF4.Dataset(p, "r") as d:
            attrs = {}
            for k in d.ncattrs():
                v = d.getncattr(k)
                if getattr(v, "size", 0) == 1 and hasattr(v, "item"):
                    v = v.item()
                attrs[k] = v if isinstance(v, (str, int, float)) else repr(v)
            names = list(d.variables)
            for v in d.variables.values():
                v.set_auto_maskandscale(False)
                v[...]
        print("OK", i, json.dumps({"attrs": attrs, "variables": names}), flush=True)
    except Exception as exc:
        print("ERR", i, " ".join(f"{type(exc).__name__}: {exc}".split())[:300], flush=True)
"""
_CHECKED: dict = {}


def _signal_name(rc: int) -> str:
    import signal

    try:
        return signal.Signals(-rc).name
    except ValueError:
        return f"signal {-rc}"


def probe_netcdf(paths, *, timeout: float | None = None) -> dict:
    """Open each netCDF file in a child process; returns {path: (info, error)}: ``info`` is
    ``{"attrs": {...}, "variables": [...]}`` for a readable file (else None) and ``error``
    the reason it is not readable (else None) — a crash of the netCDF library in the child
    (e.g. SIGSEGV on a corrupted file) names the file instead of killing the caller."""
    import subprocess
    import sys

    paths = [str(p) for p in paths]
    out: dict = {}
    todo = list(paths)
    while todo:
        size = sum(os.path.getsize(p) for p in todo if os.path.isfile(p))
        limit = timeout if timeout is not None else 60.0 + size / 20e6
        try:
            r = subprocess.run([sys.executable, "-I", "-c", _CHILD, *todo], capture_output=True,
                               text=True, timeout=limit, stdin=subprocess.DEVNULL)
            lines, rc, err = r.stdout.splitlines(), r.returncode, r.stderr
        except subprocess.TimeoutExpired as exc:
            text = exc.stdout.decode() if isinstance(exc.stdout, bytes) else exc.stdout or ""
            lines, rc, err = text.splitlines(), None, ""
        current = None
        for line in lines:
            tag, _, rest = line.partition(" ")
            idx, _, payload = rest.partition(" ")
            if not idx.isdigit() or int(idx) >= len(todo):
                continue
            p = todo[int(idx)]
            if tag == "BEGIN":
                current = p
            elif tag == "OK":
                out[p], current = (json.loads(payload), None), None
            elif tag == "ERR":
                out[p], current = (None, payload or "unreadable"), None
        if current is not None:  # the child died or hung inside this file
            out[current] = (None, f"reading it crashed the netCDF library ({_signal_name(rc)})"
                            if rc is not None and rc < 0 else
                            f"reading it did not finish in {limit:.0f} s" if rc is None else
                            f"reading it stopped the reader (exit code {rc})")
        else:  # files never begun: the child could not start
            why = "timed out" if rc is None else ((err or "").strip().splitlines()
                                                  or [f"exit code {rc}"])[-1]
            for p in todo:
                out.setdefault(p, (None, f"cannot check it in a child process: {why}"))
        todo = [p for p in todo if p not in out]
    return out


def check_netcdf(path, what: str = "netCDF file") -> None:
    """Raise ValueError naming ``path`` when it cannot be read safely (see probe_netcdf).  A
    file already checked unchanged (same inode, size and modification time) is not reopened."""
    path = Path(path)
    st = path.stat()
    key = (str(path.resolve()), st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)
    if key not in _CHECKED:
        _CHECKED[key] = probe_netcdf([path])[str(path)][1]
    err = _CHECKED[key]
    if err is not None:
        raise ValueError(f"{what} {str(path)!r} is not a readable netCDF file: {err}")


def read_dataset(path, *, verify: bool = False) -> xr.Dataset:
    """Read a dataset fully into memory (the file is closed on return).  ``verify``: open the
    file in a child process first (:func:`check_netcdf`), for files of unknown origin."""
    if verify:
        check_netcdf(path, "dataset")
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()
