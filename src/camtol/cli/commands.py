"""The commands that live in their own modules, imported only when they run.

Each entry: name → (module, attribute, short help). ``camtol --help`` lists the short help
without importing the module; a test checks it equals the command's own first line.
"""

from __future__ import annotations

__all__ = ["COMMANDS", "short_help"]

COMMANDS: dict[str, tuple[str, str, str]] = {
    "analyze": (
        "camtol.cli.analyze",
        "analyze",
        "Analyse a design: profile, pressure and shift angles, and the follower's errors.",
    ),
    "examples": (
        "camtol.cli.examples",
        "examples",
        "List the built-in example designs (`camtol examples show NAME` prints one).",
    ),
    "conjugate": (
        "camtol.cli.conjugate",
        "conjugate",
        "Conjugate-cam fixture: Δf parts, inverse analysis Δr_A,est / Δr_B,est, acceptance.",
    ),
    "profile": (
        "camtol.cli.report",
        "profile",
        "Export the cam profile for CAD/CAM (CSV, DXF or SVG, chosen by the suffix of -o).",
    ),
    "report": (
        "camtol.cli.report",
        "report",
        "Write a self-contained HTML report: verdict, inputs, conventions, extremes, figures.",
    ),
    "verify": (
        "camtol.cli.verify",
        "verify",
        "Verify a design's analytic results with the exact contact engine (THEORY §5).",
    ),
    "size": (
        "camtol.cli.size",
        "size",
        "Find the smallest base radius (offset, linkage) meeting pressure-angle and curvature"
        " limits.",
    ),
    "dynamics": (
        "camtol.cli.dynamics",
        "dynamics",
        "Follower dynamics at speed: contact force, jump, vibration, torque, contact stress.",
    ),
    "precision": (
        "camtol.cli.manufacturing",
        "precision",
        "How precise must the lift table be? (THEORY §6.1, §6.2)",
    ),
    "cut": (
        "camtol.cli.manufacturing",
        "cut",
        "Simulate cutting at discrete cam angles and follow the cut cam exactly (THEORY §6.3).",
    ),
    "derive": (
        "camtol.cli.manufacturing",
        "derive",
        "V, A and J of a measured or tabulated lift, with a stated smoothing (THEORY §6.1).",
    ),
    "records": (
        "camtol.cli.records",
        "records",
        "Inspection records: list, show, lot statistics, re-run, void, export (SQL).",
    ),
    "montecarlo": (
        "camtol.cli.tolerancing",
        "montecarlo",
        "Monte Carlo tolerance analysis: ΔS band, max |ΔS|, yield, contributions.",
    ),
    "allocate": (
        "camtol.cli.tolerancing",
        "allocate",
        "Choose the coarsest (cheapest) IT grade per source that meets a spec.",
    ),
    "inspect": (
        "camtol.cli.inspect",
        "inspect",
        "Inspect a machined cam from CMM points: registration, deviations, follower error.",
    ),
    "simulate": (
        "camtol.cli.simulate",
        "simulate",
        "Digital twins: simulated measurement files with their truth beside them.",
    ),
    "serve": (
        "camtol.cli.serve",
        "serve",
        "Serve the quality department's read-only page of a store: lots, charts, records.",
    ),
}


def short_help(text: str, limit: int = 45) -> str:
    """Shorten a command's help to one line the way click does for ``--help`` listings.

    click deprecated its own helper (``click.utils.make_default_short_help``, to go in
    Click 9), so the lazy listing keeps this copy of the rule: the first paragraph, cut
    at the first sentence end or with ``...`` at the last word that fits.

    Parameters
    ----------
    text : str
        The command's help text.
    limit : int
        Largest length of the result. [characters]

    Returns
    -------
    str
        The short help.
    """
    end = text.find("\n\n")
    words = (text if end == -1 else text[:end]).split()
    if words and words[0] == "\b":
        words = words[1:]
    if not words:
        return ""
    total, last = 0, len(words) - 1
    i = 0
    for i, word in enumerate(words):
        total += len(word) + (i > 0)
        if total > limit:
            break
        if word[-1] == ".":
            return " ".join(words[: i + 1])
        if total == limit and i != last:
            break
    else:
        return " ".join(words)
    total += len("...")
    while i > 0:
        total -= len(words[i]) + (i > 0)
        if total <= limit:
            break
        i -= 1
    return " ".join(words[:i]) + "..."
