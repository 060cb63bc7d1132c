"""The child process of ``tests/test_inspect_fuzz.py``: many ``camfab inspect`` runs in one
process (the imports, a second or two, are paid once), each under its own CPU-time limit.

``python -m tests.inspect_fuzz_child CASES.json RESULTS.jsonl CASE_CPU_S`` runs the cases (each
``{"id": ..., "args": [...]}``) through click's CliRunner and appends to RESULTS one JSON line
when a case starts and one with its outcome: exit status, stderr, CPU seconds, the process's
peak resident memory so far, and any exception that escaped the command line. Before each case
the soft ``RLIMIT_CPU`` is set to the CPU time used so far plus CASE_CPU_S, so a case that runs
away is killed (SIGXCPU) within that much CPU time, and the parent knows which from the last
line. The cases that follow run in a new child.
"""

from __future__ import annotations

import json
import resource
import sys
from pathlib import Path


def cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def limit_cpu(seconds: float) -> None:
    """Let this process use *seconds* more CPU time, within its hard limit."""
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    soft = int(cpu_seconds() + seconds) + 1
    if hard != resource.RLIM_INFINITY:
        soft = min(soft, hard)
    resource.setrlimit(resource.RLIMIT_CPU, (soft, hard))


def run(cases_path: Path, results_path: Path, case_cpu_s: float) -> None:
    from click.testing import CliRunner

    from camfab.cli import main

    cases = json.loads(cases_path.read_text())
    runner = CliRunner()
    with results_path.open("a", encoding="utf-8") as out:
        for case in cases:
            out.write(json.dumps({"start": case["id"]}) + "\n")
            out.flush()
            limit_cpu(case_cpu_s)
            before = cpu_seconds()
            result = runner.invoke(main, ["inspect", *case["args"]], catch_exceptions=True)
            used = cpu_seconds() - before
            error = result.exception
            escaped = (None if error is None or isinstance(error, SystemExit)
                       else f"{type(error).__name__}: {error}")
            out.write(json.dumps({
                "id": case["id"], "code": result.exit_code, "stderr": result.stderr,
                "cpu_s": used, "maxrss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
                "escaped": escaped}) + "\n")
            out.flush()


if __name__ == "__main__":
    run(Path(sys.argv[1]), Path(sys.argv[2]), float(sys.argv[3]))
