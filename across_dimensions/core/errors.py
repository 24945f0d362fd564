"""The one base class for problems a player, modder or command-line user can fix.

Every error type whose message is meant for a person (a bad file, entry,
option or parameter) derives from :class:`InputError`, so the command line can
tell them from bugs with a single ``except InputError``: those become one
``error:`` line, anything else is reported as an internal error.

It is a ``ValueError`` so code that already catches ``ValueError`` keeps working.
"""

from __future__ import annotations

__all__ = ["InputError", "MeshError"]


class InputError(ValueError):
    """Bad input from a person; the message names the file or option, the entry and what was expected."""


class MeshError(InputError):
    """A mesh that breaks one of the rules of :class:`~.mesh.TetMesh4` (or a mesh file that is not one)."""
