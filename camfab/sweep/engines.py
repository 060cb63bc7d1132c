"""Where a sweep's batches run: in this process, on a local pool of worker processes, or on a
Dask cluster, all through the ``concurrent.futures`` executor interface; the rows come back in
the variants' order whatever order the batches finish in, with no more batches in flight than
keep the workers busy (the memory stays flat over a sweep of millions).

The local pool is the batch builder's (:func:`camfab.batch.worker_pool`): the workers are forked
from this process after it has analysed one variant, so they start with every library a row
needs imported. Dask's workers import them once each, with the first batch they run.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from camfab.sweep.rows import Row
from camfab.sweep.vary import SweepError

#: Variants per batch sent to a local worker: some 0.1–0.2 s of work, so that sending a batch
#: and its rows costs little next to it.
BATCH = 24
#: Variants per batch sent to a Dask worker: some 0.5–1 s of work, so that the scheduler's and
#: the client's cost per task (milliseconds, on the same processors on one machine) stays far
#: under 10 %.
DASK_BATCH = 128
#: Batches in flight per worker (count): one running, the next ones waiting in its queue.
AHEAD = 3
#: How long to wait for a Dask scheduler to answer (s).
CONNECT_SECONDS = 5

Task = Callable[[list[tuple[int, tuple[Any, ...]]]], list[Row]]


def in_order(submit: Callable[[Any], Any], batches: Iterable[Any], ahead: int,
             ) -> Iterator[list[Row]]:
    """The rows of each of *batches*, in order: *submit* (an executor's, for the task) called
    for each batch, at most *ahead* of them waiting at once."""
    pending: deque[Any] = deque()
    for batch in batches:
        pending.append(submit(batch))
        if len(pending) >= ahead:
            yield pending.popleft().result()
    while pending:
        yield pending.popleft().result()


def local_rows(task: Task, batches: Iterable[Any], jobs: int,
               warm: Callable[[], object]) -> Iterator[list[Row]]:
    """The rows of *batches* run by *task* in this process (*jobs* 1) or on *jobs* worker
    processes forked after *warm* (which imports what a row needs)."""
    if jobs == 1:
        for batch in batches:
            yield task(batch)
        return
    from camfab.batch import signals_held, worker_pool

    pool = worker_pool(jobs, warm)
    try:
        with signals_held():  # the pool is set up whole before a stop can break in
            first = pool.submit(task, [])
        first.result()
        yield from in_order(lambda batch: pool.submit(task, batch), batches, AHEAD * jobs)
    except BaseException:  # Ctrl-C: the batches running are dropped, the rows so far kept
        with signals_held():
            pool.shutdown(wait=True, cancel_futures=True)
        raise
    with signals_held():
        pool.shutdown()


def dask_rows(task: Task, batches: Iterable[Any], address: str) -> Iterator[list[Row]]:
    """The rows of *batches* run by *task* on the Dask cluster whose scheduler is at
    *address* (``tcp://HOST:PORT``), through its ``concurrent.futures`` executor. The
    scheduler is reached at once (raises :class:`SweepError` when it cannot be), the batches
    are sent as the rows are taken."""
    client = connect(address)
    return _dask_stream(client, task, batches)


def _dask_stream(client: Any, task: Task, batches: Iterable[Any]) -> Iterator[list[Row]]:
    try:
        executor = client.get_executor(pure=False)
        workers = max(1, sum(w.get("nthreads", 1) for w in
                             client.scheduler_info().get("workers", {}).values()))
        try:
            yield from in_order(lambda batch: executor.submit(task, batch), batches,
                                AHEAD * workers)
        except BaseException:
            executor.shutdown(wait=False)
            raise
    finally:
        client.close()


def connect(address: str) -> Any:
    """A Dask client of the scheduler at *address* (raises :class:`SweepError`)."""
    try:
        from distributed import Client
    except ImportError:
        raise SweepError("--scheduler needs Dask's distributed scheduler: pip install "
                         "'camfab[cluster]'") from None
    try:
        return Client(address, timeout=CONNECT_SECONDS, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise SweepError(f"--scheduler {address}: cannot reach a Dask scheduler there "
                         f"({' '.join(str(exc).split())[:200]})") from None
