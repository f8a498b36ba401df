"""The dashboard's page draws the families the server describes (the device table's
series, in its hello): a family added to the table is plotted with no edit of the page."""

from __future__ import annotations

import json
import time
from typing import Any

from ego.core.telemetry import Sampler, describe_firmware
from ego.devices.proximity import ProximitySensors
from ego.devices.table import TABLE, FamilySpec, Series
from ego.seam.profile import Firmware
from ego.serial.firmware import FirmwareInfo
from ego.serial.link import LinkStats
from ego.serial.profiles import PROFILES
from ego.servers.dashboard.control import ControlDesk, Reply
from ego.servers.dashboard.server import DashboardServer

SONAR = FamilySpec("sonar", ProximitySensors, 99, Series("sonar", "mm", ("sonar",)))
WITH_SONAR = TABLE.extended(rows=[("sonar", "sonar", 0, "DistanceSensor", "mm", frozenset())],
                          families=[SONAR])  # fmt: skip


class _TableFeed:
    """A served robot's feed whose table holds the sonar row."""

    def __init__(self) -> None:
        self.desk = ControlDesk(can_act=False, table=WITH_SONAR)

    def hello(self) -> dict[str, Any]:
        robot = describe_firmware(FirmwareInfo(PROFILES[Firmware.WEBOTS]), "sonar-robot",
                                  remote=False, proximity_count=8, led_count=10,
                                  families=["proximity", "sonar"], table=WITH_SONAR)  # fmt: skip
        return {"mode": "served", "robot": robot, "world": None}

    def state(self, client: object) -> dict[str, Any]:
        return self.desk.state(client)

    def handle(self, client: object, message: object) -> Reply:
        return self.desk.handle(client, message)

    def leave(self, client: object) -> None:
        self.desk.leave(client)

    def stop_now(self) -> None:
        """Nothing to stop."""


def test_the_page_plots_a_family_it_was_told_of(page: Any) -> None:
    sampler = Sampler(table=WITH_SONAR)
    with DashboardServer(_TableFeed(), "127.0.0.1", 0) as server:  # type: ignore[arg-type]
        page.goto(server.url)
        page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
        page.wait_for_selector("#plot-series option[value='sonar']", state="attached")
        options = page.eval_on_selector_all(
            "#plot-series option", "(os) => os.map((o) => [o.value, o.textContent])"
        )
        page.select_option("#plot-series", "sonar")
        for step in range(40):
            server.publish(sampler.sample(
                t_s=step * 0.05, step=step, step_ms=50.0, wall_ms=50.0, overruns=0,
                readings={"sonar": [float(100 + step)], "proximity": [1.0] * 8},
                speed=[0, 0], leds=[0] * 10, battery=None, truth=None, stats=LinkStats(),
            ))  # fmt: skip
            time.sleep(0.05)  # the pace of a controller's 50 ms samples, not a wait
        page.wait_for_function("document.getElementById('plot-legend').children.length > 0")
        legend = page.eval_on_selector_all("#plot-legend li",
                                           "(li) => li.map((i) => i.textContent)")
        units = page.get_attribute("#plot", "data-units")
    assert ["sonar", "sonar (mm)"] in [list(o) for o in options], json.dumps(options)
    keys = [value for value, _ in options]
    assert keys[: len(TABLE.sampled) + 1] == [*(f.name for f in TABLE.sampled), "sonar"]
    assert legend == ["sonar"] and units == "mm"
