"""The studio's server: loopback only, its own origin only, small requests, files only in the data folder (issue 30,
acceptance "Security")."""

import json
import os
import socket
import urllib.request

import pytest

from domes.studio.security import MAX_BODY

JSON = {"content-type": "application/json"}


def test_it_answers_its_own_address_and_refuses_another_host(client):
    assert client.get("/api/about").json()["name"] == "DOMES Studio"
    assert client.get("/").text.startswith("<!DOCTYPE html>")
    r = client.get("/api/about", headers={"host": "evil.example:8765"})          # DNS rebinding
    assert r.status_code == 400 and "answers only as" in r.json()["error"]


def test_cross_origin_posts_are_refused(client):
    r = client.post("/api/about", json={}, headers={"origin": "http://evil.example"})
    assert r.status_code == 403 and "another site (http://evil.example)" in r.json()["error"]
    r = client.post("/api/about", json={}, headers={"sec-fetch-site": "cross-site"})
    assert r.status_code == 403
    r = client.post("/api/about", content=b"name=x", headers={"content-type": "application/x-www-form-urlencoded"})
    assert r.status_code == 415 and "application/json" in r.json()["error"]          # a plain HTML form's post
    assert client.post("/api/about", json={}, headers={"origin": "http://127.0.0.1:8765"}).status_code == 200


def test_oversized_and_malformed_bodies_get_a_clear_error(client):
    big = b'{"x": "' + b"a" * (MAX_BODY + 10) + b'"}'
    r = client.post("/api/about", content=big, headers=JSON)
    assert r.status_code == 413 and "larger than the 1,048,576 bytes" in r.json()["error"]

    def chunks():                                                                # no Content-Length: counted as read
        for _ in range(20):
            yield b" " * (MAX_BODY // 10)

    r = client.post("/api/about", content=chunks(), headers=JSON)
    assert r.status_code == 413
    r = client.post("/api/about", content=b'{"a": [1, 2', headers=JSON)
    assert r.status_code == 400 and r.json()["error"].startswith("request body: line 1, column")
    r = client.post("/api/about", content=b"[1, 2]", headers=JSON)
    assert r.status_code == 400 and "a JSON object is needed" in r.json()["error"]
    r = client.post("/api/about", content=b"\xff\xfe", headers=JSON)
    assert r.status_code == 400 and "not UTF-8" in r.json()["error"]
    r = client.post("/api/about", content=b"[" * 1000 + b"]" * 1000, headers=JSON)
    assert r.status_code == 400 and "nested deeper" in r.json()["error"]


def test_no_file_outside_the_data_folder_is_read(client, home, tmp_path):
    (home / "mechanisms").mkdir()
    (home / "mechanisms" / "mine.json").write_text(json.dumps({"name": "mine"}))
    secret = tmp_path / "secret.json"
    secret.write_text(json.dumps({"password": "x"}))
    os.symlink(secret, home / "mechanisms" / "link.json")
    assert client.get("/api/open", params={"name": "mechanisms/mine.json"}).json()["content"] == {"name": "mine"}
    assert client.get("/api/files").json()["files"] == ["mechanisms/link.json", "mechanisms/mine.json"]
    for name in ["../secret.json", str(secret), "mechanisms/../../secret.json", "mechanisms/link.json",
                 "/etc/passwd", "....//secret.json", "%2e%2e/secret.json"]:
        r = client.post("/api/open", json={"name": name})
        assert r.status_code in (403, 404), name
        assert "password" not in r.text, name
    r = client.post("/api/open", json={"name": "../secret.json"})
    assert "outside the studio's data folder" in r.json()["error"]
    for raw in ["/static/../../secret.json", "/static/%2e%2e/%2e%2e/secret.json", "/static/..%2f..%2fsecret.json"]:
        r = client.get(raw)
        assert r.status_code == 404 and "password" not in r.text, raw


def test_a_file_the_user_opened_may_be_read(home, tmp_path):
    from starlette.testclient import TestClient

    from domes.studio.app import Studio, make_app

    mine = tmp_path / "elsewhere.json"
    mine.write_text("{}")
    with TestClient(make_app(Studio(home, opened={mine})), base_url="http://127.0.0.1:8765") as c:
        assert c.post("/api/open", json={"name": str(mine)}).status_code == 200


def test_the_server_answers_only_on_the_loopback_address(server):
    port = int(server.rsplit(":", 1)[1])
    with urllib.request.urlopen(server + "/api/about", timeout=10) as r:
        assert json.load(r)["name"] == "DOMES Studio"
    outside = [a for a in _addresses() if not a.startswith("127.")]
    for address in outside:
        with pytest.raises(OSError):
            socket.create_connection((address, port), timeout=2).close()


def _addresses() -> list[str]:
    """This machine's IPv4 addresses other than loopback (none on a machine without a network)."""
    found = set()
    try:
        found |= {info[4][0] for info in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)}
    except OSError:
        pass
    probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        probe.connect(("10.255.255.255", 1))
        found.add(probe.getsockname()[0])
    except OSError:
        pass
    finally:
        probe.close()
    return sorted(found)
