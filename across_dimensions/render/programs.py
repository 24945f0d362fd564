"""The scene's shader programs: one per drawable style, for each look and palette, and their uniforms.

A look's programs are built on first use with the palette's light colours compiled in
(:func:`.shaders.program_source`), so a look or palette not used costs nothing, and one used
before costs nothing again. A style's program for meshes without normals (frustum projections,
shaded with their faces' screen-space normals) is built only when such a mesh is drawn: in every
other program that work would be paid for and thrown away on every pixel.

Uniforms that change every frame (the view, the eye, the light, the time) are written to every
program once a frame; the ones that rarely change (palette, fog, sky) only when they did: on
llvmpipe a hundred uniform writes are a tenth of a millisecond of the main thread's time.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import moderngl
import numpy as np

from . import materials
from .context import RenderError
from .shaders import FACETED_STYLES, PROGRAMS, program_source

#: Suffix of a style's program for meshes without normals (see :meth:`StylePrograms.get`).
FLAT = "/flat"
#: Suffix of a style's program for faceted meshes, one normal a triangle (the level's boxes).
FACETED = "/faceted"


def set_uniform(prog: moderngl.Program, name: str, value) -> None:
    """Set ``name`` of ``prog`` to ``value`` (bytes are written as they are); a uniform the
    compiler dropped as unused (``u_light_dir`` of the unlit wire program) is skipped."""
    # prog.get, not ``name in prog``: a moderngl Program has no __contains__, so ``in`` walks
    # its members one by one through a generator (80 uniforms a frame: 0.2-0.3 ms of the main
    # thread).
    u = prog.get(name, None)
    if u is not None:
        if isinstance(value, bytes):
            u.write(value)
        else:
            u.value = value


class FrameUniforms(NamedTuple):
    """What every program is told once a frame.

    Attributes
    ----------
    time : float
        The frame's time in seconds (the trims' pulse, the w cue's drift).
    view_proj : bytes
        Projection times view, column-major float32.
    eye, light : (3,) tuple of float
        The eye's position; the unit vector towards the key light.
    sky : (3,) tuple of float
        The sky's display colour (what fog fades to without the dome).
    dome : bool
        The sci-fi dome is drawn (fog fades to its gradient).
    fog_density, ghost_alpha : float
    """

    time: float
    view_proj: bytes
    eye: tuple
    light: tuple
    sky: tuple
    dome: bool
    fog_density: float
    ghost_alpha: float


class StylePrograms:
    """The style programs of every look and palette used, and the frame's uniforms in them.

    Parameters
    ----------
    ctx : moderngl.Context

    Attributes
    ----------
    current : dict of str to moderngl.Program
        The programs of the look and palette last :meth:`use`-d, by style (and ``style + FLAT``,
        ``style + FACETED``).
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self._sets: dict[tuple, dict[str, moderngl.Program]] = {}  # (look, palette colours) -> programs
        self._look = "flat"
        self._palette: Mapping = {}
        self.current: dict[str, moderngl.Program] = {}
        self._constants: dict[int, tuple] = {}  # program -> the rarely changing uniforms it holds
        self._frame: FrameUniforms | None = None

    def use(self, look: str, palette: Mapping) -> dict[str, moderngl.Program]:
        """Make ``look`` in ``palette`` the current set (built on first use) and return it."""
        if look not in materials.LOOKS:
            raise RenderError(f"unknown look {look!r}; expected one of {', '.join(materials.LOOKS)}")
        # Keyed by the palette's colours, which are cheap to compare every frame; its constants
        # (string formatting) are made only when a set is built.
        key = (look, tuple((k, tuple(v)) for k, v in palette.items()) if look == "scifi" else ())
        self._look, self._palette = look, palette
        progs = self._sets.get(key)
        if progs is None:
            progs = self._sets[key] = {name: self._build(name) for name in PROGRAMS}
        self.current = progs
        return progs

    def get(self, style: str, flat_normals: bool = False, faceted: bool = False) -> tuple[str, moderngl.Program]:
        """The name and program of the current set that shade ``style``; with ``flat_normals``,
        its variant for meshes without normals (``style + FLAT``), with ``faceted`` for meshes of
        one normal a triangle (``style + FACETED``, the sci-fi look's scenery and 4D matter), built
        on first use and given the frame's uniforms at once."""
        if flat_normals and style != "wire":  # lines are unlit
            name = style + FLAT
        elif faceted and self._look == "scifi" and style in FACETED_STYLES:
            name = style + FACETED
        else:
            return style, self.current[style]
        prog = self.current.get(name)
        if prog is None:
            prog = self.current[name] = self._build(style, flat_normals, faceted)
            if self._frame is not None:
                self._set_uniforms(prog, self._frame)
        return name, prog

    def _build(self, style: str, flat_normals: bool = False, faceted: bool = False) -> moderngl.Program:
        vs, fs = program_source(style, self._look, self._palette, flat_normals, faceted)
        try:
            return self.ctx.program(vertex_shader=vs, fragment_shader=fs)
        except Exception as e:  # compile/link errors carry the driver's log
            raise RenderError(f"shader for style {style!r} ({self._look} look) failed to build: {e}") from e

    def set_frame_uniforms(self, frame: FrameUniforms) -> None:
        """Write the frame's uniforms into every program of the current set (and into a program
        built later in the frame, see :meth:`get`)."""
        self._frame = frame
        for prog in self.current.values():
            self._set_uniforms(prog, frame)

    def _set_uniforms(self, prog: moderngl.Program, u: FrameUniforms) -> None:
        scifi = self._look == "scifi"
        set_uniform(prog, "u_view_proj", u.view_proj)
        set_uniform(prog, "u_eye", u.eye)
        set_uniform(prog, "u_light_dir", u.light)
        if scifi:
            set_uniform(prog, "u_time", u.time)
            set_uniform(prog, "u_pulse", 0.9 + 0.1 * float(np.sin(1.3 * u.time)))
            set_uniform(prog, "u_glow_pulse", 0.9 + 0.15 * float(np.sin(2.4 * u.time)))
            set_uniform(prog, "u_w_offset", 0.0)
            set_uniform(prog, "u_band_scale", 1.0)
        constants = (u.sky, u.dome, u.fog_density, u.ghost_alpha, tuple(self._palette.items()))
        if self._constants.get(prog.glo) == constants:
            return
        self._constants[prog.glo] = constants
        set_uniform(prog, "u_sky", u.sky)
        set_uniform(prog, "u_fog_density", u.fog_density)
        set_uniform(prog, "u_alpha", u.ghost_alpha)
        if scifi:
            materials.upload(prog, self._palette, set_uniform)
            if not u.dome:  # a one-colour sky: fog fades to it, as in the flat look
                for name in ("sky_zenith", "sky_horizon", "sky_ground"):
                    set_uniform(prog, f"u_{name}", u.sky)

    @property
    def built(self) -> int:
        """Programs built so far, in every set (a benchmark notes the frames that build one)."""
        return sum(len(progs) for progs in self._sets.values())

    def release(self) -> None:
        for progs in self._sets.values():
            for p in progs.values():
                p.release()
        self._sets.clear()
        self.current = {}
        self._constants.clear()
