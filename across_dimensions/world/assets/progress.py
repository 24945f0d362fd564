"""The status line a bake shows while it runs: ``bake pillar.obj: tetrahedralize 00:12``.

On a terminal it is one tqdm line on stderr that redraws in place, with the
time running while the long, silent tetrahedralization works; a finished bake
replaces it with a one-line summary, a failed one clears it (the error that
follows says what went wrong). When stderr is not a terminal (logs, CI, a
pipe) nothing is printed: a log gets no half-drawn lines, and a refused asset
gives its one error line and nothing else.
"""

from __future__ import annotations

import sys


class BakeProgress:
    """Stages of one bake, reported to a person at a terminal.

    Parameters
    ----------
    label : str
        What is baked (the file name).
    enabled : bool
        False prints nothing at all.
    stream : file, optional
        Default ``sys.stderr``; nothing is drawn unless it is a terminal.
    """

    def __init__(self, label: str, enabled: bool = True, stream=None):
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self._bar = None
        if enabled and getattr(self.stream, "isatty", lambda: False)():
            from tqdm import tqdm  # local: only bakes draw it

            # tqdm keeps the clock: the simulation layers never read it themselves.
            self._bar = tqdm(
                total=None,
                desc=f"bake {label}",
                file=self.stream,
                leave=False,
                bar_format="{desc} {elapsed}",
                mininterval=0.1,
                dynamic_ncols=True,
            )

    @property
    def shown(self) -> bool:
        """Whether a line is on the terminal."""
        return self._bar is not None

    def stage(self, name: str) -> None:
        """A new stage begins (``load``, ``tetrahedralize 384 triangles``, ...)."""
        if self._bar is not None:
            self._bar.set_description_str(f"bake {self.label}: {name}")

    def tick(self) -> None:
        """Redraw the running time (called while waiting on the tetrahedralizer)."""
        if self._bar is not None:
            self._bar.refresh()

    def done(self, summary: str) -> None:
        """Replace the line with a summary (``1857 tets``) and the time taken."""
        if self._bar is not None:
            elapsed = self._bar.format_dict["elapsed"]
            self.close()
            self.stream.write(f"bake {self.label}: {summary} in {elapsed:.1f} s\n")
            self.stream.flush()

    def close(self) -> None:
        """Clear the line without a summary (the bake failed or was interrupted)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
