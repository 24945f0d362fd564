"""The status line a bake shows while it runs: ``bake pillar.obj: tetrahedralize 12 s``.

On a terminal it is one tqdm line on stderr that redraws in place, with the
time running while the long, silent tetrahedralization works, and is replaced
by a summary when the bake ends. Elsewhere (logs, CI) there is no moving line:
each stage is printed once on a line of its own, then the summary.
"""

from __future__ import annotations

import sys


class BakeProgress:
    """Stages of one bake, reported to a person.

    Parameters
    ----------
    label : str
        What is baked (the file name).
    enabled : bool
        False prints nothing at all.
    stream : file, optional
        Default ``sys.stderr``.
    """

    def __init__(self, label: str, enabled: bool = True, stream=None):
        self.label, self.enabled = label, enabled
        self.stream = stream if stream is not None else sys.stderr
        self.tty = enabled and bool(getattr(self.stream, "isatty", lambda: False)())
        self._bar = None
        if self.tty:
            from tqdm import tqdm  # local: only bakes draw it

            # tqdm keeps the clock: the simulation layers never read it themselves.
            self._bar = tqdm(total=None, desc=f"bake {label}", file=self.stream, leave=False,
                             bar_format="{desc} {elapsed}", mininterval=0.1, dynamic_ncols=True)

    def stage(self, name: str) -> None:
        """A new stage begins (``load``, ``tetrahedralize 384 triangles``, ...)."""
        if self._bar is not None:
            self._bar.set_description_str(f"bake {self.label}: {name}")
        elif self.enabled:
            self._line(f"bake {self.label}: {name}")

    def tick(self) -> None:
        """Redraw the running time (called while waiting on the tetrahedralizer)."""
        if self._bar is not None:
            self._bar.refresh()

    def done(self, summary: str) -> None:
        """End the line with a summary (``1857 tets``, ``failed``)."""
        if self._bar is not None:
            elapsed = self._bar.format_dict["elapsed"]
            self._bar.close()
            self._bar = None
            self._line(f"bake {self.label}: {summary} in {elapsed:.1f} s")
        elif self.enabled:
            self._line(f"bake {self.label}: {summary}")

    def _line(self, text: str) -> None:
        self.stream.write(text + "\n")
        self.stream.flush()
