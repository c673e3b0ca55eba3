"""Refresh the scene reference of docs/user_guide.md from the schema.

Usage: python docs/generate_reference.py  (``make docs``).  Everything after the
``<!-- scene-reference -->`` marker is replaced by :func:`spectralbem.schema.reference_markdown`;
tests/test_scenes.py checks that the committed guide is current.
"""

from pathlib import Path

from spectralbem.schema import reference_markdown

MARKER = "<!-- scene-reference -->"


def write_reference(path: Path) -> None:
    text = path.read_text()
    if MARKER not in text:
        raise SystemExit(f"{path} has no {MARKER} marker")
    path.write_text(text.split(MARKER)[0] + MARKER + "\n" + reference_markdown() + "\n")


if __name__ == "__main__":
    write_reference(Path(__file__).resolve().parent / "user_guide.md")
