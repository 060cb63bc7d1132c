"""Worker processes of a batch or a sweep: a pool forked from camfab's process, and what happens
when a worker dies.

A worker can die under the task it runs — a native library's crash (SIGSEGV), the kernel's
out-of-memory killer, a ``kill -9``. The pool cannot tell which of its tasks killed it: every
task in flight fails with it. So those tasks are run again, each in a process of its own
(:func:`isolated`), which tells them apart: the one whose process dies again is reported as
dead (:class:`Died`, with the signal), the others' results come as if nothing had happened,
and the remaining tasks go on in a new pool. One dead worker costs one design (or one sweep
variant), never the batch.

A worker ignores Ctrl-C (the batch's process decides: it lets the running tasks finish and
starts no more). SIGTERM and SIGHUP stop a worker as they stop camfab: a running task's cleanup
runs (its temporary files removed) and the worker ends there, and a worker waiting for work ends
without a word. A stopped worker never goes back for work: two stops that come together (its
process group's and the pool's own, sent when another worker has ended) are one to Python, and
a worker that took the one as its task's end would then wait on the pool's queue for ever.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import suppress
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from camfab.stopping import STOPPING, defer, signals_held

if TYPE_CHECKING:
    from concurrent.futures import Future, ProcessPoolExecutor


class WorkerStopped(SystemExit):
    """A worker process stopped by SIGTERM or SIGHUP: a :class:`SystemExit` (status 128 + the
    signal), so that a worker waiting for work ends without a traceback, while a task it runs
    has its cleanup run and is reported to the batch as stopped."""

    def __init__(self, signum: int) -> None:
        super().__init__(128 + signum)
        self.signum = signum

    def __reduce__(self) -> tuple[type[WorkerStopped], tuple[int]]:
        return type(self), (self.signum,)  # (sent back from a worker as the signal, not the code)


@dataclass(frozen=True)
class Died:
    """A task whose worker process died: the process's exit status (negative: the signal that
    ended it; None: unknown)."""

    status: int | None

    def words(self) -> str:
        """``its worker died: signal 11 (SIGSEGV)``, or the exit status."""
        import signal

        if self.status is None:
            return "its worker died"
        if self.status < 0:
            try:
                name = f" ({signal.Signals(-self.status).name})"
            except ValueError:
                name = ""
            return f"its worker died: signal {-self.status}{name}"
        return f"its worker died: exit status {self.status}"


def worker_pool(workers: int, preload: Callable[[], object] | None) -> ProcessPoolExecutor:
    """A pool of *workers* processes, forked from this one after *preload* where the platform
    forks: they start with what *preload* imported instead of each importing it again, and with
    this process's signal handlers, as :func:`_worker` expects.

    Forking is safe because *preload* only imports: no thread of this process is left running
    that a worker could inherit holding a lock. A stopping signal waits for *preload* to end (a
    fraction of a second): raised inside an import, it can be printed as ignored there, or leave
    half-made objects that complain on the way out. What is loaded by then is frozen out of the
    garbage collector's reach (:func:`gc.freeze`): the workers' collections skip it, and this
    process, which ends with the batch, does not sweep it again on the way out.

    Without fork, and on macOS, whose system libraries are not safe to fork, the platform's
    default start (spawn): each worker imports what it needs itself."""
    import gc
    from concurrent.futures import ProcessPoolExecutor

    context = _context()
    if context is not None:
        if preload is not None:
            # a stop waits for the imports (broken off, they leave noise); an import that fails
            # fails again in each design's build, which reports it as that design's error
            with signals_held(), suppress(Exception):
                preload()
        gc.freeze()
    return ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=_worker)


def _context() -> Any:
    """The fork context where the platform forks safely (not macOS), else None (the default)."""
    import multiprocessing
    import sys

    if "fork" in multiprocessing.get_all_start_methods() and sys.platform != "darwin":
        return multiprocessing.get_context("fork")
    return None


def _worker() -> None:
    """A worker ignores Ctrl-C; SIGTERM and SIGHUP raise :class:`WorkerStopped` (see the
    module)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    stopping = {getattr(signal, name) for name in STOPPING[1:] if hasattr(signal, name)}
    for number in stopping:
        if signal.getsignal(number) != signal.SIG_IGN:
            signal.signal(number, _stop_worker)
    if hasattr(signal, "pthread_sigmask"):
        try:  # a stop that came while the worker started: it ends here, without a word
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, *stopping})
        except WorkerStopped as exc:
            import os

            os._exit(exc.code)


def _stop_worker(signum: int, frame: Any) -> None:
    if defer(signum):  # raised again where the code that must not be broken into ends
        return
    raise WorkerStopped(signum)


def _stoppable(function: Callable[[Any], Any], item: Any) -> Any:
    """*function* on *item* in a pool's worker: a stop ends the worker once the task's cleanup
    has run (the pool then reports the task's worker as ended; see the module)."""
    try:
        return function(item)
    except WorkerStopped as exc:
        import os

        os._exit(exc.code)


def broken(exc: BaseException) -> bool:
    """True when *exc*, a task's result, says its worker died or was stopped."""
    from concurrent.futures.process import BrokenProcessPool

    return isinstance(exc, (BrokenProcessPool, WorkerStopped))


def isolated(calls: Sequence[tuple[Callable[..., Any], tuple[Any, ...]]], jobs: int,
             ) -> list[Any]:
    """Each of *calls* (function, arguments) run in a process of its own, *jobs* at a time:
    its result, or :class:`Died` when its process died (or was stopped) before it gave one. An
    exception the function raised is raised here, as a pool's future raises it. A stop of this
    process waits for the running calls (the workers ignore Ctrl-C) and starts no more."""
    import multiprocessing
    from multiprocessing.connection import wait

    context = _context() or multiprocessing.get_context()
    results: list[Any] = [None] * len(calls)
    todo = deque(enumerate(calls))
    running: dict[Any, tuple[int, Any]] = {}
    try:
        while todo or running:
            while todo and len(running) < jobs:
                index, (function, args) = todo.popleft()
                receive, send = context.Pipe(duplex=False)
                with signals_held():
                    process = context.Process(target=_alone, args=(send, function, args),
                                              daemon=True)
                    process.start()
                send.close()
                running[receive] = (index, process)
            for receive in wait(list(running)):
                index, process = running.pop(receive)
                try:
                    given = receive.recv()
                except (EOFError, OSError):
                    given = None
                receive.close()
                process.join()
                if given is None:
                    results[index] = Died(process.exitcode)
                elif given[0]:
                    results[index] = given[1]
                elif isinstance(given[1], WorkerStopped):
                    results[index] = Died(-given[1].signum)
                else:
                    raise given[1]
    except BaseException:
        with signals_held():
            for _, process in running.values():
                process.join()
        raise
    return results


def _alone(send: Any, function: Callable[..., Any], args: tuple[Any, ...]) -> None:
    """The body of an isolated call's process: the call's result (or exception) sent back."""
    _worker()
    try:
        given: tuple[bool, Any] = (True, function(*args))
    except BaseException as exc:  # sent back; the parent raises it
        given = (False, exc)
    try:
        send.send(given)
    except Exception as exc:  # a result or exception that cannot be pickled
        send.send((False, RuntimeError(f"{type(exc).__name__}: {exc}")))
    send.close()


def in_order(function: Callable[[Any], Any], items: Iterable[Any], jobs: int,
             preload: Callable[[], object], ahead: int) -> Iterator[tuple[Any, Any]]:
    """(item, result) of *function* on each of *items*, in their order, on a pool of *jobs*
    workers forked after *preload*, at most *ahead* items in flight. A worker's death fails the
    items in flight: they are run again, each alone (:func:`isolated`), the one that dies again
    given as :class:`Died`, and the rest go on in a new pool. A stop (Ctrl-C) drops the items
    in flight, letting those running finish."""
    pool = worker_pool(jobs, preload)
    pending: deque[tuple[Any, Future[Any]]] = deque()
    feed = iter(items)
    try:
        while True:
            with signals_held():  # the pool is set up whole before a stop can break in
                for item in feed:
                    pending.append((item, pool.submit(_stoppable, function, item)))
                    if len(pending) >= ahead:
                        break
            if not pending:
                break
            item, future = pending.popleft()
            try:
                yield item, future.result()
                continue
            except BaseException as exc:
                if not broken(exc):
                    raise
            # the pool is broken: the item and those in flight again, each alone; a new pool
            lost = [item, *(waiting for waiting, _ in pending)]
            pending.clear()
            with signals_held():
                pool.shutdown(wait=True, cancel_futures=True)
            yield from zip(lost, isolated([(function, (i,)) for i in lost], jobs), strict=True)
            pool = worker_pool(jobs, None)
    except BaseException:
        with signals_held():
            pool.shutdown(wait=True, cancel_futures=True)
        raise
    with signals_held():
        pool.shutdown()
