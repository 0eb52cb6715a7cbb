"""Test session setup: the checkout's own ``domes`` first on sys.path (pytest puts this folder there),
and a scratch DOMES_HOME so that no test ever reads or writes the user's own case base."""

import os
import tempfile

os.environ["DOMES_HOME"] = tempfile.mkdtemp(prefix="domes-test-home-")
for _name in ("DOMES_DB", "DOMES_KNOWLEDGE"):
    os.environ.pop(_name, None)
