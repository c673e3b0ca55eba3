"""Rigid indenter profiles h(x, y) on a periodic cell (m).

Convention: ``h`` is the height of the rigid surface *toward the slab*: its maximum is the first
point to touch, and the displacement prescribed in contact is ``w = h - max(h) + Δ``
(seed: ``u(x) = Λ cos(kx) - Λ + Δ``).  The gap is ``g = u - w ≥ 0``.
"""

from __future__ import annotations

import hashlib
import stat
from pathlib import Path

import numpy as np

from .conventions import shown
from .spectral import Cell

__all__ = ["sinusoid", "bisinusoid", "paraboloid", "self_affine", "from_npy", "read_heights",
           "SurfaceError"]


class SurfaceError(ValueError):
    """Invalid surface parameter or file."""


def _finite_positive(name, v):
    v = float(v)
    if not np.isfinite(v) or v <= 0:
        raise SurfaceError(f"{name} = {shown(v)} must be a finite number > 0")
    return v


def sinusoid(cell: Cell, amplitude: float, wavelength: float | None = None) -> np.ndarray:
    """1D sinusoid ``h = Λ cos(k x)`` invariant along y (the seed's Fig. 2 profile).

    The summit sits at x = 0 (array index 0); ``wavelength`` defaults to ``Lx`` and must divide
    it.
    """
    amplitude = _finite_positive("amplitude", amplitude)
    lam = cell.Lx if wavelength is None else _finite_positive("wavelength", wavelength)
    n = cell.Lx / lam
    if abs(n - round(n)) > 1e-9 or round(n) < 1:
        raise SurfaceError(
            f"wavelength = {shown(lam)} must divide Lx = {shown(cell.Lx)} a whole number of times")
    X, _ = cell.coordinates()
    return amplitude * np.cos(2 * np.pi * X / lam)


def bisinusoid(cell: Cell, amplitude: float) -> np.ndarray:
    """``h = Λ cos(2πx/Lx) cos(2πy/Ly)``: one egg-box summit per cell, at the origin."""
    amplitude = _finite_positive("amplitude", amplitude)
    X, Y = cell.coordinates()
    return amplitude * np.cos(2 * np.pi * X / cell.Lx) * np.cos(2 * np.pi * Y / cell.Ly)


def paraboloid(cell: Cell, radius: float) -> np.ndarray:
    """Sphere of radius R in the paraboloid approximation, summit at the cell centre.

    ``h = -r²/(2R)`` with r measured from the centre (Nx/2, Ny/2).
    """
    radius = _finite_positive("radius", radius)
    X, Y = cell.coordinates()
    r2 = (X - cell.Nx // 2 * cell.hx) ** 2 + (Y - cell.Ny // 2 * cell.hy) ** 2
    return -r2 / (2 * radius)


# Relative tolerance of the band edge |q| ≤ q_s: a cut-off given as a whole number of modes
# (q_s = 2πK/L, computed in floating point) keeps its last ring whatever the rounding.
BAND_RTOL = 1e-10


def self_affine(cell: Cell, hurst: float, *, rolloff: float, cutoff: float,
                rms_height: float | None = None, rms_slope: float | None = None,
                seed: int = 0) -> np.ndarray:
    """Gaussian self-affine random surface with a roll-off, the same physical surface on every
    grid of the cell.

    Wavevectors are physical, in rad/m: the cell's Fourier modes are q = 2π (kx/Lx, ky/Ly)
    for integers (kx, ky), and ``rolloff`` q_r < ``cutoff`` q_s.  The power spectrum is
    C(q) = 1 for 0 < q < q_r, (q/q_r)^{-2(1+H)} for q_r ≤ q ≤ q_s, and 0 above q_s and at
    q = 0 (zero mean).  h(x) = Σ c(k) exp(i q·x) with c(k) = s √C(q) exp(iφ(k)): the phases
    φ are uniform on [0, 2π), drawn from ``numpy.random.default_rng(seed)`` in a fixed order
    over the box |kx| ≤ Kx, ky = 0..Ky (Kx = ⌊Lx q_s/2π⌋, Ky = ⌊Ly q_s/2π⌋), and
    c(−k) = conj c(k) (the half-plane ky < 0, and kx < 0 on ky = 0, are mirrors), so h is
    real.  The scale s gives the requested ``rms_height`` (Σ|c|²) or ``rms_slope`` (rms of
    |∇h|, Σ|q|²|c|²) exactly, by Parseval over the coefficients.

    Nothing depends on the grid but the sampling: for a given (cell size, hurst, rolloff,
    cutoff, seed), every grid (Nx, Ny) holding the band gives the same coefficients c(k) and
    samples of the same h(x, y) — a grid-refinement study refines the grid, not the surface.
    The grid holds the band when Nx ≥ 2Kx + 1 and Ny ≥ 2Ky + 1, i.e. q_s is below the
    Nyquist wavevector π/h along each axis (even N; π/h + π/L for odd N): the Nyquist modes
    are never used, and the grid's rms height and slope equal the requested ones to
    round-off.  A cut-off the grid cannot hold raises SurfaceError.
    """
    if not (0.0 < hurst < 1.0):
        raise SurfaceError(f"hurst = {shown(hurst)} must lie in (0, 1)")
    rolloff = _finite_positive("rolloff", rolloff)
    cutoff = _finite_positive("cutoff", cutoff)
    if cutoff <= rolloff:
        raise SurfaceError(f"cutoff = {shown(cutoff)} must exceed rolloff = {shown(rolloff)}")
    if (rms_height is None) == (rms_slope is None):
        raise SurfaceError("give exactly one of rms_height, rms_slope")
    reach = cutoff * (1 + BAND_RTOL) / (2 * np.pi)
    Kx, Ky = int(np.floor(cell.Lx * reach)), int(np.floor(cell.Ly * reach))
    if Kx == Ky == 0:
        lo = 2 * np.pi / max(cell.Lx, cell.Ly)
        raise SurfaceError(f"cutoff = {shown(cutoff)} rad/m is below the cell's lowest wavevector "
                           f"2π/max(Lx, Ly) = {lo:.6g} rad/m: no mode lies in the band")
    for axis, L, N, K in (("x", cell.Lx, cell.Nx, Kx), ("y", cell.Ly, cell.Ny, Ky)):
        if 2 * K + 1 > N:
            hi = 2 * np.pi * ((N - 1) // 2 + 1) / L  # the first |q| the grid cannot hold
            edge = f"the Nyquist wavevector π/h{axis}" if N % 2 == 0 else f"π/h{axis} + π/L{axis}"
            if hi <= rolloff:  # no cutoff above the roll-off fits: say why, not (a, b ≤ a)
                strip = (f" (N{axis} = 1 is a {axis}-invariant strip: it holds k{axis} = 0 "
                         f"only, so the band must stay below 2π/L{axis})" if N == 1 else "")
                also = f", or L{axis} < 2π/cutoff = {2 * np.pi / cutoff:.6g} m" if N == 1 else ""
                raise SurfaceError(
                    f"cutoff = {shown(cutoff)} rad/m needs modes up to |k{axis}| = {K}, i.e. "
                    f"N{axis} ≥ {2 * K + 1}; the grid (N{axis} = {N}) holds |q{axis}| < "
                    f"{hi:.10g} rad/m{strip}, not above rolloff = {shown(rolloff)}, so no "
                    f"cutoff fits: allowed N{axis} in [{2 * K + 1}, 65536] for this cutoff"
                    f"{also}")
            raise SurfaceError(
                f"cutoff = {shown(cutoff)} rad/m needs modes up to |k{axis}| = {K}, i.e. "
                f"N{axis} ≥ {2 * K + 1}; the grid (N{axis} = {N}) holds "
                f"|k{axis}| ≤ {(N - 1) // 2}: "
                f"allowed ({shown(rolloff)}, {hi:.10g}) rad/m, the upper end ({edge}) excluded")
    kx = np.arange(-Kx, Kx + 1)[:, None]
    ky = np.arange(Ky + 1)[None, :]
    q = 2 * np.pi * np.hypot(kx / cell.Lx, ky / cell.Ly)
    psd = np.where(q < rolloff, 1.0, (np.maximum(q, rolloff) / rolloff) ** (-2 * (1 + hurst)))
    psd = np.where((q > cutoff * (1 + BAND_RTOL)) | (q == 0), 0.0, psd)
    rng = np.random.default_rng(seed)
    c = np.sqrt(psd) * np.exp(2j * np.pi * rng.random(psd.shape))
    c[:Kx, 0] = np.conj(c[Kx + 1:, 0][::-1])  # ky = 0: c(−kx, 0) = conj c(kx, 0)
    # Σ over the whole plane: the column ky = 0 holds both of its halves, ky > 0 counts twice
    mult = np.where(ky == 0, 1.0, 2.0)
    if rms_height is not None:
        scale = _finite_positive("rms_height", rms_height) / np.sqrt(np.sum(mult * abs(c)**2))
    else:
        scale = _finite_positive("rms_slope", rms_slope) / np.sqrt(
            np.sum(mult * q**2 * abs(c)**2))
    H = np.zeros((cell.Nx, cell.Ny // 2 + 1), dtype=complex)
    H[kx[:, 0] % cell.Nx, : Ky + 1] = (scale * cell.Nx * cell.Ny) * c
    return np.fft.irfft2(H, s=cell.shape)


def check_heights(h: np.ndarray, cell: Cell, name: str = "heights") -> np.ndarray:
    """Validate a height map against the grid: shape and finiteness."""
    h = np.asarray(h, dtype=float)
    if h.shape != cell.shape:
        raise SurfaceError(f"{name} has shape {h.shape}, the grid is {cell.shape} (Nx, Ny)")
    bad = ~np.isfinite(h)
    if np.any(bad):
        i = tuple(int(v) for v in np.argwhere(bad)[0])
        raise SurfaceError(f"{name} has {int(bad.sum())} non-finite values (first at index {i})")
    return h


def from_npy(path, cell: Cell) -> np.ndarray:
    """Height map (m) stored as a 2D .npy array of shape (Nx, Ny) for the given cell."""
    path = Path(path)
    try:
        h = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError) as exc:
        raise SurfaceError(f"cannot read height map {str(path)!r}: {exc}") from exc
    if h.ndim == 1:
        h = h[:, None]
    return check_heights(h, cell, name=f"height map {path.name}")


TEXT_SUFFIXES = (".txt", ".csv", ".dat", ".asc")

#: input files (height maps, Δγ maps, modulus tables) may hold up to this many bytes, and a
#: grid map FILE_BYTES_PER_CELL per cell beyond it (a text matrix needs ≈ 25 bytes a value)
MIN_FILE_LIMIT = 64 * 2**20
FILE_BYTES_PER_CELL = 64


def file_limit(n_cells: int) -> int:
    """The size limit (bytes) of a map file for a grid of ``n_cells`` cells."""
    return max(MIN_FILE_LIMIT, FILE_BYTES_PER_CELL * int(n_cells))


def _quote(path) -> str:
    text = str(path)
    return repr(text) if len(text) <= 200 else repr(text[:200]) + f"... ({len(text)} characters)"


def check_input_file(path, what: str, limit: int = MIN_FILE_LIMIT) -> Path:
    """An input file must be a regular file (a FIFO would block the read, a device such as
    /dev/zero never end it) of at most ``limit`` bytes; raises SurfaceError naming it."""
    path = Path(path)
    try:
        st = path.stat()
    except (OSError, ValueError):  # missing, a dangling link, an unreadable folder, NUL
        raise SurfaceError(f"{what} {_quote(path)} does not exist") from None
    if not stat.S_ISREG(st.st_mode):
        kind = ("a folder" if stat.S_ISDIR(st.st_mode) else "a FIFO" if stat.S_ISFIFO(
            st.st_mode) else "a device" if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(
            st.st_mode) else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a file")
        raise SurfaceError(f"{what} {_quote(path)} is {kind}; allowed: a regular file of at "
                           f"most {limit} bytes")
    if st.st_size > limit:
        raise SurfaceError(f"{what} {_quote(path)} has {st.st_size} bytes; allowed: a regular "
                           f"file of at most {limit} bytes")
    return path


def _length_unit(text, where: str, path) -> float | None:
    """Metres per unit of a netCDF ``units`` attribute (None when absent or dimensionless);
    a unit that is no length is an error naming the attribute."""
    if text is None or str(text).strip() in ("", "1"):
        return None
    from .units import quantity

    m = quantity(f"1 {text}", "m")
    if isinstance(m, str):
        raise SurfaceError(f"height map {_quote(path)}: {where} = {str(text)!r} is not a "
                           f"length unit ({m})")
    return m


def read_heights(path, *, variable: str = "heights", scale: float = 1.0,
                 max_bytes: int = MIN_FILE_LIMIT):
    """Read a height map; returns ``(h, size)`` with h (Nx, Ny) in m (file values × ``scale``)
    and size = (Lx, Ly) in m when the file states it (netCDF coordinates, instrument files),
    else None.  The file must be a regular file of at most ``max_bytes`` bytes
    (:func:`check_input_file`).

    Formats: ``.npy``; plain text / CSV matrices (``.txt .csv .dat .asc``, rows = x index,
    ``#`` comments); netCDF (``.nc``: the variable ``variable`` on dimensions (x, y), with
    uniformly spaced coordinates giving the size; a ``units`` attribute on the variable or the
    coordinates, read by pint, converts them to m, and ``scale`` must then stay 1 for the
    heights); anything else through SurfaceTopography's
    ``read_topography`` when that optional package is installed.
    """
    path = Path(path)
    scale = _finite_positive("scale", scale)
    check_input_file(path, "height map", max_bytes)
    # the content's digest, not its modification time (a file rewritten within the clock's
    # granularity would otherwise be taken for the one read before)
    key = (str(path.resolve()), hashlib.blake2b(path.read_bytes(), digest_size=16).digest(),
           variable, scale)
    if _LAST_READ and _LAST_READ[0] == key:  # a scene reads its map twice (grid, surface)
        return _LAST_READ[1].copy(), _LAST_READ[2]
    h, size = _read_heights(path, variable, scale)
    _LAST_READ[:] = [key, h, size]
    return h.copy(), size


#: the last height map read: (key, heights, size), the key naming the file, a digest of its
#: contents and the reading options
_LAST_READ: list = []


def _read_heights(path: Path, variable: str, scale: float):
    """The reading of :func:`read_heights` (the file already checked)."""
    suffix = path.suffix.lower()
    size = None
    try:
        if suffix == ".npy":
            h = np.load(path, allow_pickle=False)
            if not isinstance(h, np.ndarray):  # pragma: no cover - np.load of a .npy
                raise SurfaceError(f"height map {_quote(path)} holds no array")
        elif suffix in TEXT_SUFFIXES:
            with path.open() as fh:
                first = next((ln for ln in fh if ln.strip() and not ln.startswith("#")), "")
            h = np.loadtxt(path, delimiter="," if "," in first else None, ndmin=2)
        elif suffix == ".nc":
            import xarray as xr

            from .io import check_netcdf

            try:  # in a child process first: a corrupted file can crash netCDF-C
                check_netcdf(path, "height map")
            except ValueError as exc:
                raise SurfaceError(str(exc)) from None
            with xr.open_dataset(path) as ds:
                if variable not in ds:
                    raise SurfaceError(f"height map {str(path)!r} has no variable "
                                       f"{variable!r} (variables: {', '.join(ds.data_vars)})")
                da = ds[variable].load()
            if da.ndim == 2 and set(da.dims) == {"x", "y"}:
                # named dimensions decide the orientation (CF and GDAL files store (y, x));
                # unnamed ones are taken as (x, y)
                da = da.transpose("x", "y")
            h = da.values
            stated = da.attrs.get("units", da.attrs.get("unit"))
            unit = _length_unit(stated, f"{variable}.units", path)
            if unit is not None:  # heights in a stated unit: converted, scale must be 1
                if scale != 1.0:
                    raise SurfaceError(
                        f"height map {_quote(path)} states its unit ({stated!r}); "
                        f"surface.scale = {shown(scale)} would scale it twice: leave scale at 1")
                h = np.asarray(h, float) * unit
            if h.ndim == 2 and all(d in da.coords for d in da.dims):
                size = []
                for d in da.dims:
                    c = np.asarray(da[d].values, float)
                    step = np.diff(c)
                    if c.size < 2 or np.ptp(step) > 1e-6 * abs(step.mean()):
                        size = None
                        break
                    cu = _length_unit(da[d].attrs.get("units", da[d].attrs.get("unit")),
                                      f"{d}.units", path)
                    size.append(float(step.mean() * c.size * (scale if cu is None else cu)))
                size = tuple(size) if size else None
        else:
            try:
                from SurfaceTopography import read_topography
            except ImportError as exc:
                raise SurfaceError(
                    f"height map {str(path)!r}: unknown format {suffix!r}; supported: .npy, "
                    f"{', '.join(TEXT_SUFFIXES)}, .nc, or instrument formats with the optional "
                    "package SurfaceTopography installed") from exc
            topo = read_topography(str(path))
            h = np.asarray(topo.heights(), dtype=float)
            size = tuple(float(s) for s in topo.physical_sizes)
            stated = getattr(topo, "unit", None)
            unit = _length_unit(stated, "unit", path)
            if unit is not None:  # heights and sizes in the instrument's unit: to m
                if scale != 1.0:
                    raise SurfaceError(
                        f"height map {_quote(path)} states its unit ({stated!r}); "
                        f"surface.scale = {shown(scale)} would scale it twice: leave scale at 1")
                h, size = h * unit, tuple(x * unit for x in size)
            else:  # no unit stated: the scale applies to the sizes as to the heights
                size = tuple(x * scale for x in size)
        if not (np.issubdtype(np.asarray(h).dtype, np.integer)
                or np.issubdtype(np.asarray(h).dtype, np.floating)):
            raise SurfaceError(f"height map {_quote(path)} holds {np.asarray(h).dtype} values; "
                               "heights must be real numbers")
        h = np.asarray(h, dtype=float)
    except SurfaceError:
        raise
    except Exception as exc:  # truncated or malformed files of any format
        raise SurfaceError(f"cannot read height map {_quote(path)}: {str(exc)[:300]}") from exc
    if h.ndim == 1:
        h = h[:, None]
    if h.ndim != 2 or h.size == 0:
        raise SurfaceError(f"height map {_quote(path)} must be a 2D array, got shape {h.shape}")
    with np.errstate(over="ignore"):
        return h * scale, size


# -- scene kinds ([surface] kind = ...): spectralbem.kinds ------------------------------------
def _check_sinusoid(sf: dict, g: dict, problems: list) -> None:
    if not (sf.get("wavelength") and all(g.get(k) for k in ("Lx", "Nx"))):
        return
    n = g["Lx"] / sf["wavelength"]
    if not n <= g["Nx"] / 2:  # also inf: a wavelength far below one cell
        problems.append(f"surface.wavelength: {shown(sf['wavelength'])} m is shorter than two "
                        f"cells ({2 * g['Lx'] / g['Nx']:.6g} m); allowed grid.Lx/k m for a "
                        f"whole k in [1, {g['Nx'] // 2}]")
    elif abs(n - round(n)) > 1e-9 or round(n) < 1:
        problems.append(f"surface.wavelength: {shown(sf['wavelength'])} m must divide grid.Lx = "
                        f"{shown(g['Lx'])} m a whole number of times")


def _check_self_affine(sf: dict, g: dict, problems: list) -> None:
    cut, roll = sf.get("cutoff_wavelength"), sf.get("rolloff_wavelength")
    if roll and cut and all(g.get(k) for k in ("Lx", "Ly", "Nx", "Ny")):
        if cut >= roll:
            problems.append(f"surface.cutoff_wavelength: {shown(cut)} m must be shorter than "
                            f"surface.rolloff_wavelength = {shown(roll)} m")
        # the grid holds modes |k| ≤ (N - 1)//2 along an axis (never the Nyquist mode): the
        # band |k| ≤ L/cut needs cut > L/((N - 1)//2 + 1), 2 cells for an even N (the same
        # rule, and band-edge tolerance 1e-10, as self_affine)
        lows = {a: g[f"L{a}"] / ((g[f"N{a}"] - 1) // 2 + 1) for a in "xy"}
        ax = max(lows, key=lows.get)
        lo, L, N = lows[ax], g[f"L{ax}"], g[f"N{ax}"]
        if cut <= lo * (1 + 1e-10):
            need = {a: 2 * int(np.floor(g[f"L{a}"] / cut * (1 + 1e-10))) + 1 for a in "xy"
                    if cut <= lows[a] * (1 + 1e-10)}  # the cells along a that hold cut
            refine = (" and ".join(f"grid.N{a} in [{n}, 65536]" for a, n in need.items())
                      + " for this cutoff" if max(need.values()) <= 65536
                      else f"a cutoff longer than {L / 32768:.6g} m")
            if lo < roll:
                problems.append(f"surface.cutoff_wavelength: {shown(cut)} m is too short for "
                                "the grid (at or beyond its Nyquist wavelength, 2 cells for an "
                                f"even N); allowed ({lo:.6g}, {shown(roll)}) m, or "
                                f"{refine}")
            elif ax == "y" and N == 1:  # the interval would be empty: say why
                problems.append(f"surface.cutoff_wavelength: {shown(cut)} m does not fit a "
                                "y-invariant strip (grid.Ny = 1 holds wavevectors along x only: "
                                f"the cutoff must be longer than grid.Ly = {shown(L)} m, and "
                                "shorter than surface.rolloff_wavelength = "
                                f"{shown(roll)} m); allowed {refine}, or grid.Ly < "
                                f"{shown(cut)} m")
            else:
                problems.append(f"surface.cutoff_wavelength: {shown(cut)} m is too short for "
                                f"the grid: grid.N{ax} = {N} holds no wavelength shorter than "
                                f"{lo:.6g} m (Nyquist), not below surface.rolloff_wavelength "
                                f"= {shown(roll)} m, so no cutoff fits; allowed {refine}")
        if roll > max(g["Lx"], g["Ly"]):
            problems.append(f"surface.rolloff_wavelength: {shown(roll)} m exceeds the cell; "
                            f"allowed (0, {shown(max(g['Lx'], g['Ly']))}] m")
    if (sf.get("rms_height") is None) == (sf.get("rms_slope") is None):
        problems.append("surface.rms_height / surface.rms_slope: give exactly one")


def _build_file(sf: dict, context):
    """The height map of ``surface.path`` (m), checked against the grid."""
    from .keys import HEIGHT

    cell, problems = context.cell, context.problems
    try:
        h, size = read_heights(context.base / sf["path"], variable=sf["variable"],
                               scale=sf["scale"], max_bytes=file_limit(cell.Nx * cell.Ny))
    except SurfaceError as exc:
        problems.append(f"surface.path: {exc}")
        return None
    if h.shape != cell.shape:
        problems.append(f"surface.path: the height map has shape {h.shape}, the grid is "
                        f"(grid.Nx, grid.Ny) = {cell.shape}")
        return None
    if size is not None:
        for name, got, want in (("Lx", size[0], cell.Lx), ("Ly", size[1], cell.Ly)):
            if abs(got - want) > 1e-6 * want:
                problems.append(f"grid.{name}: {shown(want)} m disagrees with the height map's "
                                f"physical size {shown(got)} m")
    bad = ~np.isfinite(h)
    if bad.any():
        problems.append(f"surface.path: the height map has {int(bad.sum())} non-finite values "
                        f"(first at index {tuple(int(i) for i in np.argwhere(bad)[0])})")
        return None
    if float(np.abs(h).max()) > HEIGHT[1]:
        problems.append(f"surface.path: heights × surface.scale reach {float(np.abs(h).max()):g} "
                        f"m; allowed within ±{HEIGHT[1]:g} m (check surface.scale)")
        return None
    return h


def _register() -> None:
    from .keys import HEIGHT, LENGTH, key
    from .kinds import register

    register("surface", "sinusoid",
             {"amplitude": key("number", "Λ in h = Λ cos(2πx/λ), invariant along y", "m",
                               *HEIGHT),
              "wavelength": key("number", "λ; must divide Lx (default Lx)", "m", 0, None, True,
                                default=None)},
             lambda sf, c: sinusoid(c.cell, sf["amplitude"], sf["wavelength"]),
             _check_sinusoid)
    register("surface", "bisinusoid",
             {"amplitude": key("number", "Λ in h = Λ cos(2πx/Lx) cos(2πy/Ly)", "m", *HEIGHT)},
             lambda sf, c: bisinusoid(c.cell, sf["amplitude"]))
    register("surface", "paraboloid",
             {"radius": key("number", "sphere radius R, h = -r²/(2R) about the cell centre",
                            "m", *LENGTH)},
             lambda sf, c: paraboloid(c.cell, sf["radius"]))
    register("surface", "self_affine",
             {"hurst": key("number", "Hurst exponent H", "", 0, 1, True, hi_open=True),
              "rolloff_wavelength": key("number", "roll-off wavelength 2π/q_r (at most the "
                                        "cell)", "m", 0, None, True),
              "cutoff_wavelength": key("number", "short cut-off wavelength 2π/q_s, physical "
                                       "(the surface is the same on every grid that holds "
                                       "it): longer than the grid's Nyquist wavelength (2 "
                                       "cells), shorter than rolloff_wavelength", "m", 0, None,
                                       True),
              "rms_height": key("number", "rms height (give this or rms_slope)", "m", *HEIGHT,
                                default=None),
              "rms_slope": key("number", "rms slope |∇h|", "", 1e-9, 100, default=None),
              "seed": key("integer", "random seed (reproducible surfaces)", "", 0, 2**63 - 1,
                          default=0)},
             lambda sf, c: self_affine(c.cell, sf["hurst"],
                                       rolloff=2 * np.pi / sf["rolloff_wavelength"],
                                       cutoff=2 * np.pi / sf["cutoff_wavelength"],
                                       rms_height=sf["rms_height"], rms_slope=sf["rms_slope"],
                                       seed=sf["seed"]),
             _check_self_affine)
    register("surface", "file",
             {"path": key("path", "height map: .npy, .txt/.csv matrix, .nc, or an instrument "
                          "format read by SurfaceTopography (optional extra); relative to the "
                          "scene file; a regular file of at most 64 bytes per grid cell (and "
                          "at least 64 MiB); heights (× scale) within ±1e3 m"),
              "variable": key("string", "netCDF variable holding the heights",
                              default="heights"),
              "scale": key("number", "factor converting the file's values to m", "m/unit",
                           1e-15, 1e3, default=1.0)},
             _build_file)


_register()
