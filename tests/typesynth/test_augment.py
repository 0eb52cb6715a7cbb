"""Chains by canonical augmentation, checked against the merge generator (the independent check).

The merge generator (level by level, every child's nauty certificate in one set) and canonical augmentation
(a child kept only if its last ear is its canonical one, no set at all) share only the ear rule; every atlas
of up to 11 links (DOF 0 to 4, with and without cut links) must be the same list, in the same order. The
14-link identity (318,162 chains) is a measurement in docs/scale.md, not a test.
"""

import pytest

from domes.cli import main
from domes.errors import InputError
from domes.execution import InProcess
from domes.io.jobs import JobFolder
from domes.model.canon import certificate
from domes.model.pebble import decode_graph6
from domes.typesynth import augment
from domes.typesynth.atlas import ChainGenerator

SIZES = [(links, dof) for dof in range(5) for links in range(dof + 3, 12) if (3 * (links - 1) - dof) % 2 == 0
         and (3 * (links - 1) - dof) // 2 - links + 1 >= 1 and (links, dof) != (11, 0)]   # 11, 0: seconds
SPEC = {"kind": "chain atlas", "isomorphism": "nauty"}


@pytest.fixture(scope="module")
def merged():
    return ChainGenerator(method="merge")


@pytest.mark.parametrize("size", SIZES)
def test_same_atlas_as_the_merge_generator(size, merged):
    links, dof = size
    assert ChainGenerator(method="augment").chains(links, dof) == merged.chains(links, dof)


@pytest.mark.parametrize("size", [(9, 2), (10, 3), (11, 2)])
def test_same_atlas_with_cut_links(size, merged):
    assert ChainGenerator(method="augment").chains(*size, True) == merged.chains(*size, True)


def test_each_chain_once_and_records_sort_as_the_atlas():
    # 12 links, DOF 3 (1962 chains, the brief's table): walked in parts, merged; keys hold nauty's certificate.
    starts, parts = augment.plan(loops=4, dof=3, workers=2)
    found = [augment.descend(starts[i::parts], 4, 3)[0] for i in range(parts)]
    merged = list(augment.merge_records(found))
    assert len(merged) == 1962 == len(set(merged))
    certificates = {augment.certificate_of(r) for r in merged}
    assert len(certificates) == 1962
    for r in merged[::97]:
        assert certificate(*decode_graph6(augment.graph6_of(r))) == augment.certificate_of(r)


def test_the_rigidity_test_of_an_ear_is_the_subset_tables():
    # ear_is_free (sets of branch links only) against the full table of 2**n sets of links, every candidate of
    # the 10-link DOF-3 parents.
    from domes.model.rigidity import pair_slack

    parents = ChainGenerator(method="merge").chains(10, 3)[::3] + ChainGenerator(method="merge").chains(9, 2)
    checked = 0
    for graph in parents:
        parent = augment._Parent(graph)
        slack = pair_slack(*graph)
        for u in range(graph[0]):
            for v in range(u + 1, graph[0]):
                for k in (0, 1):
                    if k == 0 and parent.adjm[u] >> v & 1:
                        continue
                    _, deg, _, branches, mine, _ = parent.child(u, v, k)
                    assert augment.ear_is_free(graph[0] + k, deg, branches, mine) == (slack[u, v] >= 3 - k)
                    checked += 1
    assert checked > 1000


class Stop(Exception):
    pass


class FailingFolder(JobFolder):
    """A job folder whose writes of parts fail after ``budget`` parts: the run stops, as if killed."""

    def __init__(self, path, spec, budget):
        super().__init__(path, spec)
        self.budget = budget

    def save(self, name, data):
        if name.endswith(".rec"):
            if self.budget == 0:
                raise Stop(name)
            self.budget -= 1
        super().save(name, data)


def test_a_stopped_job_resumes_from_its_parts(tmp_path):
    whole = tmp_path / "whole"
    expected = ChainGenerator(method="augment", checkpoints=JobFolder(whole, SPEC)).chains(11, 2)
    folder = tmp_path / "stopped"
    with pytest.raises(Stop):
        ChainGenerator(method="augment", checkpoints=FailingFolder(folder, SPEC, 3)).chains(11, 2)
    assert len(list((folder / "parts").glob("*.rec"))) == 3
    again = ChainGenerator(method="augment", checkpoints=JobFolder(folder, SPEC), executor=InProcess())
    assert again.chains(11, 2) == expected
    assert again.stats.candidates > 0 and again.stats.kept < len(expected)     # the three parts were not walked again
    assert (folder / "chains-n11-F2.g6").read_bytes() == (whole / "chains-n11-F2.g6").read_bytes()
    assert not list((folder / "parts").glob("*.rec"))


def test_a_part_that_is_not_one_is_walked_again(tmp_path):
    said = []
    folder = tmp_path / "job"
    job = FailingFolder(folder, SPEC, 2)
    with pytest.raises(Stop):
        ChainGenerator(method="augment", checkpoints=job).chains(11, 2)
    part = sorted((folder / "parts").glob("*.rec"))[0]
    name = f"parts/{part.name}"
    JobFolder.save(job, name, part.read_bytes()[:-3])      # listed with its checksum, but cut short
    again = ChainGenerator(method="augment", checkpoints=JobFolder(folder, SPEC, say=said.append))
    assert len(again.chains(11, 2)) == 753
    assert any(part.name in line and "not a part of this atlas" in line for line in said), said
    with pytest.raises(ValueError, match="not sorted records|not records"):
        augment.split_records(b"x" * 7, 11)


def test_stream_counts_and_writes_without_graphs(tmp_path, merged):
    count, lines = ChainGenerator(method="augment").stream(10, 3)
    assert count == 74
    assert list(lines) == list(merged.stream(10, 3)[1])
    folder = tmp_path / "job"
    count, _ = ChainGenerator(method="augment", checkpoints=JobFolder(folder, SPEC)).stream(11, 2)
    assert count == 753 == len((folder / "chains-n11-F2.g6").read_text().split())


def test_the_command_line_method(capsys):
    assert main(["chains", "--links", "11", "--dof", "2", "--count", "--method", "augment", "--no-progress"]) == 0
    assert capsys.readouterr().out.strip() == "753"
    assert main(["chains", "--links", "9", "--dof", "2", "--method", "augment", "--isomorphism", "charpoly"]) == 2
    assert "--method augment keeps chains by nauty" in capsys.readouterr().err
    with pytest.raises(InputError, match="generation method"):
        ChainGenerator(method="fast")
