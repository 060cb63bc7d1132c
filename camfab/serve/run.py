"""``camfab serve``: the studio's server started on a port of this machine, until Ctrl-C.

The file is read and the port taken before anything is served, so that a missing or unreadable
file, a port in use or a host that is not this machine's is one line and status 2. The server
listens on the loopback address unless ``--host`` names another (then with a warning line), and
the URL it prints carries the session's random token, without which every request is refused.

A request must name the server as it is reached (its Host header): on a loopback address only
the loopback names and addresses (a page of another site whose name a DNS answer points at
127.0.0.1 is refused); on another address that address and the name ``--host`` gave; on every
address (``--host 0.0.0.0``, ``0``, ``::``) any name, the machine's printed URL that of its
loopback address. The connections are bounded (:mod:`camfab.serve.connections`).
"""

from __future__ import annotations

import ipaddress
import os
import secrets
import signal
import socket
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from camfab.errors import CamfabError
from camfab.serve.connections import BACKLOG
from camfab.stopping import STOPPING

#: The port the studio takes unless told (``--port``; 0 takes any free one).
DEFAULT_PORT = 8765
#: The libraries of the ``camfab[serve]`` extra, by the name they are imported as.
LIBRARIES = ("starlette", "uvicorn", "watchfiles", "ruamel.yaml")


def _libraries() -> None:
    from importlib.util import find_spec

    for name in LIBRARIES:
        try:
            found = find_spec(name)
        except (ImportError, ValueError):
            found = None
        if found is None:
            raise CamfabError(f"camfab serve: needs the studio's libraries ({name} is not "
                              "installed): pip install 'camfab[serve]'")


def _loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _wildcard(host: str) -> bool:
    try:
        return ipaddress.ip_address(host).is_unspecified
    except ValueError:
        return False


def listen(host: str, port: int) -> socket.socket:
    """A socket listening on *host*:*port* (raises CamfabError with the one line to say)."""
    try:
        family, kind, proto, _, address = socket.getaddrinfo(
            host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)[0]
    except (socket.gaierror, UnicodeError, ValueError):
        raise CamfabError(f"camfab serve: --host {host}: not an address of this machine"
                          ) from None
    sock = socket.socket(family, kind, proto)
    try:
        if os.name != "nt":
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(address)
        sock.listen(BACKLOG)
    except OSError as exc:
        sock.close()
        import errno

        if exc.errno == errno.EADDRINUSE:
            raise CamfabError(f"camfab serve: port {port} on {host} is in use (--port takes "
                              "another; --port 0 any free one)") from None
        if exc.errno == errno.EADDRNOTAVAIL:
            raise CamfabError(f"camfab serve: --host {host}: not an address of this machine"
                              ) from None
        raise CamfabError(f"camfab serve: cannot listen on {host} port {port} "
                          f"({exc.strerror or exc})") from None
    sock.set_inheritable(False)
    return sock


def bound_address(sock: socket.socket) -> str:
    """The address *sock* is bound to, as an URL writes it (``[::1]`` for IPv6)."""
    address = str(sock.getsockname()[0])
    return f"[{address}]" if ":" in address else address


def allowed_hosts(given: str, sock: socket.socket) -> set[str] | None:
    """The Host headers a request to the server on *sock* may carry (None: any), *given*
    the ``--host`` it was asked for: on a loopback address the loopback names and addresses
    (and *given*, which named it); on every address any; on another address that address and
    *given*."""
    address, port = sock.getsockname()[:2]
    if _wildcard(address):
        return None
    shown = bound_address(sock)
    named = f"[{given}]" if ":" in given else given
    hosts = {f"{shown}:{port}", f"{named}:{port}"}
    if _loopback(address):
        hosts |= {f"localhost:{port}", f"127.0.0.1:{port}", f"[::1]:{port}"}
    return hosts


def page_url(sock: socket.socket, token: str) -> str:
    """The page's URL on *sock*: its address, or on every address the loopback one."""
    address, port = sock.getsockname()[:2]
    if _wildcard(address):
        shown = "[::1]" if sock.family == socket.AF_INET6 else "127.0.0.1"
    else:
        shown = bound_address(sock)
    return f"http://{shown}:{port}/?token={token}"


def serve(design: str, port: int = DEFAULT_PORT, host: str | None = None,
          open_page: bool | None = None) -> int:
    """Serve the studio of design file *design* on *host* (the loopback address unless
    given) and *port* until the server is stopped; *open_page*: open the page in the
    desktop's browser (None: when there is a desktop). Returns 0 (a stop by a signal raises)."""
    _libraries()
    from camfab.design.source import read_design_text

    path = Path(design)
    read_design_text(path)  # a file missing or unreadable is said before the port is taken
    host = host or "127.0.0.1"
    sock = listen(host, port)
    try:
        return _run(path, design, sock, host, open_page)
    finally:
        sock.close()


def _run(path: Path, label: str, sock: socket.socket, host: str,
         open_page: bool | None) -> int:
    import uvicorn

    from camfab.serve.app import Hub, notifier, studio_app
    from camfab.serve.connections import KEEP_ALIVE_SECONDS, connection_bound, protocol_class
    from camfab.serve.studio import Studio

    token = secrets.token_urlsafe(24)
    address, port = sock.getsockname()[:2]
    hub = Hub()
    studio = Studio(path, label, notifier(hub))
    app = studio_app(studio, token, allowed_hosts(host, sock), hub)
    # uvicorn's warnings are about clients (a request that is not HTTP, each): not logged
    config = uvicorn.Config(app, log_level="error", access_log=False, lifespan="on",
                            timeout_graceful_shutdown=2, http=protocol_class(connection_bound()),
                            backlog=BACKLOG, timeout_keep_alive=KEEP_ALIVE_SECONDS)
    server = _server_class()(config)
    hub.should_stop = lambda: bool(server.should_exit)
    url = page_url(sock, token)
    if not _loopback(address):
        reach = (f" (every address; from another machine: http://{socket.gethostname()}:"
                 f"{port}/?token={token})" if _wildcard(address) else "")
        sys.stderr.write(f"camfab serve: listening on {bound_address(sock)}: anyone who can "
                         f"reach this machine and has the URL can read and change the design"
                         f"{reach}\n")
    sys.stdout.write(f"camfab serve: {label} at {url} (Ctrl-C stops)\n")
    sys.stdout.flush()
    if open_page is None:
        open_page = sys.platform in ("darwin", "win32") or bool(
            os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    if open_page:
        import webbrowser

        threading.Timer(0.5, webbrowser.open, (url,)).start()
    try:
        server.run(sockets=[sock])
    finally:
        studio.close()
    if server.stops:  # now, outside the server's loop: camfab's handler says it and exits
        signal.raise_signal(server.stops[0])
    return 0


def _server_class() -> type:
    import uvicorn

    class Server(uvicorn.Server):
        """uvicorn's server, stopped by camfab's stopping signals (Ctrl-C, SIGTERM, SIGHUP):
        the first asks it to finish (its open requests and event streams end within a
        moment), the second to stop at once. The signal is noted in :attr:`stops` and raised
        again only after the server's loop has ended, where camfab's handler turns it into
        its one line and status (uvicorn would raise it inside the loop's shutdown)."""

        stops: list[int]

        async def startup(self, sockets: list[socket.socket] | None = None) -> None:
            import asyncio

            from camfab.serve.connections import quiet_accept_errors

            quiet_accept_errors(asyncio.get_running_loop())
            await super().startup(sockets=sockets)

        @contextmanager
        def capture_signals(self) -> Iterator[None]:
            self.stops = []
            if threading.current_thread() is not threading.main_thread():
                yield
                return
            wanted = [getattr(signal, name) for name in STOPPING if hasattr(signal, name)]
            originals = {sig: signal.signal(sig, self.handle_exit) for sig in wanted}
            try:
                yield
            finally:
                for sig, handler in originals.items():
                    signal.signal(sig, handler)

        def handle_exit(self, sig: int, frame: Any) -> None:
            if sig not in self.stops:
                self.stops.append(sig)
            super().handle_exit(sig, frame)

    return Server

