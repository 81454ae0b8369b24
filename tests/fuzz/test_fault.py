"""Fault test (issue 9): SIGKILL at random moments during every writing command.

Afterwards each target is absent, complete (byte-identical to an uninterrupted run), or
still the old file; and after the next run into the same directory no temporary file of
camtol remains (stale temporaries of dead processes are removed, THEORY-independent).
SIGTERM is also checked: the handler removes the live temporary file before dying.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
COMMANDS = {
    "analyze": (
        ["analyze", "-e", "cw11-conjugate", "--step", "0.5", "-q"],
        {"--curves": "a.csv", "--plot": "a.png"},
    ),
    "profile": (
        ["profile", "-e", "roller-translating", "-q", "--tolerance", "0.5"],
        {"-o": "p.dxf"},
    ),
    "report": (["report", "-e", "cw06-translating", "--step", "1", "-q"], {"-o": "r.html"}),
    "conjugate": (
        ["conjugate", "-e", "cw11-experiment", "--step", "0.5", "-q"],
        {"--curves": "c.csv", "--plot": "c.svg"},
    ),
}


def _argv(name: str, d: Path) -> list[str]:
    base, outs = COMMANDS[name]
    args = [sys.executable, "-m", "camtol", *base]
    for opt, file in outs.items():
        args += [opt, str(d / file)]
    return args


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    env["MPLBACKEND"] = "Agg"
    return env


def _temporaries(d: Path) -> list[Path]:
    return [p for p in d.iterdir() if ".camtol-tmp-" in p.name]


def _complete(path: Path) -> bool:
    """The file is whole: its format's closing bytes are there (ezdxf, matplotlib and the
    HTML report embed ids and times, so two runs are not byte-identical)."""
    data = path.read_bytes()
    tail = {
        ".csv": b"\n",
        ".dxf": b"EOF\n",
        ".svg": b"</svg>\n",
        ".html": b"</html>\n",
        ".png": b"IEND\xaeB`\x82",
    }[path.suffix]
    return len(data) > 100 and data.endswith(tail)


def _kill_trials(name: str, tmp_path: Path, trials: int) -> None:
    rng = np.random.default_rng(20061203 + sorted(COMMANDS).index(name))
    outs = list(COMMANDS[name][1].values())
    for trial in range(trials):
        d = tmp_path / f"t{trial}"
        d.mkdir()
        t0 = time.perf_counter()
        first = subprocess.run(_argv(name, d), env=_env(), capture_output=True, timeout=300)
        duration = time.perf_counter() - t0
        assert first.returncode in (0, 1), first.stderr.decode()
        old = {f: (d / f).read_bytes() for f in outs}
        proc = subprocess.Popen(
            _argv(name, d), env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
        # Most of the time goes to imports and computing; aim mostly at the end (writing).
        time.sleep(duration * float(rng.uniform(0.3, 1.1)))
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        for f in outs:
            target = d / f
            assert not target.exists() or _complete(target) or target.read_bytes() == old[f], (
                f"{name}: {f} is neither absent, complete nor the old file after SIGKILL"
            )
        # The next run into the directory removes what the killed one left behind.
        again = subprocess.run(_argv(name, d), env=_env(), capture_output=True, timeout=300)
        assert again.returncode in (0, 1), again.stderr.decode()
        assert _temporaries(d) == []
        assert all(_complete(d / f) for f in outs)


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_sigkill_leaves_absent_complete_or_old(name: str, tmp_path: Path) -> None:
    _kill_trials(name, tmp_path, trials=1)


@pytest.mark.fuzz
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_long_sigkill(name: str, tmp_path: Path) -> None:
    _kill_trials(name, tmp_path, trials=int(os.environ.get("CAMTOL_FAULT_TRIALS", "25")))


def test_sigterm_removes_the_live_temporary(tmp_path: Path) -> None:
    """A process terminated while writing removes its temporary file before dying."""
    script = (
        "import sys, time\n"
        "from camtol.files import atomic_output\n"
        "with atomic_output(sys.argv[1]) as tmp:\n"
        "    tmp.write_text('partial')\n"
        "    print(tmp, flush=True)\n"
        "    time.sleep(60)\n"
    )
    target = tmp_path / "out.csv"
    proc = subprocess.Popen(
        [sys.executable, "-c", script, str(target)],
        env=_env(),
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    tmp = Path(proc.stdout.readline().strip())
    assert tmp.exists() and ".camtol-tmp-" in tmp.name
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=30) == -signal.SIGTERM  # died of the signal, as without handler
    proc.stdout.close()
    assert not tmp.exists() and not target.exists()
    assert _temporaries(tmp_path) == []
