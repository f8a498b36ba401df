"""The device table is the one place a device is named, and a family's class the one place
the family is declared (``@TABLE.declare``): every family takes its names from the table,
and every consumer's list of families is the table's.

A copy of the table with one more row, and a family declared against it (``sonar``), is
handed to each consumer, never patched in: each picks it up with no edit of its own.
The faces read the table's rows (test_device_table.py), the page its series
(tests/dashboard/test_dashboard_table.py).
"""

from __future__ import annotations

import ast
from collections.abc import Sequence
from pathlib import Path

import pytest

import ego
from ego.core import telemetry
from ego.core.telemetry import Sampler, describe_firmware
from ego.devices.base import ArraySensor, Device
from ego.devices.families import family_class, make_families
from ego.devices.light import LightSensors
from ego.devices.table import TABLE, FamilySpec, Series
from ego.errors import UnknownDeviceError
from ego.recording.schemas import SCHEMAS, sensors_schema
from ego.seam.profile import Command, Firmware
from ego.serial.firmware import FirmwareInfo
from ego.serial.link import LinkStats
from ego.serial.profiles import PROFILES
from ego.servers.dashboard import control, served
from ego.servers.dashboard.control import ControlDesk

#: ego as installed: the checkout's src/ego, or on a board the wheel's.
SRC = Path(ego.__file__).resolve().parent
#: The e-puck2's time-of-flight sensor: a Webots DistanceSensor, its range in mm.
SONAR_ROW = ("sonar", "sonar", 0, "DistanceSensor", "mm", frozenset({"webots"}))
WITH_SONAR = TABLE.extended(rows=[SONAR_ROW])


@WITH_SONAR.declare("sonar", webots_rank=99, series=Series("sonar", "mm", ("sonar",)))
class Sonar(ArraySensor):
    """A family declared against the copy: its names are the copy's row."""

    family = "sonar"
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
    assert Sonar.names == ("sonar",)
    with pytest.raises(UnknownDeviceError, match="'sonar'"):
        TABLE.names_of("sonar")  # the e-puck's own table is untouched
    assert WITH_SONAR.spec_of_tag(len(TABLE.devices) + 1).name == "sonar"


def test_the_robots_families_are_the_tables_in_webots_order() -> None:
    profile = PROFILES[Firmware.WEBOTS]
    made = make_families(profile)
    assert list(made) == ["motors", "leds", "encoders", "accelerometer", "proximity", "floor",
                          "light", "microphones", "battery", "tof", "gyro", "magnetometer",
                          "temperature", "button", "selector", "sound"]  # fmt: skip
    with_sonar = make_families(profile, WITH_SONAR)
    assert list(with_sonar)[-1] == "sonar" and type(with_sonar["sonar"]) is Sonar
    assert with_sonar["sonar"].member_names == ("sonar",)


def test_a_table_row_naming_a_wrong_class_is_refused() -> None:
    wrong = FamilySpec("sonar", LightSensors, 9)
    with pytest.raises(UnknownDeviceError, match="serves the table's family 'light', not 'sonar'"):
        family_class(wrong)


def test_a_family_is_declared_once() -> None:
    copy = TABLE.extended(rows=[SONAR_ROW])
    copy.declare("sonar", webots_rank=99)(Sonar)
    with pytest.raises(ValueError, match="'sonar' is declared twice"):
        copy.declare("sonar", webots_rank=100)(Sonar)


def test_no_family_module_restates_its_family_or_table_row() -> None:
    """A family module declares its family with the decorator only (no ``table_family``
    assignment), and nothing else in ego writes a FamilySpec (the declaration does)."""
    for path in sorted(SRC.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        assert "table_family =" not in text, path
        if path.name != "table.py":
            assert "FamilySpec(" not in text, path


# -- the consumers ----------------------------------------------------------------------------

SAMPLED = tuple(f.name for f in TABLE.sampled)


def test_every_consumers_list_of_families_is_the_tables() -> None:
    assert SAMPLED == ("proximity", "light", "floor", "accelerometer", "encoders", "microphones",
                       "tof", "gyro", "magnetometer", "temperature", "button", "selector")
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
    assert "sonar" not in _sample(Sampler(), {"sonar": [42.0]})
    sample = _sample(Sampler(table=WITH_SONAR), {"sonar": [42.0], "proximity": [1.0] * 8})
    assert sample["sonar"] == [42.0] and sample["proximity"] == [1.0] * 8


def test_the_dashboard_may_switch_and_draws_a_family_added_to_the_table() -> None:
    client = object()
    for desk, accepted in ((ControlDesk(), False), (ControlDesk(table=WITH_SONAR), True)):
        desk.handle(client, {"type": "take"})
        reply = desk.handle(client, {"type": "sensor", "family": "sonar", "on": True})
        assert (reply.message is None) is accepted, reply
    info = FirmwareInfo(PROFILES[Firmware.WEBOTS])
    hello = describe_firmware(info, "sim", remote=False, proximity_count=8, led_count=10,
                              families=["sonar"], table=WITH_SONAR)  # fmt: skip
    assert hello["series"][-1] == {"key": "sonar", "title": "sonar", "unit": "mm",
                                   "lines": ["sonar"]}  # fmt: skip
    assert [s["key"] for s in hello["series"][:-1]] == list(SAMPLED)


def test_a_recording_describes_and_plots_a_family_added_to_the_table() -> None:
    assert "sonar" not in sensors_schema()["properties"]
    assert sensors_schema(WITH_SONAR)["properties"]["sonar"]["type"] == ["array", "null"]
    # The plot extra (matplotlib) is a PC's: on a board without it the plot half skips.
    pytest.importorskip("matplotlib", reason="the plot extra (matplotlib) is not installed")
    from ego.app.plot import sensors_figure

    samples = [{"t": k * 0.032, "sonar": [float(100 + k)], "speed": None} for k in range(5)]
    fig = sensors_figure(samples, WITH_SONAR)
    panels = {ax.get_title(loc="left"): ax for ax in fig.axes}
    assert set(panels) == {"sonar"}
    assert panels["sonar"].get_ylabel() == "mm"
    legend = panels["sonar"].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["sonar"]
    assert sensors_figure(samples).axes[0].get_title(loc="left") != "sonar"
