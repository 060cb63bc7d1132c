"""Print the sha256 of every file camfab writes, and of the text it prints, for every example
design and every starter: run before and after a change that must change no bytes, and compare.

    python scripts/output_digests.py            # one line per output, then the digest of all
    python scripts/output_digests.py --summary  # the digest of all only
    python scripts/output_digests.py --step     # every build with --step (the STEP files too)

Covered: ``camfab build`` of each ``designs/*.yaml`` and of each ``camfab new KIND`` starter
(every file written), ``camfab check`` of each (its text, with the terminal width fixed), and
``camfab inspect`` of each plate DXF against its design (its files and text). Nothing timed is
hashed (the build's summary line carries a time).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _camfab(*args: str, cwd: Path) -> subprocess.CompletedProcess[bytes]:
    env = {**os.environ, "COLUMNS": "160", "NO_COLOR": "1", "TERM": "dumb"}
    return subprocess.run([sys.executable, "-m", "camfab", *args], cwd=cwd, env=env,
                          capture_output=True, check=False)


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def digests(work: Path, jobs: int, step: bool = False) -> list[tuple[str, str]]:
    """(sha256, what) for every output, in a fixed order."""
    from camfab.cli import STARTER_KINDS

    sources = work / "sources"
    sources.mkdir()
    designs = sorted((ROOT / "designs").glob("*.yaml"))
    for kind in STARTER_KINDS:
        starter = sources / f"starter-{kind}.yaml"
        starter.write_bytes(_camfab("new", kind, cwd=work).stdout)
        designs.append(starter)
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(jobs) as pool:
        per_design = list(pool.map(lambda d: _design_rows(d, work, step), designs))
    return [row for rows in per_design for row in rows]


def _design_rows(design: Path, work: Path, step: bool) -> list[tuple[str, str]]:
    rows: list[tuple[str, str]] = []
    label = design.stem
    out = work / "builds" / label
    build = _camfab("build", str(design), "-o", str(out), *(["--step"] if step else []),
                    cwd=work)
    rows.append((_sha(str(build.returncode).encode() + build.stderr.replace(
        str(work).encode(), b"WORK")), f"{label} build status"))
    for path in sorted(out.iterdir()):
        rows.append((_sha(path.read_bytes()), f"{label}/{path.name}"))
    check = _camfab("check", str(design), cwd=work)
    rows.append((_sha(str(check.returncode).encode() + check.stdout + check.stderr),
                 f"{label} check text"))
    for dxf in sorted(out.glob("*.dxf")):
        folder = work / "inspections" / dxf.stem
        ins = _camfab("inspect", str(dxf), "--design", str(design), "-o", str(folder),
                      cwd=work)
        text = ins.stdout.replace(str(work).encode(), b"WORK")
        rows.append((_sha(str(ins.returncode).encode() + text + ins.stderr.replace(
            str(work).encode(), b"WORK")), f"{label} inspect {dxf.name} text"))
        if folder.is_dir():
            for path in sorted(folder.iterdir()):
                rows.append((_sha(path.read_bytes().replace(str(work).encode(), b"WORK")),
                             f"{label} inspect {dxf.name}/{path.name}"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--summary", action="store_true", help="print the digest of all only")
    parser.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 1,
                        help="designs run at once (default: the processor count)")
    parser.add_argument("--step", action="store_true",
                        help="build with --step: the STEP files (and their check) too")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temp:
        rows = digests(Path(temp), args.jobs, args.step)
    listing = "".join(f"{sha}  {what}\n" for sha, what in rows)
    if not args.summary:
        sys.stdout.write(listing)
    print(f"{len(rows)} outputs, digest of all: {_sha(listing.encode())}")


if __name__ == "__main__":
    main()
