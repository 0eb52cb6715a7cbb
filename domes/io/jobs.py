"""Job folders: a long run's results written as they come, so that a killed run resumes where it stopped.

A job folder holds ``job.json`` (what kind of job, and the settings its
files depend on), the finished results, and in ``parts/`` the partitions of
the stage under way. Every file is written atomically (a temporary file
renamed over it), so a run killed at any moment leaves only whole files;
rerun with the same folder, the job loads what is there and computes the
rest. A folder made for another kind of job, or other settings, is refused
with a message rather than mixed.

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

import json
from pathlib import Path

from domes.errors import InputError
from domes.io.files import write_atomic

#: The version of the job-folder layout; a folder of another version is refused.
VERSION = 1


class JobFolder:
    """A folder of one job's files (see the module's doc); made, or checked against ``spec``, on opening."""

    def __init__(self, path: str | Path, spec: dict):
        self.path = Path(path)
        self.spec = {**spec, "version": VERSION}
        if self.path.exists() and not self.path.is_dir():
            raise InputError(f"{self.path}: is a file; a job's output folder is needed")
        if not self.path.parent.is_dir():
            raise InputError(f"cannot make the job folder {self.path}: folder {self.path.parent} does not exist")
        marker = self.path / "job.json"
        if marker.exists():
            try:
                found = json.loads(marker.read_text(encoding="utf-8"))
            except (OSError, ValueError) as exc:
                raise InputError(f"{marker}: not a readable job file ({exc}); use another folder") from None
            if found != self.spec:
                raise InputError(f"{self.path} holds another job ({_describe(found)}), not this one "
                                 f"({_describe(self.spec)}); use another folder")
        else:
            if self.path.is_dir() and any(self.path.iterdir()):
                raise InputError(f"{self.path} is not empty and holds no job.json; use a new or empty folder")
            (self.path / "parts").mkdir(parents=True, exist_ok=True)
            write_atomic(marker, json.dumps(self.spec, indent=1, sort_keys=True) + "\n")
        (self.path / "parts").mkdir(exist_ok=True)

    def _file(self, name: str) -> Path:
        if name.startswith(("/", ".")) or ".." in Path(name).parts:
            raise InputError(f"job file names stay inside the job folder, got {name!r}")
        return self.path / name

    def load(self, name: str) -> bytes | None:
        """The file ``name`` in the folder, or None if it was not written (yet)."""
        try:
            return self._file(name).read_bytes()
        except FileNotFoundError:
            return None

    def save(self, name: str, data: bytes) -> None:
        """Write the file ``name`` (atomically)."""
        write_atomic(self._file(name), data)

    def discard(self, prefix: str) -> None:
        """Remove the files whose names start with ``prefix`` (the partitions of a finished stage)."""
        self._file(prefix)
        head, _, stem = prefix.rpartition("/")
        folder = self.path / head
        for file in folder.glob(f"{stem}*"):
            if file.is_file():
                file.unlink()

    def __repr__(self) -> str:
        return f"<JobFolder {self.path}: {_describe(self.spec)}>"


def _describe(spec: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in sorted(spec.items()))


__all__ = ["JobFolder", "VERSION"]
