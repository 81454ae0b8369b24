"""The quality department's page: a local, read-only web application over a store.

``camtol serve`` (:mod:`camtol.cli.serve`) runs :func:`camtol.web.app.create_app` under
waitress. Flask and waitress come with the ``serve`` extra and are imported only here.
A layer of its own between the command line and the rest (docs/architecture.md): it
reads the store (:mod:`camtol.records`) and formats with the report
(:mod:`camtol.report.lot_report`), and nothing below imports it. Documented in
docs/quality-page.md.
"""

from __future__ import annotations
