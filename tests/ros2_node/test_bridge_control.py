"""Issue 26, items 1 and 2: a Twist published the way rmw_zenoh publishes (exact key,
CDR written by the tests' own writer, the 33-byte attachment) drives the emulated robot,
and cmd_vel's silence stops it (the deadman); the node's, publishers' and subscriptions'
liveliness tokens are seen by a liveliness query as rmw_zenoh's graph cache makes it
(``@ros2_lv/<domain>/**``, liveliness_utils.cpp:428-432) and are gone once closed, with
no thread left behind. The tof row follows the device table."""

from __future__ import annotations

import math
import threading
import time

from helpers import wait_until
from zenoh.ext import Int64, z_serialize

from ego.servers.ros2_node.topics import PUBLISHED, served
from tests.ros2.ros2_support import CdrWriter
from tests.ros2_node.bridge_support import bridged, key_of


def _twist(linear_x: float, angular_z: float) -> bytes:
    writer = CdrWriter()
    for value in (linear_x, 0.0, 0.0, 0.0, 0.0, angular_z):
        writer.write("float64", value)
    return writer.payload()


def test_a_twist_drives_the_robot_and_silence_stops_it() -> None:
    with bridged("jazzy", namespace="/robot", deadline_s=0.3) as b:
        key = key_of("/robot/cmd_vel", "geometry_msgs/msg/Twist", "jazzy")
        publisher = b.ros.declare_publisher(key)
        gid = bytes(range(16))
        assert wait_until(lambda: publisher.matching_status.matching, 10)
        seq = 0

        def send(linear_x: float, angular_z: float) -> None:
            nonlocal seq
            seq += 1
            attachment = z_serialize((Int64(seq), Int64(time.time_ns()), gid))
            publisher.put(_twist(linear_x, angular_z), attachment=attachment)

        # 0.05 m/s and 0.5 rad/s: (2v -+ wL) / 2R rad/s for each wheel (driver.cpp:
        # 291-292), with the e-puck's R 0.0205 m and L 0.052 m, in steps/s (1000 a turn).
        left = (2 * 0.05 - 0.5 * 0.052) / (2 * 0.0205) * 1000 / (2 * math.pi)
        right = (2 * 0.05 + 0.5 * 0.052) / (2 * 0.0205) * 1000 / (2 * math.pi)
        truth = b.robot.ground_truth
        assert truth is not None and (start := truth.pose()) is not None

        def driving() -> bool:
            send(0.05, 0.5)  # a teleop keeps publishing; the first may be lost to matching
            return b.robot.motors.speed == (int(left), int(right))

        assert wait_until(driving, 5), b.robot.motors.speed
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline:  # a teleop at 20 Hz, under the deadline
            send(0.05, 0.5)
            time.sleep(0.05)
            assert b.robot.motors.speed == (int(left), int(right))
        moved = truth.pose()
        assert moved is not None and moved.x_m - start.x_m > 0.02  # it went forward
        assert math.remainder(moved.theta_rad - start.theta_rad, 2 * math.pi) > 0.2  # and left
        assert wait_until(lambda: b.robot.motors.speed == (0, 0), 2)  # silence: stopped
        assert b.bridge.commands.control.lapses == 1
        publisher.undeclare()


def test_the_tokens_are_seen_while_the_node_runs_and_go_with_it() -> None:
    before = {t for t in threading.enumerate() if t.name.startswith("ego-ros2")}
    with bridged("kilted", namespace="/robot") as b:
        zid = str(b.node.session.info.zid())

        def tokens() -> list[str]:
            replies = b.ros.liveliness().get("@ros2_lv/0/**", timeout=5)
            return sorted(str(r.ok.key_expr) for r in replies if r.ok is not None)

        # Liveliness travels between sessions: the ROS 2 side learns the node's tokens
        # as their declarations arrive, so it is asked until all of them are there.
        expected = sorted(b.node.token_keys)
        assert wait_until(lambda: tokens() == expected, 20), (tokens(), expected)
        seen = tokens()
        kinds = [key.split("/")[5] for key in seen]
        published = len(b.bridge.published) + 1  # and tf_static
        assert (kinds.count("NN"), kinds.count("MP"), kinds.count("MS")) == (1, published, 9)
        assert f"@ros2_lv/0/{zid}/" in seen[0]
        assert any("/MS/%/%robot/epuck_driver/%robot%cmd_vel/geometry_msgs::msg::dds_::"
                   "Twist_/RIHS01_9c45bf16" in key for key in seen)  # fmt: skip
        b.runner.close()
        b.bridge.detach()
        b.node.close()
        assert wait_until(lambda: tokens() == [], 5)
        assert b.runner.ended.is_set()
    after = {t for t in threading.enumerate() if t.name.startswith("ego-ros2")}
    assert after == before


def test_tof_is_published_where_the_device_table_has_it() -> None:
    epuck1 = {f"ps{i}" for i in range(8)}
    assert "tof" not in {row.name for row in served(PUBLISHED, epuck1)}
    assert "tof" in {row.name for row in served(PUBLISHED, epuck1 | {"tof"})}


def test_after_the_deadmans_stop_the_same_twist_drives_again() -> None:
    """The deadman stops the wheels over the channel, outside the step: ego's view of the
    motors must follow, or a Twist asking for the speeds of before would send nothing.
    It stops the wheels only: an LED ROS 2 switched on stays on."""
    from helpers import emulator_of

    from tests.ros2_node.flood_support import TWIST, Teleop, start_driving

    with bridged("jazzy", deadline_s=0.3) as b:
        world = emulator_of(b.robot).world
        teleop = Teleop(b.ros, key_of("/cmd_vel", TWIST, "jazzy"))
        led = b.ros.declare_publisher(key_of("/led0", "std_msgs/msg/Bool", "jazzy"))
        on = CdrWriter().write("bool", True).payload()

        def lit() -> bool:
            led.put(on, attachment=z_serialize((Int64(1), Int64(time.time_ns()), bytes(16))))
            return bool(world.leds[0])

        assert wait_until(lit, 5)
        start_driving(teleop, b.robot)
        speeds = b.robot.motors.speed
        assert wait_until(lambda: world.speeds == speeds, 5)
        assert wait_until(lambda: b.bridge.deadman.stops == 1, 5)  # silence: stopped
        assert world.speeds == (0, 0)
        assert wait_until(lambda: b.robot.motors.speed == (0, 0), 5)  # ego's view follows
        assert world.leds[0] == 1
        start_driving(teleop, b.robot)  # the same Twist as before
        assert wait_until(lambda: world.speeds == speeds, 5), world.speeds
        teleop.close()
        led.undeclare()
