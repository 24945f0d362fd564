"""The window's views: each screen a class that takes the input and draws (as arcade's ``View``).

- :mod:`.base`: :class:`~.base.View`, what every view may override.
- :mod:`.menus`: the title, the level select, the pause menu, the settings and controls
  (one model, :class:`~across_dimensions.app.menu.Menu`, behind them all).
- :mod:`.startup`: a level named on the command line, waiting for the kernels.
- :mod:`.play`: a level being played: input, the fixed-tick loop, drawing.
- :mod:`.complete`: the level finished: its results, then Continue, Retry, Time trial or Level select.
- The level editor's view is :class:`across_dimensions.app.editor.mode.EditorView` (an optional extra).

The window (:class:`~across_dimensions.app.window.GameWindow`) keeps them in a stack: the top one
gets every event, its ``on_update`` once a frame, and draws. A new screen is a :class:`~.base.View`
subclass shown with ``window.show_view(view)`` (alone), ``window.push_view(view)`` (over the
current one, which comes back on ``window.pop_view()``); what it shares with the others it finds
in its ``session`` (:class:`~across_dimensions.app.session.Session`).
"""
