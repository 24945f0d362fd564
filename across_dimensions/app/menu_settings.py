"""The settings screen's rows: the numeric settings as sliders, the on/off ones as toggles, in menu order.

:class:`~across_dimensions.app.menu.Menu` builds the settings screen from these tables; a setting
:class:`~across_dimensions.app.settings.Settings` does not have (yet) is left out.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..render.scale import SOFTWARE_SCALE


@dataclass(frozen=True)
class Slider:
    """A numeric setting shown as a bar: ``lo..hi`` in steps, displayed by ``show``."""

    label: str
    lo: float
    hi: float
    step: float
    show: Callable[[float], str]


#: The numeric settings, in menu order. One is shown only when :class:`Settings` has it.
SLIDERS: dict[str, Slider] = {
    "mouse_sensitivity": Slider("Mouse sensitivity", 0.0005, 0.01, 0.00025, lambda v: f"{v * 1000:.2f}"),
    "fov_deg": Slider("Field of view", 50.0, 120.0, 5.0, lambda v: f"{v:.0f} deg"),
    "render_scale": Slider("Render scale", 0.5, 1.0, 0.05, lambda v: f"{v * 100:.0f}%"),
    "volume": Slider("Volume", 0.0, 1.0, 0.05, lambda v: f"{v * 100:.0f}%"),
    "text_size": Slider("Text size", 1.0, 1.5, 0.25, lambda v: f"{v * 100:.0f}%"),
}
#: What a slider shows for a setting left to the game's choice ("auto"): the render scale
#: picked for a software rasterizer, the case where a player looks for this slider.
AUTO_VALUES: dict[str, float] = {"render_scale": SOFTWARE_SCALE}
#: The on/off settings, in menu order (after the sliders but for the inversions).
TOGGLES: dict[str, str] = {
    "invert_x": "Invert mouse X",
    "invert_y": "Invert mouse Y",
    "colour_blind": "Colour-blind-safe palette",
    "high_contrast": "High-contrast palette",
    "reduce_motion": "Reduce motion (snap, don't glide)",
    "captions": "Captions for sounds",
}
SETTINGS_ORDER = (
    "mouse_sensitivity",
    "invert_x",
    "invert_y",
    "fov_deg",
    "render_scale",
    "volume",
    "colour_blind",
    "high_contrast",
    "reduce_motion",
    "text_size",
    "captions",
)
