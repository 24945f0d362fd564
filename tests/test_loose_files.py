"""Loose file inputs: outputs onto special files, over-long campaign names, levels the editor cannot parse."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from across_dimensions.world.campaign import CampaignError, load_campaign
from across_dimensions.world.level_edit import LevelEditError, LevelEditor

REPO = Path(__file__).resolve().parents[1]


def run(env, cwd, *args) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=120,
    )


def one_line(r, *needles) -> str:
    assert r.returncode == 2 and "Traceback" not in r.stderr and "internal error" not in r.stderr, r.stderr
    (line,) = r.stderr.splitlines()
    for n in needles:
        assert n in line, line
    return line


# ------------------------------------------------------------------ -o
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_output_onto_a_device_a_fifo_or_a_link_to_one_is_refused(env, tmp_path):
    os.mkfifo(tmp_path / "pipe.npz")
    os.symlink("/dev/null", tmp_path / "link.npz")
    one_line(run(env, tmp_path, "level-schema", "-o", "/dev/null"), "/dev/null: is a device, not a regular file")
    for target, kind in (("pipe.npz", "is a pipe (FIFO)"), ("link.npz", "is a device")):
        for args in (["level-schema", "-o", target], ["shape", "tesseract", "-o", target]):
            one_line(run(env, tmp_path, *args), f"{target}: {kind}, not a regular file")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert stat.S_ISFIFO(os.stat(tmp_path / "pipe.npz").st_mode) and os.path.islink(tmp_path / "link.npz")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.npz", "pipe.npz"]  # no temporary file left


def test_output_to_a_new_file_or_over_a_regular_one_still_works(env, tmp_path):
    (tmp_path / "old.json").write_text("old")
    for name in ("new.json", "old.json"):
        r = run(env, tmp_path, "level-schema", "-o", name)
        assert r.returncode == 0, r.stderr
        assert (tmp_path / name).read_text().startswith("{")


# ------------------------------------------------------------ campaign
def test_a_300_character_level_name_in_the_campaign_is_one_line(env, tmp_path):
    campaign = tmp_path / "campaign.toml"
    name = "a" * 300
    campaign.write_text(
        f'[[level]]\nfile = "01_first_steps"\ntitle = "One"\n\n[[level]]\nfile = "{name}"\ntitle = "Long"\n'
    )
    with pytest.raises(CampaignError) as info:
        load_campaign(campaign)
    assert str(info.value) == (
        f"{campaign}: [[level]] #2: file = '{'a' * 24}'... (300 characters): "
        "expected a level name of at most 200 bytes in UTF-8"
    )
    one_line(run(env, tmp_path, "check-level", campaign), "[[level]] #2", "300 characters")


def test_the_shipped_campaign_still_loads():
    assert len(load_campaign()) >= 10


# -------------------------------------------------------------- editor
@pytest.mark.parametrize(
    "raw, needle",
    [
        (b'name = "x"\n\xff\xfe', "not a text file (byte 11 is not UTF-8; expected a level)"),
        (b"[level\nname = 1", "not valid TOML: "),
        (b"a = 1\na = 2\n", 'not valid TOML: Key "a" already exists'),
        (b"a = " + b"[" * 5000 + b"]" * 5000, "not valid TOML: "),
    ],
    ids=["not-utf8", "syntax", "duplicate-key", "deep"],
)
def test_the_editor_model_names_a_broken_file_in_one_line(tmp_path, raw, needle):
    path = tmp_path / "broken.toml"
    path.write_bytes(raw)
    with pytest.raises(LevelEditError) as info:
        LevelEditor(path)
    msg = str(info.value)
    assert msg.startswith(f"{path}: ") and needle in msg and "\n" not in msg
