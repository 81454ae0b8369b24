"""Fuzzing camtol from the outside: mutate designs, run the CLI in process, judge the outcome.

The property every run must satisfy (issue 9):

* exit 0 with valid outputs: strict JSON (no ``NaN``), CSV/DXF/SVG without non-finite
  numbers, an exported profile that is a simple closed curve without cusps, whose
  pressure angle recomputed from the exported points stays below 90°;
* exit 1 only for a failed part (``conjugate``/``verify``);
* exit 2 with exactly ONE ``camtol: error:`` line of bounded length;
* never a traceback, never a "numerical failure" (the safety net of
  :func:`camtol.cli.app.run_guarded` must not be what catches a bad value).

The outputs are checked independently of camtol's own computations (shapely for
self-intersection, finite differences of the exported points for cusps and pressure
angles).
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import re
import tempfile
import traceback
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from camtol.cli.app import main
from camtol.config.design_file import example_names, example_text

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

EXAMPLES = tuple(example_names())
MUTATIONS = (
    "delete",
    "zero",
    "negative",
    "nan",
    "inf",
    "-inf",
    "huge",
    "tiny",
    "int_huge",
    "string",
    "numeric_string",
    "bool",
    "list",
    "table",
    "wrong_unit",
    "empty",
)
MAX_ERROR_CHARS = 700


# --- TOML ----------------------------------------------------------------------------------
def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, Sequence):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(type(v))


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def to_toml(doc: Mapping[str, Any]) -> str:
    """Serialise a design mapping (top-level scalars, then one table per section)."""
    lines = [f"{_key(k)} = {_toml_value(v)}" for k, v in doc.items() if not isinstance(v, dict)]
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append(f"\n[{_key(k)}]")
            lines += [f"{_key(kk)} = {_toml_value(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


def example_mapping(name: str) -> dict[str, Any]:
    """The built-in example as a mutable mapping."""
    return tomllib.loads(example_text(name))


# --- mutating fields -----------------------------------------------------------------------
Path_ = tuple[Any, ...]


def leaf_paths(doc: Any, prefix: Path_ = ()) -> list[Path_]:
    """Paths (keys and list indices) of every field, leaves and containers alike."""
    out: list[Path_] = []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out.append((*prefix, k))
            out += leaf_paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:4]):  # long tables: the first entries stand for all
            out.append((*prefix, i))
            out += leaf_paths(v, (*prefix, i))
    return out


def _parent(doc: Any, path: Path_) -> Any:
    for p in path[:-1]:
        doc = doc[p]
    return doc


def mutate(doc: dict[str, Any], path: Path_, kind: str) -> dict[str, Any]:
    """Return a copy of ``doc`` with the field at ``path`` mutated by ``kind``."""
    doc = json.loads(json.dumps(doc))  # deep copy (the examples hold no NaN)
    parent = _parent(doc, path)
    key = path[-1]
    old = parent[key]
    num = old if isinstance(old, int | float) and not isinstance(old, bool) else 1.0
    new: Any
    if kind == "delete":
        if isinstance(parent, list):
            parent.pop(key)
        else:
            del parent[key]
        return doc
    if kind == "wrong_unit":
        if isinstance(parent, dict) and isinstance(key, str):
            swap = {"_mm": "_um", "_um": "_mm", "_deg": "_rad", "_rad": "_deg"}
            for a, b in swap.items():
                if key.endswith(a):
                    parent[key[: -len(a)] + b] = parent.pop(key)
                    return doc
            parent[key + "_mm"] = parent.pop(key)
        return doc
    new = {
        "zero": 0,
        "negative": -abs(num) if num else -1.0,
        "nan": float("nan"),
        "inf": float("inf"),
        "-inf": float("-inf"),
        "huge": 1e300,
        "tiny": 1e-300,
        "int_huge": 10**30,
        "string": "forty",
        "numeric_string": str(num),
        "bool": True,
        "list": [num, [num]],
        "table": {"value": num},
        "empty": "",
    }[kind]
    parent[key] = new
    return doc


# --- running the CLI -----------------------------------------------------------------------
@dataclass
class Outcome:
    """One CLI run: arguments, exit code, streams, and what it wrote."""

    args: list[str]
    code: int
    out: str
    err: str
    outputs: dict[str, Path] = field(default_factory=dict)
    crash: str = ""


def run_cli(args: Sequence[str], outputs: Mapping[str, Path] | None = None) -> Outcome:
    """Run ``camtol`` in process; an exception escaping :func:`main` is a crash."""
    out, err = io.StringIO(), io.StringIO()
    crash = ""
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(args))
        except BaseException:  # noqa: BLE001 - anything escaping is the finding
            crash = traceback.format_exc()
            code = -1
    return Outcome(list(args), code, out.getvalue(), err.getvalue(), dict(outputs or {}), crash)


# --- judging -------------------------------------------------------------------------------
def _strict_json(text: str) -> Any:
    def refuse(name: str) -> Any:
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def _check_csv(path: Path) -> list[str]:
    problems = []
    with path.open(encoding="utf-8", newline="") as fh:
        rows = list(csv.reader(fh))
    for i, row in enumerate(rows[1:], start=2):
        for cell in row:
            c = cell.strip().lower()
            if c in {"nan", "inf", "-inf", "+inf", "infinity", "-infinity"}:
                problems.append(f"{path.name} line {i}: non-finite cell {cell!r}")
                return problems
    return problems


def _check_text_numbers(path: Path) -> list[str]:
    text = path.read_text(encoding="utf-8", errors="replace")
    if re.search(r"(?<![A-Za-z])(nan|inf|infinity)(?![A-Za-z])", text, flags=re.I):
        return [f"{path.name}: holds a non-finite number"]
    return []


def profile_problems(x: np.ndarray, y: np.ndarray, label: str) -> list[str]:
    """A closed exported curve must be simple and free of cusps (independent check)."""
    from shapely.geometry import LinearRing

    problems = []
    if x.size < 8:
        return [f"{label}: only {x.size} vertices"]
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        return [f"{label}: non-finite vertices"]
    edge = np.hypot(np.diff(np.append(x, x[0])), np.diff(np.append(y, y[0])))
    keep = edge > 1e-9 * max(float(np.ptp(x)), float(np.ptp(y)), 1e-9)
    x, y = x[keep], y[keep]  # a repeated vertex has no direction
    ring = LinearRing(np.column_stack([x, y]))
    if not ring.is_simple:
        problems.append(f"{label}: the exported curve intersects itself")
    ex, ey = np.diff(np.append(x, x[0])), np.diff(np.append(y, y[0]))
    heading = np.arctan2(ey, ex)
    turn = np.angle(np.exp(1j * (np.roll(heading, -1) - heading)))
    if np.max(np.abs(turn)) > math.radians(60):
        k = int(np.argmax(np.abs(turn)))
        problems.append(
            f"{label}: cusp or corner, the curve turns by {math.degrees(turn[k]):.1f}°"
            f" at vertex {k}"
        )
    if abs(np.sum(turn) - 2 * math.pi) > 1e-3:
        problems.append(f"{label}: total turning {math.degrees(np.sum(turn)):.2f}°, not 360°")
    return problems


def _rotation_sense(theta: np.ndarray, x: np.ndarray, y: np.ndarray) -> tuple[int, np.ndarray]:
    """Which way the points rotate back into the ground frame: the sense that makes the
    follower path (pitch curve in the ground frame) a line or a circle arc, smallest."""
    best: tuple[float, int, np.ndarray] | None = None
    for sigma in (1, -1):
        c, s = np.cos(sigma * theta), np.sin(sigma * theta)
        g = np.column_stack([c * x - s * y, s * x + c * y])
        spread = float(np.ptp(g[:, 0]) * np.ptp(g[:, 1]))  # a path, not a disk
        if best is None or spread < best[0]:
            best = (spread, sigma, g)
    assert best is not None
    return best[1], best[2]


def pitch_pressure_angle_ok(theta: np.ndarray, x: np.ndarray, y: np.ndarray) -> list[str]:
    """Recompute the pressure angle of a roller follower from the exported pitch curve.

    In the ground frame the roller centre moves on a line (translating) or a circle
    (oscillating), found by fitting the rotated points; the pressure angle is the angle
    between the pitch curve's normal and that path. It must stay below 90°: the normal
    must never become perpendicular to the follower's path.
    """
    sigma, g = _rotation_sense(theta, x, y)
    # Path of the roller centre: a line (translating) or a circle (oscillating).
    centred = g - g.mean(axis=0)
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    if sv[1] <= 1e-7 * sv[0]:  # collinear: a translating follower's axis
        tx, ty = np.full(len(g), vt[0, 0]), np.full(len(g), vt[0, 1])
    else:  # algebraic circle fit: the arc of an oscillating follower's roller centre
        a = np.column_stack([g[:, 0], g[:, 1], np.ones(len(g))])
        sol, *_ = np.linalg.lstsq(a, -(g[:, 0] ** 2 + g[:, 1] ** 2), rcond=None)
        cx, cy = -sol[0] / 2, -sol[1] / 2
        tx, ty = -(g[:, 1] - cy), g[:, 0] - cx  # tangent of the circle
    moving = np.hypot(np.gradient(g[:, 0]), np.gradient(g[:, 1])) > 0
    # Normal of the pitch curve in the cam frame, rotated into the ground frame.
    dx, dy = np.roll(x, -1) - np.roll(x, 1), np.roll(y, -1) - np.roll(y, 1)
    c, s = np.cos(sigma * theta), np.sin(sigma * theta)
    gdx, gdy = c * dx - s * dy, s * dx + c * dy
    nx, ny = gdy, -gdx
    cosphi = np.abs(nx * tx + ny * ty) / (np.hypot(nx, ny) * np.hypot(tx, ty))
    if moving.any() and np.min(cosphi) < math.cos(math.radians(89.9)):
        k = int(np.argmin(cosphi))
        return [
            f"pitch curve: pressure angle recomputed from the exported points reaches"
            f" {math.degrees(math.acos(min(1.0, cosphi[k]))):.2f}°"
            f" at θ={math.degrees(theta[k]):.2f}°"
        ]
    return []


def check_profile_csv(path: Path) -> list[str]:
    """Independent checks of an exported profile CSV (every layer)."""
    with path.open(encoding="utf-8", newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    head = rows[0]
    data = np.array([[float(c) if c else np.nan for c in r] for r in rows[1:]])
    problems: list[str] = []
    layers = sorted({h.rsplit("_x_mm", 1)[0] for h in head if h.endswith("_x_mm")})
    for layer in layers:
        ix, iy = head.index(f"{layer}_x_mm"), head.index(f"{layer}_y_mm")
        it = head.index(f"{layer}_theta_deg") if f"{layer}_theta_deg" in head else 0
        keep = np.isfinite(data[:, ix])
        x, y = data[keep, ix], data[keep, iy]
        theta = np.radians(data[keep, it])
        if layer.endswith("cutter_path"):
            continue
        problems += profile_problems(x, y, layer)
        if layer.endswith("pitch_curve") and not problems:
            problems += pitch_pressure_angle_ok(theta, x, y)
    return problems


def judge(o: Outcome) -> list[str]:
    """Every violation of the property by one run (empty when it holds)."""
    if o.crash or "Traceback" in o.err:
        tail = (o.crash or o.err).strip().splitlines()
        return [f"traceback: {' | '.join(line.strip() for line in tail[-5:])}"[:1500]]
    problems: list[str] = []
    errors = [ln for ln in o.err.splitlines() if ln.startswith("camtol: error:")]
    if o.code == 2:
        if len(errors) != 1:
            problems.append(f"exit 2 with {len(errors)} error lines: {o.err[:500]!r}")
        elif len(errors[0]) > MAX_ERROR_CHARS:
            problems.append(f"error line of {len(errors[0])} characters")
        elif "numerical failure" in errors[0]:
            problems.append(f"caught only by the safety net: {errors[0][:300]}")
        return problems
    if o.code not in (0, 1):
        return [f"exit status {o.code}: {o.err[:300]!r}"]
    if errors:
        problems.append(f"exit {o.code} with an error line: {errors[0][:300]}")
    if "--json" in o.args:
        try:
            _strict_json(o.out)
        except ValueError as exc:
            problems.append(f"--json output is not strict JSON: {exc}")
    for role, p in o.outputs.items():
        if not p.exists():
            problems.append(f"{role} {p.name} was not written")
            continue
        if p.suffix == ".csv":
            problems += _check_csv(p)
            if role == "profile":
                problems += check_profile_csv(p)
        elif p.suffix in (".svg", ".dxf", ".html"):
            problems += _check_text_numbers(p) if p.suffix != ".html" else []
    return problems


def run_design(text: str | bytes, command: str, *, extra: Sequence[str] = ()) -> list[Outcome]:
    """Write a design file and run ``command`` on it (with its outputs) in a temp dir."""
    with tempfile.TemporaryDirectory(prefix="camtol-fuzz-") as tmp:
        d = Path(tmp)
        design = d / "design.toml"
        if isinstance(text, bytes):
            design.write_bytes(text)
        else:
            design.write_text(text, encoding="utf-8")
        args, outputs = command_line(command, design, d)
        o = run_cli([*args, *extra], outputs)
        o.problems = judge(o)  # type: ignore[attr-defined]  # judged while the files exist
        return [o]


def command_line(command: str, design: Path, d: Path) -> tuple[list[str], dict[str, Path]]:
    """Arguments of a fast run of ``command`` and the outputs it should write."""
    if command == "analyze":
        out = {"curves": d / "curves.csv"}
        return [
            "analyze",
            str(design),
            "--step",
            "1",
            "--json",
            "--curves",
            str(out["curves"]),
        ], out
    if command == "profile":
        out = {"profile": d / "profile.csv"}
        return ["profile", str(design), "-o", str(out["profile"]), "--tolerance", "2"], out
    if command == "profile-dxf":
        out = {"dxf": d / "profile.dxf"}
        return ["profile", str(design), "-o", str(out["dxf"]), "--tolerance", "5"], out
    if command == "verify":
        return ["verify", str(design), "--step", "2", "--json", "--no-polyline"], {}
    if command == "conjugate":
        out = {"curves": d / "fixture.csv"}
        return [
            "conjugate",
            str(design),
            "--step",
            "1",
            "--json",
            "--curves",
            str(out["curves"]),
        ], out
    if command == "report":
        out = {"report": d / "r.html"}
        return ["report", str(design), "--step", "2", "-o", str(out["report"])], out
    raise ValueError(command)


COMMANDS = ("analyze", "profile", "profile-dxf", "verify", "conjugate", "report")
FAST_COMMANDS = ("analyze", "profile", "verify", "conjugate")


def problems_of(outcomes: Sequence[Outcome]) -> list[str]:
    """Collect the judged problems, each prefixed with its command line."""
    out = []
    for o in outcomes:
        for p in getattr(o, "problems", []):
            out.append(f"{' '.join(o.args[:1])}: {p}")
    return out
