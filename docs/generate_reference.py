"""Refresh the scene reference of docs/user_guide.md from the schema.

Usage: python docs/generate_reference.py  (``make docs``).  Everything after the
``<!-- scene-reference -->`` marker is replaced by :func:`reference_markdown`, the tables of
spectralbem.schema; tests/test_scenes.py checks that the committed guide is current.
"""

from pathlib import Path

from spectralbem.schema import KIND_DEFAULTS, KINDS, REQUIRED, SECTIONS
from spectralbem.units import PINT_UNITS

MARKER = "<!-- scene-reference -->"


def reference_markdown() -> str:
    """The scene reference (docs/user_guide.md), generated from the schema."""
    lines = ["A number is in the key's SI unit (the units column). Keys in "
             + ", ".join(f"`{u}`" for u in PINT_UNITS)
             + " also take a quantity with a unit, written as a string and read by pint: "
             '`E0 = "2 MPa"`, `cutoff_wavelength = "62.5 um"`, `speed = "4 mm/s"` (on the '
             'command line `--set material.E0="2 MPa"`); it is stored in SI, so the '
             "dataset's `scene` attribute holds the SI number.", ""]

    def table(title, spec):
        lines.append(title)
        lines.append("")
        lines.append("| key | type | units | allowed | default | meaning |")
        lines.append("|---|---|---|---|---|---|")
        for key, k in spec.items():
            d = "required" if k.default is REQUIRED else repr(k.default)
            lines.append(f"| `{key}` | {k.type} | {k.units or '–'} | {k.range_text() or '–'} "
                         f"| {d} | {k.doc} |")
        lines.append("")

    for sec, spec in SECTIONS.items():
        table(f"### `[{sec}]`", spec)
    for sec, kinds in KINDS.items():
        default = KIND_DEFAULTS.get(sec)
        lines.append(f"### `[{sec}]` — `kind` = {', '.join(repr(k) for k in kinds)}"
                     + (f" (default {default!r})" if default else " (required)"))
        lines.append("")
        for kind, spec in kinds.items():
            if spec:
                table(f"#### `{sec}.kind = {kind!r}`", spec)
            else:
                lines.append(f"#### `{sec}.kind = {kind!r}`: no further keys")
                lines.append("")
    return "\n".join(lines)


def write_reference(path: Path) -> None:
    text = path.read_text()
    if MARKER not in text:
        raise SystemExit(f"{path} has no {MARKER} marker")
    path.write_text(text.split(MARKER)[0] + MARKER + "\n" + reference_markdown() + "\n")


if __name__ == "__main__":
    write_reference(Path(__file__).resolve().parent / "user_guide.md")
