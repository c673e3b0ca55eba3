# %% [markdown]
# # Viscoelastic friction of a rough surface against sliding speed
#
# A rubber-like standard linear solid (E0 = 2 MPa, E∞ = 20 MPa, τ = 10 ms) slides on a
# self-affine rough surface (H = 0.8, rms slope 0.1) at a mean pressure of 10.7 kPa, without
# adhesion. The friction coefficient μ is the hysteresis friction of Eq. (19); it peaks
# where the surface's wavelengths are excited near 1/τ. Run it as a script
# (`python docs/examples/rough_friction_velocity.py`) or open it with jupytext.

# %%
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spectralbem as sb  # noqa: E402
from spectralbem.scenes import load_scene  # noqa: E402

SMALL = bool(os.environ.get("SPECTRALBEM_EXAMPLE_SMALL"))  # the test suite's quick run
N = 32 if SMALL else 128
speeds = np.logspace(-5, 0, 4 if SMALL else 11)  # m/s

# %% [markdown]
# The scene is the shipped `cases/rubber_rough.toml`; only the grid and the speed change.
# Its surface keeps the same Fourier coefficients on every grid (a fixed physical surface).

# %%
case = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "cases",
                    "rubber_rough.toml")
mu, area = [], []
for v in speeds:
    ds = sb.solve(load_scene(case, overrides={
        "grid.Nx": N, "grid.Ny": N, "motion.speed": float(v),
        "surface.cutoff_wavelength": 1.25e-4 if SMALL else 6.25e-5}))
    assert ds.status.item() == "partial", ds.attrs["solver_message"]
    mu.append(float(ds.mu))
    area.append(float(ds.area_fraction))
    print(f"v = {v:.3g} m/s: μ = {mu[-1]:.4f}, contact area {area[-1]:.4f}")

# %%
fig, ax = plt.subplots(1, 2, figsize=(9, 3.5), constrained_layout=True)
ax[0].semilogx(speeds, mu, "o-")
ax[0].set_xlabel("sliding speed v (m/s)")
ax[0].set_ylabel("friction coefficient μ")
ax[1].semilogx(speeds, area, "o-")
ax[1].set_xlabel("sliding speed v (m/s)")
ax[1].set_ylabel("contact area fraction")
fig.savefig("rough_friction_velocity.png", dpi=110)
