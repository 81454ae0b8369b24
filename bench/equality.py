"""Behaviour unchanged: every command's ``--json`` and ``--curves`` on every built-in example.

``python bench/equality.py record FILE.json`` runs the matrix below in-process and writes, for
each invocation, its exit status and the SHA-256 of what it printed (stdout, stderr) and of
every file it wrote (the ``--curves`` CSV, exported profiles, the report's JSON).
``python bench/equality.py compare FILE.json`` runs the same matrix and lists every
invocation whose exit status or output differs (exit status 1 when any does).

A refactoring that must not change behaviour (issue 27) records the file before and
compares after. What varies between two runs of the same code is normalised first: the
scratch directory's path, and the few wall-clock fields (an inspection's ``stored_at``),
so ``record`` followed by ``compare`` on one commit reports no difference.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import re
import sys
import tempfile
import warnings
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent / "tests" / "cli"))

EXAMPLES = [
    "cw06-translating",
    "cw06-oscillating",
    "roller-translating",
    "roller-oscillating",
    "cw11-conjugate",
    "cw11-experiment",
    "popa-eccentric",
]

#: Per example: (name, arguments); ``{ex}`` is the example, ``{tmp}`` the scratch folder.
PER_EXAMPLE = [
    ("analyze-json", ["analyze", "-e", "{ex}", "--step", "0.5", "--json"]),
    ("analyze-curves", ["analyze", "-e", "{ex}", "--step", "1", "-q", "--curves", "{out}.csv"]),
    ("analyze-text", ["analyze", "-e", "{ex}", "--step", "1"]),
    ("verify-json", ["verify", "-e", "{ex}", "--step", "1", "--json"]),
    ("size-json", ["size", "-e", "{ex}", "--json"]),
    ("precision-json", ["precision", "-e", "{ex}", "--decimals", "4", "--json"]),
    ("cut-json", ["cut", "-e", "{ex}", "--cut-step", "2", "--json"]),
    ("cut-curves", ["cut", "-e", "{ex}", "--cut-step", "2", "--curves", "{out}.csv"]),
    ("conjugate-json", ["conjugate", "-e", "{ex}", "--step", "1", "--json"]),
    ("conjugate-curves", ["conjugate", "-e", "{ex}", "--step", "1", "--curves", "{out}.csv"]),
    ("montecarlo-json", ["montecarlo", "-e", "{ex}", "--samples", "400", "--json"]),
    (
        "montecarlo-curves",
        ["montecarlo", "-e", "{ex}", "--samples", "400", "--curves", "{out}.csv"],
    ),
    ("montecarlo-exact", ["montecarlo", "-e", "{ex}", "--samples", "8", "--mode", "exact"]),
    ("allocate-json", ["allocate", "-e", "{ex}", "--json"]),
    ("profile-csv", ["profile", "-e", "{ex}", "-o", "{out}.csv", "--json"]),
    ("profile-dxf", ["profile", "-e", "{ex}", "-o", "{out}.dxf", "--json"]),
    ("gcode", ["profile", "-e", "{ex}", "-o", "{out}.nc"]),
    ("simulate-cmm", ["simulate", "cmm", "-e", "{ex}", "-o", "{out}.csv", "--seed", "2"]),
]

#: Keys whose values are wall-clock times or library versions, not results.
VOLATILE_KEYS = re.compile(r'"(stored_at|created_at|inspected_at|time_utc)": "[^"]*"')
#: The HTML report's "generated YYYY-MM-DD HH:MM UTC" stamp.
GENERATED = re.compile(r"generated \d{4}-\d\d-\d\d \d\d:\d\d UTC")


#: Set EQUALITY_KEEP=DIR to keep every normalised output file there (to read a difference).
KEEP = os.environ.get("EQUALITY_KEEP")


def _invocations(tmp: str) -> list[tuple[str, list[str]]]:
    from json_invocations import INVOCATIONS, prepare

    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        subs = prepare(tmp)
    out: list[tuple[str, list[str]]] = []
    for command, runs in INVOCATIONS.items():
        for k, args in enumerate(runs):
            out.append((f"schema:{command}:{k}", [a.format(**subs) for a in args]))
    for ex in EXAMPLES:
        for name, args in PER_EXAMPLE:
            key = f"{ex}:{name}"
            out.append((key, [a.format(ex=ex, out=f"{tmp}/{key.replace(':', '_')}") for a in args]))
    return out


def _dxf_entities(path: Path) -> bytes:
    """The model space's entities as text: ezdxf stamps times and GUIDs, and may order
    its objects section differently from one run to the next."""
    import ezdxf

    rows = []
    for e in ezdxf.readfile(path).modelspace():
        attribs = {k: v for k, v in e.dxfattribs().items() if k not in {"handle", "owner"}}
        points = list(e.get_points()) if e.dxftype() == "LWPOLYLINE" else []
        rows.append(f"{e.dxftype()} {sorted(attribs.items())} {points}")
    return "\n".join(rows).encode()


def _digest(text: str | bytes) -> str:
    data = text.encode() if isinstance(text, str) else text
    return hashlib.sha256(data).hexdigest()


def _normalise(text: str, tmp: str) -> str:
    text = VOLATILE_KEYS.sub(r'"\1": "-"', text.replace(tmp, "{tmp}"))
    return GENERATED.sub("generated -", text)


def run_matrix() -> dict[str, dict[str, object]]:
    """Run every invocation; return its exit status and output digests by name."""
    from camtol.cli import main

    results: dict[str, dict[str, object]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for key, args in _invocations(tmp):
            before = {p: p.stat().st_mtime_ns for p in Path(tmp).iterdir()}
            out, err = io.StringIO(), io.StringIO()
            with (
                contextlib.redirect_stdout(out),
                contextlib.redirect_stderr(err),
                warnings.catch_warnings(),
            ):
                warnings.simplefilter("ignore")
                code = main(args)
            written = {}
            for p in sorted(Path(tmp).iterdir()):
                if p.is_file() and before.get(p) != p.stat().st_mtime_ns:
                    raw = p.read_bytes()
                    if p.suffix in {".csv", ".json", ".nc", ".svg", ".txt", ".html"}:
                        raw = _normalise(raw.decode("utf-8", "replace"), tmp).encode()
                    if p.suffix == ".db":  # a store: its rows are checked through records
                        continue
                    if p.suffix == ".dxf":
                        raw = _dxf_entities(p)
                    if KEEP:
                        (Path(KEEP) / f"{key.replace(':', '_')}_{p.name}").write_bytes(raw)
                    written[p.name] = _digest(raw)
            results[key] = {
                "exit": code,
                "stdout": _digest(_normalise(out.getvalue(), tmp)),
                "stderr": _digest(_normalise(err.getvalue(), tmp)),
                "files": written,
            }
    return results


def main(argv: list[str]) -> int:
    if len(argv) != 2 or argv[0] not in {"record", "compare"}:
        print(__doc__.split("\n\n")[1])
        return 2
    mode, path = argv
    results = run_matrix()
    if mode == "record":
        Path(path).write_text(json.dumps(results, indent=1, sort_keys=True) + "\n")
        print(f"recorded {len(results)} invocations in {path}")
        return 0
    base = json.loads(Path(path).read_text())
    differ = [k for k in sorted(set(base) | set(results)) if base.get(k) != results.get(k)]
    for k in differ:
        b, r = base.get(k, {}), results.get(k, {})
        parts = [f for f in ("exit", "stdout", "stderr", "files") if b.get(f) != r.get(f)]
        print(f"DIFFERS {k}: {', '.join(parts) or 'missing'}")
    same = len(results) - len(differ)
    print(f"{same} of {len(set(base) | set(results))} invocations identical")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
