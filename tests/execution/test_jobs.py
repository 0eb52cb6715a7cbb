"""Job folders: results written as they come, and a killed run resumed to the same files (issue 17).

The chain atlas is the job: every finished atlas goes to the folder as
graph6, the slices of the level under way as they come. A run stopped
after some slices (by an error in the store, or by SIGKILL from outside)
and run again with the same folder must leave the files an uninterrupted
run leaves, byte for byte.

The runs in this process build the 11-link DOF-2 atlas (a second) with levels of 16 parents and more cut into
slices (the product cuts levels of PARALLEL_PARENTS = 256 and more, first met at 12 links): what is written,
dropped and loaded again does not depend on the size. The killed command runs the 12-link atlas, sliced as it
ships.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from domes.errors import InputError
from domes.io.jobs import JobFolder
from domes.typesynth.atlas import ChainGenerator, chains
from tests.typesynth.reference import chain_atlas

DOMES = [sys.executable, "-m", "domes"]
SPEC = {"kind": "chain atlas", "isomorphism": "nauty"}
#: The atlas the runs in this process build, and its levels' name.
LINKS, DOF = 11, 2
NAME = f"chains-n{LINKS}-F{DOF}"


@pytest.fixture
def sliced(monkeypatch):
    """Levels of 16 parents or more are cut into slices (each level of the 11-link DOF-2 atlas, k = 0 to 3)."""
    monkeypatch.setattr("domes.typesynth.atlas.PARALLEL_PARENTS", 16)


class Stop(Exception):
    pass


class FailingFolder(JobFolder):
    """A job folder whose writes fail after ``budget`` slices of the atlas ``level``: the run stops, as if killed."""

    def __init__(self, path, spec, level, budget):
        super().__init__(path, spec)
        self.level, self.budget = level, budget

    def save(self, name, data):
        if name.startswith(f"parts/{self.level}-") and name.endswith(".ears"):
            if self.budget == 0:
                raise Stop(name)
            self.budget -= 1
        super().save(name, data)


def files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_checkpointed_atlas_is_the_plain_one_and_is_loaded_again(tmp_path, monkeypatch, sliced):
    saved = []

    class Saving(JobFolder):
        def save(self, name, data):
            saved.append(name)
            super().save(name, data)

    job = Saving(tmp_path / "job", SPEC)
    atlas = ChainGenerator(checkpoints=job).chains(LINKS, DOF)
    assert atlas == ChainGenerator().chains(LINKS, DOF)
    written = files(tmp_path / "job")
    assert [line for line in written[f"{NAME}.g6"].decode().split()] == [c.graph6 for c in chains(LINKS, DOF)]
    assert any(name.startswith(f"parts/{NAME}-k") and name.endswith(".ears") for name in saved)   # it was sliced
    assert not [name for name in written if name.startswith("parts/")]       # slices dropped once a level is done
    nine = ChainGenerator().chains(9, 2)                                      # the level of its k=2 ears' parents
    monkeypatch.setattr("domes.typesynth.atlas.ears", None)                    # nothing may be computed again
    # the generator that merges levels (from 13 links `auto` augments instead, and calls no ears)
    again = ChainGenerator(checkpoints=JobFolder(tmp_path / "job", SPEC), method="merge")
    assert again.chains(LINKS, DOF) == atlas and again.chains(9, 2) == nine
    with pytest.raises(TypeError):                                            # ... but a size not on disk is
        again.chains(13, 2)


def test_interrupted_run_resumes_to_the_same_files(tmp_path, sliced):
    ChainGenerator(checkpoints=JobFolder(tmp_path / "whole", SPEC)).chains(LINKS, DOF)
    with pytest.raises(Stop):
        ChainGenerator(checkpoints=FailingFolder(tmp_path / "resumed", SPEC, f"{NAME}-k1", 1)).chains(LINKS, DOF)
    partial = files(tmp_path / "resumed")
    kept = sorted(name for name in partial if name.endswith(".ears"))        # earlier levels' slices are gone
    assert len(kept) >= 2 and f"{NAME}.g6" not in partial                   # slices of k=0 and one of k=1
    seen = []

    class Watching(JobFolder):
        def load(self, name):
            data = super().load(name)
            if name.endswith(".ears") and data is not None:
                seen.append(name)
            return data

    ChainGenerator(checkpoints=Watching(tmp_path / "resumed", SPEC)).chains(LINKS, DOF)
    assert sorted(seen) == kept                                              # the slices on disk were not redone
    assert files(tmp_path / "resumed") == files(tmp_path / "whole")



def test_a_killed_runs_half_written_temporaries_are_removed_on_opening(tmp_path):
    # A SIGKILL inside write_atomic leaves `.job.json.XXXX.tmp`: the resumed folder then differed from a whole
    # run's (the killed-command test failed so on a loaded CI machine).
    job = JobFolder(tmp_path / "job", SPEC)
    job.save("parts/a.ears", b"x")
    (tmp_path / "job" / ".job.json.k2j3.tmp").write_text("{")
    (tmp_path / "job" / "parts" / ".a.ears.q8w1.tmp").write_bytes(b"")
    said = []
    again = JobFolder(tmp_path / "job", SPEC, say=said.append)
    assert sorted(files(tmp_path / "job")) == ["job.json", "parts/a.ears"]
    assert again.load("parts/a.ears") == b"x"
    assert len(said) == 2 and all("a killed run left half written, removed" in s for s in said)

def test_job_folder_refuses_another_job_and_stray_folders(tmp_path):
    JobFolder(tmp_path / "job", SPEC)
    with pytest.raises(InputError, match="holds another job"):
        JobFolder(tmp_path / "job", {**SPEC, "isomorphism": "charpoly"})
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="not empty and holds no job.json"):
        JobFolder(tmp_path / "full", SPEC)
    with pytest.raises(InputError, match="does not exist"):
        JobFolder(tmp_path / "no" / "such", SPEC)
    with pytest.raises(InputError, match="inside the job folder"):
        JobFolder(tmp_path / "job", SPEC).load("../notes.txt")


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs /proc, a folder that takes no new folders")
def test_a_job_folder_that_cannot_be_made_is_named_with_the_reason(tmp_path, capsys):
    # issue 25, item 2: --out under a system folder ended in FileNotFoundError
    from domes.cli import main

    assert main(["chains", "--links", "8", "--dof", "1", "--out", "/proc/domes-atlas"]) == 2
    err = capsys.readouterr().err
    assert "cannot make the job folder /proc/domes-atlas: /proc takes no new folders" in err
    assert "Traceback" not in err


def test_a_job_folder_the_user_may_not_make_is_named_with_the_reason(tmp_path, monkeypatch):
    def refused(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(Path, "mkdir", refused)
    with pytest.raises(InputError, match=f"job folder {tmp_path}/atlas: {tmp_path} does not let this user make "
                                         r"folders in it \(Permission denied\)"):
        JobFolder(tmp_path / "atlas", SPEC)


def test_a_job_folder_under_a_file_says_the_parent_is_a_file(tmp_path):
    # issue 25, item 5: it was called a missing folder
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match=f"job folder {tmp_path}/notes.txt/atlas: {tmp_path}/notes.txt is a file, "
                                         "not a folder"):
        JobFolder(tmp_path / "notes.txt" / "atlas", SPEC)


@pytest.mark.slow
def test_killed_command_resumes_to_the_same_files(tmp_path, tmp_path_factory):
    # A real kill: SIGKILL to `domes chains --out` on two workers once the first slices are on disk; rerun in
    # this process (other workers: the slices an earlier run planned are kept). The 12-link atlas is the smallest
    # the command cuts into slices (levels of 1,962 and 753 parents).
    args = [*DOMES, "chains", "--links", "12", "--dof", "1", "--no-progress"]
    whole = subprocess.run([*args, "--out", str(tmp_path / "whole")], check=True, capture_output=True, text=True)
    killed = subprocess.Popen([*args, "--out", str(tmp_path / "killed"), "--workers", "2"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    parts = tmp_path / "killed" / "parts"
    deadline = time.monotonic() + 120
    while not (parts.is_dir() and any(parts.glob("chains-n12-F1-*.ears"))):
        assert killed.poll() is None and time.monotonic() < deadline, "the run ended before a slice was written"
        time.sleep(0.02)
    os.killpg(killed.pid, signal.SIGKILL)
    killed.wait()
    assert not (tmp_path / "killed" / "chains-n12-F1.g6").exists()
    out = subprocess.run([*args, "--out", str(tmp_path / "killed")], check=True, capture_output=True, text=True)
    # the count of the atlas built in one process (checked against geng in tests/typesynth/test_pebble.py)
    count = len(chain_atlas(tmp_path_factory, 12, 1))
    assert whole.stdout.startswith(f"{count} chains of 12 links, DOF 1: ") and out.stdout.startswith(f"{count} chains ")
    assert files(tmp_path / "killed") == files(tmp_path / "whole")


class Payload:
    """A pickle that, loaded, leaves a mark: what a planted slice file would do if it were unpickled."""

    def __reduce__(self):
        return (os.mkdir, (os.environ["DOMES_TEST_MARK"],))


def _interrupted(folder: Path) -> list[str]:
    """A folder of the 11-link atlas stopped after one slice of its level k=1: the slices' names."""
    with pytest.raises(Stop):
        ChainGenerator(checkpoints=FailingFolder(folder, SPEC, f"{NAME}-k1", 1)).chains(LINKS, DOF)
    return sorted(str(p.relative_to(folder)) for p in (folder / "parts").glob("*.ears"))


def test_a_planted_pickle_in_a_job_folder_runs_nothing_and_is_named(tmp_path, monkeypatch, sliced):
    # issue 31, item 1: resuming loaded slice files with pickle.loads, so a planted payload ran.
    import pickle

    mark = tmp_path / "payload-ran"
    monkeypatch.setenv("DOMES_TEST_MARK", str(mark))
    whole = tmp_path / "whole"
    ChainGenerator(checkpoints=JobFolder(whole, SPEC)).chains(LINKS, DOF)
    folder = tmp_path / "job"
    slices = _interrupted(folder)
    planted = folder / slices[0]
    planted.write_bytes(pickle.dumps(Payload()))                     # a damaged slice, listed with another checksum
    foreign = folder / "parts" / f"{NAME}-k1-0-1.ears"              # and one no run of this job wrote
    foreign.write_bytes(pickle.dumps(Payload()))
    said = []
    again = ChainGenerator(checkpoints=JobFolder(folder, SPEC, say=said.append)).chains(LINKS, DOF)
    assert not mark.exists()                                         # nothing ran
    assert again == ChainGenerator().chains(LINKS, DOF)
    assert any(str(planted) in s and "is damaged" in s for s in said), said
    assert files(folder)[f"{NAME}.g6"] == files(whole)[f"{NAME}.g6"]
    # listed with its own checksum (a folder copied from elsewhere, job.json and all): read as data, refused
    folder2 = tmp_path / "job2"
    slices = _interrupted(folder2)
    job = JobFolder(folder2, SPEC)
    job.save(slices[0], pickle.dumps(Payload()))
    said.clear()
    assert ChainGenerator(checkpoints=JobFolder(folder2, SPEC, say=said.append)).chains(LINKS, DOF) == again
    assert not mark.exists() and any("is not a slice file" in s for s in said), said


@pytest.mark.parametrize("damage", ["cut", "doubled line", "flipped byte", "empty"])
def test_a_damaged_finished_atlas_is_named_and_made_again(tmp_path, damage, capsys):
    # issue 31, item 2: a finished chains-n13-F2.g6 cut in half gave "13748 chains" and exit 0 (27,496 in fact).
    from domes.cli import main

    folder = tmp_path / "atlas"
    assert main(["chains", "--links", "11", "--dof", "2", "--no-progress", "--out", str(folder)]) == 0
    target = folder / "chains-n11-F2.g6"
    good = target.read_bytes()
    lines = good.splitlines(keepends=True)
    target.write_bytes({"cut": good[: len(good) // 2], "doubled line": good + lines[-1],
                        "flipped byte": good[:5] + bytes([good[5] ^ 1]) + good[6:], "empty": b""}[damage])
    capsys.readouterr()
    assert main(["chains", "--links", "11", "--dof", "2", "--no-progress", "--out", str(folder)]) == 0
    out, err = capsys.readouterr()
    assert out.startswith(f"{len(chains(11, 2))} chains of 11 links")
    assert f"{target} is damaged" in err and "computed again" in err
    assert target.read_bytes() == good
