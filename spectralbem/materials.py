"""Linear (visco)elastic materials: the complex modulus E(ω) in the seed's Fourier convention.

Convention (stated once, see also :mod:`spectralbem.conventions`): the Fourier transform is
``f(q, ω) = ∫ dt d²x f e^{-i(q·x - ωt)}`` (seed Eq. A.7), so the time kernel is ``e^{+iωt}``.
With it a passive material has ``Im E(ω) < 0`` and ``Im[1/E(ω)] > 0`` for ω > 0 — the complex
conjugate of the engineering convention ``E' + iE''``.  ``E(-ω) = conj E(ω)``.

Every material exposes

* ``modulus(omega)``: E(ω) for an array of angular frequencies (rad/s), complex128;
* ``compliance(omega)``: 1/E(ω);
* ``E0`` (relaxed, ω → 0) and ``Einf`` (glassy, ω → ∞) moduli, ``nu`` (Poisson ratio);
* ``is_elastic``: True when E does not depend on ω (an elastic scene never builds the
  viscoelastic kernel).

Units: moduli in Pa (any consistent unit works: the solver is linear), times in s.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .conventions import shown

__all__ = ["Material", "Elastic", "StandardLinearSolid", "Prony", "Tabulated", "MaterialError"]


class MaterialError(ValueError):
    """Invalid material parameter (names the parameter, its value and the allowed range)."""


def _check_nu(nu: float) -> float:
    nu = float(nu)
    if not np.isfinite(nu) or not (-1.0 < nu <= 0.5):
        raise MaterialError(f"nu = {shown(nu)} is outside the allowed range (-1, 0.5]")
    return nu


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise MaterialError(f"{name} = {shown(value)} must be a finite number > 0")
    return value


class Material:
    """Base class.  Subclasses implement :meth:`modulus`."""

    nu: float
    E0: float
    Einf: float
    is_elastic: bool = False

    def modulus(self, omega) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def compliance(self, omega) -> np.ndarray:
        """1/E(ω) (1/Pa), complex128."""
        return 1.0 / self.modulus(omega)

    @property
    def beta(self) -> float:
        """β = E∞/E0 (seed Section 4)."""
        return self.Einf / self.E0

    def reduced(self, E: float) -> float:
        """E* = E/(1-ν²), the plane-strain modulus of a rigid-on-elastic contact."""
        return E / (1.0 - self.nu**2)


@dataclass(frozen=True)
class Elastic(Material):
    """Linear elastic solid: E(ω) = E for every ω."""

    E: float
    nu: float = 0.5
    is_elastic: bool = field(default=True, init=False)

    def __post_init__(self):
        object.__setattr__(self, "E", _check_positive("E", self.E))
        object.__setattr__(self, "nu", _check_nu(self.nu))

    @property
    def E0(self) -> float:  # type: ignore[override]
        return self.E

    @property
    def Einf(self) -> float:  # type: ignore[override]
        return self.E

    def modulus(self, omega) -> np.ndarray:
        return np.full(np.shape(omega), self.E, dtype=np.complex128)


@dataclass(frozen=True)
class StandardLinearSolid(Material):
    """Standard linear solid with one retardation (creep) time τ, seed Eq. (14).

    ``J(t) = H(t) [1/E0 - (1/E0 - 1/E∞) exp(-t/τ)]`` gives, with the ``e^{+iωt}`` kernel,
    ``1/E(ω) = 1/E∞ + (1/E0 - 1/E∞)/(1 - iωτ)`` and ``E(ω) = E0 (1 - iωτ)/(1 - iωτ/β)``.
    The relaxation time is τ/β.  In steady sliding on a sinusoid, ζ = k v τ.
    """

    E0: float
    Einf: float
    tau: float
    nu: float = 0.5

    def __post_init__(self):
        object.__setattr__(self, "E0", _check_positive("E0", self.E0))
        object.__setattr__(self, "Einf", _check_positive("Einf", self.Einf))
        object.__setattr__(self, "tau", _check_positive("tau", self.tau))
        object.__setattr__(self, "nu", _check_nu(self.nu))
        if self.Einf < self.E0:
            raise MaterialError(
                f"Einf = {shown(self.Einf)} must be >= E0 = {shown(self.E0)} (glassy modulus is "
                "the larger)"
            )

    @property
    def is_elastic(self) -> bool:  # type: ignore[override]
        return self.Einf == self.E0

    def creep(self, t) -> np.ndarray:
        """Creep function J(t) of Eq. (14) (1/Pa)."""
        t = np.asarray(t, dtype=float)
        j = 1.0 / self.E0 - (1.0 / self.E0 - 1.0 / self.Einf) * np.exp(-np.maximum(t, 0) / self.tau)
        return np.where(t >= 0, j, 0.0)

    def compliance(self, omega) -> np.ndarray:
        w = np.asarray(omega, dtype=float)
        return 1.0 / self.Einf + (1.0 / self.E0 - 1.0 / self.Einf) / (1.0 - 1j * w * self.tau)

    def modulus(self, omega) -> np.ndarray:
        w = np.asarray(omega, dtype=float)
        return self.E0 * (1.0 - 1j * w * self.tau) / (1.0 - 1j * w * self.tau / self.beta)


@dataclass(frozen=True)
class Prony(Material):
    """Generalised Maxwell model (Prony series of the relaxation modulus).

    ``E(t) = E_eq + Σ_k E_k exp(-t/τ_k)`` gives ``E(ω) = E_eq + Σ_k E_k (-iωτ_k)/(1 - iωτ_k)``
    in the seed's convention.  E0 = E_eq, E∞ = E_eq + Σ E_k.  With one branch,
    E_1 = E∞ - E0 and τ_1 = τ/β it is the :class:`StandardLinearSolid`.
    """

    E_eq: float
    moduli: tuple
    times: tuple
    nu: float = 0.5

    def __post_init__(self):
        object.__setattr__(self, "E_eq", _check_positive("E_eq", self.E_eq))
        mods = tuple(float(m) for m in np.atleast_1d(self.moduli))
        times = tuple(float(t) for t in np.atleast_1d(self.times))
        if len(mods) != len(times):
            raise MaterialError(
                f"moduli has {len(mods)} entries but times has {len(times)}: they must match"
            )
        for i, (m, t) in enumerate(zip(mods, times, strict=True)):
            _check_positive(f"moduli[{i}]", m)
            _check_positive(f"times[{i}]", t)
        object.__setattr__(self, "moduli", mods)
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "nu", _check_nu(self.nu))

    @property
    def E0(self) -> float:  # type: ignore[override]
        return self.E_eq

    @property
    def Einf(self) -> float:  # type: ignore[override]
        return self.E_eq + sum(self.moduli)

    @property
    def is_elastic(self) -> bool:  # type: ignore[override]
        return len(self.moduli) == 0

    def modulus(self, omega) -> np.ndarray:
        w = np.asarray(omega, dtype=float)
        E = np.full(w.shape, self.E_eq, dtype=np.complex128)
        for Ek, tk in zip(self.moduli, self.times, strict=True):
            x = -1j * w * tk
            E += Ek * x / (1.0 + x)
        return E


#: relative drop of a tabulated storage modulus below its running maximum accepted as
#: measurement scatter (DMA tables scatter by ~0.5-1 %); larger drops are non-causal
STORAGE_NOISE = 0.02


@dataclass(frozen=True)
class Tabulated(Material):
    """Measured complex modulus, interpolated log-log.

    The table holds ω (rad/s, strictly increasing, > 0), storage E'(ω) > 0 (non-decreasing: a
    passive material stiffens with frequency; scatter within STORAGE_NOISE is accepted) and
    loss E''(ω) >= 0 in the **engineering** convention in which DMA data are published.
    Internally ``E(ω) = E' - iE''`` (seed convention).  Outside the table E' is held
    constant and E'' follows the causal asymptotes of a solid: E'' ∝ ω below the first point
    and E'' ∝ 1/ω above the last.
    """

    omega: tuple
    storage: tuple
    loss: tuple
    nu: float = 0.5

    def __post_init__(self):
        w = np.asarray(self.omega, dtype=float)
        s = np.asarray(self.storage, dtype=float)
        l_ = np.asarray(self.loss, dtype=float)
        if w.ndim != 1 or w.size < 2:
            raise MaterialError(f"omega must be a 1D table of >= 2 rows, got shape {w.shape}")
        if s.shape != w.shape or l_.shape != w.shape:
            raise MaterialError(
                f"storage {s.shape} and loss {l_.shape} must have the shape of omega {w.shape}"
            )
        for name, arr in (("omega", w), ("storage", s), ("loss", l_)):
            if not np.all(np.isfinite(arr)):
                raise MaterialError(f"{name} contains NaN or inf; all entries must be finite")
        if np.any(w <= 0):
            raise MaterialError(f"omega min = {shown(w.min())}: frequencies must be > 0")
        if np.any(np.diff(w) <= 0):
            i = int(np.argmax(np.diff(w) <= 0))
            raise MaterialError(
                f"omega is not strictly increasing at row {i + 1} ({shown(w[i])} -> "
                f"{shown(w[i + 1])})"
            )
        if np.any(s <= 0):
            raise MaterialError(f"storage min = {shown(s.min())}: storage modulus must be > 0")
        peak = np.maximum.accumulate(s)
        drop = s[1:] < (1.0 - STORAGE_NOISE) * peak[:-1]
        if np.any(drop):  # measured tables scatter: drops within STORAGE_NOISE are kept
            i = int(np.argmax(drop))
            raise MaterialError(
                f"storage decreases at row {i + 2} ({shown(s[i + 1])} after a maximum of "
                f"{shown(peak[i])}, {1 - s[i + 1] / peak[i]:.1%} lower): a passive, causal "
                f"material has a non-decreasing storage modulus (measurement scatter up to "
                f"{STORAGE_NOISE:.0%} is accepted)"
            )
        if np.any(l_ < 0):
            raise MaterialError(
                f"loss min = {shown(l_.min())}: a negative loss modulus is non-causal (active); "
                "the allowed range is >= 0 (engineering convention)"
            )
        object.__setattr__(self, "omega", tuple(w))
        object.__setattr__(self, "storage", tuple(s))
        object.__setattr__(self, "loss", tuple(l_))
        object.__setattr__(self, "nu", _check_nu(self.nu))

    @classmethod
    def from_csv(cls, path, nu: float = 0.5) -> "Tabulated":
        """Load a CSV with columns ``omega, storage, loss`` (a header row is optional)."""
        path = Path(path)
        try:
            with path.open(newline="") as fh:
                rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
        except OSError as exc:
            raise MaterialError(f"cannot read modulus table {str(path)!r}: {exc}") from exc
        try:
            float(rows[0][0])
        except (ValueError, IndexError):
            rows = rows[1:]
        try:
            data = np.array([[float(x) for x in r[:3]] for r in rows])
        except ValueError as exc:
            raise MaterialError(
                f"modulus table {str(path)!r} has a non-numeric entry: {exc}") from exc
        if data.ndim != 2 or data.shape[1] != 3:
            raise MaterialError(
                f"modulus table {str(path)!r} must have 3 columns (omega, storage, loss)"
            )
        return cls(tuple(data[:, 0]), tuple(data[:, 1]), tuple(data[:, 2]), nu=nu)

    @property
    def E0(self) -> float:  # type: ignore[override]
        return self.storage[0]

    @property
    def Einf(self) -> float:  # type: ignore[override]
        return self.storage[-1]

    def modulus(self, omega) -> np.ndarray:
        w = np.abs(np.asarray(omega, dtype=float))
        lw = np.log(np.asarray(self.omega))
        s = np.asarray(self.storage)
        l_ = np.asarray(self.loss)
        # ω = 0 (the modes that do not slide, q·v = 0) is the relaxed plateau below the table:
        # the first row (it was read at 1 rad/s, E' there: 5× too stiff on a table spanning it)
        x = np.log(np.where(w > 0, w, self.omega[0]))
        Es = np.exp(np.interp(x, lw, np.log(s)))
        pos = l_ > 0
        if np.all(pos):
            El = np.exp(np.interp(x, lw, np.log(l_)))
        else:  # zero losses in the table: interpolate linearly in E'' over log ω
            El = np.interp(x, lw, l_)
        lo, hi = w < self.omega[0], w > self.omega[-1]
        El = np.where(lo, l_[0] * w / self.omega[0], El)
        El = np.where(hi, l_[-1] * self.omega[-1] / np.where(hi, w, 1.0), El)
        El = np.where(w == 0, 0.0, El)
        sign = np.sign(np.asarray(omega, dtype=float))
        return Es - 1j * sign * El


# -- scene kinds ([material] kind = ...): spectralbem.kinds -----------------------------------
def _check_sls(m: dict, grid: dict, problems: list) -> None:
    from .keys import STIFFENING

    if m.get("E0") and m.get("Einf"):
        if m["Einf"] < m["E0"]:
            problems.append(f"material.Einf: {shown(m['Einf'])} Pa is below material.E0 = "
                            f"{shown(m['E0'])} Pa; allowed [E0, inf)")
        elif m["Einf"] > STIFFENING * m["E0"]:
            problems.append(f"material.Einf: {shown(m['Einf'])} Pa is more than {STIFFENING:g} "
                            f"times material.E0 = {shown(m['E0'])} Pa; allowed [E0, "
                            f"{STIFFENING * m['E0']:g}] Pa")


def _check_prony(m: dict, grid: dict, problems: list) -> None:
    from .keys import STIFFENING

    if m.get("moduli") and m.get("times"):
        if len(m["moduli"]) != len(m["times"]):
            problems.append(f"material.times: {len(m['times'])} entries but material.moduli "
                            f"has {len(m['moduli'])}; they must match")
        if m.get("E_eq") and sum(m["moduli"]) > (STIFFENING - 1) * m["E_eq"]:
            problems.append(f"material.moduli: their sum {sum(m['moduli']):g} Pa is more than "
                            f"{STIFFENING:g} times material.E_eq = {shown(m['E_eq'])} Pa; allowed "
                            f"a sum in (0, {(STIFFENING - 1) * m['E_eq']:g}] Pa")


def _build_tabulated(m: dict, context) -> Tabulated | None:
    """The modulus table of ``material.path`` (problems go to ``context.problems``)."""
    from .keys import MODULUS
    from .schema import short
    from .surfaces import MIN_FILE_LIMIT, SurfaceError, check_input_file

    problems = context.problems
    try:
        path = check_input_file(context.base / m["path"], "modulus table", MIN_FILE_LIMIT)
        table = Tabulated.from_csv(path, nu=m["nu"])
    except SurfaceError as exc:
        problems.append(f"material.path: {exc}")
        return None
    except MaterialError as exc:
        problems.append(f"material: {str(exc)[:300]}")
        return None
    except (ValueError, RecursionError) as exc:  # e.g. not UTF-8 text
        problems.append(f"material.path: cannot read modulus table {short(m['path'])}: "
                        f"{str(exc)[:200]}")
        return None
    lo, hi = MODULUS
    moduli = np.abs(np.concatenate([table.storage, table.loss]))
    if table.storage[0] < lo or moduli.max() > hi:
        problems.append(f"material.path: the moduli of {short(m['path'])} span "
                        f"[{min(table.storage):g}, {moduli.max():g}] Pa; allowed E' in "
                        f"[{lo:g}, {hi:g}] Pa and |E''| ≤ {hi:g} Pa")
        return None
    return table


def _register() -> None:
    from .keys import MODULUS, TIME, key
    from .kinds import register

    def nu():
        return key("number", "Poisson's ratio", "", -1, 0.5, True, default=0.5)

    register("material", "elastic",
             {"E": key("number", "Young's modulus", "Pa", *MODULUS), "nu": nu()},
             lambda m, context: Elastic(m["E"], m["nu"]))
    register("material", "sls",
             {"E0": key("number", "relaxed (low-frequency) modulus E0", "Pa", *MODULUS),
              "Einf": key("number", "glassy (high-frequency) modulus E∞, in [E0, 1e8 E0]", "Pa",
                          *MODULUS),
              "tau": key("number", "retardation (creep) time τ of the creep function, "
                         "Eq. (14); the relaxation time is τ/β = τ E0/E∞", "s", *TIME),
              "nu": nu()},
             lambda m, context: StandardLinearSolid(m["E0"], m["Einf"], m["tau"], m["nu"]),
             _check_sls)
    register("material", "prony",
             {"E_eq": key("number", "equilibrium modulus (= E0)", "Pa", *MODULUS),
              "moduli": key("numbers", "branch moduli E_k (E_eq + Σ E_k at most 1e8 E_eq)",
                            "Pa", *MODULUS),
              "times": key("numbers", "branch relaxation times τ_k", "s", *TIME),
              "nu": nu()},
             lambda m, context: Prony(m["E_eq"], tuple(m["moduli"]), tuple(m["times"]),
                                      m["nu"]),
             _check_prony)
    register("material", "tabulated",
             {"path": key("path", "CSV with columns ω (rad/s), E' (Pa), E'' (Pa, engineering "
                          "sign); a regular file of at most 64 MiB"),
              "nu": nu()},
             _build_tabulated)


_register()
