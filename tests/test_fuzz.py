"""Fuzzing: hostile levels, replays, settings, meshes and options, run as a user runs them.

Each case mutates a shipped file (``levels/*.toml``, ``levels/replays/*.json``,
the default settings, ``assets/meshes/*.obj``, ``.npz`` meshes made with
``core.shapes``), puts a special file (a FIFO, a symlink to ``/dev/zero``, a
folder...) in its place, or passes a hostile option, then runs the real entry
point (``across-dimensions`` ``check-level``, ``replay``, ``slice``, ``shape``,
``lift``, or the settings loader) in a memory-capped worker process. It fails
on a traceback or "internal error", an exit status other than 0, 2 or 3
(replay divergence), a refusal that names neither the file nor the option, a
hang past the time limit, a leftover ``*.tmp`` file, a numpy warning shown to
the user, a certainly-invalid input being accepted, and, for a level that
passes check-level, a game that does not keep a finite state over 120 ticks of
seeded random actions.

Run (the default is 300 cases, in about two minutes once the input loaders
refuse quickly; the first run also compiles the numba kernels)::

    python -m pytest tests/test_fuzz.py                       # the CI set
    python -m pytest tests/test_fuzz.py --fuzz-cases 5000     # as many as asked
    python -m pytest tests/test_fuzz.py --fuzz-seed 7         # another set of cases
    python -m pytest tests/test_fuzz.py --fuzz-case 17        # rerun one reported case
    python -m pytest tests/test_fuzz.py --fuzz-keep out/fuzz  # keep failing cases' files there
    python -m tests.fuzz --case 17 --keep out/fuzz            # the same case outside pytest

Every failure names its seed, index, mutation, the folder holding its files
and the commands to type again; the run ends with the failures grouped by
category. Cases are a pure function of (seed, index), so a case reruns alone.
"""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from fuzz import cases as C
from fuzz.emit import json_dumps, toml_dumps
from fuzz.harness import Worker, judge, leftover_temporaries, report

pytestmark = pytest.mark.fuzz


def pytest_generate_tests(metafunc):
    if "fuzz_index" not in metafunc.fixturenames:
        return
    cfg = metafunc.config
    seed = cfg.getoption("--fuzz-seed")
    indices = cfg.getoption("--fuzz-case") or list(range(cfg.getoption("--fuzz-cases")))
    ids = [f"{i:05d}-{'-'.join(C.plan(seed, i))}" for i in indices]
    metafunc.parametrize("fuzz_index", indices, ids=ids)


@pytest.fixture(scope="session")
def fuzz_seed(request) -> int:
    return request.config.getoption("--fuzz-seed")


@pytest.fixture(scope="session")
def fuzz_root(request, tmp_path_factory) -> Path:
    keep = request.config.getoption("--fuzz-keep")
    if keep:
        root = Path(keep).resolve()
        root.mkdir(parents=True, exist_ok=True)
        return root
    return tmp_path_factory.mktemp("fuzz")


@pytest.fixture(scope="session")
def fuzz_worker(request, fuzz_root):
    worker = Worker(fuzz_root / "worker.log", timeout=request.config.getoption("--fuzz-timeout"))
    worker.start()
    yield worker
    worker.stop()


def test_fuzz_case(fuzz_index, fuzz_seed, fuzz_worker, fuzz_root, fuzz_failures):
    case = C.build_case(fuzz_seed, fuzz_index)
    folder = fuzz_root / f"case-{fuzz_index:05d}"
    if folder.exists() or folder.is_symlink():
        shutil.rmtree(folder)
    steps = C.write_case(case, folder)
    reply = fuzz_worker.run(steps)
    failures = judge(case, steps, reply, folder)
    if not failures:
        shutil.rmtree(folder)  # keep only what a developer needs to look at
        return
    fuzz_failures.extend((case.label, f.category, f.message) for f in failures)
    pytest.fail(report(case, steps, reply, folder, failures), pytrace=False)


# ------------------------------------------------------- the harness itself
def test_cases_are_a_pure_function_of_seed_and_index():
    for i in (0, 7, 31, 123):
        a, b = C.build_case(5, i), C.build_case(5, i)
        assert (a.kind, a.mutation, a.detail, a.files, a.steps) == (b.kind, b.mutation, b.detail, b.files, b.steps)
    assert [C.build_case(5, i).files for i in range(6)] != [C.build_case(6, i).files for i in range(6)]


def test_one_cycle_of_cases_tries_every_mutation():
    cycle = C.schedule(0)
    assert set(cycle) == {(k, m) for k, m, _ in C.CATALOGUE}
    assert len(cycle) * 2 <= 300, "the default run should try each mutation at least twice"


@pytest.mark.parametrize("level", C.LEVELS, ids=lambda p: p.stem)
def test_unmutated_levels_survive_the_writer(level, tmp_path):
    """The TOML writer alone changes nothing a loader sees, so a failure is the mutation's doing."""
    from across_dimensions.world.level import load_level

    doc = tomllib.loads(level.read_text(encoding="utf-8"))
    assert tomllib.loads(toml_dumps(doc)) == doc
    out = tmp_path / level.name
    out.write_text(toml_dumps(doc), encoding="utf-8")
    loaded = load_level(out)
    assert len(loaded.boxes) == len(doc.get("box", [])) and len(loaded.objects) == len(doc.get("object", []))


def test_writers_carry_values_a_strict_writer_refuses():
    doc = {"a": float("nan"), "b": 10**5000, "c": [float("inf")]}
    text = toml_dumps(doc)
    assert "a = nan" in text and "c = [inf]" in text and len(text) > 5000
    assert json_dumps({"x": float("nan")}) == '{"x":NaN}'


def test_judge_flags_what_a_user_must_not_see(tmp_path):
    case = C.Case(0, 0, "level", "test", names=("level.toml",))
    steps = [{"op": "cli", "argv": ["check-level", str(tmp_path / "level.toml")], "allowed": [0, 2]}]

    def reply(code, err, **kw):
        res = {
            "op": "cli",
            "exit": code,
            "stdout": "",
            "stderr": err,
            "exception": None,
            "traceback": None,
            "timed_out": False,
            "seconds": 0.1,
            "problems": [],
        }
        res.update(kw)
        return {"steps": [res]}

    def categories(r):
        return sorted({f.category for f in judge(case, steps, r, tmp_path)})

    assert categories(reply(0, "")) == []
    assert categories(reply(2, f"{tmp_path}/level.toml: [spawn]: missing field 'position'")) == []
    assert categories(reply(2, "error: could not convert string to float")) == ["unnamed file"]
    assert categories(reply(1, "across-dimensions: internal error: KeyError: 'x'")) == ["internal error"]
    assert categories(reply(0, "Traceback (most recent call last):\n  ...")) == ["traceback"]
    assert categories(reply(0, "foo.py:3: RuntimeWarning: invalid value")) == ["python warning"]
    assert categories(reply(None, "", timed_out=True)) == ["hang"]
    assert categories(reply(0, "", problems=[["non-finite state", "w = nan"]])) == ["non-finite state"]
    case.must_refuse = True
    assert categories(reply(0, "")) == ["accepted bad input"]
    (tmp_path / ".level.toml.x1y2.tmp").write_bytes(b"")
    assert leftover_temporaries(tmp_path) == [".level.toml.x1y2.tmp"]
    assert "leftover temporary" in categories(reply(2, "level.toml: no"))


def test_worker_survives_hangs_and_huge_allocations(fuzz_worker):
    t = fuzz_worker.run([{"op": "selftest", "what": "sleep"}], timeout=1.0)
    assert t["steps"][0]["timed_out"] and t["steps"][0]["seconds"] < 5
    m = fuzz_worker.run([{"op": "selftest", "what": "allocate"}])
    assert m["steps"][0]["exception"].startswith("MemoryError"), m
    p = fuzz_worker.run([{"op": "selftest", "what": "print"}])
    assert p["steps"][0]["stdout"] == "to stdout\n" and p["steps"][0]["stderr"] == "to fd 2\n"


@pytest.mark.slow
def test_worker_stuck_outside_python_is_killed_and_replaced(tmp_path):
    worker = Worker(tmp_path / "worker.log", timeout=1.0, grace=1.0)
    try:
        stuck = worker.run([{"op": "selftest", "what": "deaf"}])
        assert stuck.get("hang") and "killed" in stuck["died"], stuck
        assert worker.proc is None  # stopped; the next case starts a fresh one
        fine = worker.run([{"op": "selftest", "what": "print"}])
        assert fine["steps"][0]["exit"] == 0 and worker.starts == 2
    finally:
        worker.stop()


def test_zip_bomb_is_small_on_disk_and_huge_inside():
    import zipfile
    from io import BytesIO

    from fuzz import npzgen

    data, _ = npzgen.zip_bomb(np.random.default_rng(3), npzgen.base_arrays(np.random.default_rng(0))[1])
    with zipfile.ZipFile(BytesIO(data)) as z:
        inflated = sum(i.file_size for i in z.infolist())
        assert z.testzip() is None  # CRCs are right: the loader sees a valid archive
    assert len(data) < 3 * 2**20 and inflated >= 512 * 2**20
