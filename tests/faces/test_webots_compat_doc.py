"""docs/webots-compat.md stays true: every method it marks same or differs exists on its
class in ego.controller, and the counts at its top are the table's."""

from __future__ import annotations

import re
from pathlib import Path

import ego.controller as controller
from ego.controller import supervisor as supervision

DOC = Path(__file__).parents[2] / "docs" / "webots-compat.md"
#: The sections whose rows name methods of one class (what they are checked against).
SECTION_CLASS = {
    "Robot": "Robot",
    "Device (every device)": "Device",
    "DistanceSensor (ps0..ps7, gs0..gs2) and LightSensor (ls0..ls7)": "DistanceSensor",
    "Accelerometer": "Accelerometer",
    "PositionSensor (left/right wheel sensor)": "PositionSensor",
    "Motor (left/right wheel motor)": "Motor",
    "LED (led0..led9)": "LED",
    "Camera": "Camera",
    "Keyboard": "Keyboard",
    "Mouse and Joystick": "Mouse",
    "Supervisor": "Supervisor",
    "Supervisor's nodes and fields (emulator only)": "SceneNode",
    "Emitter (emitter)": "Emitter",
    "Receiver (receiver)": "Receiver",
    "DifferentialWheels (Webots' old e-puck class)": "DifferentialWheels",
}


def _rows() -> list[tuple[str, list[str], str]]:
    """(section, names in the first cell, status word) of every method row."""
    rows, section = [], ""
    for line in DOC.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        elif line.startswith("| ") and section in SECTION_CLASS and not line.startswith("| ---"):
            first, status = (cell.strip() for cell in line.strip("|").split("|")[:2])
            if first == "method":
                continue
            names = re.findall(r"`([A-Za-z_0-9*]+)[(`]", first)
            rows.append((section, names, status.split(":")[0].split(" (")[0]))
    return rows


def test_every_name_marked_same_or_differs_exists() -> None:
    missing = []
    for section, names, status in _rows():
        if status not in ("same", "differs"):
            continue
        cls = getattr(controller, SECTION_CLASS[section], None) or getattr(
            supervision, SECTION_CLASS[section]
        )
        others = {
            "Mouse and Joystick": (controller.Mouse, controller.Joystick),
            "Supervisor's nodes and fields (emulator only)": (supervision.SceneField,),
        }.get(section, ())
        for name in names:
            if name.endswith("*") or (name[0].isupper() and hasattr(controller, name)):
                continue
            declared = name in getattr(cls, "__annotations__", {})  # a plain attribute
            if not (hasattr(cls, name) or declared) and not any(hasattr(o, name) for o in others):
                missing.append(f"{cls.__name__}.{name}")
    assert missing == []


def test_the_counts_at_the_top_are_the_tables() -> None:
    text = DOC.read_text(encoding="utf-8")
    counted = {"same": 0, "differs": 0, "not on this robot": 0}
    for _, names, status in _rows():
        counted[status] += len(names) or 1
    line = re.search(
        r"Counts \(.*?\): (\d+) names; same (\d+), differs (\d+), not on this robot (\d+)\.", text
    )
    assert line is not None
    total, same, differs, absent = map(int, line.groups())
    assert (same, differs, absent) == (
        counted["same"],
        counted["differs"],
        counted["not on this robot"],
    )
    assert total == sum(counted.values())
