"""The ROS 2 bridge of one robot: its step publishes epuck_ros2's topics, and what ROS 2
sends (cmd_vel, the LEDs) drives it at the next step.

The bridge hooks into a :class:`~ego.core.robot.Robot`'s own step (a guard applies the
commands before the batch, a listener publishes after it): whoever steps the robot (the
:class:`~ego.servers.ros2_node.runner.NodeRunner`'s thread, a controller) carries the
bridge along. Only the topics whose devices the robot serves are declared
(:mod:`ego.servers.ros2_node.topics`). The samples ROS 2 sends are decoded on each
subscription's own thread, never on Zenoh's (:class:`~ego.ros2.participant.Subscription`);
the cmd_vel deadman has a thread of its own (:mod:`ego.servers.ros2_node.deadman`), which
:meth:`Ros2Bridge.close` joins.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ego.devices.table import TABLE, DeviceTable
from ego.ros2.attachment import Attachment
from ego.servers.ros2_node import convert
from ego.servers.ros2_node.build import Messages
from ego.servers.ros2_node.commands import Commands
from ego.servers.ros2_node.deadman import Deadman
from ego.servers.ros2_node.sampling import Sampler, sampled, served_devices
from ego.servers.ros2_node.topics import PUBLISHED, SUBSCRIBED, TF_STATIC, served

if TYPE_CHECKING:
    from ego.core.robot import Robot
    from ego.ros2.participant import Participant, Publisher, Subscription

__all__ = ["Ros2Bridge"]

log = logging.getLogger(__name__)

#: How often the static transforms go out again (no history for late joiners).
STATIC_PERIOD_S = 1.0


class Ros2Bridge:
    """``robot`` as the ROS 2 node ``node`` (see the module's doc); ``table`` is the device
    table whose rows say what the robot serves (the e-puck's, or a copy with more rows)."""

    def __init__(
        self, robot: Robot, node: Participant, *, period_ms: int = 64,
        deadline_s: float = 0.5, camera_period_ms: int = 128,
        clock: Callable[[], float] = time.monotonic, wall_ns: Callable[[], int] = time.time_ns,
        table: DeviceTable = TABLE,
    ) -> None:  # fmt: skip
        self.robot, self.node = robot, node
        self.period_s = period_ms / 1000
        self.commands = Commands(deadline_s, clock)
        self.deadman = Deadman(robot, self.commands, name=node.resolve("~"), clock=clock)
        self.messages = Messages(node.distro)
        self._clock, self._wall_ns = clock, wall_ns
        devices = served_devices(robot, table)
        self.published = served(PUBLISHED, devices)
        self.subscribed = served(SUBSCRIBED, devices)
        self.sampler = Sampler(robot, sampled(self.published, devices), period_ms,
                               camera_period_ms, table)  # fmt: skip
        self.publishers: dict[str, Publisher] = {}
        self.subscriptions: dict[str, Subscription] = {}
        self._static_at = -STATIC_PERIOD_S
        #: The stamp of the last step published (ns since the epoch).
        self.last_stamp_ns: int | None = None
        self._attached = False

    def attach(self) -> Ros2Bridge:
        """Declare the publishers and subscriptions, enable the sensors, hook the steps."""
        for row in (*self.published, TF_STATIC):
            self.publishers[row.name] = self.node.publisher(row.name, row.type_name, row.qos)
        for sub in self.subscribed:
            self.subscriptions[sub.name] = self.node.subscription(
                sub.name, sub.type_name, sub.qos, self._handler(sub.name)
            )
        self.sampler.enable()
        self.deadman.start()
        return self.hook()

    def hook(self) -> Ros2Bridge:
        """Ride the robot's steps (again, after :meth:`detach`); attached once first."""
        if not self._attached:
            self.robot.add_step_guard(self._guard)
            self.robot.add_step_listener(self._publish)
            self._attached = True
        return self

    def detach(self) -> None:
        """Unhook the steps (the node's owner closes the node); again does nothing."""
        if self._attached:
            self._attached = False
            self.robot.remove_step_hooks(self._guard)
            self.robot.remove_step_hooks(self._publish)

    def close(self) -> None:
        """Unhook the steps and join the deadman's thread; again does nothing."""
        self.detach()
        self.deadman.close()

    # -- ROS 2 to the robot ------------------------------------------------------------

    def _handler(self, topic: str) -> Callable[[Any, Attachment], None]:
        if topic == "cmd_vel":
            return self._on_twist
        index = int(topic[3:])
        if index % 2 == 0:
            return lambda msg, _: self.commands.led(index, bool(msg.data))
        # An RGB LED's 0xRRGGBB (driver.cpp:246-250): on an e-puck1 the red ring LED
        # it stands for is on when any colour is.
        return lambda msg, _: self.commands.led(index, any(convert.rgb_percent(int(msg.data))))

    def _on_twist(self, message: Any, _: Attachment) -> None:
        speeds = convert.twist_to_steps(float(message.linear.x), float(message.angular.z))
        self.commands.drive(speeds)

    def _guard(self, robot: Robot) -> None:
        pending = self.commands.take()
        self.deadman.before_step(pending.lapses)
        if pending.stop is not None:  # the deadman stopped the wheels: ego's view follows
            robot.motors.set_speed(0, 0)
        if pending.speeds is not None:  # a Twist heard after it
            robot.motors.set_speed(*pending.speeds)
        for index, on in pending.leds.items():
            robot.leds.set(index, on)

    # -- the robot to ROS 2 ------------------------------------------------------------

    def _publish(self, robot: Robot) -> None:
        self.deadman.after_step()
        stamp = self._wall_ns()
        wants_image = any(self.publishers[r.name].matched for r in self.published if r.on_demand)
        wants_jpeg = "image_raw/compressed" in self.publishers and (
            self.publishers["image_raw/compressed"].matched
        )
        reading = self.sampler.read(stamp, wants_image, wants_jpeg)
        for row in self.published:
            message = row.build(self.messages, reading, self.period_s)
            if message is None or (row.on_demand and not self.publishers[row.name].matched):
                continue
            self.publishers[row.name].publish(message, stamp)
        now = self._clock()
        if now - self._static_at >= STATIC_PERIOD_S:
            self._static_at = now
            with_tof = any(row.name == "tof" for row in self.published)
            self.publishers[TF_STATIC.name].publish(self.messages.static_tf(stamp, with_tof), stamp)
        self.last_stamp_ns = stamp
