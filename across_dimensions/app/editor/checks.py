"""The editor's Checks panel: the level checker and the design probe on the level being edited.

"Run checks" writes the level as it is now (unsaved changes included) to a folder of its own,
under its own name and with its replay beside it (the probe follows the designer's route from
it), and runs ``across-dimensions check-level`` and ``across-dimensions probe --json`` on it in a
background process, so the window stays responsive through the probe's minutes. Each problem
found is listed; clicking one selects the entry it names.

As you edit, the quick warnings of :mod:`across_dimensions.world.level_lint` (out of the w range,
spawns overlapping geometry, unreachable goals) are listed here too, and the outline shows their
entries in red.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from imgui_bundle import imgui

from ...world.level_lint import lint

YELLOW = imgui.ImVec4(1.0, 0.8, 0.3, 1.0)
RED = imgui.ImVec4(1.0, 0.45, 0.4, 1.0)
GREEN = imgui.ImVec4(0.5, 0.9, 0.5, 1.0)
GREY = imgui.ImVec4(0.6, 0.6, 0.65, 1.0)
PANEL_H = 150  # pixels: under the inspector, as high as the w panel


def command(*args: str) -> list[str]:
    """The game's command line as a subprocess (the frozen build runs itself)."""
    if getattr(sys, "frozen", False):
        return [sys.executable, *args]
    return [sys.executable, "-m", "across_dimensions", *args]


class Checks:
    """The checks of an :class:`~.mode.EditorView`'s level: quick ones live, the full ones on demand."""

    def __init__(self, mode):
        self.mode = mode
        self.findings: list[tuple[str, tuple | None]] = []  # (text, entry) from the last run
        self.running: list[subprocess.Popen] = []
        self.folder: Path | None = None
        self.status = "not run yet"
        self._lint_text = None
        self._lint: dict = {}

    @property
    def model(self):
        return self.mode.model

    # ------------------------------------------------------------ live warnings
    def warnings(self) -> dict:
        """``ref -> [text]`` of the quick checks, for the level as it is now."""
        text = self.model.text()
        if text != self._lint_text:
            level, _ = self.model.check()
            self._lint = lint(self.model, level) if level is not None else {}
            self._lint_text = text
        return self._lint

    def flagged(self) -> set:
        return set(self.warnings())

    # ------------------------------------------------------------ the full checks
    def run(self) -> None:
        """Start check-level and the probe on the level as it is now, in the background."""
        self.stop()
        m = self.model
        self.folder = Path(tempfile.mkdtemp(prefix="ad-checks-"))
        target = self.folder / m.path.name
        target.write_text(m.text(), encoding="utf-8")
        replay = m.path.resolve().parent / "replays" / f"{m.path.stem}.json"
        if replay.is_file():
            (self.folder / "replays").mkdir()
            shutil.copy(replay, self.folder / "replays" / replay.name)
        self.running = [
            subprocess.Popen(command(*args, str(target)), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for args in (("check-level",), ("probe", "--json", "--workers", "1"))
        ]
        self.findings, self.status = [], "running check-level and the probe..."

    def stop(self) -> None:
        for p in self.running:
            if p.poll() is None:
                p.terminate()
                p.wait(timeout=10)
        self.running = []
        if self.folder is not None:
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None

    def poll(self) -> None:
        """Collect what the checks said once both have finished (called every frame)."""
        if not self.running or any(p.poll() is None for p in self.running):
            return
        check, probe = self.running
        self.running = []
        found = []
        c_out, c_err = check.communicate()
        for line in (c_out + c_err).splitlines():
            line = line.strip()
            if line and ": ok - " not in line and not line.endswith("problem(s)"):
                found.append(self._named(line.replace(str(self.folder) + "/", "")))
        p_out, p_err = probe.communicate()
        try:
            rows = json.loads(p_out.strip().splitlines()[-1]) if p_out.strip() else []
        except ValueError:
            rows = []
        for row in rows if isinstance(rows, list) else []:
            for b in row.get("bypasses", []):
                text = f"bypass: {b['strategy']} won at {b['seconds']:.2f} s without {', '.join(b['avoided'])}"
                found.append((text, ("design",) if self.model.exists(("design",)) else ("goal",)))
            for s in row.get("softlocks", []):
                found.append(self._named(f"soft-lock: after {s['strategy']}: {s['proof']}"))
        if probe.returncode not in (0, 1) and not rows:
            found.append((f"probe: {(p_err.strip().splitlines() or ['failed'])[-1]}", None))
        self.findings = found
        self.status = f"{len(found)} problem(s) found" if found else "no problem: check-level and the probe passed"
        shutil.rmtree(self.folder, ignore_errors=True)
        self.folder = None

    def _named(self, text: str) -> tuple[str, tuple | None]:
        """``text`` and the entry it names: by the loader's ``[[kind]] #n``, or by a quoted name."""
        m = self.model
        hit = re.search(r"\[\[(\w+)\]\] #(\d+)", text)
        if hit and m.exists((hit.group(1), int(hit.group(2)) - 1)):
            return text, (hit.group(1), int(hit.group(2)) - 1)
        hit = re.search(r"\[(\w+)\]", text)
        if hit and m.exists((hit.group(1),)):
            return text, (hit.group(1),)
        for name in re.findall(r"'([^']+)'", text):
            for ref in m.entries():
                if len(ref) == 2 and m.get(ref, "name") == name:
                    return text, ref
        return text, None

    # ------------------------------------------------------------ drawing
    def panel(self, width: int, height: int) -> None:
        self.poll()
        from .panels import PANEL_W

        # Under the inspector, beside the w panel.
        imgui.set_next_window_pos(imgui.ImVec2(width - PANEL_W, height - PANEL_H), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size(imgui.ImVec2(PANEL_W, PANEL_H - 22), imgui.Cond_.first_use_ever)
        warnings = self.warnings()
        title = f"Checks: {sum(len(v) for v in warnings.values())} warning(s), {len(self.findings)} problem(s)"
        if imgui.begin(f"{title}###Checks"):
            if imgui.button("Run checks" if not self.running else "Stop"):
                self.stop() if self.running else self.run()
            imgui.same_line()
            imgui.push_text_wrap_pos(0.0)  # the status wraps inside the panel
            imgui.text_colored(GREY if self.running else GREEN if not self.findings else RED, self.status)
            imgui.pop_text_wrap_pos()
            for k, (text, ref) in enumerate(self.findings):
                self._line(RED, text, ref, f"f{k}")
            for ref, texts in warnings.items():
                for k, text in enumerate(texts):
                    self._line(YELLOW, f"{self.model.where(ref)}: {text}", ref, f"w{ref}{k}")
        self.mode.panels.track()
        imgui.end()

    def _line(self, color, text: str, ref, key: str) -> None:
        imgui.push_style_color(imgui.Col_.text, color)
        imgui.push_text_wrap_pos(0.0)
        if imgui.selectable(f"{text}##{key}", ref is not None and ref in self.model.selected)[0] and ref is not None:
            self.model.select(ref)
            self.mode.focus()
        imgui.pop_text_wrap_pos()
        imgui.pop_style_color()
