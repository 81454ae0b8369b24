"""A design with the modified constant-velocity law is accepted end to end (issue 32 item 6)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from camtol.cli.app import main
from camtol.config.design_file import example_text


def _design(tmp_path: Path, example: str) -> Path:
    text = example_text(example).replace('"cycloidal"', '"modified_constant_velocity"')
    assert "modified_constant_velocity" in text
    p = tmp_path / "mcv.toml"
    p.write_text(text, encoding="utf-8")
    return p


@pytest.mark.parametrize("example", ["cw06-translating", "cw06-oscillating"])
def test_analyze_and_profile_accept_it(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, example: str
) -> None:
    design = _design(tmp_path, example)
    assert main(["analyze", str(design), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert "modified constant velocity" in json.dumps(doc)
    out = tmp_path / "p.csv"
    assert main(["profile", str(design), "-o", str(out)]) == 0
    with out.open(encoding="utf-8") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    assert len(rows) > 100  # a header and the profile's vertices
