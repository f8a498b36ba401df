"""Issue 26, item 3: an ego controller reads ROS 2 topics and publishes to them through
the same mapping (ego.ros2.topic.Topic): here it reads the bridged robot's ps0 and
drives it with a Twist, over a session of its own and over one opened for an ego Robot
(as the Webots face's robot hands its core), whose closing withdraws the node."""

from __future__ import annotations

from helpers import wait_until

from ego.core.robot import Robot
from ego.ros2.topic import Topic
from tests.ros2_node.bridge_support import bridged


def test_a_controller_reads_the_robots_topics_and_drives_it() -> None:
    with bridged("jazzy", namespace="/robot", deadline_s=0.3) as b:
        ps0 = Topic(b.ros, "/robot/ps0", "sensor_msgs/msg/Range", node="planner")
        cmd = Topic(b.ros, "cmd_vel", "geometry_msgs/msg/Twist", namespace="/robot",
                    node="planner2")  # fmt: skip
        try:
            assert wait_until(lambda: ps0.latest() is not None, 10)
            assert ps0.latest().header.frame_id == "ps0"

            def stamped_at_a_step() -> bool:  # the stamp of one of the robot's steps
                stamp = ps0.latest().header.stamp
                with b.lock:
                    return stamp.sec * 10**9 + stamp.nanosec in b.truths

            assert wait_until(stamped_at_a_step, 5)
            twist = cmd.message(linear=cmd.field("linear", x=0.05),
                                angular=cmd.field("angular"))  # fmt: skip

            def driving() -> bool:
                cmd.publish(twist)
                return b.robot.motors.speed[0] > 0

            assert wait_until(driving, 5)
            assert cmd.latest() is not None  # it hears its own topic too, as ROS 2 nodes do
        finally:
            ps0.close()
            cmd.close()


def test_a_topic_of_a_robot_shares_its_node_and_closes_with_it() -> None:
    with bridged("jazzy", namespace="/robot") as b:
        endpoint = b.endpoint
        controller = Robot("sim", seed=2)
        try:
            scan = Topic(controller, "/robot/scan", "sensor_msgs/msg/LaserScan",
                         router=endpoint)  # fmt: skip
            odom = Topic(controller, "/robot/odom", "nav_msgs/msg/Odometry", router=endpoint)
            assert scan.node is odom.node and scan.node.info.name == "ego_controller"
            assert wait_until(lambda: scan.latest() is not None, 10)
            assert len(scan.latest().ranges) == 21
        finally:
            controller.close()

        def controller_tokens() -> list[str]:
            replies = b.ros.liveliness().get("@ros2_lv/0/**", timeout=5)
            keys = [str(r.ok.key_expr) for r in replies if r.ok is not None]
            return [k for k in keys if "/ego_controller" in k]

        assert wait_until(lambda: controller_tokens() == [], 5)
