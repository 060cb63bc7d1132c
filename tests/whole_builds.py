"""One ``camfab build`` of a design's data, run in a child forked from this process under a limit
of CPU time, and what the contract says of its outcome: no internal error, a refusal (exit 2) on
one located line, and the ``verification`` check passed wherever the design is buildable.

Shared by the property test of the whole build (``tests/test_property_build.py``) and
``scripts/random_builds.py``, so both judge a build the same way.
"""

from __future__ import annotations

import json
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from tests.limited_child import run_forked

#: CPU seconds one build may take before it counts as a runaway (the slowest ordinary builds,
#: a globoid at a fine tolerance, take some 20 s on a slow machine).
BUILD_CPU_S = 120.0


@dataclass(frozen=True)
class BuildOutcome:
    """How one build ended and what its report says."""

    code: int
    stdout: str
    stderr: str
    cpu_s: float
    #: The report's ``checks`` (empty when the build wrote none: a refusal or a crash).
    checks: list[dict[str, Any]] = field(default_factory=list)

    @property
    def internal_error(self) -> str | None:
        """Why the build is an internal error (a traceback, a crash, a runaway), or None."""
        text = self.stdout + self.stderr
        if self.code < 0:
            return f"killed by signal {-self.code} after {self.cpu_s:.1f} s of CPU time"
        if self.code not in (0, 1, 2):
            return f"exit {self.code}: {self.stderr.strip()[-600:]}"
        if "internal error" in text or "Traceback" in text:
            return self.stderr.strip()[-600:] or self.stdout.strip()[-600:]
        if self.code in (0, 1) and not self.checks:
            return f"exit {self.code} without a report"
        return None

    def unlocated_refusal(self, design: str) -> str | None:
        """What is wrong with a refusal's message (exit 2): it must be one line
        ``FILE:LINE: field: problem``; None when it is (or the build was not refused)."""
        if self.code != 2 or self.internal_error:
            return None
        message = self.stderr.strip()
        if "\n" in message:
            return f"more than one line: {message[:400]!r}"
        if not re.match(re.escape(design) + r":\d+: \S", message):
            return f"not located as {design}:LINE: ...: {message[:400]!r}"
        return None

    @property
    def verification(self) -> dict[str, Any] | None:
        """The report's ``verification`` check, or None."""
        return next((c for c in self.checks if c["id"] == "verification"), None)

    @property
    def failed_checks(self) -> list[str]:
        """The ids of the failed error checks other than ``verification``."""
        return sorted({c["id"] for c in self.checks if c["id"] != "verification"
                       and c["ok"] is False and c["severity"] == "error"})

    @property
    def steps(self) -> list[str]:
        """What the motion steps in, by the failed ``continuity`` checks (``velocity``, an
        error; ``acceleration``, a warning)."""
        return sorted({c.get("quantity") or "?" for c in self.checks
                       if c["id"] == "continuity" and c["ok"] is False
                       and c.get("quantity") in ("velocity", "acceleration")})

    @property
    def verification_failed(self) -> bool:
        """True when the files do not hold a buildable design: the ``verification`` check
        failed. A design the checks declare unbuildable has its verification *not applicable*
        (``ok`` null: no cam the files could hold, the check it defers to named in its
        message), or held to the cam camfab computes (an undercut's cut cam) — so a failed
        verification is a failure whatever the other checks say."""
        check = self.verification
        return check is not None and check["ok"] is False

    @property
    def ratio(self) -> float | None:
        """The failed verification's value over its limit (deviation / tolerance)."""
        check = self.verification
        if check is None or check.get("value") is None or not check.get("limit"):
            return None
        return float(check["value"]) / float(check["limit"])

    @property
    def stl_unclean(self) -> bool:
        """True when the verification says the STL did not read back as a clean solid."""
        check = self.verification
        return check is not None and "NOT a clean closed outward solid" in check["message"]


def dump(data: dict[str, Any]) -> str:
    """The design file's text of *data*."""
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=100)


def build_design(text: str, cpu_s: float = BUILD_CPU_S) -> BuildOutcome:
    """``camfab build design.yaml -o out`` of the design file *text*, in a child forked from
    this process under *cpu_s* seconds of CPU time, in a temporary folder; its outcome and its
    report's checks."""
    with tempfile.TemporaryDirectory(prefix="camfab-random-") as tmp:
        folder = Path(tmp)
        (folder / "design.yaml").write_text(text, encoding="utf-8")
        run = run_forked(["build", "design.yaml", "-o", "out"], folder, cpu_s=cpu_s,
                         wall_s=max(600.0, 10 * cpu_s))
        reports = sorted((folder / "out").glob("*-report.json"))
        checks = json.loads(reports[0].read_text(encoding="utf-8"))["checks"] if reports else []
    return BuildOutcome(run.code, run.stdout, run.stderr, run.cpu_s, checks)
