"""``ego plot``'s sensors.png names its lines: each panel has a legend (ps0..ps7, left and
right...) and its unit on the y axis."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from PIL import Image

from ego.app.plot import sensors_figure


def _samples(count: int = 30) -> list[dict[str, Any]]:
    return [
        {
            "t": k * 0.032,
            "proximity": [float(40 + k + i) for i in range(8)],
            "light": None,
            "floor": None,
            "accelerometer": [0.0, 0.1, 9.81],
            "encoders": [float(10 * k), float(12 * k)],
            "microphones": None,
            "speed": [300, 360],
        }
        for k in range(count)
    ]


def _legends(fig: Any) -> dict[str, tuple[list[str], str]]:
    """Each panel's title: its legend's labels and its y axis label."""
    panels = {}
    for ax in fig.axes:
        legend = ax.get_legend()
        labels = [text.get_text() for text in legend.get_texts()] if legend is not None else []
        panels[ax.get_title(loc="left")] = (labels, ax.get_ylabel())
    return panels


def test_each_sensor_panel_has_a_legend_of_its_lines_and_its_unit() -> None:
    fig = sensors_figure(_samples())
    panels = _legends(fig)
    assert panels["proximity"] == ([f"ps{i}" for i in range(8)], "raw counts")
    assert panels["encoders"] == (["left", "right"], "steps")
    assert panels["wheel speeds asked"] == (["left", "right"], "steps/s")
    assert panels["accelerometer"] == (["x", "y", "z"], "m/s²")
    assert set(panels) == {"proximity", "encoders", "wheel speeds asked", "accelerometer"}
    assert fig.axes[-1].get_xlabel() == "controller time (s)"


def test_the_legend_lies_beside_the_panel_and_the_png_holds_it(tmp_path: Path) -> None:
    fig = sensors_figure(_samples())
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    for ax in fig.axes:
        legend = ax.get_legend().get_window_extent(renderer)
        panel = ax.get_window_extent(renderer)
        assert legend.x0 >= panel.x1 - 1  # beside the traces, hiding none of them
        assert legend.x1 <= fig.bbox.width + 1  # and inside the picture
    fig.savefig(tmp_path / "sensors.png", dpi=110)
    with Image.open(tmp_path / "sensors.png") as image:
        assert image.width > 500
