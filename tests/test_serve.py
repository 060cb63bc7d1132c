"""``camfab serve`` as a user and a script use it, over HTTP: the server started as a program
(``python -m camfab serve … --port 0``) on a copy of an example. The API's report is, byte for
byte, the ``NAME-report.json`` that ``camfab build`` writes of the same file, and an edit's
answer that of the edited file, the file on disk untouched; every request without the token, or
naming another host, or a POST from another origin, is refused; a save changes the one value
and keeps every comment and the layout, and is refused once the file changed on disk; the file
saved in another editor reaches the events stream as the new report, and so does a table law's
CSV file changed, a change made the moment the address is printed, and a design path made a
symbolic link (and its file changed); a file that cannot be read (a loop of links, a table's name
with a NUL) is the design's error and the watch goes on, as it does after a fault of its own;
Ctrl-C stops the server with 130 and leaves no temporary file; a missing file, a port in use or
a host that is not this machine's is one line and status 2."""

from __future__ import annotations

import difflib
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from camfab.pipeline import build

from .conftest import DESIGNS

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")
pytest.importorskip("watchfiles")
pytest.importorskip("ruamel.yaml")

#: A backstop (s) for waits on the server: a loaded machine is slow, a hung server is not.
BACKSTOP = 120.0


@dataclass
class Served:
    """A running ``camfab serve``: its process, base URL, token and the design file."""

    process: subprocess.Popen[str]
    base: str
    token: str
    file: Path

    def request(self, path: str, data: Any = None, token: bool = True,
                headers: dict[str, str] | None = None) -> tuple[int, bytes]:
        """The status and body of a GET (or a POST of *data* as JSON)."""
        sent = dict(headers or {})
        if token:
            sent["X-Camfab-Token"] = self.token
        body = None if data is None else json.dumps(data).encode()
        request = urllib.request.Request(self.base + path, data=body, headers=sent,
                                         method="GET" if data is None else "POST")
        try:
            with urllib.request.urlopen(request, timeout=BACKSTOP) as answer:
                return answer.status, answer.read()
        except urllib.error.HTTPError as exc:
            return exc.code, exc.read()

    def stop(self) -> tuple[int, str]:
        """Ctrl-C: the exit status and what it wrote on stderr."""
        self.process.send_signal(signal.SIGINT)
        _, err = self.process.communicate(timeout=BACKSTOP)
        return self.process.returncode, err


def serve(folder: Path, name: str, *args: str) -> Served:
    """``camfab serve`` of a copy of example *name* in *folder* (its working folder)."""
    file = folder / "design.yaml"
    shutil.copy(DESIGNS / f"{name}.yaml", file)
    process = subprocess.Popen(
        [sys.executable, "-m", "camfab", "serve", file.name, "--no-open", "--port", "0", *args],
        cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    found = re.search(r"(http://[^/\s]+)/\?token=(\S+)", line)
    assert found, (line, process.stderr.read() if process.poll() is not None else "")
    return Served(process, found.group(1), found.group(2), file)


@pytest.fixture(scope="module")
def disc(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    served = serve(tmp_path_factory.mktemp("studio"), "seed-10-4")
    yield served
    if served.process.poll() is None:
        served.stop()


def built_report(file: Path, folder: Path) -> bytes:
    """``camfab build``'s NAME-report.json of design *file*."""
    result = build(file, folder)
    return (folder / f"{result.analysis.design.name}-report.json").read_bytes()


def test_the_api_s_report_is_the_build_s_json_byte_for_byte(disc: Served,
                                                            tmp_path: Path) -> None:
    status, body = disc.request("/api/report")
    assert status == 200
    assert body == built_report(disc.file, tmp_path)


def test_an_edit_answers_the_edited_design_s_report_and_leaves_the_file(
        disc: Served, tmp_path: Path) -> None:
    before = disc.file.read_bytes()
    status, body = disc.request("/api/edit", {"path": "cam.base_radius", "value": 42})
    assert status == 200, body
    assert disc.file.read_bytes() == before
    edited = tmp_path / "edited.yaml"
    edited.write_text(before.decode().replace("base_radius: 20", "base_radius: 42"))
    assert body == built_report(edited, tmp_path / "out")
    report = json.loads(body)
    assert report["design"]["cam"]["base_radius"] == 42
    # the model's form of a segment's path (as camfab sweep --vary takes it) is the same key
    status, body = disc.request("/api/edit", {"path": "motion[0].lift", "value": 30})
    assert status == 200 and json.loads(body)["segments"][0]["lift_mm"] == 30
    status, _ = disc.request("/api/reload", {})
    assert status == 200


def test_an_edit_of_an_anchored_value_shows_its_aliases_new_value_at_once(
        tmp_path: Path) -> None:
    """The page's answer to an edit carries every value, so an alias of the value edited (the
    same value, written once) shows its new value without the page being opened again."""
    served = serve(tmp_path, "seed-10-4")
    try:
        first = json.loads(served.request("/api/state")[1])["version"]
        text = served.file.read_text()
        served.file.write_text(text.replace("thickness: 10", "thickness: &t 10")
                               .replace("bore: 10", "bore: *t"))
        assert _state_when(served, lambda state: state["version"] > first)["error"] is None
        status, body = served.request("/api/edit?respond=view",
                                      {"path": "cam.thickness", "value": 12})
        assert status == 200, body
        values = {f["path"]: f["value"] for f in json.loads(body)["fields"]}
        assert values["cam.thickness"] == 12 and values["cam.bore"] == 12
    finally:
        served.stop()


@pytest.mark.parametrize(("edit", "said"), [
    ({"path": "cam.nowhere.x", "value": 1}, "cam.nowhere.x: the design has no cam.nowhere"),
    ({"path": "cam", "value": 1}, "cam: holds a mapping, not a value"),
    ({"path": "motion[7].lift", "value": 1}, "the design has no motion[7]"),
    ({"path": "cam.base_radius", "value": [1]}, "must be a number, a word or true/false"),
    ({"path": "cam.base_radius"}, 'the body must be {"path": ..., "value": ...}'),
    ({"path": "motion[0].rise.csv", "value": "/etc/passwd"},
     "motion[0].rise.csv: names a file, which the studio does not change"),
])
def test_an_edit_the_design_cannot_take_is_refused_with_its_line(
        disc: Served, edit: dict[str, Any], said: str) -> None:
    status, body = disc.request("/api/edit", edit)
    assert status == 400
    assert said in json.loads(body)["error"]


def test_an_edit_that_breaks_the_design_answers_its_located_line(disc: Served) -> None:
    status, body = disc.request("/api/edit", {"path": "cam.base_radius", "value": -3})
    assert status == 422
    line = json.loads(body)["error"]
    assert re.match(r"design\.yaml:\d+: cam\.base_radius: ", line), line
    status, body = disc.request("/api/state")
    state = json.loads(body)
    assert state["error"] == line and state["html"]  # the last good picture is kept
    disc.request("/api/reload", {})


def test_requests_without_the_token_from_another_host_or_origin_are_refused(
        disc: Served) -> None:
    for path in ("/", "/api/report", "/api/state", "/api/events", "/api/verified",
                 "/api/part/0", "/s/x/studio.js", "/favicon.ico"):
        assert disc.request(path, token=False)[0] == 403, path
        assert disc.request(path, token=False, headers={"X-Camfab-Token": "x"})[0] == 403
    for path in ("/api/edit", "/api/save", "/api/reload", "/api/size", "/api/build"):
        assert disc.request(path, {}, token=False)[0] == 403, path
        assert disc.request(path, {}, headers={"Origin": "http://evil.example"})[0] == 403
    port = disc.base.rsplit(":", 1)[1]
    assert disc.request("/api/state", headers={"Host": f"evil.example:{port}"})[0] == 403
    # with it: the page, its static files (the token in their path) and the query's token
    assert disc.request("/")[0] == 200
    assert disc.request(f"/s/{disc.token}/studio.js", token=False)[0] == 200
    assert disc.request(f"/s/{disc.token}/three/three.module.js", token=False)[0] == 200
    assert disc.request(f"/s/{disc.token}/../app.py", token=False)[0] == 404
    assert disc.request(f"/api/state?token={disc.token}", token=False)[0] == 200


def test_a_save_changes_the_one_value_keeps_the_comments_and_refuses_after_a_change_on_disk(
        disc: Served) -> None:
    before = disc.file.read_text()
    mode = 0o640
    os.chmod(disc.file, mode)
    assert disc.request("/api/edit", {"path": "cam.base_radius", "value": 22.5})[0] == 200
    status, body = disc.request("/api/save", {})
    assert status == 200, body
    after = disc.file.read_text()
    changed = [line for line in difflib.ndiff(before.splitlines(), after.splitlines())
               if line[:1] in "+-"]
    assert changed == ["-   base_radius: 20          # D_b = 40 mm",
                       "+   base_radius: 22.5        # D_b = 40 mm"], changed
    assert before.count("#") == after.count("#") > 0
    assert os.stat(disc.file).st_mode & 0o777 == mode
    # another editor saves the file while the studio holds an edit: the studio's save is
    # refused, the file stays theirs (the edit first: a studio that read their file before
    # the edit would rightly edit and save it)
    assert disc.request("/api/edit", {"path": "cam.base_radius", "value": 25})[0] == 200
    theirs = after + "# a note from another editor\n"
    disc.file.write_text(theirs)
    status, body = disc.request("/api/save", {})
    assert status == 409
    assert "changed on disk since the studio loaded it" in json.loads(body)["error"]
    assert disc.file.read_text() == theirs
    status, body = disc.request("/api/reload", {})
    assert status == 200 and not json.loads(body)["edited"]
    assert not list(disc.file.parent.glob(".*.tmp"))


def test_size_answers_camfab_size_and_build_writes_the_build_s_files(disc: Served) -> None:
    status, body = disc.request("/api/size", {})
    assert status == 200
    answer = json.loads(body)
    size = subprocess.run([sys.executable, "-m", "camfab", "size", disc.file.name],
                          cwd=disc.file.parent, capture_output=True, text=True)
    assert answer["lines"] == size.stdout.splitlines()
    assert answer["edits"][0]["path"] == "cam.base_radius"
    status, body = disc.request("/api/build", {})
    assert status == 200
    made = json.loads(body)
    folder = disc.file.parent / made["folder"]
    assert sorted(made["files"]) == sorted(p.name for p in folder.iterdir())
    assert "seed-10-4.dxf" in made["files"] and made["exit_code"] == 1


def _events(served: Served, until: float) -> Iterator[tuple[str, str]]:
    """The events of the stream until *until* (a monotonic time)."""
    request = urllib.request.Request(served.base + f"/api/events?token={served.token}")
    with urllib.request.urlopen(request, timeout=BACKSTOP) as stream:
        event, data = "", []
        while time.monotonic() < until:
            line = stream.readline().decode()
            if not line:
                return
            line = line.rstrip("\n")
            if line.startswith("event: "):
                event = line[7:]
            elif line.startswith("data: "):
                data.append(line[6:])
            elif line == "" and event:
                yield event, "\n".join(data)
                event, data = "", []


def test_the_file_saved_in_an_editor_reaches_the_events_as_its_new_report(
        tmp_path: Path) -> None:
    served = serve(tmp_path, "demo-inch-flat")
    try:
        events = _events(served, time.monotonic() + BACKSTOP)
        first = next(events)
        assert first[0] == "state"
        # an editor that saves by writing a new file and renaming it over the old one
        text = served.file.read_text().replace("name: demo-inch-flat", "name: renamed")
        new = served.file.with_suffix(".new")
        new.write_text(text)
        os.replace(new, served.file)
        report = next(data for event, data in events
                      if event == "report" and '"name": "renamed"' in data)
        assert report.encode() + b"\n" == built_report(served.file, tmp_path / "out")
        # a design that does not load: its located line, the last good page kept
        served.file.write_text(text.replace("base_radius:", "base_radius: [", 1))
        state = next(json.loads(data) for event, data in events
                     if event == "state" and json.loads(data)["error"])
        assert re.match(r"design\.yaml:\d+: ", state["error"]), state
        status, body = served.request("/api/report")
        assert status == 422 and json.loads(body)["error"] == state["error"]
        assert json.loads(served.request("/api/state")[1])["html"]
    finally:
        code, err = served.stop()
    assert code == 130 and err == "camfab: interrupted\n"


def test_a_table_law_s_csv_file_is_watched_too(tmp_path: Path) -> None:
    served = serve(tmp_path, "demo-table")
    points = "0, 0\n20, 1.2\n40, 6.0\n60, 12.5\n80, 16.8\n100, {}\n"
    table = tmp_path / "lift.csv"
    table.write_text(points.format(18))
    try:
        events = _events(served, time.monotonic() + BACKSTOP)
        assert next(events)[0] == "state"
        text = served.file.read_text()
        served.file.write_text(re.sub(r"points: \[\[.*\]\]", "csv: lift.csv", text))
        lift = next(json.loads(data)["segments"][0]["lift_mm"] for event, data in events
                    if event == "report" and '"csv": "lift.csv"' in data)
        assert lift == 18
        table.write_text(points.format(21))
        lift = next(json.loads(data)["segments"][0]["lift_mm"] for event, data in events
                    if event == "report" and json.loads(data)["segments"][0]["lift_mm"] != 18)
        assert lift == 21
    finally:
        assert served.stop()[0] == 130


def _state_when(served: Served, wanted: Any) -> dict[str, Any]:
    """The page's state once *wanted* (a test of it) holds; the last one at the backstop."""
    until = time.monotonic() + BACKSTOP
    while True:
        state = json.loads(served.request("/api/state")[1])
        if wanted(state) or time.monotonic() > until:
            return state
        time.sleep(0.05)


def _replace_by_link(path: Path, target: str) -> None:
    """*path* made a symbolic link to *target* in one step, as an editor's rename does."""
    link = path.with_name(path.name + ".link")
    link.symlink_to(target)
    os.replace(link, path)


def test_a_change_made_at_once_after_the_address_is_printed_is_seen(tmp_path: Path) -> None:
    served = serve(tmp_path, "demo-inch-flat")
    try:  # (before the server has started, let alone watched the folder)
        text = served.file.read_text()
        served.file.write_text(text.replace("name: demo-inch-flat", "name: early"))
        state = _state_when(served, lambda state: state["name"] == "early")
        assert state["name"] == "early" and state["error"] is None, state
    finally:
        assert served.stop()[0] == 130


def test_a_design_path_that_becomes_a_symbolic_link_is_followed(tmp_path: Path) -> None:
    served = serve(tmp_path, "demo-inch-flat")
    text = served.file.read_text()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    target = elsewhere / "real.yaml"
    target.write_text(text.replace("name: demo-inch-flat", "name: linked"))
    try:
        _replace_by_link(served.file, str(target))
        state = _state_when(served, lambda state: state["name"] == "linked")
        assert state["name"] == "linked", state
        # the file the link leads to, changed: seen too
        target.write_text(text.replace("name: demo-inch-flat", "name: target-changed"))
        state = _state_when(served, lambda state: state["name"] == "target-changed")
        assert state["name"] == "target-changed", state
    finally:
        assert served.stop()[0] == 130


def test_the_watch_outlives_link_loops_and_tables_it_cannot_read(tmp_path: Path) -> None:
    """A design path that loops through symbolic links, a table's name with a NUL, a table
    that loops: each is the design's located error in the page, and the file is still watched
    (a good design after them is seen, and so is its table changed)."""
    served = serve(tmp_path, "demo-table")
    points = "0, 0\n20, 1.2\n40, 6.0\n60, 12.5\n80, 16.8\n100, {}\n"
    (tmp_path / "lift.csv").write_text(points.format(18))
    text = re.sub(r"points: \[\[.*\]\]", "csv: lift.csv", served.file.read_text())
    (tmp_path / "a.yaml").symlink_to("b.yaml")
    (tmp_path / "b.yaml").symlink_to("a.yaml")
    (tmp_path / "c.csv").symlink_to("d.csv")
    (tmp_path / "d.csv").symlink_to("c.csv")
    try:
        _replace_by_link(served.file, "a.yaml")
        state = _state_when(served, lambda state: state["error"] is not None)
        assert state["error"].startswith("design.yaml: "), state
        for name, said in (('"lift\\0.csv"', "a path holds no NUL character"),
                           ("c.csv", "cannot read the table: c.csv cannot be read")):
            served.file.unlink()
            served.file.write_text(text.replace("csv: lift.csv", f"csv: {name}"))
            state = _state_when(served, lambda state, said=said: said in (state["error"] or ""))
            assert re.match(r"design\.yaml:\d+: motion\[0\]\.csv: ", state["error"]), state
            assert said in state["error"], state
        served.file.write_text(text.replace("name: demo-table", "name: recovered"))
        state = _state_when(served, lambda state: state["name"] == "recovered")
        assert state["name"] == "recovered" and state["error"] is None, state
        (tmp_path / "lift.csv").write_text(points.format(21))
        _state_when(served, lambda state: state["version"] > 0 and state["error"] is None
                    and json.loads(served.request("/api/report")[1])["segments"][0][
                        "lift_mm"] == 21)
        assert json.loads(served.request("/api/report")[1])["segments"][0]["lift_mm"] == 21
    finally:
        assert served.stop()[0] == 130


def test_a_fault_of_the_watch_is_said_in_the_page_and_the_watch_goes_on(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The watch of a studio (in this process) whose first try fails: the fault is the
    design's error in the page until the watch runs again, then the design is shown again and
    a change on disk is seen."""
    import asyncio

    import watchfiles

    from camfab.serve.studio import Studio
    from camfab.serve.watch import Watcher

    file = tmp_path / "design.yaml"
    shutil.copy(DESIGNS / "demo-inch-flat.yaml", file)
    studio = Studio(file, "design.yaml")
    tries: list[int] = []
    awatch = watchfiles.awatch

    def failing_once(*args: Any, **kwargs: Any) -> Any:
        tries.append(1)
        if len(tries) == 1:
            raise RuntimeError("the watch broke")
        return awatch(*args, **kwargs)

    monkeypatch.setattr(watchfiles, "awatch", failing_once)

    async def until(wanted: Any) -> None:
        deadline = time.monotonic() + BACKSTOP
        while not wanted() and time.monotonic() < deadline:
            await asyncio.sleep(0.05)

    async def scenario() -> None:
        stopping = asyncio.Event()
        watching = asyncio.create_task(Watcher(studio).run(stopping))
        try:
            await until(lambda: "the watch broke" in (studio.view.error or ""))
            assert (studio.view.error or "").startswith("design.yaml: "), studio.view
            await until(lambda: len(tries) > 1 and studio.view.error is None)
            assert studio.view.error is None and studio.view.name == "demo-inch-flat"
            file.write_text(file.read_text().replace("name: demo-inch-flat", "name: later"))
            await until(lambda: studio.view.name == "later")
            assert studio.view.name == "later"
        finally:
            stopping.set()
            await asyncio.wait_for(watching, BACKSTOP)

    try:
        asyncio.run(scenario())
    finally:
        studio.close()


def test_ctrl_c_stops_it_with_130_and_no_temporary_file(disc: Served) -> None:
    code, err = disc.stop()
    assert code == 130
    assert err == "camfab: interrupted\n"
    assert not [p for p in disc.file.parent.rglob("*") if p.name.endswith(".tmp")]


def test_a_missing_file_a_port_in_use_and_another_machine_s_host_are_one_line(
        tmp_path: Path) -> None:
    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "camfab", "serve", *args, "--no-open"],
                              cwd=tmp_path, capture_output=True, text=True, timeout=BACKSTOP)

    shutil.copy(DESIGNS / "seed-10-4.yaml", tmp_path / "d.yaml")
    (tmp_path / "folder.yaml").mkdir()
    taken = socket.socket()
    taken.bind(("127.0.0.1", 0))
    taken.listen()
    port = taken.getsockname()[1]
    try:
        cases = {
            ("nothing.yaml",): "nothing.yaml: no such design file",
            ("folder.yaml",): "folder.yaml: ",
            ("d.yaml", "--port", str(port)):
                f"camfab serve: port {port} on 127.0.0.1 is in use",
            ("d.yaml", "--host", "192.0.2.1"):
                "camfab serve: --host 192.0.2.1: not an address of this machine",
        }
        for args, said in cases.items():
            done = run(*args)
            assert done.returncode == 2, (args, done.stderr)
            assert done.stdout == "" and done.stderr.count("\n") == 1, done.stderr
            assert done.stderr.startswith(said), done.stderr
    finally:
        taken.close()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.yaml", "folder.yaml"]


def test_another_host_is_served_with_a_warning(tmp_path: Path) -> None:
    served = serve(tmp_path, "seed-10-4", "--host", "0.0.0.0")
    try:
        assert served.request("/api/state")[0] == 200
    finally:
        code, err = served.stop()
    assert code == 130
    assert err.startswith("camfab serve: listening on 0.0.0.0: anyone who can reach")
