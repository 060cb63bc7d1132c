"""The studio's connections, bounded: a request's head must arrive in time, the connections
open at once are few, and a system out of file descriptors is said in one line a minute.

uvicorn's HTTP protocol (h11) times out a connection only while it idles between two requests
(``timeout_keep_alive``): one that sends half a request head is held for ever, and the token
is checked only once the head is whole, so anyone on the machine could hold every file
descriptor of the process. Here a connection whose head has not arrived within
:data:`HEAD_SECONDS` of its first byte (or of its opening) is closed, and when
:func:`connection_bound` connections are open the oldest one still waiting for its head is
closed to make room for the new one (a request being answered, an events stream, is never
closed; a new connection is refused only when every one open is such).

uvicorn's own ``limit_concurrency`` is not used: it counts the connections still sending
their head, so a flood of half requests would turn every real request into a 503.
"""

from __future__ import annotations

import asyncio
import errno
import sys
import time
from typing import Any

#: How long a request's head may take to arrive (s), counted from the connection's opening or
#: from the first byte after an answer: a browser or a script sends its head at once.
HEAD_SECONDS = 10.0
#: How long a connection may idle between two requests (s): uvicorn's ``timeout_keep_alive``.
KEEP_ALIVE_SECONDS = 5
#: The most connections open at once, and the listening socket's queue of connections not
#: yet taken (also how many the event loop takes at a time): a studio has one page or a few.
MAX_CONNECTIONS = 100
BACKLOG = 64
#: File descriptors kept free for the rest of the process (the design file, the watcher, the
#: build's files) besides the connections and a backlog's worth being taken.
RESERVED_FILES = 64
#: Seconds between two lines saying that connections cannot be taken (no file descriptors).
ACCEPT_LINE_SECONDS = 60.0
#: What the event loop says when it cannot take a connection (asyncio's words).
_ACCEPT_ERRORS = frozenset({errno.EMFILE, errno.ENFILE, errno.ENOBUFS, errno.ENOMEM})


def connection_bound() -> int:
    """How many connections the studio keeps open at once: :data:`MAX_CONNECTIONS`, or fewer
    when the process may open few files (half of those left once :data:`RESERVED_FILES` and a
    :data:`BACKLOG` are set aside), at least 8."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    except (ImportError, OSError, ValueError):  # Windows: no such limit
        return MAX_CONNECTIONS
    if soft == resource.RLIM_INFINITY or soft < 0:
        return MAX_CONNECTIONS
    return max(8, min(MAX_CONNECTIONS, (soft - RESERVED_FILES - BACKLOG) // 2))


def protocol_class(bound: int, head_seconds: float = HEAD_SECONDS) -> type[asyncio.Protocol]:
    """uvicorn's h11 protocol with a time limit on each request's head and at most *bound*
    connections open (the oldest waiting for its head closed for a new one)."""
    import h11
    from uvicorn.protocols.http.h11_impl import H11Protocol

    class Protocol(H11Protocol):  # type: ignore[misc]
        """One connection: closed when its request head is not whole *head_seconds* after
        the connection opened or the head's first byte came."""

        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, **kwargs)
            self.head_timer: asyncio.TimerHandle | None = None
            self.waiting_since = time.monotonic()

        def waiting(self) -> bool:
            """True while no request is under way: the connection waits for a head."""
            return self.conn.their_state is h11.IDLE

        def connection_made(self, transport: asyncio.BaseTransport) -> None:
            super().connection_made(transport)  # type: ignore[arg-type]
            self.waiting_since = time.monotonic()
            if len(self.connections) > bound:
                idle = [c for c in self.connections
                        if c is not self and isinstance(c, Protocol) and c.waiting()
                        and not c.transport.is_closing()]
                if not idle:
                    transport.close()
                    return
                min(idle, key=lambda c: c.waiting_since).transport.close()
            self._await_head()

        def data_received(self, data: bytes) -> None:
            super().data_received(data)
            if self.waiting() and not self.transport.is_closing():
                self._await_head()  # after an answer, the next head's time runs from
                # its first byte (the connection's opening, for the first head)
            else:
                self._head_done()

        def on_response_complete(self) -> None:
            self.waiting_since = time.monotonic()
            super().on_response_complete()

        def connection_lost(self, exc: Exception | None) -> None:
            self._head_done()
            super().connection_lost(exc)

        def _await_head(self) -> None:
            if self.head_timer is None:
                self.head_timer = self.loop.call_later(head_seconds, self._head_late)

        def _head_done(self) -> None:
            if self.head_timer is not None:
                self.head_timer.cancel()
                self.head_timer = None

        def _head_late(self) -> None:
            self.head_timer = None
            if self.waiting():
                self.transport.close()

    return Protocol


def quiet_accept_errors(loop: asyncio.AbstractEventLoop) -> None:
    """Make *loop* say that it cannot take connections (no file descriptors left) in one line
    at most every :data:`ACCEPT_LINE_SECONDS`, with the count of the times not said, instead of
    a traceback each time; every other error goes to the handler it had."""
    before = loop.get_exception_handler()
    said = {"at": -float("inf"), "unsaid": 0}

    def handler(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        exc = context.get("exception")
        if not (isinstance(exc, OSError) and exc.errno in _ACCEPT_ERRORS):
            if before is not None:
                before(loop, context)
            else:
                loop.default_exception_handler(context)
            return
        now = time.monotonic()
        if now - said["at"] < ACCEPT_LINE_SECONDS:
            said["unsaid"] += 1
            return
        more = f" ({said['unsaid']} more times since the last line)" if said["unsaid"] else ""
        sys.stderr.write(f"camfab serve: cannot take new connections for now "
                         f"({exc.strerror or exc}){more}\n")
        said["at"], said["unsaid"] = now, 0

    loop.set_exception_handler(handler)
