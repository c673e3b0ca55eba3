"""The self-affine surface is a physical surface: the same seed gives the same Fourier
coefficients and samples of the same h(x, y) on every grid that holds its band.

Tolerances: everything asserted at 1e-12 relative is exact in exact arithmetic (a band-limited
sum of the same coefficients, sampled on nested grids); the measured gaps are round-off:
shared modes ≤ 6e-16 of the largest, samples ≤ 5e-16 of max |h|, rms height and slope
≤ 6e-16, |c(k)|/√C(q) constant to 3e-15.  The former generator (phases drawn on each grid's
own rfft modes, ky = 0 line not mirrored) fails the refinement, rectangular, spectrum and
scene tests by O(1).
"""

from pathlib import Path

import numpy as np
import pytest

from spectralbem.scenes import SceneError, load_scene
from spectralbem.spectral import Cell
from spectralbem.surfaces import SurfaceError, self_affine

L = 1e-3
QR, QS = 2 * np.pi / 2.5e-4, 2 * np.pi / 6.25e-5  # roll-off at L/4, cut-off at L/16 (rad/m)
CASES = Path(__file__).resolve().parent.parent / "cases"


def surface(cell, seed=7, **scale):
    return self_affine(cell, 0.8, rolloff=QR, cutoff=QS, seed=seed,
                       **(scale or {"rms_slope": 0.1}))


def band_coefficients(h, cell):
    """c(k) = rfft2(h)/(Nx Ny) on the box |kx| ≤ Kx, 0 ≤ ky ≤ Ky of the cut-off QS."""
    Kx, Ky = int(cell.Lx * QS / (2 * np.pi) + 1e-9), int(cell.Ly * QS / (2 * np.pi) + 1e-9)
    F = np.fft.rfft2(h) / h.size
    return F[np.arange(-Kx, Kx + 1) % cell.Nx][:, : Ky + 1], F


@pytest.mark.parametrize("n, m", [(64, 128), (128, 1024), (45, 135)])
def test_same_fourier_modes_and_samples_on_every_grid(n, m):
    """The modes of the band are identical on both grids (measured ≤ 6e-16 of the largest);
    outside the band the finer grid's spectrum is zero (band-limited: ≤ 1e-14 of the band's
    sum); the coarse surface is the fine one at every (m/n)-th point.  Odd N (45, 135)
    included."""
    coarse, fine = Cell(L, L, n, n), Cell(L, L, m, m)
    hc, hf = surface(coarse), surface(fine)
    cc, _ = band_coefficients(hc, coarse)
    cf, Ff = band_coefficients(hf, fine)
    assert np.max(np.abs(cc - cf)) <= 1e-12 * np.max(np.abs(cf))
    outside = np.abs(Ff).sum() - np.abs(cf).sum()
    assert outside <= 1e-12 * np.abs(cf).sum()
    r = m // n
    assert np.max(np.abs(hc - hf[::r, ::r])) <= 1e-12 * np.max(np.abs(hf))


def test_rectangular_cell_refined_along_one_axis():
    """Lx ≠ Ly, Nx ≠ Ny; refining x only, or both, samples the same surface."""
    base = Cell(2 * L, L, 96, 40)
    h = surface(base, seed=11)
    for fx, fy in ((2, 1), (2, 3)):
        fine = surface(Cell(2 * L, L, 96 * fx, 40 * fy), seed=11)
        assert np.max(np.abs(h - fine[::fx, ::fy])) <= 1e-12 * np.max(np.abs(h))
    # the band spans |kx| ≤ 32, |ky| ≤ 16 (2Lx/λs, Ly/λs): modes along both axes are present
    c, _ = band_coefficients(h, base)
    assert c.shape == (65, 17) and np.abs(c[:, 16]).max() > 0 and np.abs(c[0]).max() > 0


@pytest.mark.parametrize("n", [33, 48, 100])
@pytest.mark.parametrize("scale", [{"rms_height": 2e-6}, {"rms_slope": 0.1}])
def test_rms_as_requested_real_and_zero_mean(n, scale):
    """The grid's rms height (mean of h²) or rms slope (spectral derivative: the Nyquist
    modes, which the derivative zeroes, are never in the band) equals the request to
    round-off (measured ≤ 6e-16 relative; asserted 1e-12)."""
    cell = Cell(L, L, n, n)
    h = surface(cell, **scale)
    assert h.dtype == np.float64 and h.shape == (n, n)
    rms_h = np.sqrt(np.mean(h**2))
    assert abs(h.mean()) <= 1e-14 * rms_h
    if "rms_height" in scale:
        assert rms_h == pytest.approx(scale["rms_height"], rel=1e-12)
    else:
        g2 = cell.derivative(h, (1.0, 0.0)) ** 2 + cell.derivative(h, (0.0, 1.0)) ** 2
        assert np.sqrt(np.mean(g2)) == pytest.approx(scale["rms_slope"], rel=1e-12)


def test_hermitian_spectrum_follows_the_psd_with_unit_phases():
    """c(−k) = conj c(k) on the full spectrum, and every mode of the band, both halves of the
    ky = 0 line included, has |c(k)| ∝ √C(q) (flat below q_r, (q/q_r)^{-(1+H)} above): a
    half-plane drawn but not mirrored would be projected by the inverse real FFT and break
    the modulus on that line.  No power outside the band or at q = 0."""
    cell = Cell(L, L, 64, 64)
    h = surface(cell)
    F = np.fft.fft2(h) / h.size
    flipped = np.roll(F[::-1, ::-1], (1, 1), axis=(0, 1))  # F(−k)
    assert np.max(np.abs(F - np.conj(flipped))) <= 1e-12 * np.max(np.abs(F))
    qx, qy = cell.wavevectors(half=False)
    q = np.hypot(qx, qy)
    band = (q > 0) & (q <= QS * (1 + 1e-10))
    psd = np.where(q < QR, 1.0, (np.maximum(q, QR) / QR) ** (-2 * 1.8))
    ratio = np.abs(F[band]) / np.sqrt(psd[band])
    assert np.ptp(ratio) <= 1e-12 * ratio.mean()
    assert np.max(np.abs(F[~band])) <= 1e-12 * np.max(np.abs(F))
    phases = np.angle(F[band & (qy > 0)])  # independent uniform phases: no structure
    assert abs(np.mean(np.exp(1j * phases))) < 0.2


def test_different_seeds_differ_and_seed_is_reproducible():
    cell = Cell(L, L, 64, 64)
    assert np.array_equal(surface(cell, seed=3), surface(cell, seed=3))
    a, b = surface(cell, seed=3), surface(cell, seed=4)
    assert np.corrcoef(a.ravel(), b.ravel())[0, 1] < 0.5


@pytest.mark.parametrize("shape, axis, words", [
    ((32, 64), "x", ["cutoff = 100530.9649", "Nx ≥ 33", "Nx = 32", "|kx| ≤ 15",
                     "100530.9649) rad/m", "Nyquist wavevector π/hx"]),
    ((64, 31), "y", ["Ny ≥ 33", "Ny = 31", "|ky| ≤ 15", "π/hy + π/Ly"]),
])
def test_cutoff_the_grid_cannot_hold_is_rejected(shape, axis, words):
    """q_s = π/h of a 32-cell axis (λs = 2 cells) puts the Nyquist mode in the band: rejected
    with the parameter, its value and the allowed range; 33 cells hold it."""
    with pytest.raises(SurfaceError) as err:
        surface(Cell(L, L, *shape))
    msg = str(err.value)
    for w in words:
        assert w in msg, (w, msg)
    assert f"allowed ({QR!r}, " in msg
    surface(Cell(L, L, 33, 33))
    with pytest.raises(SurfaceError, match="below the cell's lowest wavevector"):
        self_affine(Cell(L, L, 64, 64), 0.8, rolloff=0.1 / L, cutoff=0.5 / L, rms_slope=0.1)


def test_scene_surface_is_the_same_at_every_resolution():
    """cases/rubber_rough.toml at 32², 64² and its own 128²: the physical cut-off of the case
    makes the coarse scenes samples of the 128² surface."""
    h = {n: load_scene(CASES / "rubber_rough.toml", overrides={
        "grid.Nx": n, "grid.Ny": n, "surface.cutoff_wavelength": 1.25e-4}).heights
        for n in (32, 64, 128)}
    for n in (32, 64):
        r = 128 // n
        assert np.max(np.abs(h[n] - h[128][::r, ::r])) <= 1e-12 * np.max(np.abs(h[128]))


@pytest.mark.parametrize("value, words", [
    (None, ["surface.cutoff_wavelength: missing", "Nyquist wavelength", "allowed (0, inf]"]),
    (6.25e-5, ["surface.cutoff_wavelength: 6.25e-05 m is too short", "Nyquist",
               "allowed (6.25e-05, 0.00025) m"]),
])
def test_scene_cutoff_is_required_and_held_by_the_grid(value, words):
    """No default tied to the cells; at 32² a 6.25e-5 m cut-off (2 cells) is the Nyquist
    wavelength: rejected with the key, the value and the grid's allowed range."""
    surf = {"kind": "self_affine", "hurst": 0.8, "rolloff_wavelength": 2.5e-4,
            "rms_slope": 0.1}
    if value is not None:
        surf["cutoff_wavelength"] = value
    raw = {"grid": {"Lx": L, "Ly": L, "Nx": 32, "Ny": 32}, "surface": surf,
           "material": {"kind": "elastic", "E": 1e6}, "control": {"mean_pressure": 1e4}}
    with pytest.raises(SceneError) as err:
        load_scene(raw)
    msg = str(err.value)
    for w in words:
        assert w in msg, (w, msg)


def test_netcdf_height_map_in_micrometres_is_read_in_metres(tmp_path):
    """A netCDF height map whose heights and coordinates state their unit (µm, as
    instruments and SurfaceTopography write them) is converted to m by pint, and the grid's
    physical size is checked against the converted coordinates; a scale on top of a stated
    unit, or a unit that is no length, is refused naming it."""
    import xarray as xr

    from spectralbem.surfaces import read_heights

    rng = np.random.default_rng(3)
    h_um = rng.normal(size=(16, 16))
    xs = (np.arange(16) + 0.5) * 1000.0 / 16  # µm
    ds = xr.Dataset({"heights": (("x", "y"), h_um, {"units": "um"})},
                    coords={"x": ("x", xs, {"units": "µm"}), "y": ("y", xs, {"units": "um"})})
    path = tmp_path / "topo.nc"
    ds.to_netcdf(path)
    h, size = read_heights(path)
    assert np.allclose(h, h_um * 1e-6) and np.allclose(size, (1e-3, 1e-3))
    scene = load_scene({"grid": {"Lx": "1 mm", "Ly": "1 mm", "Nx": 16, "Ny": 16},
                        "surface": {"kind": "file", "path": str(path)},
                        "material": {"kind": "elastic", "E": "1 MPa", "nu": 0.5},
                        "control": {"mean_pressure": "10 kPa"}})
    assert np.allclose(scene.heights, h_um * 1e-6)
    with pytest.raises(SurfaceError, match="would scale it twice"):
        read_heights(path, scale=1e-6)
    ds["heights"].attrs["units"] = "Pa"
    ds.to_netcdf(tmp_path / "bad.nc")
    with pytest.raises(SurfaceError, match="heights.units = 'Pa' is not a length unit"):
        read_heights(tmp_path / "bad.nc")
    with pytest.raises(SceneError, match="grid.Lx"):  # 2 mm against the file's 1 mm
        load_scene({"grid": {"Lx": "2 mm", "Ly": "1 mm", "Nx": 16, "Ny": 16},
                    "surface": {"kind": "file", "path": str(path)},
                    "material": {"kind": "elastic", "E": "1 MPa", "nu": 0.5},
                    "control": {"mean_pressure": "10 kPa"}})


def test_instrument_file_in_micrometres_is_read_in_metres(tmp_path, monkeypatch):
    """An instrument file (any other suffix) goes through SurfaceTopography's
    ``read_topography``; its heights and physical sizes are in the file's unit, converted
    to m (a 500 µm scan read as 500 m was refused against the grid); with a stated unit a
    scale is refused, without one the scale applies to the sizes as to the heights.  The
    reader is a stand-in here, so the test runs without the optional package."""
    import sys
    import types

    from spectralbem import surfaces
    from spectralbem.surfaces import read_heights

    h_um = np.random.default_rng(5).normal(size=(8, 4))

    class Topo:
        physical_sizes = (500.0, 250.0)
        unit = "µm"

        def heights(self):
            return h_um

    fake = types.ModuleType("SurfaceTopography")
    fake.read_topography = lambda path: Topo()
    monkeypatch.setitem(sys.modules, "SurfaceTopography", fake)
    path = tmp_path / "scan.opd"
    path.write_bytes(b"instrument bytes")
    h, size = read_heights(path)
    assert np.allclose(h, h_um * 1e-6) and np.allclose(size, (5e-4, 2.5e-4))
    with pytest.raises(SurfaceError, match="would scale it twice"):
        read_heights(path, scale=1e-6)
    Topo.unit = None
    surfaces._LAST_READ.clear()
    h, size = read_heights(path, scale=1e-6)
    assert np.allclose(h, h_um * 1e-6) and np.allclose(size, (5e-4, 2.5e-4))
    Topo.unit = "Pa"
    surfaces._LAST_READ.clear()
    with pytest.raises(SurfaceError, match="unit = 'Pa' is not a length unit"):
        read_heights(path)


def test_a_height_map_scene_takes_its_grid_from_the_file(tmp_path, monkeypatch):
    """Without a [grid] the scene takes Nx, Ny from the map's shape and Lx, Ly from the size
    the netCDF file states; a .npy map states no size, so Lx, Ly stay required (named)."""
    import xarray as xr

    h = np.random.default_rng(4).normal(size=(24, 16))
    x = (np.arange(24) + 0.5) * 500.0 / 24
    y = (np.arange(16) + 0.5) * 250.0 / 16
    xr.Dataset({"heights": (("x", "y"), h, {"units": "um"})},
               coords={"x": ("x", x, {"units": "um"}), "y": ("y", y, {"units": "um"})}
               ).to_netcdf(tmp_path / "t.nc")
    common = {"material": {"kind": "elastic", "E": "1 MPa", "nu": 0.5},
              "control": {"mean_pressure": "10 kPa"}}
    from spectralbem import surfaces

    reads = []
    real = surfaces._read_heights
    monkeypatch.setattr(surfaces, "_read_heights", lambda *a: reads.append(a) or real(*a))
    sc = load_scene({"surface": {"kind": "file", "path": str(tmp_path / "t.nc")}, **common})
    assert len(reads) == 1  # the grid and the surface share one reading of the file
    assert sc.cell.shape == (24, 16)
    np.testing.assert_allclose(sc.heights, h * 1e-6)
    # a file rewritten in place (same name and size) is read again
    xr.Dataset({"heights": (("x", "y"), 2 * h, {"units": "um"})},
               coords={"x": ("x", x, {"units": "um"}), "y": ("y", y, {"units": "um"})}
               ).to_netcdf(tmp_path / "t.nc")
    sc2 = load_scene({"surface": {"kind": "file", "path": str(tmp_path / "t.nc")}, **common})
    assert len(reads) == 2
    np.testing.assert_allclose(sc2.heights, 2e-6 * h)
    assert (sc.cell.Lx, sc.cell.Ly) == pytest.approx((5e-4, 2.5e-4), rel=1e-9)
    np.save(tmp_path / "t.npy", h)
    with pytest.raises(SceneError, match="grid.Lx"):
        load_scene({"surface": {"kind": "file", "path": str(tmp_path / "t.npy")}, **common})


def test_netcdf_height_map_is_oriented_by_its_dimension_names(tmp_path):
    """A netCDF map stored (y, x), as CF and GDAL files are, is the same surface as the one
    stored (x, y): its dimensions are read by name (a square map was silently transposed, a
    non-square one refused with a size error that did not say why)."""
    import xarray as xr

    from spectralbem.surfaces import read_heights

    x = np.arange(32) * 1e-3 / 32
    y = np.arange(16) * 0.5e-3 / 16
    h = 1e-6 * np.cos(2 * np.pi * x / 1e-3)[:, None] * np.ones(16)  # ridges along y
    for dims, values in ((("x", "y"), h), (("y", "x"), h.T)):
        path = tmp_path / f"{''.join(dims)}.nc"
        xr.Dataset({"heights": (dims, values, {"units": "m"})},
                   coords={"x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"})}
                   ).to_netcdf(path)
        got, size = read_heights(path)
        assert got.shape == (32, 16) and np.array_equal(got, h), dims
        assert np.allclose(size, (1e-3, 0.5e-3))
