"""``camfab sweep --scheduler`` with no usable Dask scheduler at the address: a scheme camfab
does not take, an empty or malformed address, a peer that is not a Dask scheduler (an HTTP
server, one that answers in HTTP, one that says nothing, sends bytes that are not Dask's or
closes the connection), a name that does not resolve in time, and a scheduler without workers.
Each is one line on stderr naming ``--scheduler``, exit 2 and nothing written (the output
folder not made), within the deadline; camfab run as its own process, so that a thread left
behind would keep it from exiting (the run's timeout, not wall-time asserts, catches a hang).
"""

from __future__ import annotations

import json
import resource
import select
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib.util import find_spec
from pathlib import Path

import pytest

from camfab.sweep.engines import ANSWER_SECONDS, scheduler_address
from camfab.sweep.vary import SweepError

from .conftest import DESIGNS, REQUIRED, run_cli

SEED = DESIGNS / "seed-10-4.yaml"
#: A sweep's process gets this long (s), some five times the longest deadline: past it, a hang.
RUN_SECONDS = 60
#: CPU a refused sweep may spend (s): importing camfab and Dask takes about one.
CPU_SECONDS = 20


def need_distributed() -> None:
    if find_spec("distributed") is None:
        if REQUIRED:
            pytest.fail("dask distributed (camfab[cluster]) is not installed")
        pytest.skip("dask distributed (camfab[cluster]) is not installed")


@dataclass(frozen=True)
class Run:
    code: int
    out: str
    err: list[str]
    wall_seconds: float
    cpu_seconds: float


def sweep(tmp_path: Path, address: str, *args: str) -> Run:
    """``camfab sweep`` of the seed on the scheduler at *address*, into ``tmp_path/out``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "camfab", "sweep", str(SEED), "--vary", "cam.base_radius=20,30",
         "--scheduler", address, "-o", "out", "--format", "csv", *args],
        cwd=tmp_path, capture_output=True, text=True, timeout=RUN_SECONDS, check=False)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return Run(done.returncode, done.stdout, done.stderr.splitlines(), wall, cpu)


def refused(run: Run, tmp_path: Path, *said: str, lines: int = 1) -> str:
    """The refusal's line: exit 2, *lines* lines on stderr, the last naming --scheduler and
    saying each of *said*, nothing on stdout, no output folder, CPU time sane."""
    assert run.code == 2, (run.code, run.err)
    assert len(run.err) == lines, run.err
    line = run.err[-1]
    assert line.startswith("camfab sweep: --scheduler "), line
    assert "internal error" not in line
    for words in said:
        assert words in line, line
    assert run.out == ""
    assert not (tmp_path / "out").exists()
    assert run.cpu_seconds < CPU_SECONDS, run
    return line


@pytest.mark.parametrize(("address", "said"), [
    ("ucx://127.0.0.1:8786", "over tcp:// only"),
    ("inproc://127.0.0.1/1/1", "over tcp:// only"),
    ("tls://127.0.0.1:8786", "tls:// needs Dask's security settings"),
    ("http://127.0.0.1:8787", "give the scheduler's"),
    ("", "--scheduler '': no address"),
    ("tcp://127.0.0.1", "no port"),
    ("tcp://::1:8786", "an IPv6 address goes in brackets"),
])
def test_an_address_camfab_cannot_use_is_refused_before_any_work(
        tmp_path: Path, address: str, said: str) -> None:
    refused(sweep(tmp_path, address), tmp_path, said)


@pytest.mark.parametrize(("address", "said"), [
    ("tcp://h:0", "the port must be a number from 1 to 65535"),
    ("tcp://h:8786/", "the port must be a number"),
    ("tcp://[::1]", "no port"),
    ("tcp://:8786", "no host"),
    ("tcp://h st:1", "holds no spaces"),
    (" tcp://h:1", "holds no spaces"),
    ("tcp://h@x:1", "'h@x' is not a host name"),
    ("://h:1", "not (none)://"),
    ("wss://h:1", "not wss://"),
])
def test_a_malformed_address_says_what_is_wrong(address: str, said: str) -> None:
    with pytest.raises(SweepError, match=r"^camfab sweep: --scheduler ") as caught:
        scheduler_address(address)
    assert said in str(caught.value)


@pytest.mark.parametrize(("address", "dask"), [
    ("tcp://10.0.0.5:8786", "tcp://10.0.0.5:8786"),
    ("10.0.0.5:8786", "tcp://10.0.0.5:8786"),  # a bare HOST:PORT is tcp://, as in Dask
    ("TCP://node-3.cluster.local:08786", "tcp://node-3.cluster.local:8786"),
    ("tcp://[::1]:8786", "tcp://[::1]:8786"),
])
def test_a_tcp_address_is_taken(address: str, dask: str) -> None:
    assert scheduler_address(address) == dask


def test_cluster_timeout_is_seconds_from_0_to_a_day_with_a_scheduler(tmp_path: Path) -> None:
    for args, said in [(("5",), "--cluster-timeout: only with --scheduler"),
                       *[(("--scheduler", "tcp://127.0.0.1:9", value),
                          f"--cluster-timeout {value}: must be 0 to 86400 s")
                         for value in ("-1", "86401", "inf", "nan")]]:
        result = run_cli("sweep", str(SEED), "--vary", "cam.base_radius=20,30", "-o", "out",
                         *args[:-1], "--cluster-timeout", args[-1], cwd=tmp_path)
        assert result.exit_code == 2, result.output
        assert said in result.output
        assert len(result.output.strip().splitlines()) == 1
        assert not (tmp_path / "out").exists()


class Peer:
    """A TCP server on 127.0.0.1 that hands each connection to *treat*, in a thread of its
    own, and holds it open (unless *treat* closes it)."""

    def __init__(self, treat: Treat) -> None:
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.listener.settimeout(0.1)
        self.address = f"tcp://127.0.0.1:{self.listener.getsockname()[1]}"
        self.held: list[socket.socket] = []
        self.stop = threading.Event()
        self.treat = treat
        threading.Thread(target=self.serve, daemon=True).start()

    def serve(self) -> None:
        while not self.stop.is_set():
            try:
                conn, _ = self.listener.accept()
            except TimeoutError:
                continue
            conn.settimeout(RUN_SECONDS)
            self.held.append(conn)
            threading.Thread(target=self.handle, args=(conn,), daemon=True).start()

    def handle(self, conn: socket.socket) -> None:
        try:
            self.treat(conn)
        except OSError:
            pass

    def close(self) -> None:
        self.stop.set()
        self.listener.close()
        for conn in self.held:
            conn.close()


Treat = Callable[[socket.socket], None]
#: Starts a :class:`Peer` that treats connections so; returns its address.
Start = Callable[[Treat], str]


@pytest.fixture
def peer() -> Iterator[Start]:
    """Start a :class:`Peer` that treats connections so; its address."""
    need_distributed()
    peers: list[Peer] = []

    def start(treat: Treat) -> str:
        peers.append(Peer(treat))
        return peers[-1].address

    yield start
    for p in peers:
        p.close()


def test_an_http_server_is_not_taken_for_a_scheduler(tmp_path: Path) -> None:
    """Python's HTTP server waits for a line of the request (Dask's handshake has one or not,
    by the Python version in it), then answers 400: either way one line."""
    need_distributed()

    class Quiet(BaseHTTPRequestHandler):
        def log_message(self, format: str, *args: object) -> None:
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        run = sweep(tmp_path, f"tcp://127.0.0.1:{server.server_address[1]}")
    finally:
        server.shutdown()
        server.server_close()
    line = refused(run, tmp_path)
    assert ("is not a Dask scheduler" in line
            or f"did not answer Dask's handshake in {ANSWER_SECONDS} s" in line), line
    if "did not answer" in line:  # a peer that takes the connection and says nothing: the
        assert run.wall_seconds >= ANSWER_SECONDS  # deadline bounds the handshake as well


def test_a_peer_that_answers_in_http_is_not_a_scheduler(tmp_path: Path, peer: Start) -> None:
    """'HTTP/1.1' read as the length of Dask's frames is 3.07 EiB: no MemoryError shown."""
    def answer(conn: socket.socket) -> None:
        conn.recv(4096)
        conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")

    refused(sweep(tmp_path, peer(answer)), tmp_path, "the peer there is not a Dask scheduler")


def test_a_peer_that_sends_garbage_is_not_a_scheduler(tmp_path: Path, peer: Start) -> None:
    for garbage in (b"\xff" * 64, b"\x01" + b"\x00" * 7 + b"\x05" + b"\x00" * 7 + b"abcde"):
        address = peer(lambda conn, garbage=garbage: conn.sendall(garbage))
        refused(sweep(tmp_path, address), tmp_path, "the peer there is not a Dask scheduler",
                "not Dask's protocol")


def test_a_peer_that_closes_the_connection_is_one_line(tmp_path: Path, peer: Start) -> None:
    refused(sweep(tmp_path, peer(lambda conn: conn.close())), tmp_path,
            "cannot reach a Dask scheduler there", "the peer closed the connection")


def test_a_name_that_does_not_resolve_in_time_is_one_line(tmp_path: Path) -> None:
    """The name looked up in a thread that does not keep camfab from exiting: here the
    look-up of one name takes a minute."""
    need_distributed()
    slow = ("import socket, sys, time\n"
            "real = socket.getaddrinfo\n"
            "def slow(host, *args, **kwargs):\n"
            "    if host == 'slow.invalid':\n"
            "        time.sleep(600)\n"
            "    return real(host, *args, **kwargs)\n"
            "socket.getaddrinfo = slow\n"
            "from camfab.cli import main\n"
            "sys.argv[0] = 'camfab'\n"
            "main()\n")
    start = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-c", slow, "sweep", str(SEED), "--vary", "cam.base_radius=20,30",
         "--scheduler", "tcp://slow.invalid:8786", "-o", "out"], cwd=tmp_path,
        capture_output=True, text=True, timeout=RUN_SECONDS, check=False)
    run = Run(done.returncode, done.stdout, done.stderr.splitlines(), time.monotonic() - start,
              0.0)
    refused(run, tmp_path, "cannot reach a Dask scheduler there", "no address for slow.invalid")


def _dask(*args: str, **kwargs) -> subprocess.Popen:  # type: ignore[no-untyped-def]
    return subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_" + args[0],
                             *args[1:]], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            **kwargs)


def _stop(processes: list[subprocess.Popen]) -> None:
    for process in processes:
        process.terminate()
    for process in processes:
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()


@pytest.fixture
def scheduler(tmp_path: Path) -> Iterator[str]:
    """A Dask scheduler of its own process, with no worker: its address."""
    need_distributed()
    file = tmp_path / "scheduler.json"
    process = _dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                    "--scheduler-file", str(file))
    try:
        deadline = time.monotonic() + RUN_SECONDS
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        time.sleep(0.1)  # the file written whole
        yield json.loads(file.read_text())["address"]
    finally:
        _stop([process])


def test_a_scheduler_without_workers_is_waited_for_then_refused(tmp_path: Path,
                                                                 scheduler: str) -> None:
    run = sweep(tmp_path, scheduler, "--cluster-timeout", "2")
    refused(run, tmp_path, "no worker joined the scheduler in 2 s", "--cluster-timeout",
            lines=2)
    assert run.err[0] == (f"camfab sweep: waiting for workers at {scheduler}: 0 so far (up "
                          f"to 2 s; --cluster-timeout)")
    assert run.wall_seconds >= 2
    no_wait = sweep(tmp_path, scheduler, "--cluster-timeout", "0")
    refused(no_wait, tmp_path, "the scheduler has no worker (--cluster-timeout 0")


def test_a_worker_that_joins_in_the_wait_runs_the_sweep(tmp_path: Path, scheduler: str) -> None:
    """The sweep waits for the first worker, then runs; a worker's own address is refused."""
    process = subprocess.Popen(
        [sys.executable, "-m", "camfab", "sweep", str(SEED), "--vary", "cam.base_radius=20,30",
         "--scheduler", scheduler, "-o", "out", "--format", "csv", "--cluster-timeout",
         str(RUN_SECONDS)], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True)
    workers: list[subprocess.Popen] = []
    try:
        assert process.stderr is not None
        assert select.select([process.stderr], [], [], RUN_SECONDS)[0], "no word"
        waiting = process.stderr.readline()
        assert waiting.startswith(f"camfab sweep: waiting for workers at {scheduler}: 0 so far")
        assert not (tmp_path / "out").exists()
        workers.append(_dask("worker", scheduler, "--nthreads", "1", "--no-dashboard",
                             cwd=tmp_path))
        out, err = process.communicate(timeout=RUN_SECONDS)
        assert process.returncode == 0, err
        assert "2 variants" in out
        assert err == ""
        assert (tmp_path / "out" / "seed-10-4-sweep.csv").exists()
        from distributed import Client

        with Client(scheduler, timeout=30, set_as_default=False) as client:
            worker = next(iter(client.scheduler_info()["workers"]))
        (tmp_path / "w").mkdir()
        line = refused(sweep(tmp_path / "w", worker), tmp_path / "w")
        assert "the peer there is not a Dask scheduler (it is a Dask worker" in line
    finally:
        if process.poll() is None:
            process.kill()
        _stop(workers)

