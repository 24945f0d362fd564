"""pyglet's options, set on import, before ``pyglet.window`` or ``pyglet.gl`` load.

pyglet checks ``glGetError`` after every GL call by default, and that check imports a module
on each call: slow, and a pyglet object garbage-collected on the window's thread then waits
for the import lock, which the kernel warm-up thread may hold (a start-up hang seen once).
Our drawing goes through moderngl, which checks its own calls.
"""

import pyglet

pyglet.options["debug_gl"] = False
