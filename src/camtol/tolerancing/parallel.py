"""Run linear Monte Carlo tasks on a Dask cluster (optional extra ``camtol[dask]``).

The tasks are the same chunk groups as on one machine and their results are merged in
chunk order (:func:`camtol.tolerancing.linear.merge`), so a seed gives the same numbers
on one core, on a ``LocalCluster`` and on a remote cluster.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import camtol.tolerancing.linear as lin
from camtol.exceptions import DesignError

__all__ = ["run_on_dask"]


def _client(scheduler: Any) -> tuple[Any, bool]:
    try:
        from distributed import Client
    except ImportError:
        raise DesignError(
            "scheduler: Dask is not installed; install the extra: pip install 'camtol[dask]'"
        ) from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str) or not scheduler:
        raise DesignError(
            f"scheduler={scheduler!r} is not allowed; give an address such as"
            " tcp://host:8786 or a dask.distributed.Client"
        )
    try:
        return Client(scheduler, timeout="10s"), True  # type: ignore[no-untyped-call]
    except (OSError, TimeoutError, ValueError) as exc:
        raise DesignError(f"scheduler={scheduler!r}: cannot connect ({exc})") from None


def run_on_dask(
    scheduler: Any,
    spec: lin.LinearSpec,
    tasks: list[tuple[int, ...]],
    fold: Callable[[lin.LinearTotals], None],
) -> None:
    """Run the tasks on a Dask cluster, handing each result to ``fold`` as it finishes.

    Parameters
    ----------
    scheduler : str or dask.distributed.Client
        Scheduler address (``tcp://host:port``) or a connected client.
    spec : LinearSpec
        The study, sent once to the cluster.
    tasks : list of tuple of int
        Chunk indices of each task.
    fold : callable
        Receives each task's result (integer sums commute; floating partials are kept
        per chunk and folded in chunk order at the end).
    """
    from distributed import as_completed

    client, owned = _client(scheduler)
    try:
        remote = client.scatter(spec, broadcast=True)
        futures = [client.submit(lin.run_task, remote, t, pure=False) for t in tasks]
        for fut in as_completed(futures):  # type: ignore[no-untyped-call]
            fold(fut.result())
            fut.release()
    finally:
        if owned:
            client.close()
