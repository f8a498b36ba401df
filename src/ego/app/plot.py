"""``ego plot run.mcap --out DIR``: PNG plots of a recorded run, with matplotlib.

Three figures: ``sensors.png`` (every family the run sampled, against controller
time, each panel with a legend of its lines and its unit), ``path.png`` (the odometry
and, on the emulator, the true path), and ``timing.png`` (each step's wall time against
the step asked, and the overruns).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ego.devices.table import TABLE, DeviceTable
from ego.recording.reader import Recording

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_recording", "sensors_figure"]

_Panel = tuple[str, str, str, Callable[[int], str]]
#: After the table's families, the sensors figure shows the wheel speeds asked.
_SPEED: _Panel = ("speed", "wheel speeds asked", "steps/s", lambda i: ("left", "right")[i])


def _panels(table: DeviceTable) -> list[_Panel]:
    """Each family the sensors figure may show (the table's sampled ones, then the wheel
    speeds): its key, title, unit, and its lines' names."""
    panels: list[_Panel] = []
    for family in table.sampled:
        series = family.series
        assert series is not None  # the sampled families are those with a series
        panels.append((family.name, series.title, series.unit, _line_names(series.lines)))
    return [*panels, _SPEED]


def _line_names(lines: tuple[str, ...]) -> Callable[[int], str]:
    return lambda i: lines[i] if i < len(lines) else str(i)


def plot_recording(path: str | Path, out: str | Path = ".") -> list[Path]:
    """Write the run's plots into ``out`` (made if missing); their paths."""
    import matplotlib

    matplotlib.use("Agg")  # files only: no display on a robot or a CI machine
    import matplotlib.pyplot as plt

    recording = Recording.open(path)
    samples = recording.samples
    if not samples:
        raise ValueError(f"{recording.path}: the recording holds no step")
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    t = [s["t"] for s in samples]
    written = []

    fig = sensors_figure(samples)
    written.append(_save(fig, folder / "sensors.png"))

    fig, ax = plt.subplots(figsize=(6, 6))
    world = recording.world
    if world is not None:
        hx, hy = world["half_x"], world["half_y"]
        ax.plot([-hx, hx, hx, -hx, -hx], [-hy, -hy, hy, hy, -hy], color="#8a7f6a", lw=2)
        for box in world["boxes"]:
            ax.add_patch(_box_patch(box))
    truth = [s["truth"] for s in samples if s["truth"] is not None]
    if truth:
        ax.plot([p[0] for p in truth], [p[1] for p in truth], label="true path", lw=3,
                color="#e8871e", alpha=0.7)  # fmt: skip
    odometry = [s["odometry"] for s in samples]
    ax.plot([p[0] for p in odometry], [p[1] for p in odometry], "--", label="odometry", lw=1.5,
            color="#2f6fdf")  # fmt: skip
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"path over {recording.duration_s:.1f} s", fontsize=10)
    written.append(_save(fig, folder / "path.png"))

    fig, ax = plt.subplots(figsize=(9, 3))
    ax.plot(t, [s["wall_ms"] for s in samples], lw=0.8, label="step wall time")
    ax.plot(t, [s["step_ms"] for s in samples], lw=1.2, label="step asked")
    ax.set_xlabel("controller time (s)")
    ax.set_ylabel("ms")
    ax.set_title(f"step timing: {samples[-1]['overruns']} overruns", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    written.append(_save(fig, folder / "timing.png"))
    return written


def sensors_figure(samples: list[dict[str, Any]], table: DeviceTable = TABLE) -> Figure:
    """Every family of ``table`` the samples hold, one panel each against controller time,
    with a legend naming its lines (ps0..ps7, left/right...) and its unit on the y axis."""
    import matplotlib

    matplotlib.use("Agg")  # files only: no display on a robot or a CI machine
    import matplotlib.pyplot as plt

    t = [s["t"] for s in samples]
    sampled = [panel for panel in _panels(table) if any(s.get(panel[0]) for s in samples)]
    fig, axes = plt.subplots(max(1, len(sampled)), 1, figsize=(9, 2.2 * max(1, len(sampled))),
                             sharex=True, squeeze=False)  # fmt: skip
    for ax, (key, title, unit, name) in zip(axes[:, 0], sampled, strict=False):
        width = max(len(s[key] or ()) for s in samples)
        for k in range(width):
            ax.plot(t, [s[key][k] if s[key] else float("nan") for s in samples], lw=0.9,
                    label=name(k))  # fmt: skip
        ax.set_title(title, fontsize=9, loc="left")
        ax.set_ylabel(unit, fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=7, frameon=False,
                  ncol=2 if width > 5 else 1)  # fmt: skip
    axes[-1, 0].set_xlabel("controller time (s)")
    fig.tight_layout()
    return fig


def _box_patch(box: dict[str, float]):  # type: ignore[no-untyped-def]
    import math

    from matplotlib.patches import Rectangle

    c, s = math.cos(box["yaw"]), math.sin(box["yaw"])
    corner = (box["x"] - c * box["hx"] + s * box["hy"], box["y"] - s * box["hx"] - c * box["hy"])
    rgb = tuple(v / 255 for v in box["rgb"])  # type: ignore[attr-defined]
    return Rectangle(corner, 2 * box["hx"], 2 * box["hy"], angle=math.degrees(box["yaw"]),
                     color=rgb)  # fmt: skip


def _save(fig, path: Path) -> Path:  # type: ignore[no-untyped-def]
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
