"""Solving a scene: the seed's 1D method, or the grid — one solve for seed and physical
scenes (:func:`_grid_state`; a seed scene is a physical one in k = Λ = E0* = 1 units), whose
state is reported in the seed's dimensionless names or in SI (:mod:`spectralbem.results`) —,
and the verification of each state's status.

:func:`solve` (re-exported as ``spectralbem.solve`` and ``spectralbem.scenes.solve``) runs a
:class:`spectralbem.scenes.Scene` step by step along its load path.
"""

from __future__ import annotations

import datetime as _dt
import json
import math

import numpy as np

from . import __version__
from .conventions import shown
from .fft import transform_counts
from .friction import sliding_direction
from .io import FIELDS, SCALARS, cf_attributes
from .io import attrs as _attrs
from .keys import DELAYED_DEFAULT, FRONT_TOL
from .load_path import (  # noqa: F401  (SUBSTEP_HALVINGS, PathInterrupted: part of this API)
    SUBSTEP_HALVINGS,
    PathInterrupted,
    needs_substeps,
    step_status,
    substepped,
)
from .progress import progress_bar
from .results import (
    edges_y_invariant,
    friction_observables,
    front_friction,
    grid_dataset,
    profile_friction,
    quotient,
    seed_dataset,
    seed_front_outputs,
)
from .scenes import Scene, _dimensionless_groups
from .schema import SceneError
from .spectral import SpectralOperator

#: the states whose status promises a verified equilibrium (every other is not_converged)
REPORTED = ("partial", "full_contact", "detached")


#: the friction coefficients a state carries (friction.friction)
FRICTION = ("mu", "mu_lateral", "mu_profile", "mu_dissipation")


def _friction(op, h, p, u, state) -> dict:
    """The friction coefficients of (p, u): the solver's (``state``'s) when they are its
    fields, with :func:`quotient`'s convention where the net normal force vanishes (a
    detached state, an adhesive contact at zero load): never nan."""
    from .friction import friction

    fr = ({k: getattr(state, k) for k in FRICTION} if p is state.pressure
          else friction(op, h, p, u))
    if not any(np.isnan(v) for v in fr.values()):
        return fr
    cell = op.cell
    vhat = sliding_direction(op)
    vperp = np.array([-vhat[1], vhat[0]])
    du, dl, dh = (cell.derivative(u, vhat), cell.derivative(u, vperp),
                  cell.derivative(h, vhat))
    ap = np.abs(p)
    forces = dict(mu=(-float(np.sum(p * du)), float(np.sum(ap * np.abs(du)))),
                  mu_lateral=(-float(np.sum(p * dl)), float(np.sum(ap * np.abs(dl)))),
                  mu_profile=(-float(np.sum(p * dh)), float(np.sum(ap * np.abs(dh)))))
    fd = op.dissipation_friction_force(p, vhat) / cell.cell_area if ap.any() else 0.0
    forces["mu_dissipation"] = (fd, forces["mu"][1])
    total, tscale = float(np.sum(p)), float(np.sum(ap))
    return {k: quotient(f, total, fs, tscale) for k, (f, fs) in forces.items()}


def _verify(status: str, message: str, scene: Scene, mask) -> tuple:
    """A status is a promise: (status, message) after the checks a reported state must pass.
    ``detached`` is a zero pressure field that leaves no interpenetration: no compressive
    load, Δ ≤ 0; an adhesiveless solve that converged without a contact cell is that state.
    It carries no load: a tensile load prescribed is not carried (the message says so; the
    dataset reports the load carried, 0, and the prescribed one as ``prescribed_*``)."""
    if status == "partial" and not np.any(mask):
        status = "detached"
    if status != "detached":
        return status, message
    seed = scene.kind == "sinusoid"
    if scene.mean_pressure is not None and scene.mean_pressure > 0:
        load = f"p̃ = {scene.mean_pressure / 0.5:g}" if seed else f"{scene.mean_pressure:g} Pa"
        return "not_converged", (f"no equilibrium found: the contact vanished under the "
                                 f"compressive mean pressure {load}, which a detached state "
                                 f"cannot carry (solver: {message})")
    if scene.penetration is not None and scene.penetration > 0:
        pen = f"Δ̃ = {scene.penetration:g}" if seed else f"{scene.penetration:g} m"
        return "not_converged", (f"no equilibrium found: the contact vanished at the "
                                 f"penetration {pen} > 0, where a detached state "
                                 f"interpenetrates (solver: {message})")
    if scene.mean_pressure is not None and scene.mean_pressure < 0:
        load = f"p̃ = {scene.mean_pressure / 0.5:g}" if seed else f"{scene.mean_pressure:g} Pa"
        message += (f"; the prescribed tensile mean pressure {load} is not carried (a "
                    "detached state carries no load: the mean pressure reported is 0)")
    return status, message


def _undefined(status: str, message: str, scalars: dict, skip=()) -> tuple:
    """A reported state with a nan scalar is not a verified state: not_converged, naming
    them (the conventions above leave none in a sound state)."""
    bad = [k for k, v in scalars.items() if k not in skip and isinstance(v, float)
           and math.isnan(v)]
    if status in REPORTED and bad:
        return "not_converged", (f"the state's {', '.join(bad)} are undefined (nan), so it "
                                 f"is not reported as {status}; solver: {message}")
    return status, message


def _solve_seed_grid(scene: Scene, mask0=None, progress=None):
    """The seed scene on the grid: the 1D method's dimensionless names."""
    from . import front

    op = _operator(scene)
    cell, h = scene.cell, scene.heights
    pstar = 0.5
    out = {}
    G_front = None
    if scene.adhesive:
        if mask0 is None and scene.kind == "sinusoid":  # start from Johnson's E0 contact
            from . import reference as ref

            pt = scene.mean_pressure / pstar if scene.mean_pressure is not None else 0.3
            a = ref.johnson_a(pt, scene.params["Gamma"]) if pt is not None else np.nan
            a = a if np.isfinite(a) else 1.0
            xw = (cell.x + np.pi) % (2 * np.pi) - np.pi
            mask0 = np.repeat((np.abs(xw) < a)[:, None], cell.Ny, axis=1)
        obs = friction_observables(op, h)
        state = r = _grid_state(scene, op, mask0, progress, obs)
        p, mask, delta, status = r.pressure, r.contact, r.penetration, r.status
        out["p_front"] = r.mean_pressure
        u = r.displacement
        if status == "partial" and r.tests is not None:  # the local G/Δγ on the front
            G_front = front.front_outputs(op, r, scene.dgamma)["G_map"]
        if scene.kind == "sinusoid" and status == "partial":
            l1, l2, more = seed_front_outputs(op, r, scene.dgamma, obs)
            out.update(more)
        else:
            l1 = l2 = np.nan
            out.update(G1_over_dgamma=np.nan, G2_over_dgamma=np.nan)
        info = dict(outer_iterations=r.iterations, solves=r.solves, message=r.message,
                    balanced_fraction=r.balanced_fraction, front_residual=r.residual)
        if status in ("detached", "full_contact"):  # no front: nothing unbalanced
            info.update(balanced_fraction=1.0, front_residual=0.0)
    else:
        state = res = _grid_state(scene, op, progress=progress)
        p, mask, delta, u = res.pressure, res.contact, res.penetration, res.displacement
        status = res.status
        l1 = l2 = np.nan
        if scene.kind == "sinusoid" and status == "partial":
            zeros = np.zeros(cell.shape)
            l1, l2 = edges_y_invariant(mask, zeros, cell)
        out.update(G1_over_dgamma=np.nan, G2_over_dgamma=np.nan)
        info = dict(iterations=res.iterations, message=res.message)
    status, info["message"] = _verify(status, info["message"], scene, mask)
    if status == "detached":  # the zero field, no edge (the 1D method's values)
        p, u, l1, l2 = np.zeros(cell.shape), np.zeros(cell.shape), 0.0, 0.0
    elif status == "full_contact":
        l1 = l2 = np.pi
    if status in ("detached", "full_contact") or not scene.adhesive:
        out.update(G1_over_dgamma=0.0, G2_over_dgamma=0.0)  # no edge, or no adhesion
    fr = _friction(op, h, p, u, state)
    pm = out.pop("p_front", float(p.mean()))
    mu = out.pop("mu_bar_force_front", fr["mu_profile"])
    mu_lat = out.pop("mu_bar_lateral_front", fr["mu_lateral"])
    # l1, l2: the edges on −x and +x; ẽ > 0 toward the leading edge, +x when v̂·x̂ ≥ 0
    lead = -1.0 if sliding_direction(op)[0] < 0 else 1.0
    out.update(a_tilde=(l1 + l2) / 2, e_tilde=lead * (l2 - l1) / 2, p_tilde=pm / pstar,
               delta_tilde=float(delta), mu_bar=mu, mu_bar_mask=fr["mu_profile"],
               mu_bar_dissipation=fr["mu_dissipation"], mu_bar_lateral=mu_lat)
    G1, G2 = out["G1_over_dgamma"], out["G2_over_dgamma"]
    # the edges (along y) sweep the surface at |v̂·x̂| v: the adhesive force along v is that
    # fraction of (G1 − G2) Δγ per edge, as μ̄ is along v (oblique sliding)
    sweep = abs(float(sliding_direction(op)[0]))
    out["mu_bar_adhesive"] = 0.0 if G1 == G2 == 0.0 else quotient(
        sweep * (G1 - G2) * scene.dgamma, cell.Lx * pm, (abs(G1) + abs(G2)) * scene.dgamma,
        cell.Lx * float(np.abs(p).mean()))
    status, info["message"] = _undefined(status, info["message"], out)
    if status == "partial" and not out["a_tilde"] > 0:
        status, info["message"] = "not_converged", (
            f"the contact edges give ã = {shown(out['a_tilde'])} ≤ 0, so the state is not "
            f"reported as partial; solver: {info['message']}")
    ds = seed_dataset(cell, out, status, p / pstar, mask,
                      G_front if status == "partial" else None)
    ds.attrs.update(**scene.params, **info)
    return ds


# -- physical scenes -------------------------------------------------------------------------
def _spec_as_solved(scene: Scene) -> dict:
    """The scene mapping of the dataset, with the defaults a scene decides (None in the
    schema) as the solve took them: ``solver.extrapolate_a0`` of an adhesive grid scene; the
    keys left unset (None) are left out, so that ``load_scene`` of the recorded mapping
    reruns the same scene (it refuses a None)."""
    spec = scene.spec
    solver = spec.get("solver") or {}  # a seed scene without [solver] decides it too
    if not (solver.get("extrapolate_a0") is not None or not scene.adhesive
            or scene.model != "grid2d"):
        spec = dict(spec, solver=dict(solver, extrapolate_a0=scene.extrapolate_a0))
    return _without_none(spec)


def _input_checksums(scene: Scene) -> dict:
    """``scene_inputs``: the SHA-256 of each file the scene read (its ``scene`` attribute
    names them by absolute path), so that a rerun from the dataset can tell a changed file;
    nothing for a scene that reads none."""
    from .io import sha256_file
    from .schema import input_paths

    files = input_paths(scene.spec, "/")
    if not files:
        return {}
    return {"scene_inputs": json.dumps({k: sha256_file(p) if p.is_file() else "missing"
                                        for k, p in files.items()}, sort_keys=True)}


def _without_none(d):
    """A copy of the nested mapping ``d`` without its None values."""
    if not isinstance(d, dict):
        return d
    return {k: _without_none(v) for k, v in d.items() if v is not None}


def _operator(scene: Scene) -> SpectralOperator:
    return SpectralOperator(scene.cell, scene.material, scene.layer, velocity=scene.velocity,
                            threads=scene.solver["threads"],
                            delayed=scene.solver.get("delayed_kernel", DELAYED_DEFAULT))


def _grid_state(scene: Scene, op: SpectralOperator, mask0=None, progress=None,
                observables: dict | None = None):
    """The state of a grid scene (seed or physical: the same solve): the adhesive front from
    ``mask0`` (an AdhesiveState), or the adhesiveless contact (a ContactState)."""
    from .adhesive import solve_adhesive
    from .contact import solve_contact

    solver = scene.solver
    if not scene.adhesive:
        return solve_contact(op, scene.heights, mean_pressure=scene.mean_pressure,
                             penetration=scene.penetration, tol=solver["tol"],
                             maxiter=solver["max_iterations"], progress=progress)
    return solve_adhesive(op, scene.heights, scene.dgamma, scene.a0,
                          penetration=scene.penetration, mean_pressure=scene.mean_pressure,
                          mask0=mask0, rtol=solver["tol"], observables=observables,
                          max_outer=solver["max_outer"], **_smoothing(scene),
                          criterion=solver.get("criterion", "exact"),
                          front_tol=solver.get("front_tol", FRONT_TOL),
                          flaw_radius=scene.flaw_radius, progress=progress,
                          coarse_start=solver.get("coarse_start", False),
                          extrapolate_a0=scene.extrapolate_a0,
                          band_tol=solver.get("band_tol"))


def _adhesiveless_mask(op, scene: Scene):
    """Initial mask of an adhesive solve: the adhesiveless contact at the same penetration,
    or at the same load (at |load|, or a light touch at zero load)."""
    from .contact import solve_contact

    h = scene.heights
    guard = scene.solver["max_iterations"]
    if scene.penetration is not None:
        if scene.penetration <= 0:
            return None
        res = solve_contact(op, h, penetration=scene.penetration, tol=1e-6, maxiter=guard)
    else:
        p = abs(scene.mean_pressure) or 1e-4 * scene.material.E0 * float(np.std(h)) / max(
            scene.cell.Lx, scene.cell.Ly)
        res = solve_contact(op, h, mean_pressure=p, tol=1e-6, maxiter=guard)
    return res.contact if res.contact.any() and not res.contact.all() else None


def _solve_grid(scene: Scene, mask0=None, progress=None):
    from .front import front_outputs, small_patch_diameter

    op = _operator(scene)
    cell, h = scene.cell, scene.heights
    sc = {}
    fields = {"heights": h}
    counted = transform_counts()  # the solve's FFTs: the difference at its end
    if scene.adhesive:
        # start from the adhesiveless contact (not from one summit cell); along a path,
        # from the carried mask joined with it (loading: no overshoot of the nucleation at
        # the new load's Δ; unloading: the adhesiveless contact is inside the carried one)
        m_free = _adhesiveless_mask(op, scene)
        mask0 = m_free if mask0 is None else (mask0 | m_free if m_free is not None else mask0)
        # the profile force's fields, recorded per band state (viscoelastic μ, below)
        obs = friction_observables(op, h) if op.viscoelastic else None
        state = r = _grid_state(scene, op, mask0, progress, obs)
        p, mask, delta, status = r.pressure, r.contact, r.penetration, r.status
        u = r.displacement
        msg = r.message
        sc.update(iterations=r.iterations, solves=r.solves,
                  unresolved_patches=r.unresolved_patches,
                  unresolved_front=r.unresolved_front,
                  balanced_fraction=r.balanced_fraction, front_residual=r.residual)
        area = None
        pm = r.mean_pressure
        status, msg = _verify(status, msg, scene, mask)
        fo = front_outputs(op, r, scene.dgamma) if (status == "partial"
                                                    and r.tests is not None) else None
        if fo is not None and not fo["area_fraction"] > 0:
            # the balanced front lies inside the mask by more than the patches hold: their
            # edges recede past each other, so no contact of this mask is in equilibrium
            status, msg = "not_converged", (
                f"the balanced sub-cell front encloses no area (area fraction "
                f"{fo['area_fraction']:.3g} from {int(mask.sum())} contact cells): the "
                f"contact patches are too small for the band a0 = {scene.a0:.3g} m; "
                f"solver: {msg}")
        if status == "partial" and fo is not None:
            area = fo["area_fraction"]
            mu_a = fo["mu_adhesive"]
            if np.isnan(mu_a):  # no net normal force: 0 when G1 = G2, else ±inf (the sign
                # of −∮(G − Δγ)(n·v̂)ds, that of G1 − G2)
                mu_a = quotient(fo["G1"] - fo["G2"], 0.0, abs(fo["G1"]) + abs(fo["G2"]))
            sc.update(G1=fo["G1"], G2=fo["G2"], mu_adhesive=mu_a,
                      front_length=fo["front_length"],
                      crack_tip_length=fo["crack_tip_length"],
                      small_patch_diameter=small_patch_diameter(
                          mask, scene.a0, (cell.hx, cell.hy)))
            fields["G_front"] = fo["G_map"]
        elif status in ("detached", "full_contact"):  # no front (the 1D method's values)
            sc.update(G1=0.0, G2=0.0, mu_adhesive=0.0, front_length=0.0, crack_tip_length=0.0,
                      balanced_fraction=1.0, front_residual=0.0,
                      small_patch_diameter=0.0 if status == "detached" else
                      small_patch_diameter(mask, scene.a0, (cell.hx, cell.hy)))
            if status == "detached":
                p, mask, u = np.zeros(cell.shape), np.zeros(cell.shape, bool), np.zeros(
                    cell.shape)
        else:
            sc.update(G1=np.nan, G2=np.nan, mu_adhesive=np.nan, front_length=np.nan,
                      crack_tip_length=np.nan,
                      small_patch_diameter=np.nan)
        diag = {"a0": r.a0, "edge_shift": r.edge_shift, "method": r.method,
                "history": r.history[-20:]}
    else:
        state = res = _grid_state(scene, op, progress=progress)
        p, mask, delta, u = res.pressure, res.contact, res.penetration, res.displacement
        status = res.status
        msg = res.message
        status, msg = _verify(status, msg, scene, mask)
        sc.update(iterations=res.iterations)
        area, pm = None, float(p.mean())
        diag = {"method": res.method, **res.diagnostics}
    gap = state.gap if p is state.pressure else np.where(
        mask, 0.0, u - (h - float(h.max()) + delta))
    fr = _friction(op, h, p, u, state)
    if scene.adhesive and op.viscoelastic:
        # the force on the profile, at the sub-cell front when it balances: −v̂·∇u's
        # spectral derivative at the mask edge, where the tension is singular, grows with
        # N (docs/theory.md, outputs); elastic: −Σ p v̂·∇u = 0 exactly (C symmetric)
        ff = (front_friction(r, obs) if status == "partial" and r.tests is not None
              else profile_friction(p, obs))
        fr.update(mu=ff["force"], mu_lateral=ff["lateral"])
    sc.update(mean_pressure=pm, penetration=float(delta),
              area_fraction=float(mask.mean()) if area is None else area, **fr)
    status, msg = _undefined(status, msg, sc)
    if scene.fields:
        fields.update(pressure=p, displacement=u, gap=gap, contact=mask.astype(np.int8))
    ds = grid_dataset(cell, sc, status, fields if scene.fields else {})
    forward, inverse = np.subtract(transform_counts(), counted).tolist()
    diag["fft_transforms"] = {"forward": forward, "inverse": inverse}
    ds.attrs.update(solver_message=msg, solver_diagnostics=json.dumps(diag, default=str),
                    velocity_x=float(op.velocity[0]), velocity_y=float(op.velocity[1]))
    return ds, mask


#: an adhesiveless grid solve shows its iterations from this many cells (512²: seconds)
PROGRESS_CELLS = 512 * 512

def _bar_progress(bar):
    """A solve's progress callback (the adhesive front's outer iterations, the contact
    solver's iterations) on a tqdm bar: the text first, then the count
    (so that the line shows the current iteration's text; a repeated count refreshes it).
    A count below the bar's is a new solve on the same bar (a load path's sub-steps): the
    bar's count starts again there."""
    def show(k: int, text: str) -> None:
        bar.set_postfix_str(text, refresh=False)
        if k > bar.n:
            bar.update(k - bar.n)
        else:
            bar.n = k
            bar.refresh()
    return show


def _smoothing(scene) -> dict:
    """The front-smoothing keywords of solve_adhesive: the scene's, else criterion's
    defaults (front_smoothing None: that of the scene's kind, criterion.default_smoothing;
    the schema documents the same numbers, tested)."""
    from .criterion import SMOOTHING_PER_RADIUS

    return {"front_smoothing": scene.solver.get("front_smoothing"),
            "smoothing_per_radius": scene.solver.get("smoothing_per_radius",
                                                     SMOOTHING_PER_RADIUS)}


def _solve_1d(scene: Scene, guess=None):
    """A sinusoid scene through the seed's 1D method (dimensionless, then SI for physical
    scenes)."""
    from . import oned

    phys = scene.kind == "physical"
    d = _dimensionless_groups(scene) if phys else dict(scene.params, k=1.0, amp=1.0, pstar=0.5)
    if not 0.0 <= d["a0_tilde"] <= 1.0:
        raise SceneError(f"adhesion.a0: k a0 = {shown(d['a0_tilde'])} is outside the 1D method's "
                         "range [0, 1]")
    pt = None if scene.mean_pressure is None else scene.mean_pressure / d["pstar"]
    dt = None if scene.penetration is None else scene.penetration / d["amp"]
    ds = oned.solve(d["zeta"], d["beta"], d["Gamma"], p_tilde=pt, delta_tilde=dt,
                          a0_tilde=d["a0_tilde"], guess=guess)
    if not phys:
        return ds
    k, amp, ps = d["k"], d["amp"], d["pstar"]
    dg = scene.dgamma if scene.adhesive else np.nan
    vals = dict(mean_pressure=ds.p_tilde.item() * ps, penetration=ds.delta_tilde.item() * amp,
                area_fraction=ds.a_tilde.item() / np.pi, mu=ds.mu_bar.item() * k * amp,
                mu_adhesive=ds.mu_bar_adhesive.item() * k * amp,
                G1=ds.G1_over_dgamma.item() * dg, G2=ds.G2_over_dgamma.item() * dg,
                contact_half_width=ds.a_tilde.item() / k, eccentricity=ds.e_tilde.item() / k)
    for key, v in vals.items():
        ds[key] = ((), float(v), _attrs(SCALARS[key]))
    ds["pressure"] = (("x",), -ds.sigma_tilde.values * ps,
                      _attrs(FIELDS["pressure"]))
    ds["displacement"] = (("x",), ds.u_tilde.values * amp,
                          _attrs(FIELDS["displacement"]))
    ds = ds.assign_coords(position=("x", ds.x_tilde.values / k,
                                    {"units": "m", "long_name": "position along x"}))
    if scene.velocity[0] < 0:  # the 1D method slides along +x: its fields mirrored in x
        ds = ds.isel(x=slice(None, None, -1))
        ds = ds.assign_coords({c: ("x", -ds[c].values, ds[c].attrs)
                               for c in ("x_tilde", "position")})
    ds.attrs.update({f"dimensionless_{n}": float(d[n]) for n in ("zeta", "beta", "Gamma",
                                                                  "a0_tilde")})
    ds.attrs.update(velocity_x=float(scene.velocity[0]), velocity_y=float(scene.velocity[1]))
    return ds


def _solve_one(scene: Scene, state, progress=None):
    """One control value; ``state`` carries the mask (grid) or edges (1D) between steps;
    ``progress``: the solve's per-iteration callback (solve_adhesive, solve_contact)."""
    if scene.model == "sinusoid1d":
        ds = _solve_1d(scene, guess=state)
        ok = ds.status.item() == "partial"
        return ds, ((ds.attrs["l1_tilde"], ds.attrs["l2_tilde"]) if ok else None)
    if scene.kind == "sinusoid":
        ds = _solve_seed_grid(scene, mask0=state, progress=progress)
        mask = ds.contact.values.astype(bool) if "contact" in ds else None
        # a detached state carries nothing: the next step starts afresh (an empty mask
        # would be 'detached' at once, whatever the load)
        return ds, mask if mask is not None and mask.any() else None
    ds, mask = _solve_grid(scene, mask0=state, progress=progress)
    return ds, (mask if scene.adhesive and mask.any() and not mask.all() else None)


def solve(scene: Scene, *, mask0=None, progress: bool = False):
    """Solve a scene; returns an xarray Dataset.

    Seed scenes use the 1D method's dimensionless names (``a_tilde``, ``e_tilde``,
    ``p_tilde``, ``delta_tilde``, ``mu_bar``, ``mu_bar_adhesive``, ``G1_over_dgamma``,
    ``G2_over_dgamma``, ``status``); physical scenes SI names (``mean_pressure``, ``mu``,
    ``G1``, ...).  A path scene returns a ``step`` dimension.  Attributes: the model that ran,
    the scene (JSON), package version, UTC timestamp, FFT backend and threads, solver message
    and the prescribed control, ``prescribed_mean_pressure`` or ``prescribed_penetration``
    (seed scenes ``prescribed_p_tilde`` or ``prescribed_delta_tilde``; a path: the coordinate
    ``control_value``).  The scalars are what the state carries: a detached state carries no
    load (mean pressure 0 under a tensile prescribed load).
    """
    import xarray as xr

    from . import fft
    from .plausibility import warn

    warn(scene)
    steps = scene.steps
    state = mask0
    out = []
    it, bar, bars = steps, None, []
    try:  # the bars are closed before anything else is printed (Ctrl-C included)
        if progress:
            if len(steps) > 1:
                it = progress_bar(steps, desc="path", unit="step")
                bars.append(it)
            if scene.model == "grid2d" and (scene.adhesive
                                            or scene.cell.shape[0] * scene.cell.shape[1]
                                            >= PROGRESS_CELLS):
                bar = progress_bar(desc="front" if scene.adhesive else "contact", unit="it",
                                   position=int(len(steps) > 1), leave=False)
                bars.append(bar)
        prev = None  # the control value of the last verified partial state
        for v in it:
            if bar is not None:
                bar.reset()
            show = None if bar is None else _bar_progress(bar)
            carried = state
            ds, state = _solve_one(scene.at_step(v), carried, show)
            k = 1
            if needs_substeps(scene, ds, carried, prev, v):
                ds, state, k = substepped(_solve_one, scene, ds, state, carried, prev, v,
                                          show)
            if scene.model == "grid2d" and scene.adhesive:
                ds["substeps"] = ((), k, _attrs(SCALARS["substeps"]))
            prev = v if step_status(ds) == "partial" else None
            out.append(ds)
    except KeyboardInterrupt:
        if len(steps) == 1 or not out:
            raise
        interrupted = True  # the finished steps are returned with the exception (below)
    else:
        interrupted = False
    finally:
        for b in reversed(bars):
            b.close()
    if len(steps) == 1:
        ds = out[0]
        name = scene.control[0] if scene.control else (
            "mean_pressure" if scene.mean_pressure is not None else "penetration")
        v = float(steps[0])
        if scene.kind == "sinusoid":  # the seed's names: p̃ = p/p* (p* = 1/2), Δ̃ = Δ/Λ (Λ = 1)
            name, v = ("p_tilde", v / 0.5) if name == "mean_pressure" else ("delta_tilde", v)
        ds.attrs[f"prescribed_{name}"] = v  # the state's scalars are what it carries
    else:
        name = scene.control[0]
        diagnostics = [d.attrs.pop("solver_diagnostics", None) for d in out]
        for d in out:  # per-step solver messages survive the concatenation as a variable
            msg = d.attrs.get("solver_message", d.attrs.get("message", ""))
            d.attrs.pop("message", None)
            d["solver_message"] = ((), str(msg), {"units": "1",
                                                  "long_name": "solver message of the step"})
        ds = xr.concat(out, dim="step", combine_attrs="drop_conflicts", data_vars="all")
        if any(x is not None for x in diagnostics):
            # each step's diagnostics (the JSON object of a single state), in step order
            ds.attrs["solver_diagnostics"] = json.dumps(
                [None if x is None else json.loads(x) for x in diagnostics])
        vals = np.asarray(scene.control[1], float)[:len(out)]
        if scene.kind == "sinusoid" and name == "mean_pressure":
            name, vals = "p_tilde", vals / 0.5
        ds = ds.assign_coords(step=("step", np.arange(len(out)), {"units": "1",
                                                                 "long_name": "path step"}),
                              control_value=("step", vals, {
                                  "units": "1" if scene.kind == "sinusoid" else (
                                      "Pa" if name == "mean_pressure" else "m"),
                                  "long_name": f"prescribed {name}"}))
    for var in list(ds.variables.values()):
        var.attrs.setdefault("units", "1")
        var.attrs.setdefault("long_name", var.name if hasattr(var, "name") else "")
    ds.attrs.update(
        title=f"spectralbem result: {scene.spec.get('scene', {}).get('name', scene.kind)}",
        model=scene.model, spectralbem_version=__version__,
        created_utc=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        fft_backend=fft.backend(), fft_threads=int(scene.solver["threads"]),
        fft_planner=fft.planner() if fft.backend() == "pyfftw" else "numpy",
        scene=json.dumps(_spec_as_solved(scene), sort_keys=True, default=str),
        **_input_checksums(scene),
        conventions=("spectralbem.conventions: "
                     + ("the seed's dimensionless units (k = Λ = E0* = τ = 1)"
                        if scene.kind == "sinusoid" else "SI units")
                     + "; u into the slab, p compressive positive; seed Fourier convention "
                       "(Im E < 0 for ω > 0)"))
    if interrupted:
        raise PathInterrupted(cf_attributes(ds), len(steps))
    warn(scene, ds)
    return cf_attributes(ds)
