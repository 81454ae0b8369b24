"""Bad inputs of issue 32 as fuzz seeds: each must be refused with one line, exit 2.

Shared by ``tests/fuzz/test_seeds.py`` (every run of the suite) and ``bench/fuzz.py`` (the
long campaign runs them before its random cases). A seed is a set of files, a command
line and the words its error line must contain; the property of :mod:`fuzz_harness`
holds for it, and it must exit 2 and write none of its outputs.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fuzz_harness import Outcome, example_mapping, judge, run_cli, to_toml


@dataclass(frozen=True)
class Seed:
    """One bad input: files to write, the command (``{d}`` is their directory), needles."""

    name: str
    files: dict[str, str]
    args: tuple[str, ...]
    needles: tuple[str, ...]
    outputs: tuple[str, ...] = ()
    absent: tuple[str, ...] = field(default=())


def _table(rows: list[tuple[float, float]], column: str = "lift_mm") -> str:
    return f"theta_deg,{column}\n" + "".join(f"{a:.10g},{b:.10g}\n" for a, b in rows)


def _lift(theta: float) -> float:
    return 5.0 * (1.0 - math.cos(math.radians(theta)))


def _bad_tables() -> dict[str, tuple[str, tuple[str, ...]]]:
    """File text and needles of each bad lift table of issue 32."""
    full = [(float(t), _lift(t)) for t in range(360)]
    swapped = list(full)
    swapped[50], swapped[51] = swapped[51], swapped[50]
    unequal = list(full)
    unequal[200] = (200.3, unequal[200][1])
    return {
        "missing": (
            _table([r for r in full if not 100 <= r[0] < 120]),
            ("line 102", "20 rows missing (100° to 119°", "one revolution"),
        ),
        "non_monotonic": (
            _table(swapped),
            ("line 53", "theta_deg=50° comes after 51°", "must increase"),
        ),
        "duplicated": (
            _table([*full[:51], full[50], *full[51:]]),
            ("line 53", "repeats the angle of the row before"),
        ),
        "unequal_step": (_table(unequal), ("line 202", "where the table steps by 1°")),
        "half_revolution": (_table(full[:180]), ("line 181", "ends at 179°", "360 rows")),
        "two_revolutions": (
            _table(full + [(360.0 + t, v) for t, v in full]),
            ("line 362", "beyond one revolution"),
        ),
        "closing_row_disagrees": (
            _table([*full, (360.0, 0.5)]),
            ("line 362", "closing 360° row", "must repeat the 0° row"),
        ),
        "huge_lifts": (
            _table([(t, v * 1e200) for t, v in full]),
            ("line 3", "is not allowed", "at most"),
        ),
    }


def _edited(example: str, edit: Callable[[dict[str, Any]], None]) -> str:
    """TOML text of a built-in example with ``edit`` applied to its parsed mapping.

    Edits go through the parsed mapping, not the text, so that a reformatted example
    file still gives the same seed.
    """
    doc = copy.deepcopy(example_mapping(example))
    edit(doc)
    return to_toml(doc)


def _table_design(table: str) -> str:
    def edit(doc: dict[str, Any]) -> None:
        doc["motion"] = {"table_file": table}

    return _edited("cw06-translating", edit)


def _set(section: str, key: str, value: Any, *, drop: str | None = None) -> Callable[..., None]:
    def edit(doc: dict[str, Any]) -> None:
        if drop is not None:
            del doc[section][drop]
        doc[section][key] = value

    return edit


def _laws(law: str) -> Callable[[dict[str, Any]], None]:
    def edit(doc: dict[str, Any]) -> None:
        for seg in doc["motion"]["segments"]:
            if "law" in seg:
                seg["law"] = law

    return edit


def _second_lift(value: float) -> Callable[[dict[str, Any]], None]:
    def edit(doc: dict[str, Any]) -> None:
        moves = [g for g in doc["motion"]["segments"] if g["kind"] == "return"]
        moves[0]["lift_deg"] = value

    return edit


#: Every command that reads a design, with the arguments of a short run and its output.
DESIGN_COMMANDS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "analyze": ((), ()),
    "report": (("-o", "{d}/r.html"), ("r.html",)),
    "montecarlo": (("--samples", "50"), ()),
    "profile": (("-o", "{d}/p.csv"), ("p.csv",)),
    "precision": ((), ()),
    "cut": ((), ()),
    "size": ((), ()),
}


def seeds() -> list[Seed]:
    """All the bad-input seeds of issue 32."""
    out: list[Seed] = []
    for name, (text, needles) in _bad_tables().items():
        out.append(
            Seed(
                f"derive-{name}",
                {"lift.csv": text},
                ("derive", "{d}/lift.csv", "-o", "{d}/out.csv"),
                ("lift.csv", *needles),
                ("out.csv",),
            )
        )
        out.append(
            Seed(
                f"table_file-{name}",
                {"lift.csv": text, "design.toml": _table_design("lift.csv")},
                ("analyze", "{d}/design.toml", "--curves", "{d}/curves.csv"),
                ("motion.table_file=", *needles),
                ("curves.csv",),
            )
        )
    offset0 = _edited("cw06-translating", _set("follower", "offset_mm", 0.0))
    for command, (extra, outputs) in DESIGN_COMMANDS.items():
        out.append(
            Seed(
                f"it6-offset-0-{command}",
                {"design.toml": offset0},
                (command, "{d}/design.toml", *extra),
                ("tolerances.e='IT6' cannot be applied", "give tolerances.e_um"),
                outputs,
            )
        )
    out.append(
        Seed(
            "oscillating-lift-balance",
            {"design.toml": _edited("cw06-oscillating", _second_lift(13.5))},
            ("analyze", "{d}/design.toml"),
            ("end 1.5° above where they start", "rises 15°, returns 13.5°"),
        )
    )
    out.append(
        Seed(
            "e-wrong-suffix",
            {"design.toml": _edited("cw06-translating", _set("tolerances", "e_mm", 9, drop="e"))},
            ("analyze", "{d}/design.toml"),
            ("tolerances.e_mm", "_um"),
        )
    )
    unknown = _edited("cw06-translating", _set("tolerances", "e_foo", 9, drop="e"))
    out.append(
        Seed(
            "e-unknown-suffix-lists-what-is-allowed",
            {"design.toml": unknown},
            ("analyze", "{d}/design.toml"),
            ("allowed:", "e (grade) or e_um", "phase_deg"),
            absent=("phase (grade)",),
        )
    )
    phase = _edited("cw06-translating", _set("tolerances", "phase", "IT6", drop="e"))
    for command in ("analyze", "profile"):
        extra, outputs = DESIGN_COMMANDS[command]
        out.append(
            Seed(
                f"phase-grade-{command}",
                {"design.toml": phase},
                (command, "{d}/design.toml", *extra),
                ("tolerances.phase='IT6' cannot be applied", "phase_deg"),
                outputs,
            )
        )
    cv = _edited("cw06-translating", _laws("constant_velocity"))
    for command in ("analyze", "profile"):
        extra, outputs = DESIGN_COMMANDS[command]
        out.append(
            Seed(
                f"constant-velocity-{command}",
                {"design.toml": cv},
                (command, "{d}/design.toml", *extra),
                ("'constant_velocity' is not allowed", "modified_constant_velocity"),
                outputs,
            )
        )
    return out


def run_seed(seed: Seed, d: Path) -> tuple[Outcome, list[str]]:
    """Run one seed in directory ``d``; return the outcome and every violation."""
    for name, text in seed.files.items():
        (d / name).write_text(text, encoding="utf-8")
    args = [a.replace("{d}", str(d)) for a in seed.args]
    o = run_cli(args)
    problems = judge(o)
    if o.code != 2:
        problems.append(f"exit {o.code}, expected 2: {o.err[:300]!r}")
    line = next((ln for ln in o.err.splitlines() if ln.startswith("camtol: error:")), "")
    problems += [f"error line lacks {n!r}: {line[:300]}" for n in seed.needles if n not in line]
    problems += [f"error line has {n!r}: {line[:300]}" for n in seed.absent if n in line]
    problems += [f"{name} was written" for name in seed.outputs if (d / name).exists()]
    return o, problems
