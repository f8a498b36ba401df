"""The C-style faces open a robot served as a Zenoh node (issue 24, item 2).

``wb_robot_init()`` and ``overo_serial_init()`` used to give every port a baud rate,
which a ``zenoh://`` port refuses; the node's endpoint comes from the face's environment
(``EGO_ZENOH_CONNECT``, read once where the face's context is made).
"""

from __future__ import annotations

from zenoh_support import served_node

from ego import overo
from ego import webots as wb
from ego.core.environment import read_environment
from ego.faces import default_robot
from ego.faces.default_robot import FaceContext, activate
from ego.faces.runtime import RunOptions


def test_wb_robot_init_and_overo_serial_init_open_a_zenoh_node() -> None:
    with served_node("faces") as served:
        environment = read_environment({"EGO_ZENOH_CONNECT": served.endpoint})
        context = FaceContext(RunOptions(port="zenoh://faces"), environment)
        try:
            with activate(context):
                assert wb.wb_robot_init() == 1
                assert default_robot.get().port == "zenoh://faces"
                assert wb.wb_robot_step(32) == 0
                wb.wb_robot_cleanup()
                overo.overo_serial_init(230400)  # E-GO's call, as its controllers make it
                assert overo.overo_scheduler_robot_step(32) == 0
                assert default_robot.get().remote
        finally:
            context.close()
