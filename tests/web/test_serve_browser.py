"""``camtol serve`` in headless Chromium: the quality page loads, a lot and a record open.

The server runs for real (``python -m camtol serve``, waitress) on a free local port over
a SQLite store written through the Python API; Playwright drives the system's Chromium
(``executable_path``: no browser download). Skipped, saying why, without Chromium,
Playwright or the ``serve`` extra.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")
pytest.importorskip("flask", reason="camtol serve needs camtol[serve] (Flask, waitress)")
pytest.importorskip("waitress", reason="camtol serve needs camtol[serve] (Flask, waitress)")

from camtol.records.store import Traceability, make_record, open_store

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
TOKEN = "s3cret-token-for-tests"
#: Values of the lot's largest deviation [µm]; part 12 far above the others (WE1).
VALUES = [20.0, 21.5, 19.0, 20.5, 22.0, 19.5, 20.0, 21.0, 20.5, 19.0, 21.0, 34.0, 20.0, 20.5]


def _store(path: Path) -> str:
    url = str(path / "quality.db")
    theta = np.arange(360) * np.pi / 180
    with open_store(url) as s:
        for i, v in enumerate(VALUES, start=1):
            s.add(
                make_record(
                    design_name="cam-7",
                    design_hash="sha256:" + "2" * 64,
                    method="cmm",
                    cam="",
                    dr_um=(v - 20.0) + 20.0 * np.cos(theta),
                    verdict="pass" if v <= 30.0 else "fail",
                    tolerance_um=(-30.0, 30.0),
                    traceability=Traceability(serial=str(i), lot="L-42", part_number="CAM-7"),
                    judged_on="dr",
                )
            )
    return url


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    url = _store(tmp_path_factory.mktemp("serve"))
    port = _free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "camtol", "serve", "--store", url, "--port", str(port)]
        + ["--token", TOKEN],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):  # up to 30 s for the interpreter and the imports
            if proc.poll() is not None:
                pytest.fail(f"camtol serve exited: {proc.stderr.read().decode()}")  # type: ignore[union-attr]
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=0.2):
                    break
            except OSError:
                time.sleep(0.1)
        yield base
    finally:
        proc.terminate()
        proc.communicate(timeout=10)  # and close the pipe


def _status(url: str, headers: dict[str, str] | None = None) -> int:
    try:
        with urllib.request.urlopen(urllib.request.Request(url, headers=headers or {})) as r:
            return int(r.status)
    except urllib.error.HTTPError as e:
        return int(e.code)


def test_token_is_required_on_every_request(server: str) -> None:
    assert _status(server + "/") == 401
    assert _status(server + "/?token=wrong-token-123") == 401
    assert _status(server + "/record/1", {"Authorization": "Bearer nope-nope-nope"}) == 401
    assert _status(server + "/record/1", {"Authorization": f"Bearer {TOKEN}"}) == 200
    assert _status(server + f"/search?serial=3&token={TOKEN}") == 200


@pytest.mark.browser
@pytest.mark.skipif(CHROMIUM is None, reason="chromium is not on PATH; .ci/run installs it")
def test_quality_page_in_chromium(server: str) -> None:
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="the browser test drives Chromium with Playwright"
    )
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        try:
            page = browser.new_page()
            errors: list[str] = []
            statuses: list[tuple[int, str]] = []
            page.on(
                "console",
                lambda m: (
                    errors.append(m.text)
                    if m.type == "error" and not m.text.startswith("Failed to load resource")
                    else None
                ),
            )
            page.on("requestfailed", lambda r: errors.append(f"failed: {r.url}"))
            page.on("response", lambda r: statuses.append((r.status, r.url)))

            # a wrong token: 401, nothing shown
            denied = page.goto(server + "/?token=wrong-token-123")
            assert denied is not None and denied.status == 401

            # the lots page loads (the token once, then the cookie)
            resp = page.goto(server + f"/?token={TOKEN}")
            assert resp is not None and resp.status == 200
            row = page.locator("#lots tbody tr")
            assert row.count() == 1
            assert "L-42" in row.inner_text() and "92.9 %" in row.inner_text()  # 13 of 14
            spark = row.locator("svg.sparkline")
            assert spark.bounding_box() is not None and spark.locator("circle.flagged").count()

            # open the lot: the chart renders, the part beyond the UCL is flagged
            page.locator("a.lot").first.click()
            page.wait_for_load_state()
            assert "/lot?" in page.url
            chart = page.locator("svg.control-chart")
            box = chart.bounding_box()
            assert box is not None and box["width"] > 300 and box["height"] > 100
            assert chart.locator("circle.point").count() == len(VALUES)
            flagged = chart.locator("circle.flagged")
            assert flagged.count() >= 1
            assert flagged.first.bounding_box() is not None  # drawn, not just in the DOM
            assert page.locator("svg.histogram rect.bar").count() >= 5
            assert "WE1" in page.locator("#parts").inner_text()

            # open a record from the lot page
            page.locator("#parts a.record", has_text="12").first.click()
            page.wait_for_load_state()
            assert page.url.endswith("/record/12")
            verdict = page.locator("#verdict")
            assert "FAIL" in verdict.inner_text() and verdict.is_visible()
            assert page.locator("svg.curve polyline").count() == 1

            # search by serial
            page.goto(server + "/search?serial=3")
            assert page.locator("#found a.record").count() == 1
            assert errors == [], errors
            # the only refusals: the wrong token's page and the icon that page asked for
            refused = {(code, url.split("?")[0]) for code, url in statuses if code >= 400}
            assert refused <= {(401, server + "/"), (401, server + "/favicon.ico")}, refused
        finally:
            browser.close()
