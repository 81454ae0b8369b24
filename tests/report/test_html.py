"""HTML report: self-contained content, CLI `camtol report`, rendering in headless Chromium."""

from __future__ import annotations

import html
import os
import re
import shutil
import subprocess
import sys
from collections import Counter
from functools import cache
from pathlib import Path

import pytest

from camtol import __version__
from camtol.analysis.radius_table import radius_table
from camtol.analysis.result import Analysis, analyse
from camtol.cli.app import main
from camtol.config.design_file import example_names, load_example
from camtol.design.cam_design import IT_CONVENTIONS
from camtol.report.display import accuracy_words
from camtol.report.export import ExportError
from camtol.report.html import CONVENTIONS, report_html, write_report
from camtol.study import study

EXAMPLES = example_names()


@cache
def analysis_of(name: str) -> Analysis:
    return analyse(load_example(name), step_deg=0.5)


@cache
def page_of(name: str) -> str:
    return report_html(study(analysis_of(name)))


def expected_figures(name: str) -> int:
    design = load_example(name)
    return 2 if design.mechanism.kind == "conjugate" and design.inspection is not None else 1


@pytest.mark.parametrize("name", EXAMPLES)
def test_report_content(name: str) -> None:
    page = page_of(name)
    a = analysis_of(name)
    assert page.startswith("<!DOCTYPE html>")
    assert f"camtol {__version__}" in page
    for text in (*IT_CONVENTIONS, *CONVENTIONS):
        assert html.escape(text) in page
    assert html.escape(accuracy_words(a.accuracy)) in page  # not assessed: no tolerances
    for q in a.quantities:  # the extremes table has a row per quantity
        assert f"<td>{html.escape(q.label)}</td>" in page
    for _param, value in a.design.mechanism.summary():
        assert html.escape(value) in page
    assert page.count("<svg") == expected_figures(name)
    assert page.count("<figure") == expected_figures(name)


@pytest.mark.parametrize("name", EXAMPLES)
def test_report_is_self_contained(name: str) -> None:
    page = page_of(name)
    assert "<script" not in page.lower()
    assert not re.search(r"""(src|href)\s*=\s*["'](https?:|//)""", page)
    assert not re.search(r"url\(\s*['\"]?(https?:|//)", page)
    assert not re.search(r"@import", page)
    links = re.findall(r"<link[^>]*>", page)
    assert links == ['<link rel="icon" href="data:,">']
    # Ids stay unique across the inline SVGs (each figure's ids are prefixed).
    ids = Counter(re.findall(r'\bid="([^"]+)"', page))
    assert [k for k, n in ids.items() if n > 1] == []
    # Every internal reference points at an id of the page.
    refs = set(re.findall(r'href="#([^"]+)"', page)) | set(re.findall(r"url\(#([^)]+)\)", page))
    assert refs <= set(ids)


def test_conjugate_report_has_fixture_verdicts() -> None:
    page = page_of("cw11-conjugate")
    # THEORY §8.3: with Δf_mea = 22 µm both cams fail somewhere (the published figures).
    assert "Fixture, cam A:" in page and "Fixture, cam B:" in page
    assert "Measuring fixture" in page


def test_write_report_from_design_and_atomic(tmp_path: Path) -> None:
    out = tmp_path / "r.html"
    a = write_report(study(load_example("cw06-translating")), out)
    assert a.design.name == "cw06-translating"
    assert out.read_text(encoding="utf-8").rstrip().endswith("</html>")
    assert [p.name for p in tmp_path.iterdir()] == ["r.html"]  # no temporary left over
    with pytest.raises(ExportError, match=r"\.html"):
        write_report(study(a), tmp_path / "r.pdf")
    with pytest.raises(ExportError, match="does not exist"):
        write_report(study(a), tmp_path / "missing" / "r.html")
    assert [p.name for p in tmp_path.iterdir()] == ["r.html"]


def test_cli_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "r.html"
    assert main(["report", "--example", "cw06-oscillating", "-o", str(out), "--step", "0.5"]) == 0
    assert "wrote" in capsys.readouterr().out
    assert out.stat().st_size > 10_000
    assert main(["report", "-e", "cw06-oscillating", "-o", str(tmp_path / "r.txt")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and ".html" in err
    assert main(["report", "-o", str(tmp_path / "x.html")]) == 2  # no design given
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.html"]


def test_cli_report_from_fresh_process(tmp_path: Path) -> None:
    # The acceptance command, as a user runs it (python -m camtol = the console script).
    r = subprocess.run(
        [sys.executable, "-m", "camtol", "report", "--example", "cw06-translating", "-o", "r.html"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "r.html").read_text(encoding="utf-8").count("<svg") == 1


# ---------------------------------------------------------------------------------------
# Headless Chromium (Debian package `chromium`; .ci/run installs it)
# ---------------------------------------------------------------------------------------
CHROMIUM = shutil.which("chromium")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None,
    reason="chromium is not on PATH (Debian: apt-get install chromium); .ci/run installs it",
)


def run_chromium(page: Path, tmp_path: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    assert CHROMIUM is not None
    profile = tmp_path / "chromium-profile"
    profile.mkdir(exist_ok=True)
    args = [
        CHROMIUM,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={profile}",
        "--enable-logging=stderr",
        "--v=0",
        "--window-size=1200,2000",
        *extra,
        page.resolve().as_uri(),
    ]
    env = dict(os.environ, HOME=str(tmp_path))
    return subprocess.run(args, capture_output=True, text=True, timeout=180, env=env)


def console_lines(stderr: str) -> list[str]:
    """Chromium's log of the page's console (any message: the report has no scripts)."""
    return [ln for ln in stderr.splitlines() if ":CONSOLE" in ln or "Uncaught" in ln]


@pytest.mark.browser
@needs_chromium
def test_console_detection_works(tmp_path: Path) -> None:
    # The check below is only meaningful if a broken page is caught the same way.
    bad = tmp_path / "bad.html"
    bad.write_text('<!DOCTYPE html><p>x</p><script>throw new Error("boom")</script>')
    r = run_chromium(bad, tmp_path, "--dump-dom")
    assert any("boom" in ln for ln in console_lines(r.stderr)), r.stderr[-2000:]


@pytest.mark.browser
@needs_chromium
@pytest.mark.parametrize("name", EXAMPLES)
def test_report_renders_in_chromium(name: str, tmp_path: Path) -> None:
    import matplotlib.image as mpimg
    import numpy as np

    out = tmp_path / f"{name}.html"
    write_report(study(analysis_of(name)), out)
    # 1. The DOM holds every figure as an <svg>, and the page logs nothing to the console.
    r = run_chromium(out, tmp_path, "--dump-dom")
    assert r.returncode == 0, r.stderr[-2000:]
    assert console_lines(r.stderr) == []
    dom = r.stdout
    assert dom.count("<svg") == expected_figures(name)
    assert len(re.findall(r"<figure[^>]*>\s*<svg", dom)) == expected_figures(name)
    # 2. A screenshot is not blank.
    shot = tmp_path / "shot.png"
    r = run_chromium(out, tmp_path, f"--screenshot={shot}")
    assert r.returncode == 0, r.stderr[-2000:]
    assert console_lines(r.stderr) == []
    img = mpimg.imread(shot)
    assert img.shape[0] >= 1000 and img.shape[1] >= 1000
    ink = np.any(img[..., :3] < 0.9, axis=-1).mean()
    assert ink > 0.01, f"screenshot nearly blank ({ink:.2%} non-white pixels)"


def pdf_pages(pdf: Path) -> int:
    """Number of page objects (``/Type /Page``, not ``/Pages``) in a PDF file."""
    return len(re.findall(rb"/Type\s*/Page(?![s\w])", pdf.read_bytes()))


@pytest.mark.browser
@needs_chromium
@pytest.mark.parametrize("name", EXAMPLES)
def test_report_prints_to_pdf(name: str, tmp_path: Path) -> None:
    # Print CSS (issue 13 item 15): A4, no table or figure split, no orphan headings. The
    # built-in examples print to 4-5 pages today (verdicts, inputs, conventions and
    # extremes, one page per figure); 3-8 allows for font metrics of other machines.
    out = tmp_path / f"{name}.html"
    write_report(study(analysis_of(name)), out)
    pdf = tmp_path / f"{name}.pdf"
    r = run_chromium(out, tmp_path, "--no-pdf-header-footer", f"--print-to-pdf={pdf}")
    assert r.returncode == 0, r.stderr[-2000:]
    assert pdf.read_bytes()[:5] == b"%PDF-"
    pages = pdf_pages(pdf)
    assert 3 <= pages <= 8, pages
    if name == "roller-translating":  # the 1° radius table: 360 rows, a few more pages
        write_report(study(analysis_of(name)), out, radius_table=radius_table(load_example(name)))
        r = run_chromium(out, tmp_path, "--no-pdf-header-footer", f"--print-to-pdf={pdf}")
        assert r.returncode == 0, r.stderr[-2000:]
        assert 3 <= pdf_pages(pdf) - pages <= 12
