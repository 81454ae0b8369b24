"""The Flask application of ``camtol serve``: lots, a lot, a record, search by serial.

Read-only: the store is opened read-only once and every page is a query. Pages (Jinja2
templates in ``camtol/web/templates``, charts as inline SVG from
:mod:`camtol.report.lot_report`: nothing fetched, no script, works offline):

* ``/``: every lot (design, cam, lot) with its parts, yield, Ppu of the largest deviation
  with its 95 % interval, the capability judgement and the out-of-control signals;
* ``/lot?design=&cam=&lot=[&characteristic=&rules=]``: the lot's summary, capability
  table, control chart (each point a link to its record), histogram and parts;
* ``/record/<id>``: the record's verdict, its deviation curve, its part report
  (traceability, figures, what it was judged on), raw inputs, options and results;
* ``/search?serial=S``: the records of a serial.

With a token every request must carry it: ``Authorization: Bearer TOKEN``, or
``?token=TOKEN`` once (a browser then keeps it in an HttpOnly cookie); anything else gets
401. Pages read summaries only, never curves, except a record's own: the lot page over
10,000 inspections stays within half a second (bench/bench_spc.py).
"""

from __future__ import annotations

import hmac
import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any
from urllib.parse import urlencode

import numpy as np
from flask import Flask, Response, abort, render_template, request, url_for

from camtol._version import __version__
from camtol.exceptions import CamtolError
from camtol.records.lot_summary import CHARACTERISTICS, summarise_lot
from camtol.records.record import InspectionRecord
from camtol.records.store import InspectionStore, open_store
from camtol.report.lot_report import (
    chart_svg,
    histogram_svg,
    sparkline_svg,
    summary_html,
    unit_of,
)

__all__ = ["create_app"]

COOKIE = "camtol_token"
#: Rows of a lot's parts table per page (the chart and the statistics show every part).
PARTS_PER_PAGE = 500


def _lot_key(r: InspectionRecord) -> tuple[str, str, str]:
    return r.design_name, r.cam, r.lot


def _lot_href(design: str, cam: str, lot: str, **extra: str) -> str:
    query = {"design": design, "cam": cam or "single", "lot": lot, **extra}
    return url_for("lot") + "?" + urlencode(query)


def _needs_details(recs: list[InspectionRecord], characteristic: str) -> bool:
    """Whether the characteristic needs the records' options and results (JSON, slower)."""
    return characteristic == "max_abs_ds" or any(r.judged_on == "dn" for r in recs)


def _doc(
    recs: list[InspectionRecord], design: str, lot: str, characteristic: str, rules: str
) -> dict[str, Any]:
    summary = summarise_lot(
        recs, design=design, lot=lot, characteristic=characteristic, rules=rules
    )
    doc = summary.to_dict()
    doc["camtol_version"] = __version__
    return doc


def _curve_svg(rec: InspectionRecord) -> str:
    """Δr(θ) of a record with its tolerance, as inline SVG."""
    w, h, ml, mr, mt, mb = 720, 240, 56, 16, 12, 30
    y = np.asarray(rec.dr_um, dtype=np.float64)
    if y.size == 0:
        return "<p>No deviation curve stored with this record.</p>"
    lo_t, hi_t = rec.tolerance_um
    lo = min(float(y.min()), lo_t)
    hi = max(float(y.max()), hi_t)
    pad = 0.08 * (hi - lo or 1.0)
    lo, hi = lo - pad, hi + pad
    xs = ml + np.arange(y.size) * (w - ml - mr) / max(y.size - 1, 1)
    ys = mt + (hi - y) * (h - mt - mb) / (hi - lo)
    step = max(1, y.size // 1440)
    pts = " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(xs[::step], ys[::step], strict=True))
    out = [
        f'<svg class="curve" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w} {h}"'
        f' width="{w}" height="{h}" role="img" aria-label="deviation curve">',
        f'<rect x="{ml}" y="{mt}" width="{w - ml - mr}" height="{h - mt - mb}" fill="none"'
        ' stroke="#999"/>',
    ]
    for v in (lo_t, 0.0, hi_t):
        ly = mt + (hi - v) * (h - mt - mb) / (hi - lo)
        colour = "#11702b" if v == 0.0 else "#b00020"
        out.append(
            f'<line x1="{ml}" x2="{w - mr}" y1="{ly:.1f}" y2="{ly:.1f}" stroke="{colour}"/>'
            f'<text x="{ml - 4}" y="{ly + 4:.1f}" font-size="11" text-anchor="end">{v:g}</text>'
        )
    out.append(f'<polyline points="{pts}" fill="none" stroke="#3465a4"/>')
    out.append(
        f'<text x="{(ml + w - mr) / 2}" y="{h - 8}" font-size="12" text-anchor="middle">'
        "cam angle θ, 0° to 360°; Δr [µm] with the tolerance</text></svg>"
    )
    return "".join(out)


def create_app(store: str, *, token: str | None = None) -> Flask:
    """Build the read-only application over a store.

    Parameters
    ----------
    store : str
        ``--store`` (opened read-only, kept open).
    token : str, optional
        When given, every request must carry it (else 401).

    Returns
    -------
    flask.Flask
    """
    app = Flask("camtol.web", template_folder=str(Path(__file__).parent / "templates"))
    db: InspectionStore = open_store(store, create=False, readonly=True)
    store_name = Path(store).name if "://" not in store else store.split("@")[-1]

    @app.before_request
    def _check_token() -> Response | None:
        if token is None:
            return None
        given = request.args.get("token")
        auth = request.headers.get("Authorization", "")
        candidates = [
            given,
            auth.removeprefix("Bearer ") if auth.startswith("Bearer ") else None,
            request.cookies.get(COOKIE),
        ]
        if any(c is not None and hmac.compare_digest(c, token) for c in candidates):
            return None
        return Response(
            "401 Unauthorized: this page needs the token given to camtol serve --token\n",
            status=401,
            mimetype="text/plain",
            headers={"WWW-Authenticate": 'Bearer realm="camtol"'},
        )

    @app.after_request
    def _remember(resp: Response) -> Response:
        if token is not None and request.args.get("token") == token:
            resp.set_cookie(COOKIE, token, httponly=True, samesite="Strict")
        resp.headers["Cache-Control"] = "no-store"
        return resp

    def page(template: str, **context: Any) -> str:
        return render_template(
            template,
            store_name=store_name,
            version=__version__,
            serial=request.args.get("serial"),
            **context,
        )

    @app.route("/")
    def lots() -> str:
        groups: dict[tuple[str, str, str], list[InspectionRecord]] = {}
        every = db.records()
        if _needs_details(every, "max_dev"):
            every = db.records(with_details=True)
        for r in every:
            groups.setdefault(_lot_key(r), []).append(r)
        rows = []
        for (design, cam, lot), recs in sorted(groups.items()):
            row: dict[str, Any] = {
                "design": design,
                "cam": cam,
                "lot": lot,
                "count": len(recs),
                "href": _lot_href(design, cam, lot),
            }
            n_pass = sum(r.verdict == "pass" for r in recs)
            row["yield"] = f"{100 * n_pass / len(recs):.1f} %"
            try:
                doc = _doc(recs, design, lot, "max_dev", "we")
            except CamtolError as exc:  # a lot that cannot be judged says why
                row.update(
                    index=str(exc)[:60], capable=False, capable_text="-", signals="-", chart=""
                )
            else:
                v = doc["ppu"]
                lo, hi = v["ci95"]
                row["index"] = f"{_f(v['value'])} [{_f(lo)}, {_f(hi)}]"
                row["capable"] = doc["capable"]
                row["capable_text"] = "yes" if doc["capable"] else "no"
                row["signals"] = len(doc["out_of_control"])
                row["chart"] = sparkline_svg(doc)
            rows.append(row)
        return page("lots.html", rows=rows)

    @app.route("/lot")
    def lot() -> str:
        design = request.args.get("design", "")
        cam = request.args.get("cam", "single")
        lot_name = request.args.get("lot", "")
        characteristic = request.args.get("characteristic", "max_dev")
        rules = request.args.get("rules", "we")
        if characteristic not in CHARACTERISTICS or rules not in ("we", "nelson"):
            abort(400)
        cam_filter = "" if cam == "single" else cam
        recs = db.records(design=design, lot=lot_name, cam=cam_filter)
        if _needs_details(recs, characteristic):
            recs = db.records(design=design, lot=lot_name, cam=cam_filter, with_details=True)
        recs = [r for r in recs if r.lot == lot_name]
        if not recs:
            abort(404)
        try:
            doc = _doc(recs, design, lot_name, characteristic, rules)
        except CamtolError as exc:  # e.g. a characteristic the records lack
            abort(Response(f"400 Bad Request: {exc}\n", status=400, mimetype="text/plain"))
        record_root = url_for("record", record_id=0)[:-1]  # one URL build, not one per part
        href: Callable[[int], str] = lambda rid: f"{record_root}{rid}"  # noqa: E731
        flags: dict[int, list[str]] = {}
        for o in doc["out_of_control"]:
            flags.setdefault(o["record_id"], []).append(o["rule"])
        n_pages = max(1, math.ceil(len(doc["parts"]) / PARTS_PER_PAGE))
        page_no = min(max(request.args.get("page", 1, type=int) or 1, 1), n_pages)
        first = (page_no - 1) * PARTS_PER_PAGE
        parts = [
            {**p, "href": href(p["record_id"]), "signals": ", ".join(flags.get(p["record_id"], []))}
            for p in doc["parts"][first : first + PARTS_PER_PAGE]
        ]
        pages = [
            (k, _lot_href(design, "" if cam == "single" else cam, lot_name,
                          characteristic=characteristic, rules=rules, page=str(k)))
            for k in range(1, n_pages + 1)
        ]  # fmt: skip
        return page(
            "lot.html",
            doc=doc,
            unit=unit_of(doc),
            characteristics=list(CHARACTERISTICS),
            summary=summary_html(doc),
            chart=chart_svg(doc, record_href=href),
            histogram=histogram_svg(doc),
            parts=parts,
            pages=pages if n_pages > 1 else [],
            page_no=page_no,
        )

    @app.route("/record/<int:record_id>")
    def record(record_id: int) -> str:
        try:
            rec = db.get(record_id)
        except CamtolError:
            abort(404)
        data = rec.summary()
        summary = [(k, _cell(v)) for k, v in data.items()]
        details = json.dumps(
            {"options": rec.options, "results": rec.results}, indent=2, default=str
        )
        return page(
            "record.html",
            rec=rec,
            judged_on={"dn": "Δn (normal)", "dr": "Δr (radial)"}.get(
                rec.judged_on or "", "an unrecorded deviation"
            ),
            lot_href=_lot_href(rec.design_name, rec.cam, rec.lot),
            curve=_curve_svg(rec),
            summary=summary,
            inputs=db.input_list(record_id),
            details=details,
        )

    @app.route("/search")
    def search() -> str:
        serial = request.args.get("serial", "").strip()
        found = [
            {
                "id": r.id,
                "href": url_for("record", record_id=r.id),
                "when": r.inspected_at.strftime("%Y-%m-%d %H:%M"),
                "design": r.design_name,
                "cam": r.cam,
                "lot": r.lot,
                "verdict": r.verdict,
            }
            for r in (db.records() if serial else [])
            if r.serial == serial
        ]
        return page("search.html", found=found)

    return app


def _cell(v: object) -> str:
    """Format a record's value for the page: floats to 6 significant digits."""
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, list):
        return "[" + ", ".join(_cell(x) for x in v) + "]"
    return str(v)


def _f(x: float | None) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{x:.2f}"
