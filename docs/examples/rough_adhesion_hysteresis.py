# %% [markdown]
# # Adhesion hysteresis of a rough contact
#
# An elastic slab (E = 1 MPa, ν = 0.5) with a work of adhesion Δγ = 0.01 J/m² is loaded on
# a self-affine rough surface and unloaded along a mean-pressure path; the contact mask is
# carried from step to step. At the same load the unloading branch holds more contact than
# the loading branch: adhesion hysteresis. In an elastic scene the advance width a0 is a
# numerical length: one cell is the most accurate (docs/theory.md); the area converges with
# the grid as shown in docs/rough_convergence.md.

# %%
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import spectralbem as sb  # noqa: E402
from spectralbem.scenes import load_scene, read_scene_file  # noqa: E402

SMALL = bool(os.environ.get("SPECTRALBEM_EXAMPLE_SMALL"))
N = 64 if SMALL else 256
loads = [5e3, 1e4, 2e4, 1e4, 5e3]  # Pa: loading, then unloading

case = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "cases",
                    "rough_convergence.toml")
raw = read_scene_file(case)
raw["material"] = {"kind": "elastic", "E": "1 MPa", "nu": 0.5}  # units are read by pint
raw.pop("motion")  # an elastic slab at rest
ds = sb.solve(load_scene(raw, overrides={
    "grid.Nx": N, "grid.Ny": N, "adhesion.a0": 1e-3 / N,  # one cell
    "control.mean_pressure": loads,
    "surface.cutoff_wavelength": 1.25e-4 if SMALL else 6.25e-5}))
for k in range(len(loads)):
    st = ds.isel(step=k)
    print(f"p̄ = {loads[k]:g} Pa: area {float(st.area_fraction):.4f} ({st.status.item()})")

# %%
fig, ax = plt.subplots(figsize=(4.5, 3.5), constrained_layout=True)
ax.plot(loads[:3], ds.area_fraction.values[:3], "o-", label="loading")
ax.plot(loads[2:], ds.area_fraction.values[2:], "s--", label="unloading")
ax.set_xlabel("mean pressure p̄ (Pa)")
ax.set_ylabel("contact area fraction")
ax.legend()
fig.savefig("rough_adhesion_hysteresis.png", dpi=110)
