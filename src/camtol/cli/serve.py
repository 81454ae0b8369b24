"""``camtol serve``: the quality department's read-only page of an inspection store.

Runs :func:`camtol.web.app.create_app` under waitress (the ``serve`` extra: Flask and
waitress, imported only here). Bound to 127.0.0.1 by default; another host is refused
without ``--token`` (then every request needs it, a wrong one gets 401). Exit status 0
when stopped (Ctrl-C), 2 on bad input (no such store, a non-local host without a token, the
extra not installed). Documented in docs/quality-page.md.
"""

from __future__ import annotations

import click

from camtol.cli.common import EXIT_OK, _Exit, fail, run_guarded
from camtol.cli.recording import STORE_HELP, open_for_reading

__all__ = ["serve"]

#: Hosts that reach this machine only.
LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1")


@click.command("serve")
@click.option("--store", "store", required=True, metavar="DB", help=STORE_HELP)
@click.option(
    "--host", default="127.0.0.1", show_default=True, metavar="HOST", help="Address to listen on."
)
@click.option(
    "--port",
    type=click.IntRange(1, 65535),
    default=8000,
    show_default=True,
    metavar="PORT",
    help="TCP port.",
)
@click.option(
    "--token",
    metavar="TOKEN",
    help="Require this token on every request (needed for a non-local --host).",
)
def serve(store: str, host: str, port: int, token: str | None) -> None:
    """Serve the quality department's read-only page of a store: lots, charts, records.

    Pages: every lot with its yield, capability and out-of-control signals; a lot with its
    control chart, histogram and parts; a record with its verdict, deviation curve and
    part report; search by serial. Nothing is fetched from the internet (charts are inline
    SVG). With --token, give it once as ?token=TOKEN (the browser keeps it) or as an
    `Authorization: Bearer TOKEN` header. Stop with Ctrl-C.
    """

    def body() -> int:
        if host not in LOCAL_HOSTS and not token:
            fail(
                f"--host={host!r}: not a local address (allowed without --token:"
                f" {', '.join(LOCAL_HOSTS)}); give --token TOKEN to serve other machines"
            )
        if token is not None and len(token) < 8:
            fail(f"--token: {len(token)} characters; allowed at least 8")
        try:
            import waitress

            from camtol.web.app import create_app
        except ImportError as exc:
            fail(
                f"camtol serve needs the serve extra ({exc.name} is missing):"
                " pip install 'camtol[serve]'"
            )
        with open_for_reading(store):  # a missing or foreign store: one line, exit 2
            pass
        app = create_app(store, token=token)
        click.echo(f"camtol serve: http://{host}:{port}/ (read-only; Ctrl-C stops)", err=True)
        waitress.serve(app, host=host, port=port, threads=4, _quiet=True)
        return EXIT_OK

    raise _Exit(run_guarded(body))
