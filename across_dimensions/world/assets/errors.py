"""The one error every asset step raises."""

from __future__ import annotations

from ...core.fileio import FileProblem


class AssetError(FileProblem):
    """An asset file that cannot be used; the message names the file and the problem.

    A :class:`~across_dimensions.core.fileio.FileProblem` (and so a
    ``ValueError``): whatever reports a bad file to a player reports this too.
    """
