"""The settings file and PNG images go through the bounded reader and the atomic writer."""

from __future__ import annotations

import os
import zlib

import numpy as np
import pytest

from across_dimensions.app.settings import (
    CONFIG_DIR_ENV,
    SETTINGS_MAX_BYTES,
    Settings,
    default_settings,
    load_settings,
    save_settings,
)
from across_dimensions.core.fileio import FileProblem
from across_dimensions.render import png


# ----------------------------------------------------------------- settings
@pytest.fixture
def special(tmp_path):
    os.mkfifo(tmp_path / "fifo.toml")
    os.symlink("/dev/zero", tmp_path / "zero.toml")
    (tmp_path / "folder.toml").mkdir()
    (tmp_path / "big.toml").write_text("# padding\n" * (SETTINGS_MAX_BYTES // 10 + 1), encoding="utf-8")
    return tmp_path


@pytest.mark.parametrize(
    "name, needle", [("fifo.toml", "FIFO"), ("zero.toml", "device"), ("folder.toml", "folder"), ("big.toml", "larger")]
)
def test_special_settings_files_give_one_warning_and_defaults(special, name, needle):
    settings, warnings = load_settings(special / name)  # must not block or read forever
    assert settings == default_settings()
    assert len(warnings) == 1
    assert str(special / name) in warnings[0] and needle in warnings[0] and "\n" not in warnings[0]


def test_missing_settings_file_is_silent(tmp_path):
    assert load_settings(tmp_path / "none.toml") == (default_settings(), [])


def test_deeply_nested_settings_give_one_warning(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text("x = " + "[" * 5000 + "]" * 5000 + "\n", encoding="utf-8")
    settings, warnings = load_settings(path)
    assert settings == default_settings() and len(warnings) == 1 and str(path) in warnings[0]


def test_saving_to_a_missing_folder_is_refused(tmp_path):
    with pytest.raises(FileProblem, match="does not exist"):
        save_settings(Settings(fov_deg=80), tmp_path / "typo" / "settings.toml")
    assert list(tmp_path.iterdir()) == []


def test_the_config_folder_is_created(tmp_path, monkeypatch):
    monkeypatch.setenv(CONFIG_DIR_ENV, str(tmp_path / "config" / "across"))
    written = save_settings(Settings(fov_deg=80))
    assert written == tmp_path / "config" / "across" / "settings.toml"
    assert load_settings() == (Settings(fov_deg=80), [])
    assert os.listdir(written.parent) == ["settings.toml"]


# ---------------------------------------------------------------------- png
def test_write_png_is_atomic_and_refuses_missing_folders(tmp_path, monkeypatch):
    img = np.arange(48, dtype=np.uint8).reshape(4, 4, 3)
    png.write_png(tmp_path / "a.png", img)
    np.testing.assert_array_equal(png.read_png(tmp_path / "a.png"), img)
    with pytest.raises(FileProblem, match="does not exist"):
        png.write_png(tmp_path / "no" / "a.png", img)

    def full_disk(*args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(FileProblem, match="No space left"):
        png.write_png(tmp_path / "a.png", np.zeros((4, 4, 3), np.uint8))
    np.testing.assert_array_equal(png.read_png(tmp_path / "a.png"), img)  # the old file is untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png"]


def test_read_png_refuses_special_files_and_names_the_file(tmp_path):
    os.mkfifo(tmp_path / "fifo.png")
    with pytest.raises(FileProblem, match="FIFO"):
        png.read_png(tmp_path / "fifo.png")
    (tmp_path / "bad.png").write_bytes(b"not a png")
    with pytest.raises(png.PngError, match="bad.png"):
        png.read_png(tmp_path / "bad.png")


def test_png_bomb_is_not_inflated_past_its_header():
    # A 16x16 grey image whose data inflates to 64 MiB: only what the header promises is decoded.
    header = png.struct.pack(">IIBBBBB", 16, 16, 8, 0, 0, 0, 0)
    data = (
        png._SIGNATURE
        + png._chunk(b"IHDR", header)
        + png._chunk(b"IDAT", zlib.compress(bytes(64 << 20), 9))
        + png._chunk(b"IEND", b"")
    )
    assert len(data) < 1 << 20
    with pytest.raises(png.PngError, match="expected 272"):
        png.decode_png(data)


def test_png_with_too_many_pixels_is_refused():
    header = png.struct.pack(">IIBBBBB", 100_000, 100_000, 8, 6, 0, 0, 0)
    data = png._SIGNATURE + png._chunk(b"IHDR", header) + png._chunk(b"IEND", b"")
    with pytest.raises(png.PngError, match="pixels"):
        png.decode_png(data)
