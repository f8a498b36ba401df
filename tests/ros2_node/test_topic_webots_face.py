"""Issue 26, item 3, in the Webots Python face: a controller's ``Robot()`` hands its core
to ``Topic``, which reads the bridged robot's scan and drives it; ``cleanup()`` (the
face's close) withdraws the controller's node."""

from __future__ import annotations

from helpers import wait_until

from ego.controller import Robot as WebotsRobot
from ego.faces import default_robot, runtime
from ego.ros2.topic import Topic
from tests.ros2_node.bridge_support import bridged


def test_a_webots_controller_reads_and_writes_ros2_topics() -> None:
    with bridged("jazzy", namespace="/robot", deadline_s=0.3) as b:
        default_robot.set_options(runtime.RunOptions(port="sim"))
        try:
            robot = WebotsRobot()
            scan = Topic(robot, "/robot/scan", "sensor_msgs/msg/LaserScan", router=b.endpoint)
            cmd = Topic(robot, "/robot/cmd_vel", "geometry_msgs/msg/Twist", router=b.endpoint)
            assert wait_until(lambda: scan.latest() is not None, 10)
            assert scan.latest().header.frame_id == "laser_scanner"
            twist = cmd.message(linear=cmd.field("linear", x=-0.05), angular=cmd.field("angular"))

            def reversing() -> bool:
                cmd.publish(twist)
                robot.step(32)
                return b.robot.motors.speed[0] < 0

            assert wait_until(reversing, 5)
            robot.cleanup()

            def controller_tokens() -> list[str]:
                replies = b.ros.liveliness().get("@ros2_lv/0/**", timeout=5)
                keys = [str(r.ok.key_expr) for r in replies if r.ok is not None]
                return [k for k in keys if "/ego_controller" in k]

            assert wait_until(lambda: controller_tokens() == [], 5)
        finally:
            default_robot.close()
            default_robot.set_options(runtime.RunOptions())
