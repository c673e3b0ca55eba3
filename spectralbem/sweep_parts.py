"""The parts folder of a sweep (``OUT.nc.parts``): its lock, its manifest of finished points
with their SHA-256, the removal of stale temporary files, and the checks that decide which
finished points can be kept (:mod:`spectralbem.sweep` runs the points)."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

from .io import _full_disk, probe_netcdf, sha256_file, write_text

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: no output lock
    fcntl = None

#: the driver rewrites the manifest at most this often (s) while points finish
MANIFEST_EVERY = 1.0


class SweepError(RuntimeError):
    """A sweep could not complete; finished points are kept on disk."""


def _say(msg: str, command: str = "sweep") -> None:
    print(f"spectralbem {command}: {msg}", file=sys.stderr, flush=True)


class _Lock:
    """One sweep per output: an exclusive ``flock`` on ``parts/lock`` (released when the
    process ends, whatever the way)."""

    def __init__(self, path: Path, out: Path):
        self.path, self.out, self.fd = path, out, None

    def __enter__(self):
        if fcntl is None:
            return self
        try:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC,
                         0o666)
        except OSError as exc:
            full = _full_disk(exc, self.path, 0, guess=False)
            if full is not None:
                raise full from exc
            raise SweepError(f"cannot open the lock file {str(self.path)!r}: "
                             f"{exc.strerror}") from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            try:
                pid = os.pread(fd, 32, 0).decode(errors="replace").strip()
            except OSError:
                pid = ""
            os.close(fd)
            who = f"another sweep (pid {pid})" if pid.isdigit() else "another sweep"
            raise SweepError(f"{who} is writing {str(self.out)!r} (lock "
                             f"{str(self.path)!r} held): wait for it to finish or choose "
                             "another -o") from exc
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        except OSError:
            pass  # the pid is only for the message of a second sweep
        self.fd = fd
        return self

    def __exit__(self, *exc):
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None


def _clean_temporaries(parts: Path, out: Path) -> int:
    """Remove the temporary files of killed runs (the lock is held: nobody writes them)."""
    def stale_part(name):
        return name == "manifest.tmp" or (name.endswith(".tmp") and name.startswith(
            (".point_", ".manifest.json.")))

    def stale_out(name):
        return name.startswith(f".{out.name}.") and name.endswith(".tmp")

    n = 0
    for folder, stale in ((parts, stale_part), (out.parent, stale_out)):
        try:
            names = os.listdir(folder)
        except OSError:
            continue
        for name in filter(stale, names):
            try:
                os.unlink(folder / name)  # a symlink is removed, never followed
                n += 1
            except OSError:  # a directory, or gone meanwhile
                pass
    return n


class _Manifest:
    """``parts/manifest.json``: the sweep's identity and the SHA-256 of each finished point."""

    def __init__(self, path: Path, head: dict, parts: dict | None = None):
        self.path, self.head = path, head
        self.parts = dict(parts or {})
        self._dirty, self._saved = parts is None, 0.0

    @classmethod
    def open(cls, path: Path, head: dict) -> _Manifest:
        try:
            old = json.loads(path.read_text()) if path.is_file() else None
        except (OSError, ValueError, UnicodeDecodeError):
            old = None  # damaged: rewritten; unrecorded point files are checked one by one
        if not isinstance(old, dict):
            old = None
        if old is not None and old.get("digest") != head["digest"]:
            raise SweepError(f"{str(path.parent)!r} holds the points of a different sweep "
                             f"({_difference(old, head)}); remove it or choose another -o")
        m = cls(path, head, old.get("parts") if old and isinstance(old.get("parts"), dict)
                else None)
        m.save(force=True)
        return m

    def record(self, i: int, sha: str) -> None:
        self.parts[str(i)] = sha
        self._dirty = True

    def forget(self, i: int) -> None:
        if self.parts.pop(str(i), None) is not None:
            self._dirty = True

    def save(self, force: bool = False) -> None:
        if not self._dirty or (not force and time.monotonic() - self._saved < MANIFEST_EVERY):
            return
        write_text(self.path, json.dumps({**self.head, "parts": self.parts}, indent=1))
        self._dirty, self._saved = False, time.monotonic()


def _difference(old: dict, head: dict) -> str:
    """What differs between the sweep of an existing manifest and this one."""
    why = []
    if "version" in old and old["version"] != head["version"]:
        why.append(f"spectralbem {old['version']} → {head['version']}")
    elif "version" not in old:
        why.append("written by an earlier spectralbem")
    oi, ni = old.get("inputs") or {}, head["inputs"]
    for k in sorted(set(oi) | set(ni)):
        if oi.get(k) != ni.get(k) and "version" in old:
            why.append(f"the contents of {k} changed" if k in oi and k in ni
                       else f"{k} {'added' if k in ni else 'removed'}")
    if old.get("keys") != head["keys"] or old.get("values") != head["values"]:
        why.append("other swept keys or values")
    if not why:
        why.append("another scene or other --set values")
    return f"digest {old.get('digest')} ≠ {head['digest']}: " + "; ".join(why)


def _set_aside(path: Path, reason: str, what: str = "point", command: str = "sweep") -> None:
    """Move an unusable point file (a refinement's grid: ``what``, ``command``) out of the
    way, kept for inspection, and say so."""
    target = path.with_name(path.name + ".corrupt")
    k = 1
    while target.exists() or target.is_symlink():
        target = path.with_name(f"{path.name}.corrupt{k}")
        k += 1
    try:
        os.rename(path, target)
        where = f"moved to {target.name}"
    except OSError:
        path.unlink(missing_ok=True)
        where = "removed"
    _say(f"{path} is unusable ({reason}); {where}, the {what} is recomputed", command)


def _check_parts(files: list, manifest: _Manifest, digest: str) -> list:
    """Indices of the points to compute: a point file is kept when its checksum is the one
    recorded, or (not recorded: the driver stopped first) when a child process reads it as a
    complete point of this sweep; any other point file is moved aside."""
    keep, unrecorded = set(), []
    for i, f in enumerate(files):
        present = f.exists() or f.is_symlink()
        sha = manifest.parts.get(str(i))
        if not present:
            manifest.forget(i)
        elif f.is_symlink() or not f.is_file():
            manifest.forget(i)
            _set_aside(f, "not a regular file")
        elif sha is None:
            unrecorded.append(i)
        elif sha256_file(f) == sha:
            keep.add(i)
        else:
            manifest.forget(i)
            _set_aside(f, "its checksum differs from the one recorded when it was written")
    if unrecorded:
        found = probe_netcdf([files[i] for i in unrecorded])
        for i in unrecorded:
            info, err = found[str(files[i])]
            if err is None:
                attrs = info["attrs"]
                if attrs.get("sweep_digest") != digest:
                    err = "written by another sweep"
                elif attrs.get("sweep_index") != i:
                    err = f"it holds point {attrs.get('sweep_index')}, not {i}"
                elif "status" not in info["variables"]:
                    err = "no status variable"
            if err is None:
                manifest.record(i, sha256_file(files[i]))
                keep.add(i)
            else:
                _set_aside(files[i], err)
    manifest.save(force=True)
    return [i for i in range(len(files)) if i not in keep]


