"""Job folders: a long run's results written as they come, so that a killed run resumes where it stopped.

A job folder holds ``job.json`` (what kind of job, and the settings its
files depend on), the finished results, and in ``parts/`` the partitions of
the stage under way. Every file is written atomically (a temporary file
renamed over it), so a run killed at any moment leaves only whole files
(and perhaps a hidden temporary, removed when the folder is opened again);
rerun with the same folder, the job loads what is there and computes the
rest. A folder made for another kind of job, or other settings, is refused
with a message rather than mixed.

``job.json`` also lists every file the job wrote with its size and SHA-256.
A file that is not listed (planted, or copied from elsewhere) or whose
checksum differs (cut short, a line doubled, damaged) is never believed:
``load`` names it (``say``) and answers None, so the job computes it again.
Files hold data read by parsers (graph6, numpy arrays without objects),
never code.

It is the store the chain atlas checkpoints to
(:class:`~domes.typesynth.atlas.ChainGenerator`'s ``checkpoints``): ``load``,
``save`` and ``discard`` by name.

>>> import tempfile
>>> job = JobFolder(tempfile.mkdtemp() + "/atlas", {"kind": "chain atlas", "isomorphism": "nauty"})
>>> job.save("parts/a.bin", b"x"); job.load("parts/a.bin"), job.load("parts/b.bin")
(b'x', None)
>>> job.discard("parts/"); job.load("parts/a.bin") is None
True
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Callable

from domes.errors import InputError
from domes.io.files import missing_folder, why_not_made, write_atomic

#: The version of the job-folder layout; a folder of another version is refused.
VERSION = 2


class JobFolder:
    """A folder of one job's files (see the module's doc); made, or checked against ``spec``, on opening."""

    def __init__(self, path: str | Path, spec: dict, say: Callable[[str], None] | None = None):
        self.path = Path(path)
        self.spec = {**spec, "version": VERSION}
        self.say = say
        self.files: dict[str, dict] = {}
        self.refused: list[str] = []
        if self.path.exists() and not self.path.is_dir():
            raise InputError(f"{self.path}: is a file; a job's output folder is needed")
        if why := missing_folder(self.path.parent):
            raise InputError(f"cannot make the job folder {self.path}: {why}")
        marker = self.path / "job.json"
        if marker.exists():
            found, self.files = _read_marker(marker)
            if found != self.spec:
                raise InputError(f"{self.path} holds another job ({_describe(found)}), not this one "
                                 f"({_describe(self.spec)}); use another folder")
        else:
            if self.path.is_dir() and any(self.path.iterdir()):
                raise InputError(f"{self.path} is not empty and holds no job.json; use a new or empty folder")
            self._make(self.path)
            self._write_marker()
        self._make(self.path / "parts")
        self._sweep()

    def _sweep(self) -> None:
        """Remove the temporary files a killed run left half written (``.name.<random>.tmp``, see
        :func:`~domes.io.files.write_atomic`): never read, they would only make the folder differ."""
        for folder in (self.path, self.path / "parts"):
            for tmp in folder.glob(".*.tmp"):
                if tmp.is_file():
                    tmp.unlink()
                    if self.say is not None:
                        self.say(f"{tmp}: a file a killed run left half written, removed")

    def _write_marker(self) -> None:
        text = json.dumps({"job": self.spec, "files": self.files}, indent=1, sort_keys=True) + "\n"
        write_atomic(self.path / "job.json", text)

    def _make(self, folder: Path) -> None:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"cannot make the job folder {self.path}: {why_not_made(folder, exc)}") from None

    def _file(self, name: str) -> Path:
        if name.startswith(("/", ".")) or ".." in Path(name).parts:
            raise InputError(f"job file names stay inside the job folder, got {name!r}")
        return self.path / name

    def load(self, name: str) -> bytes | None:
        """The file ``name`` in the folder as the job wrote it; None if it was not written (yet), or if it is not
        the file the job wrote (then it is named, see the module's doc, and left to be written again)."""
        try:
            data = self._file(name).read_bytes()
        except FileNotFoundError:
            return None
        except OSError as exc:
            return self.refuse(name, f"cannot be read ({exc.strerror})")
        listed = self.files.get(name)
        if listed is None:
            return self.refuse(name, "was not written by this job (it is not listed in job.json)")
        if listed != _stamp(data):
            return self.refuse(name, f"is damaged: {len(data):,} bytes with another checksum than the "
                                      f"{listed.get('bytes', 0):,} bytes written")
        return data

    def refuse(self, name: str, why: str) -> None:
        """Say that the file ``name`` is not used, and why (it will be written again)."""
        self.refused.append(name)
        if self.say is not None:
            self.say(f"{self.path / name} {why}: not used, computed again")
        return None

    def save(self, name: str, data: bytes) -> None:
        """Write the file ``name`` (atomically), and list it with its checksum."""
        write_atomic(self._file(name), data)
        self.files[name] = _stamp(data)
        self._write_marker()

    def discard(self, prefix: str) -> None:
        """Remove the files whose names start with ``prefix`` (the partitions of a finished stage)."""
        self._file(prefix)
        head, _, stem = prefix.rpartition("/")
        folder = self.path / head
        for file in folder.glob(f"{stem}*"):
            if file.is_file():
                file.unlink()
        gone = [name for name in self.files if name.startswith(prefix)]
        for name in gone:
            del self.files[name]
        if gone:
            self._write_marker()

    def __repr__(self) -> str:
        return f"<JobFolder {self.path}: {_describe(self.spec)}>"


def _stamp(data: bytes) -> dict:
    return {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}


def _read_marker(marker: Path) -> tuple[dict, dict]:
    """The job spec and the files listed in ``job.json``."""
    try:
        found = json.loads(marker.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(f"{marker}: not a readable job file ({str(exc)[:200]}); use another folder") from None
    if isinstance(found, dict) and "version" in found and "job" not in found:
        raise InputError(f"{marker.parent} was written by an older DOMES-py (job folder layout {found['version']}, "
                         f"now {VERSION}), whose files are not checked; use another folder")
    job, files = (found.get("job"), found.get("files")) if isinstance(found, dict) else (None, None)
    if not isinstance(job, dict) or not isinstance(files, dict) or not all(
            isinstance(v, dict) and set(v) == {"bytes", "sha256"} for v in files.values()):
        raise InputError(f"{marker}: not a job file of DOMES-py (it needs 'job' and 'files'); use another folder")
    return job, files


def _describe(spec: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in sorted(spec.items()))


__all__ = ["JobFolder", "VERSION"]
