"""Rebuild and rerun fuzz cases by index, outside pytest.

Usage (from the repository root)::

    python -m tests.fuzz --case 17 [--case 42] [--seed 0] [--keep DIR] [--timeout 10]
    python -m tests.fuzz --list 40          # what the first 40 cases do

Each case's files are written to ``DIR/case-NNNNN`` (kept), the commands are
printed so they can be typed again by hand, and every failure is listed.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

if __package__ in (None, ""):  # pragma: no cover - run as a script
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    __package__ = "fuzz"

from .cases import build_case, write_case  # noqa: E402
from .harness import Worker, judge, report  # noqa: E402

DEFAULT_SEED = 20261201  # the same as tests/conftest.py's FUZZ_DEFAULT_SEED


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m tests.fuzz", description=__doc__.splitlines()[0])
    p.add_argument("--seed", type=int, default=DEFAULT_SEED)
    p.add_argument("--case", type=int, action="append", default=[], help="case index (repeatable)")
    p.add_argument("--list", type=int, metavar="N", help="print what the first N cases do and stop")
    p.add_argument("--keep", type=Path, help="folder for the case files (default: a new temporary folder)")
    p.add_argument("--timeout", type=float, default=10.0)
    args = p.parse_args(argv)
    if args.list:
        for i in range(args.list):
            c = build_case(args.seed, i)
            print(f"{c.label}: {c.detail[:100]}")
        return 0
    if not args.case:
        p.error("give --case INDEX (or --list N)")
    keep = args.keep or Path(tempfile.mkdtemp(prefix="fuzz-cases-"))
    worker = Worker(keep / "worker.log", timeout=args.timeout)
    bad = 0
    try:
        for index in args.case:
            case = build_case(args.seed, index)
            folder = keep / f"case-{index:05d}"
            if folder.exists() or folder.is_symlink():
                shutil.rmtree(folder)
            steps = write_case(case, folder)
            reply = worker.run(steps)
            failures = judge(case, steps, reply, folder)
            print(
                report(case, steps, reply, folder, failures)
                if failures
                else f"case {case.label}: ok ({case.detail[:100]})"
            )
            bad += bool(failures)
    finally:
        worker.stop()
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
