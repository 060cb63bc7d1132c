"""Where a sweep's batches run: in this process, on a local pool of worker processes, or on a
Dask cluster, all through the ``concurrent.futures`` executor interface; the rows come back in
the variants' order whatever order the batches finish in, with no more batches in flight than
keep the workers busy (the memory stays flat over a sweep of millions).

The local pool is the batch builder's (:mod:`camfab.workers`): the workers are forked from this
process after it has analysed one variant, so they start with every library a row needs
imported, and a variant whose worker dies is a FAIL row, not the sweep's end. Dask's workers
import them once each, with the first batch they run.

A Dask scheduler's address is checked with the options, before any work
(:func:`check_scheduler`: ``tcp://`` only); the peer there is asked who it is within
:data:`ANSWER_SECONDS` before a client is made, and a scheduler without workers waited on for
its first, all before anything is written (:func:`connect`).
"""

from __future__ import annotations

import re
import sys
import time
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
#: How long a Dask scheduler has to take the connection (s): Dask's own connect, which tries
#: again while the port refuses or the packets go unanswered, as while a scheduler starts.
CONNECT_SECONDS = 5
#: How long it has to answer in all (s): its name looked up, the connection, Dask's handshake
#: and the scheduler's identity. Dask bounds the connection only: a peer that takes it and
#: says nothing, or announces a message it never sends, would hold a sweep for ever.
ANSWER_SECONDS = 10
#: How long a sweep waits by default for the first worker of a scheduler that has none (s;
#: ``--cluster-timeout``): a worker starting takes seconds; a minute leaves room for a few.
CLUSTER_SECONDS = 60
#: The longest ``--cluster-timeout`` (s): a day.
CLUSTER_SECONDS_MAX = 86400
#: The port a Dask scheduler listens on unless told otherwise, and its dashboard's.
DASK_PORT, DASHBOARD_PORT = 8786, 8787
#: A host in an address: a name or IPv4 address, or an IPv6 address in brackets.
HOST = re.compile(r"[\w.-]+|\[[0-9A-Fa-f:.]+(%[\w.-]+)?\]")

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


def local_rows(task: Task, batches: Iterable[Any], jobs: int, warm: Callable[[], object],
               died: Callable[[tuple[int, tuple[Any, ...]], Any], Row]) -> Iterator[list[Row]]:
    """The rows of *batches* run by *task* in this process (*jobs* 1) or on *jobs* worker
    processes forked after *warm* (which imports what a row needs). A batch whose worker died
    is run again a variant at a time, each alone: a variant that kills its worker again is the
    row *died* makes of it and the :class:`~camfab.workers.Died` (:mod:`camfab.workers`)."""
    if jobs == 1:
        for batch in batches:
            yield task(batch)
        return
    from camfab.workers import Died, in_order, isolated

    for batch, rows in in_order(task, batches, jobs, warm, AHEAD * jobs):
        if not isinstance(rows, Died):
            yield rows
            continue
        alone = isolated([(task, ([variant],)) for variant in batch], jobs)
        yield [died(variant, result) if isinstance(result, Died) else result[0]
               for variant, result in zip(batch, alone, strict=True)]


def dask_rows(task: Task, batches: Iterable[Any], address: str,
              wait_seconds: float | None = None) -> Iterator[list[Row]]:
    """The rows of *batches* run by *task* on the Dask cluster whose scheduler is at
    *address* (``tcp://HOST:PORT``), through its ``concurrent.futures`` executor. The
    scheduler is reached at once, and its first worker waited for up to *wait_seconds*
    (default :data:`CLUSTER_SECONDS`) when it has none (raises :class:`SweepError` when it
    cannot be reached or no worker comes); the batches are sent as the rows are taken."""
    client = connect(address, CLUSTER_SECONDS if wait_seconds is None else wait_seconds)
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


def check_scheduler(address: str | None, wait_seconds: float | None) -> None:
    """Refuse, before any work, a ``--scheduler`` address camfab cannot use (see
    :func:`scheduler_address`), ``--scheduler`` without Dask's distributed scheduler installed,
    and a ``--cluster-timeout`` (*wait_seconds*) out of range or without ``--scheduler``
    (raises :class:`SweepError`)."""
    from importlib.util import find_spec

    if address is None:
        if wait_seconds is not None:
            raise SweepError("--cluster-timeout: only with --scheduler (it bounds the wait for "
                             "the Dask cluster's first worker)")
        return
    scheduler_address(address)
    if wait_seconds is not None and not 0 <= wait_seconds <= CLUSTER_SECONDS_MAX:  # NaN too
        raise SweepError(f"--cluster-timeout {wait_seconds:g}: must be 0 to "
                         f"{CLUSTER_SECONDS_MAX} s")
    if find_spec("distributed") is None:
        raise SweepError("--scheduler needs Dask's distributed scheduler: pip install "
                         "'camfab[cluster]'")


def scheduler_address(address: str) -> str:
    """*address* (``--scheduler``) as Dask's ``tcp://HOST:PORT`` (raises :class:`SweepError`).

    A bare ``HOST:PORT`` is ``tcp://HOST:PORT``, as Dask reads it unless configured otherwise.
    ``tls://`` is refused: it needs Dask's security settings (certificates and keys), which
    camfab does not take; so is every other scheme (``ucx://``, ``inproc://``, a dashboard's
    ``http://``), and an address that is empty, holds a space or lacks its host or port.
    """
    shown = address if address and not any(c.isspace() for c in address) else repr(address)
    option = f"--scheduler {shown}"
    example = f"tcp://HOST:{DASK_PORT}"
    if not address.strip():
        raise SweepError(f"{option}: no address; give the scheduler's, such as {example}")
    if shown != address:
        raise SweepError(f"{option}: an address holds no spaces (such as {example})")
    scheme, sep, location = address.partition("://")
    if not sep:
        scheme, location = "tcp", address
    scheme = scheme.lower()
    if scheme == "tls":
        raise SweepError(
            f"{option}: tls:// needs Dask's security settings (certificates and keys), which "
            f"camfab does not take; run the scheduler on tcp:// and reach it on a private "
            f"network or through an SSH tunnel (ssh -N -L {DASK_PORT}:localhost:{DASK_PORT} "
            f"HOST, then --scheduler tcp://localhost:{DASK_PORT})")
    if scheme in ("http", "https"):
        raise SweepError(f"{option}: {scheme}:// is a web address, such as a Dask dashboard's; "
                         f"give the scheduler's, {example} (port {DASK_PORT} unless it was "
                         f"told otherwise)")
    if scheme != "tcp":
        raise SweepError(f"{option}: camfab reaches a Dask scheduler over tcp:// only "
                         f"({example}, or HOST:PORT), not {scheme or '(none)'}://")
    host, colon, port = location.rpartition(":")
    if not colon or location.endswith("]"):
        raise SweepError(f"{option}: no port (a scheduler listens on {DASK_PORT} unless it was "
                         f"told otherwise: tcp://{location or 'HOST'}:{DASK_PORT})")
    if not (port.isascii() and port.isdigit() and 1 <= int(port) <= 65535):
        raise SweepError(f"{option}: the port must be a number from 1 to 65535 (got "
                         f"{port!r})")
    if not host:
        raise SweepError(f"{option}: no host (such as tcp://HOST:{port})")
    if not HOST.fullmatch(host):
        hint = (f"an IPv6 address goes in brackets: tcp://[{host}]:{port}" if ":" in host
                and not host.startswith("[") else f"{host!r} is not a host name or address")
        raise SweepError(f"{option}: {hint}")
    return f"tcp://{host}:{int(port)}"


def connect(address: str, wait_seconds: float = CLUSTER_SECONDS,
            note: Callable[[str], None] | None = None) -> Any:
    """A Dask client of the scheduler at *address*, which has a worker (raises
    :class:`SweepError`).

    The peer is first asked who it is, with Dask's own connection and handshake, all within
    :data:`ANSWER_SECONDS` (Dask's client bounds the connection, not the handshake, and reads
    whatever frame length the peer sends); then the client is made. When the scheduler has no
    worker, *note* (a line on stderr by default) says so and the first is waited for up to
    *wait_seconds*.
    """
    target = scheduler_address(address)
    option = f"--scheduler {address}"
    try:
        from distributed import Client
    except ImportError:
        raise SweepError("--scheduler needs Dask's distributed scheduler: pip install "
                         "'camfab[cluster]'") from None
    _ask_identity(option, target)
    try:
        client = Client(target, timeout=CONNECT_SECONDS, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise SweepError(f"{option}: cannot reach a Dask scheduler there "
                         f"({' '.join(str(exc).split())[:200]})") from None
    try:
        _wait_for_a_worker(client, option, address, wait_seconds, note or _to_stderr)
    except BaseException:
        client.close()
        raise
    return client


def _ask_identity(option: str, address: str) -> None:
    """Raise :class:`SweepError` unless a Dask scheduler at *address* (``tcp://HOST:PORT``)
    says who it is within :data:`ANSWER_SECONDS`, whatever the peer does (says nothing, sends
    bytes that are not Dask's, closes the connection)."""
    import asyncio

    start = time.monotonic()
    host, _, port = address.removeprefix("tcp://").rpartition(":")
    _look_up(option, host.strip("[]"), int(port))
    left = ANSWER_SECONDS - (time.monotonic() - start)
    # Dask's connect ends on its own past CONNECT_SECONDS: it says why before the deadline
    connect_seconds = min(CONNECT_SECONDS, left - 1)
    dashboard = (f"; {DASHBOARD_PORT} is a dashboard's port, the scheduler's is {DASK_PORT} "
                 f"unless it was told otherwise" if int(port) == DASHBOARD_PORT else "")
    try:
        identity = asyncio.run(asyncio.wait_for(_identity(address, connect_seconds), left))
    except (asyncio.TimeoutError, TimeoutError):
        raise SweepError(f"{option}: cannot reach a Dask scheduler there (the peer took the "
                         f"connection but did not answer Dask's handshake in "
                         f"{ANSWER_SECONDS} s{dashboard})") from None
    except OSError as exc:  # Dask's connect gave up, or the peer closed the connection
        raise SweepError(f"{option}: cannot reach a Dask scheduler there "
                         f"({_why(exc, connect_seconds)}{dashboard})") from None
    except Exception:  # whatever Dask's reader makes of bytes that are not its messages
        raise SweepError(f"{option}: the peer there is not a Dask scheduler (its answer to "
                         f"Dask's handshake is not Dask's protocol{dashboard})") from None
    kind = identity.get("type") if isinstance(identity, dict) else None
    if not isinstance(kind, str) or "Scheduler" not in kind:
        what = (f"it is a Dask {kind.lower()}; the scheduler's address is in its log"
                if kind in ("Worker", "Nanny") else "it does not say it is one")
        raise SweepError(f"{option}: the peer there is not a Dask scheduler ({what})")


async def _identity(address: str, connect_seconds: float) -> Any:
    """The identity a Dask server at *address* gives, through Dask's connection and handshake
    (its messages not unpickled)."""
    from distributed.comm import connect

    comm = await connect(address, timeout=connect_seconds, deserialize=False)
    try:
        await comm.write({"op": "identity", "reply": True})
        return await comm.read()
    finally:
        comm.abort()


def _look_up(option: str, host: str, port: int) -> None:
    """Raise :class:`SweepError` unless *host*'s name resolves within
    :data:`CONNECT_SECONDS`. The look-up runs in a thread of its own that does not keep camfab
    from exiting (Dask's runs in the event loop's executor, which the loop's end waits for)."""
    import socket
    import threading

    found: list[str] = []

    def look_up() -> None:
        try:
            socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
            found.append("")
        except OSError as exc:
            found.append(exc.strerror or str(exc))

    thread = threading.Thread(target=look_up, name="camfab-look-up", daemon=True)
    thread.start()
    thread.join(CONNECT_SECONDS)
    if not found:
        raise SweepError(f"{option}: cannot reach a Dask scheduler there (no address for "
                         f"{host} in {CONNECT_SECONDS} s)")
    if found[0]:
        raise SweepError(f"{option}: cannot reach a Dask scheduler there (no address for "
                         f"{host}: {found[0]})")


def _why(exc: OSError, connect_seconds: float) -> str:
    """Why Dask's connect raised *exc*: the peer closed the connection (at once, each time it
    was tried, or in the handshake), or the system's reason (``connection refused``)."""
    from distributed.comm import CommClosedError

    closed = ("the peer closed the connection before Dask's handshake was through, as a "
              "scheduler on tls:// does, or a tunnel with nothing at its far end")
    if isinstance(exc, CommClosedError):  # in the handshake: the connection's are retried
        return closed
    chain: list[BaseException] = []
    seen: BaseException | None = exc
    while seen is not None:
        chain.append(seen)
        seen = seen.__cause__ or seen.__context__
    said = [e.strerror for e in chain if isinstance(e, OSError) and e.strerror
            and not isinstance(e, ConnectionResetError | BrokenPipeError)]
    if said:
        return f"no connection in {connect_seconds:.2g} s: {said[0][:1].lower()}{said[0][1:]}"
    if any(isinstance(e, CommClosedError | ConnectionResetError | BrokenPipeError)
           for e in chain):
        return closed
    return f"no connection in {connect_seconds:.2g} s"


def _wait_for_a_worker(client: Any, option: str, address: str, seconds: float,
                       note: Callable[[str], None]) -> None:
    """Return once the scheduler of *client* has a worker; wait up to *seconds* for the first
    (raises :class:`SweepError`)."""
    if client.scheduler_info().get("workers"):
        return
    start = f"a worker joins with: dask worker {address}"
    if seconds <= 0:
        raise SweepError(f"{option}: the scheduler has no worker (--cluster-timeout 0 waits "
                         f"for none; {start})")
    note(f"camfab sweep: waiting for workers at {address}: 0 so far (up to {seconds:g} s; "
         f"--cluster-timeout)")
    try:
        client.wait_for_workers(1, timeout=seconds)
    except TimeoutError:
        raise SweepError(f"{option}: no worker joined the scheduler in {seconds:g} s "
                         f"(--cluster-timeout; {start})") from None
    except OSError as exc:
        raise SweepError(f"{option}: lost the Dask scheduler while waiting for a worker "
                         f"({' '.join(str(exc).split())[:200]})") from None


def _to_stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)
