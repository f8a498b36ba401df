"""The device table is the one place a device or a family is named: every family takes its
names from it, and every consumer's list of families is the table's.

A copy of the table with one more row and family (the e-puck2's time-of-flight sensor,
``tof``) is handed to each consumer, never patched in: each picks it up with no edit of
its own. The faces read the table's rows (test_device_table.py), the page its series
(tests/dashboard/test_dashboard_table.py).
"""

from __future__ import annotations

import ast
from collections.abc import Sequence
from pathlib import Path

import pytest

from ego.core import telemetry
from ego.core.telemetry import Sampler, describe_firmware
from ego.devices.base import ArraySensor, Device
from ego.devices.families import family_class, make_families
from ego.devices.table import TABLE, FamilySpec, Series
from ego.errors import UnknownDeviceError
from ego.recording.schemas import SCHEMAS, sensors_schema
from ego.serial.firmware import FirmwareInfo
from ego.serial.link import LinkStats
from ego.serial.protocol import PROFILES, Command, Firmware
from ego.servers.dashboard import control, served
from ego.servers.dashboard.control import ControlDesk

SRC = Path(__file__).resolve().parents[2] / "src" / "ego"
#: The e-puck2's time-of-flight sensor: a Webots DistanceSensor, its range in mm.
TOF_ROW = ("tof", "tof", 0, "DistanceSensor", "mm", frozenset({"webots"}))
TOF = FamilySpec("tof", f"{__name__}:TimeOfFlight", 9, Command.PROXIMITY,
                 Series("time of flight", "mm", ("tof",)))  # fmt: skip
WITH_TOF = TABLE.extended(rows=[TOF_ROW], families=[TOF])


class TimeOfFlight(ArraySensor, table=WITH_TOF):
    """A family written against the copy: its names are the copy's row."""

    table_family = "tof"
    family = "time of flight"
    command = Command.PROXIMITY

    def take(self, values: Sequence[float]) -> None:
        super().take(values[:1])


# -- the families -----------------------------------------------------------------------------


def _family_classes() -> list[type[Device]]:
    found: list[type[Device]] = []
    pending = list(Device.__subclasses__())
    while pending:
        cls = pending.pop()
        pending.extend(cls.__subclasses__())
        if cls.__module__.startswith("ego.devices.") and cls.table_family:
            found.append(cls)
    return found


def test_every_family_and_part_takes_its_names_from_the_table() -> None:
    classes = _family_classes()
    assert {cls.table_family for cls in classes} == {f.name for f in TABLE.families}
    assert len(classes) >= 13  # the families, and the motors' and encoders' parts
    for cls in classes:
        assert cls.names == TABLE.names_of(cls.table_family), cls


def test_no_family_module_writes_a_device_name() -> None:
    """No family class assigns its ``names``: the table's are derived (base.py's default
    of none aside)."""
    for path in sorted((SRC / "devices").glob("*.py")):
        for cls in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(cls, ast.ClassDef) or path.name == "base.py":
                continue
            for node in cls.body:
                targets = [node.target] if isinstance(node, ast.AnnAssign) else (
                    node.targets if isinstance(node, ast.Assign) else [])  # fmt: skip
                assert not any(
                    isinstance(t, ast.Name) and t.id == "names" for t in targets
                ), f"{path.name}:{node.lineno} ({cls.name})"


def test_a_family_written_against_a_copy_takes_the_copys_row() -> None:
    assert TimeOfFlight.names == ("tof",)
    with pytest.raises(UnknownDeviceError, match="'tof'"):
        TABLE.names_of("tof")  # the e-puck's own table is untouched
    assert WITH_TOF.spec_of_tag(len(TABLE.devices) + 1).name == "tof"


def test_the_robots_families_are_the_tables_in_webots_order() -> None:
    profile = PROFILES[Firmware.WEBOTS]
    made = make_families(profile)
    assert list(made) == ["motors", "leds", "encoders", "accelerometer", "proximity", "floor",
                          "light", "microphones", "battery"]  # fmt: skip
    with_tof = make_families(profile, WITH_TOF)
    assert list(with_tof)[-1] == "tof" and type(with_tof["tof"]) is TimeOfFlight
    assert with_tof["tof"].member_names == ("tof",)


def test_a_table_row_naming_a_wrong_class_is_refused() -> None:
    wrong = FamilySpec("tof", "ego.devices.light:LightSensors", 9)
    with pytest.raises(UnknownDeviceError, match="serves the table's family 'light', not 'tof'"):
        family_class(wrong)


# -- the consumers ----------------------------------------------------------------------------

SAMPLED = tuple(f.name for f in TABLE.sampled)


def test_every_consumers_list_of_families_is_the_tables() -> None:
    assert SAMPLED == ("proximity", "light", "floor", "accelerometer", "encoders", "microphones")
    assert telemetry.SENSOR_FAMILIES == SAMPLED
    assert (*SAMPLED, "camera") == control.SWITCHABLE
    assert served._SAMPLED_FAMILIES == SAMPLED
    assert set(SAMPLED) <= set(SCHEMAS["ego.Sensors"]["properties"])


def _sample(table_sampler: Sampler, readings: dict[str, list[float] | None]) -> dict[str, object]:
    return table_sampler.sample(
        t_s=0.032, step=1, step_ms=32.0, wall_ms=32.0, overruns=0, readings=readings,
        speed=[0, 0], leds=[0] * 10, battery=None, truth=None, stats=LinkStats(),
    )  # fmt: skip


def test_telemetry_samples_a_family_added_to_the_table() -> None:
    assert "tof" not in _sample(Sampler(), {"tof": [42.0]})
    sample = _sample(Sampler(table=WITH_TOF), {"tof": [42.0], "proximity": [1.0] * 8})
    assert sample["tof"] == [42.0] and sample["proximity"] == [1.0] * 8


def test_the_dashboard_may_switch_and_draws_a_family_added_to_the_table() -> None:
    client = object()
    for desk, accepted in ((ControlDesk(), False), (ControlDesk(table=WITH_TOF), True)):
        desk.handle(client, {"type": "take"})
        reply = desk.handle(client, {"type": "sensor", "family": "tof", "on": True})
        assert (reply.message is None) is accepted, reply
    info = FirmwareInfo(PROFILES[Firmware.WEBOTS])
    hello = describe_firmware(info, "sim", remote=False, proximity_count=8, led_count=10,
                              families=["tof"], table=WITH_TOF)  # fmt: skip
    assert hello["series"][-1] == {"key": "tof", "title": "time of flight", "unit": "mm",
                                   "lines": ["tof"]}  # fmt: skip
    assert [s["key"] for s in hello["series"][:-1]] == list(SAMPLED)


def test_a_recording_describes_and_plots_a_family_added_to_the_table() -> None:
    assert "tof" not in sensors_schema()["properties"]
    assert sensors_schema(WITH_TOF)["properties"]["tof"]["type"] == ["array", "null"]
    from ego.app.plot import sensors_figure

    samples = [{"t": k * 0.032, "tof": [float(100 + k)], "speed": None} for k in range(5)]
    fig = sensors_figure(samples, WITH_TOF)
    panels = {ax.get_title(loc="left"): ax for ax in fig.axes}
    assert set(panels) == {"time of flight"}
    assert panels["time of flight"].get_ylabel() == "mm"
    legend = panels["time of flight"].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["tof"]
    assert sensors_figure(samples).axes[0].get_title(loc="left") != "time of flight"
