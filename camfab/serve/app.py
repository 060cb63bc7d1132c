"""The studio's web application (Starlette): the page, its static files and the API under it.

Every request must carry the session's token — in the query (``?token=…``), in the header
``X-Camfab-Token``, or, for the page's static files (which import one another by relative
paths), as the first part of their path (``/s/TOKEN/…``); without it the answer is 403. A
request must name this server as its host (no other name reaches it through DNS), and a POST
from a browser must come from this server's own page (its ``Origin``). No request names a file:
the studio reads and writes its one design file (and reads the table laws' CSV files it names).

API (JSON unless said):

``GET /api/report``
    the current design's report JSON, byte for byte the ``NAME-report.json`` that
    ``camfab build`` writes (422 with ``{"error": line}`` when the design does not load).
``POST /api/edit`` ``{"path": "cam.base_radius", "value": 42}``
    the key set in the studio's text (not saved) and the new report JSON; with
    ``?respond=view`` the page's view instead (the report page of the analysis, at once,
    before the files are made and read back). 400 for a path the design has not (with the
    closest it has) or a value that is not a number, a word or true/false; 409 when the text
    is not YAML the editor reads; 422 with the located line and the edit (``"edit"``) when the
    edited design does not load (the next edit is made without it).
``POST /api/save``, ``POST /api/reload``
    write the edits into the design file (409 when it changed on disk since it was loaded,
    403 when the file or its folder is read-only, 507 when the disk is full); drop them and
    take the file as it is.
``POST /api/size``, ``POST /api/build``
    ``camfab size``'s answer and the edits that apply it; the files written as
    ``camfab build`` writes them, listed.
``GET /api/state``, ``GET /api/verified?version=N``, ``GET /api/part/I?version=N``
    the page's view; the verified report page and the 3-D scene of version N; its I-th STL.
``GET /api/events``
    server-sent events: ``state`` after each change (an edit, the file changed on disk),
    ``verified`` when its files are made and read back, ``report`` with the new report JSON
    (as ``/api/report`` gives it) after that, ``fault`` for a failure of camfab's own.

Every refusal is a status and ``{"error": line}``, one line; a request the client gives up
half way is dropped without a word; a fault of camfab's own is a 500 with its one line (and
one line on stderr), never a traceback.
"""

from __future__ import annotations

import asyncio
import errno
import functools
import json
import math
import os
import re
import secrets
import sys
import time
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from importlib import resources
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import ClientDisconnect, Request
from starlette.responses import JSONResponse, Response, StreamingResponse
from starlette.routing import Route
from starlette.types import ASGIApp, Receive, Scope, Send

from camfab.errors import CamfabError, OutputError
from camfab.serve.studio import Conflict, Studio, Unreadable
from camfab.serve.watch import Watcher
from camfab.serve.yamledit import EditError

#: The version of three.js vendored in ``camfab/serve/static/three`` (its README).
THREE_VERSION = "0.187.0"
#: Largest request body the API reads (bytes): an edit is a path and a value.
MAX_BODY = 64 * 1024
#: How long a request's body may take to arrive (s): an edit's is a few dozen bytes.
BODY_SECONDS = 10.0
#: The status of a save that failed, by the system's error: a read-only file or folder, a
#: full disk (or quota).
SAVE_STATUS = {errno.EACCES: 403, errno.EPERM: 403, errno.EROFS: 403, errno.ENOSPC: 507,
               getattr(errno, "EDQUOT", errno.ENOSPC): 507}
#: Seconds between the events stream's keep-alive comments, and between its looks at whether
#: the server stops (a stop ends the streams within that time).
KEEPALIVE_SECONDS = 15.0
POLL_SECONDS = 0.25


class Hub:
    """The events streams open now, and the way to send each an event from any thread."""

    def __init__(self) -> None:
        self.loop: asyncio.AbstractEventLoop | None = None
        self.queues: set[asyncio.Queue[tuple[str, str]]] = set()
        self.stopping = asyncio.Event()
        #: True once the server is asked to stop (it waits for the open streams to end).
        self.should_stop: Callable[[], bool] = lambda: False

    def send(self, event: str, data: str) -> None:
        """Send *event* with *data* (text) to every stream, from any thread."""
        loop = self.loop
        if loop is None or loop.is_closed():
            return
        for queue in list(self.queues):
            loop.call_soon_threadsafe(queue.put_nowait, (event, data))


def _static_files() -> dict[str, tuple[Path, str]]:
    """The page's static files by their path under ``/s/TOKEN/``: a fixed list, read from the
    package (no request names a file)."""
    root = Path(str(resources.files("camfab.serve") / "static"))
    files = {}
    for path in sorted(root.rglob("*")):
        if path.is_file() and path.suffix in (".js", ".css"):
            kind = "text/javascript" if path.suffix == ".js" else "text/css"
            files[path.relative_to(root).as_posix()] = (path, kind)
    return files


def studio_app(studio: Studio, token: str, hosts: set[str] | None, hub: Hub) -> ASGIApp:
    """The studio's application for *studio*: its routes behind the token, host and origin
    checks (:func:`guarded`), the design file watched while it runs (from now: a change made
    before the server starts is seen too)."""
    static = _static_files()
    watch = Watcher(studio)

    async def page(request: Request) -> Response:
        from camfab.export.report_html import page_template

        text = page_template("studio.html.j2").render(
            token=token, file=studio.label, three=THREE_VERSION)
        return Response(text, media_type="text/html; charset=utf-8",
                        headers={"Cache-Control": "no-store"})

    async def asset(request: Request) -> Response:
        found = static.get(request.path_params["name"])
        if found is None:
            return Response("not found", status_code=404)
        path, kind = found
        return Response(path.read_bytes(), media_type=kind,
                        headers={"Cache-Control": "private, max-age=3600"})

    async def state(request: Request) -> Response:
        return _state(studio, await run_in_threadpool(studio.state))

    async def report(request: Request) -> Response:
        return await _report_of(studio)

    async def edit(request: Request) -> Response:
        body = await _json_body(request)
        if not isinstance(body, dict) or set(body) != {"path", "value"}:
            return _problem(400, 'the body must be {"path": ..., "value": ...}')
        path, value = body["path"], _edit_value(body["value"])
        started = time.perf_counter()
        try:
            view = await run_in_threadpool(studio.edit, path, value)
        except EditError as exc:
            return _problem(400, str(exc))
        except Unreadable as exc:
            return _problem(409, str(exc))
        if request.query_params.get("respond") == "view":  # the page's, with every value:
            spent = (time.perf_counter() - started) * 1e3  # an alias of the one edited, or
            return _state(studio, studio.state(),          # an edit taken back, changes others
                          headers={"Server-Timing": f"edit;dur={spent:.1f}"})
        if view.error is not None:
            return JSONResponse({"error": view.error, "edit": studio.broken}, status_code=422)
        return await _report_of(studio)

    async def save(request: Request) -> Response:
        try:
            saved = await run_in_threadpool(studio.save)
        except Conflict as exc:
            return _problem(409, str(exc))
        except OutputError as exc:
            return _problem(SAVE_STATUS.get(exc.errno or 0, 500), str(exc))
        except CamfabError as exc:
            return _problem(500, str(exc))
        return JSONResponse({"saved": saved, "edited": studio.edited})

    async def reload(request: Request) -> Response:
        try:
            await run_in_threadpool(studio.reload)
        except CamfabError as exc:
            return _problem(422, str(exc))
        return _state(studio, await run_in_threadpool(studio.state))

    async def size(request: Request) -> Response:
        try:
            return JSONResponse(await run_in_threadpool(studio.size))
        except CamfabError as exc:
            return _problem(422, str(exc))

    async def build(request: Request) -> Response:
        try:
            return JSONResponse(await run_in_threadpool(studio.build))
        except CamfabError as exc:
            return _problem(422, str(exc))

    async def verified(request: Request) -> Response:
        version = _version(request)
        try:
            made = await run_in_threadpool(studio.verified, version)
            scene = await run_in_threadpool(_scene, made)
        except CamfabError as exc:
            return _problem(409, str(exc))
        return JSONResponse({"version": made.version, "html": made.html, "scene": scene,
                             "exit_code": made.analysis.exit_code})

    async def part(request: Request) -> Response:
        named = request.path_params["index"]
        index, version = _whole(named), _version(request)
        if index is None:
            return _problem(404, f"part {json.dumps(named[:20])}: not a part's number")
        try:
            made = await run_in_threadpool(studio.verified, version)
        except CamfabError as exc:
            return _problem(409, str(exc))
        if index >= len(made.stl_names):
            return _problem(404, f"part {index}: version {made.version} has "
                                 f"{len(made.stl_names)} part(s)")
        return Response(made.artifacts.files[made.stl_names[index]], media_type="model/stl")

    async def events(request: Request) -> Response:
        return StreamingResponse(_stream(hub, studio), media_type="text/event-stream",
                                 headers={"Cache-Control": "no-store"})

    @asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        hub.loop = asyncio.get_running_loop()
        watcher = asyncio.create_task(watch.run(hub.stopping))
        try:
            yield
        finally:
            hub.stopping.set()
            watcher.cancel()
            studio.close()

    def route(path: str, endpoint: Callable[[Request], Any], post: bool = False) -> Route:
        return Route(path, _answering(endpoint), methods=["POST"] if post else None)

    routes = [
        route("/", page),
        route("/s/{key}/{name:path}", asset),
        route("/api/state", state),
        route("/api/report", report),
        route("/api/edit", edit, post=True),
        route("/api/save", save, post=True),
        route("/api/reload", reload, post=True),
        route("/api/size", size, post=True),
        route("/api/build", build, post=True),
        route("/api/verified", verified),
        route("/api/part/{index}", part),
        route("/api/events", events),
    ]
    return guarded(Starlette(routes=routes, lifespan=lifespan), token, hosts)


def guarded(app: ASGIApp, token: str, hosts: set[str] | None) -> ASGIApp:
    """*app* behind the checks every request passes: the token (query ``token``, header
    ``X-Camfab-Token``, or ``/s/TOKEN/`` for the static files), a Host header naming this
    server (one of *hosts*; any when None, a server on every address), and for a POST an
    ``Origin``, when the client sends one (a browser does), of this server's own page. A
    request that fails one gets 403 and nothing else."""
    from urllib.parse import parse_qs

    async def check(scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await app(scope, receive, send)
            return
        headers = {k.decode("latin-1").lower(): v.decode("latin-1")
                   for k, v in scope.get("headers", [])}
        path = scope.get("path", "")
        given = headers.get("x-camfab-token")
        if given is None and path.startswith("/s/"):
            given = path.split("/", 3)[2]
        if given is None:
            query = parse_qs(scope.get("query_string", b"").decode("latin-1"))
            given = (query.get("token") or [None])[0]
        ok = given is not None and secrets.compare_digest(given.encode(), token.encode())
        host = headers.get("host", "")
        ok = ok and (hosts is None or host in hosts)
        if ok and scope.get("method") not in ("GET", "HEAD"):
            origin = headers.get("origin")
            ok = origin is None or origin == f"http://{host}"
        if not ok:
            await Response("forbidden: this studio needs its token (see the URL camfab serve "
                           "printed)", status_code=403, media_type="text/plain")(
                scope, receive, send)
            return
        await app(scope, receive, send)

    return check


class Refused(Exception):
    """A request the API refuses: its status and its one line (``{"error": line}``)."""

    def __init__(self, status: int, line: str) -> None:
        super().__init__(line)
        self.status = status
        self.line = line


def _problem(status: int, line: str) -> JSONResponse:
    return JSONResponse({"error": line}, status_code=status)


def _answering(endpoint: Callable[[Request], Any]) -> Callable[[Request], Any]:
    """*endpoint* answering every way out in one line: a :class:`Refused` request its status
    and line; a client gone half way nothing (there is no one to answer); a fault of camfab's
    own a 500 with its line, and the same line on stderr (the traceback with
    ``CAMFAB_DEBUG=1``)."""

    @functools.wraps(endpoint)
    async def answer(request: Request) -> Response:
        try:
            return await endpoint(request)
        except Refused as exc:
            return _problem(exc.status, exc.line)
        except ClientDisconnect:
            return Response(status_code=400)  # not sent: the client is gone
        except Exception as exc:
            if os.environ.get("CAMFAB_DEBUG"):
                raise
            line = (f"camfab serve: internal error answering {request.method} "
                    f"{request.url.path}: {type(exc).__name__}: {exc}")
            line = " ".join(line.split())[:500]
            sys.stderr.write(line + " (set CAMFAB_DEBUG=1 for details; please report it)\n")
            return _problem(500, line)

    return answer


def _whole(text: str) -> int | None:
    """*text* as a whole number when it is one, in ASCII digits and of a sane size (Python's
    ``str.isdigit`` takes ``²``, which ``int`` refuses)."""
    return int(text) if re.fullmatch(r"[0-9]{1,12}", text) else None


def _version(request: Request) -> int | None:
    """The query's ``version`` (None when not given); refused (400) when not a whole
    number."""
    text = request.query_params.get("version")
    if text is None:
        return None
    version = _whole(text)
    if version is None:
        raise Refused(400, f"version: must be a whole number, got {json.dumps(text[:20])}")
    return version


def _edit_value(value: Any) -> Any:
    """An edit's *value* as JSON gave it; refused (400) when it is a whole number no float
    holds (``10**400``: no design value is that big)."""
    if isinstance(value, int) and not isinstance(value, bool):
        try:
            float(value)
        except OverflowError:
            raise Refused(400, f"value: a number of {len(str(abs(value)))} digits is out "
                               "of range") from None
    return value


async def _json_body(request: Request) -> Any:
    """The request's JSON body, of at most :data:`MAX_BODY` bytes (None when it is not, or
    is JSON nested deeper than Python's parser goes); refused (408) when it takes longer than
    :data:`BODY_SECONDS` to arrive."""

    async def read() -> bytes | None:
        data = bytearray()
        async for chunk in request.stream():
            data += chunk
            if len(data) > MAX_BODY:
                return None
        return bytes(data)

    try:
        data = await asyncio.wait_for(read(), BODY_SECONDS)
    except asyncio.TimeoutError:
        raise Refused(408, f"the request's body took longer than {BODY_SECONDS:g} s") from None
    if data is None:
        return None
    try:
        return json.loads(data)
    except (ValueError, UnicodeDecodeError, RecursionError):
        return None


def _state(studio: Studio, state: dict[str, Any], **options: Any) -> JSONResponse:
    """The page's view *state* of *studio* as JSON, with the edit that broke the design
    (``broken``); a number JSON cannot hold (``1e400`` read as infinity) as null: the design's
    own line says what is wrong with it."""
    state["broken"] = studio.broken
    return JSONResponse(_finite(state), **options)


def _finite(data: Any) -> Any:
    """*data* with each float that is not finite replaced by None."""
    if isinstance(data, float):
        return data if math.isfinite(data) else None
    if isinstance(data, dict):
        return {k: _finite(v) for k, v in data.items()}
    if isinstance(data, list):
        return [_finite(v) for v in data]
    return data


async def _report_of(studio: Studio) -> Response:
    try:
        made = await run_in_threadpool(studio.verified)
    except CamfabError as exc:
        return _problem(422, str(exc))
    return Response(made.report_json, media_type="application/json")


def _scene(made: Any) -> dict[str, Any] | None:
    """The 3-D scene of a verified version (None when it has no STL)."""
    if not made.stl_names:
        return None
    from camfab.serve.scene import scene_json

    return scene_json(made.analysis, list(made.stl_names))


def event_text(event: str, data: str) -> str:
    """A server-sent event: its name and its data, a ``data:`` line per line of it."""
    lines = "".join(f"data: {line}\n" for line in data.split("\n"))
    return f"event: {event}\n{lines}\n"


async def _stream(hub: Hub, studio: Studio) -> AsyncIterator[str]:
    """An events stream: the studio's state first, then each event sent, until the server
    stops."""
    queue: asyncio.Queue[tuple[str, str]] = asyncio.Queue()
    hub.queues.add(queue)
    try:
        view = studio.view
        yield event_text("state", json.dumps({
            "version": view.version, "error": view.error, "edited": studio.edited,
            "conflict": studio.conflict, "origin": "connect"}))
        quiet = 0.0
        while not (hub.stopping.is_set() or hub.should_stop()):
            try:
                event, data = await asyncio.wait_for(queue.get(), POLL_SECONDS)
            except asyncio.TimeoutError:
                quiet += POLL_SECONDS
                if quiet >= KEEPALIVE_SECONDS:
                    quiet = 0.0
                    yield ": keep-alive\n\n"
                continue
            quiet = 0.0
            yield event_text(event, data)
    finally:
        hub.queues.discard(queue)


def notifier(hub: Hub) -> Callable[[str, dict[str, Any] | str], None]:
    """The studio's *notify*: each event sent to the streams, its data as JSON (text as it
    is: the report JSON)."""

    def notify(event: str, data: dict[str, Any] | str) -> None:
        hub.send(event, data if isinstance(data, str) else json.dumps(data))

    return notify
