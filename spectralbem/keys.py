"""Scene keys: the declaration of one key of a scene file (:class:`Key`: type, unit, allowed
range, default, meaning) and the magnitude ranges of physical inputs, shared by the schema
(:mod:`spectralbem.schema`) and the kinds each module registers (:mod:`spectralbem.kinds`)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Key", "key", "REQUIRED", "LENGTH", "HEIGHT", "MODULUS", "TIME", "STIFFENING",
           "TOL_MIN", "FRONT_TOL", "front_tol_max", "BAND_TOL_MAX", "DELAYED",
           "DELAYED_DEFAULT", "LOAD_TOL"]

class _Required:
    """The default of a required key (a sentinel with a stable name)."""

    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED = _Required()


@dataclass(frozen=True)
class Key:
    """One scene key: its type, unit, allowed range or choices, default and meaning."""

    type: str  # number | integer | string | boolean | numbers | number_or_numbers | path
    doc: str
    units: str = ""
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False  # lo itself is excluded
    choices: tuple = ()
    default: object = REQUIRED
    tiny: float | None = None  # smallest magnitude allowed besides 0 (None: no floor)
    hi_open: bool = False  # hi itself is excluded

    def range_text(self) -> str:
        if self.choices:
            return "one of " + ", ".join(str(c) for c in self.choices)
        if self.lo is None and self.hi is None:
            return "any finite value" if self.type.startswith("number") else ""
        lo = "-inf" if self.lo is None else f"{self.lo:g}"
        hi = "inf" if self.hi is None else f"{self.hi:g}"
        if self.tiny is not None:  # 0, or a magnitude in [tiny, ...]
            t = f"{self.tiny:g}"
            if self.lo is not None and self.lo < 0:
                return f"0 or ±[{t}, {hi}]" if -self.lo == self.hi else (
                    f"[{lo}, -{t}], 0 or [{t}, {hi}]")
            return f"0 or [{t}, {hi}]"
        return f"{'(' if self.lo_open else '['}{lo}, {hi}{')' if self.hi_open else ']'}"

    def allows(self, x: float) -> bool:
        """Whether the finite number ``x`` lies in the allowed range."""
        if (self.lo is not None and (x <= self.lo if self.lo_open else x < self.lo)) or (
                self.hi is not None and (x >= self.hi if self.hi_open else x > self.hi)):
            return False
        return self.tiny is None or x == 0 or abs(x) >= self.tiny


def key(type_, doc, units="", lo=None, hi=None, lo_open=False, choices=(), default=REQUIRED,
       tiny=None, hi_open=False):
    return Key(type_, doc, units, lo, hi, lo_open, tuple(choices), default, tiny, hi_open)


#: magnitude ranges of physical inputs (SI): wide enough for any continuum contact problem,
#: narrow enough that no product or quotient of them over- or underflows a double (values
#: such as 5e-324 or 1e308 gave "float division by zero", "Numerical result out of range" or
#: a singular matrix deep inside a solve)
LENGTH = (1e-9, 1e3)  # m: cell sizes, wavelengths, radii
HEIGHT = (1e-12, 1e3)  # m: amplitudes, rms heights, layer thicknesses
MODULUS = (1.0, 1e13)  # Pa
TIME = (1e-12, 1e12)  # s
#: the largest ratio E∞/E0 (the seed's β range): the kernel then spans 8 decades
STIFFENING = 1e8
#: the smallest relative tolerance of the solves that double precision can reach
TOL_MIN = 1e-14

#: default tolerance of the adhesive front's balance in position (cells): a resolved front
#: point is balanced when its balanced edge lies within ½ h + front_tol·h of the mask edge,
#: one cell by default (the resolution of the mask); larger values, up to
#: :func:`front_tol_max`, converge faster where a0 spans many cells and cost accuracy in G
#: (docs/theory.md, the 2D criterion, "Convergence")
FRONT_TOL = 0.5

#: load control of a 2D adhesive solve: the sub-cell front carries the prescribed mean
#: pressure within this fraction of the mean |p| (the mask state carries it minus the
#: front's correction); a carried load within it of zero is no net normal force
LOAD_TOL = 1e-6

#: the loosest ``solver.band_tol`` (the band tests' tolerance while the front moves): at 1e-4
#: the rough elastic loading state at 256² reached another balanced state (area +1.4 %, 79
#: front iterations against 37), at 1e-5 the same one (docs/performance.md)
BAND_TOL_MAX = 1e-5


#: the discretisations of a viscoelastic kernel's delayed part (solver.delayed_kernel,
#: SpectralOperator ``delayed``; docs/theory.md, "The viscoelastic kernel on the grid"), the
#: default first: averaged over the cells, which resolves the relaxation length vτ from
#: two cells on (docs/performance.md, "Resolving the relaxation length")
DELAYED = ("cell", "sampled")
DELAYED_DEFAULT = DELAYED[0]


#: ``solver.extrapolate_a0`` needs a0 of at least this many cells (the a0/2 bands hold one)
EXTRAPOLATE_MIN_CELLS = 2.0


def extrapolable(a0_cells: float) -> bool:
    """Whether an a0 of ``a0_cells`` cells can be extrapolated to a0 → 0 (adhesive)."""
    return a0_cells >= EXTRAPOLATE_MIN_CELLS * (1 - 1e-9)


def front_tol_max(a0_cells: float) -> float:
    """The largest front_tol (cells) for a band of a0 = ``a0_cells`` cells: the edge stays
    within half the band (at least :data:`FRONT_TOL`)."""
    return max(FRONT_TOL, 0.5 * a0_cells)
