"""The small atlas of coupler curves (closed paths, and the window index of open ones), built once in a test run."""

import pytest

from domes.io.atlas import load_atlas
from domes.motion.coupler.atlas import Atlas, OpenAtlas
from tests.shared import small_atlas_file


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    """The small atlas (600 four-bars), as ``domes curves match`` builds it."""
    return Atlas(load_atlas(small_atlas_file(tmp_path_factory)))


@pytest.fixture(scope="module")
def small_open_atlas(tmp_path_factory):
    """The small atlas's window index of open paths, as ``domes curves match --open`` builds it."""
    return OpenAtlas(load_atlas(small_atlas_file(tmp_path_factory, "open")))
