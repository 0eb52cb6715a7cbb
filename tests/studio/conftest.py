"""Fixtures of the studio's tests: a test client in this process, a real server, and Debian's Chromium.

The browser tests drive /usr/bin/chromium through Playwright (no browser download); they are skipped
when either is missing.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from domes.io.resources import shipped_casebase
from tests.shared import studio_server

CHROMIUM = "/usr/bin/chromium"
#: The flags Chromium needs on a closed machine as root (no sandbox, no background connections).
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync"]


@pytest.fixture
def home(tmp_path, monkeypatch) -> Path:
    """A data folder of the user's own, with a case base copied from the embedded one."""
    folder = tmp_path / "home"
    folder.mkdir()
    shutil.copyfile(shipped_casebase(), folder / "casebase.db")
    monkeypatch.setenv("DOMES_HOME", str(folder))
    monkeypatch.delenv("DOMES_DB", raising=False)
    return folder


@pytest.fixture
def studio(home):
    from domes.studio.app import Studio

    return Studio(home, port=8765)


@pytest.fixture
def client(studio):
    """Starlette's test client on the studio's app, sending the studio's own Host."""
    from starlette.testclient import TestClient

    from domes.studio.app import make_app

    with TestClient(make_app(studio), base_url="http://127.0.0.1:8765") as c:
        yield c


@pytest.fixture
def server(home):
    """``domes studio`` on the test's data folder: its address."""
    yield from studio_server(home)


@pytest.fixture(scope="module")
def browser():
    if not os.path.exists(CHROMIUM):
        pytest.skip("needs the Debian package chromium (/usr/bin/chromium)")
    playwright = pytest.importorskip("playwright.sync_api")
    with playwright.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        yield b
        b.close()


@pytest.fixture
def page(browser, server):
    """A new page of the browser, at the studio's address."""
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(server + "/")
    yield page
    context.close()
    assert not errors, f"the page raised: {errors}"
