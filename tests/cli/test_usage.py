"""The README's usage block is generated from the CLI, and they agree (issue 13 item 9)."""

from __future__ import annotations

from pathlib import Path

import pytest

from camtol.cli.app import main
from camtol.cli.usage import BEGIN, END, usage_block

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_usage_block_matches_the_cli() -> None:
    text = README.read_text(encoding="utf-8")
    block = text[text.index(BEGIN) + len(BEGIN) : text.index(END)]
    assert block.strip() == f"```text\n{usage_block()}```", (
        "README usage block is stale: run `python -m camtol.cli.usage --write README.md`"
    )


def test_usage_lists_every_command() -> None:
    from camtol.cli.app import cli

    block = usage_block()
    for name in cli.list_commands(None):  # type: ignore[arg-type]
        assert f"camtol {name}" in block


def test_profile_help_names_the_layers_the_files_use(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["profile", "--help"]) == 0
    help_text = " ".join(capsys.readouterr().out.split())
    assert "CAM_PITCH_CURVE" in help_text and "CAM_CUTTER_PATH" in help_text


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--plot-angle", "30"], "--plot-angle draws on the figure: give --plot"),
        (["--plot", "f.png", "--plot-angle", "400"], "--plot-angle=400.0 is not allowed"),
        (["--plot", "f.png", "--plot-angle", "-1"], "--plot-angle=-1.0 is not allowed"),
    ],
)
def test_plot_angle_checked(
    args: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = [a if a != "f.png" else str(tmp_path / "f.png") for a in args]
    assert main(["analyze", "--example", "cw06-translating", *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "f.png").exists()


def test_analyze_says_what_it_wrote(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    curves = tmp_path / "c.csv"
    assert main(["analyze", "--example", "cw06-translating", "--curves", str(curves)]) == 0
    assert f"wrote {curves}" in capsys.readouterr().out
    assert main(["analyze", "-e", "cw06-translating", "--json", "--curves", str(curves)]) == 0
    cap = capsys.readouterr()
    assert cap.out.lstrip().startswith("{") and f"wrote {curves}" in cap.err
