"""epuck_ros2's messages from one :class:`~ego.servers.ros2_node.reading.Reading` (no I/O).

Each builder returns a rosbags message of the bridge's distribution, filled as
cyberbotics/epuck_ros2@91ff8a1 fills it (``epuck_ros2_driver/src/driver.cpp``,
``epuck_ros2_camera/src/camera.cpp``, cited by line). Where the driver leaves a frame
empty (the IMU, the light sensors) ego names the frame the driver's own static
transforms give (``base_link``, ``ls0``...), so that RViz can place them.
"""

from __future__ import annotations

import math
from typing import Any

from ego.ros2.distros import Distro
from ego.ros2.messages import message_class
from ego.servers.ros2_node import convert
from ego.servers.ros2_node.reading import Reading

__all__ = ["Messages"]

#: sensor_msgs/Range's INFRARED (radiation_type).
INFRARED = 1
#: The wheels' joints as webots_ros2's e-puck names them.
JOINTS = ("left wheel joint", "right wheel joint")
#: REP-145: a covariance starting -1 says the field is not measured.
_NOT_MEASURED = [-1.0, *([0.0] * 8)]


class Messages:
    """Builds the bridge's messages in ``distro``'s definitions (rosbags' store)."""

    def __init__(self, distro: Distro | str) -> None:
        self.distro = Distro(distro)
        self._classes: dict[str, Any] = {}

    def make(self, type_name: str, **fields: Any) -> Any:
        cls = self._classes.get(type_name)
        if cls is None:
            cls = self._classes[type_name] = message_class(type_name, self.distro)
        return cls(**fields)

    def header(self, stamp_ns: int, frame_id: str) -> Any:
        stamp = self.make("builtin_interfaces/msg/Time", sec=stamp_ns // 10**9,
                          nanosec=stamp_ns % 10**9)  # fmt: skip
        return self.make("std_msgs/msg/Header", stamp=stamp, frame_id=frame_id)

    def range(self, reading: Reading, frame: str, value: float, limits: tuple[float, float],
              fov: float) -> Any:  # fmt: skip
        fields = dict(header=self.header(reading.stamp_ns, frame), radiation_type=INFRARED,
                      field_of_view=fov, min_range=limits[0], max_range=limits[1],
                      range=value)  # fmt: skip
        cls = message_class("sensor_msgs/msg/Range", self.distro)
        if "variance" in cls.__dataclass_fields__:  # not in Humble's definition
            fields["variance"] = 0.0
        return cls(**fields)

    def proximity(self, reading: Reading, index: int) -> Any:
        """``ps<i>``: driver.cpp:432-441."""
        assert reading.proximity is not None
        distance = convert.interpolate_table(reading.proximity[index], convert.INFRARED_TABLE)
        limits = (convert.INFRARED_MIN_RANGE, convert.INFRARED_MAX_RANGE)
        return self.range(reading, f"ps{index}", distance, limits, convert.IR_FOV_RAD)

    def ground(self, reading: Reading, index: int) -> Any:
        """``gs<i>``: driver.cpp:352-365."""
        assert reading.floor is not None
        distance = convert.interpolate_table(reading.floor[index], convert.GROUND_TABLE)
        limits = (convert.GROUND_MIN_RANGE, convert.GROUND_MAX_RANGE)
        return self.range(reading, f"gs{index}", distance, limits, convert.IR_FOV_RAD)

    def tof(self, reading: Reading) -> Any:
        """``tof``: driver.cpp:443-452."""
        assert reading.tof_m is not None
        limits = (convert.TOF_MIN_RANGE, convert.TOF_MAX_RANGE)
        return self.range(reading, "tof", reading.tof_m, limits, convert.TOF_FOV_RAD)

    def illuminance(self, reading: Reading, index: int) -> Any:
        """``ls<i>``: the raw count as illuminance, uncalibrated (driver.cpp:368-376)."""
        assert reading.light is not None
        return self.make("sensor_msgs/msg/Illuminance",
                         header=self.header(reading.stamp_ns, f"ls{index}"),
                         illuminance=float(reading.light[index]), variance=0.0)  # fmt: skip

    def scan(self, reading: Reading, period_s: float) -> Any:
        """``scan``: driver.cpp:390-428 (:class:`convert.ScanSpec`)."""
        import numpy as np

        assert reading.proximity is not None
        distances = [convert.interpolate_table(v, convert.INFRARED_TABLE)
                     for v in reading.proximity[:8]]  # fmt: skip
        ranges = convert.scan_ranges(distances, reading.tof_m or convert.OUT_OF_RANGE)
        spec = convert.ScanSpec
        return self.make(
            "sensor_msgs/msg/LaserScan", header=self.header(reading.stamp_ns, "laser_scanner"),
            angle_min=spec.ANGLE_MIN, angle_max=spec.ANGLE_MAX,
            angle_increment=spec.ANGLE_INCREMENT, time_increment=0.0, scan_time=period_s,
            range_min=spec.RANGE_MIN, range_max=spec.RANGE_MAX,
            ranges=np.array(ranges, dtype=np.float32), intensities=np.zeros(0, np.float32),
        )  # fmt: skip

    def vector3(self, x: float, y: float, z: float) -> Any:
        return self.make("geometry_msgs/msg/Vector3", x=x, y=y, z=z)

    def quaternion(self, yaw_rad: float) -> Any:
        x, y, z, w = convert.yaw_quaternion(yaw_rad)
        return self.make("geometry_msgs/msg/Quaternion", x=x, y=y, z=z, w=w)

    def imu(self, reading: Reading) -> Any:
        """``imu``: the acceleration and, where the robot has a gyro (an e-puck2, a
        Pi-puck's IMU), the angular velocity (driver.cpp:307-322); no orientation, and no
        angular velocity on a robot without a gyro: their covariances say "not measured"
        (REP-145)."""
        import numpy as np

        assert reading.acceleration is not None
        rates = reading.angular_velocity
        return self.make(
            "sensor_msgs/msg/Imu", header=self.header(reading.stamp_ns, "base_link"),
            orientation=self.make("geometry_msgs/msg/Quaternion", x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=np.array(_NOT_MEASURED),
            angular_velocity=self.vector3(*(rates or (0.0, 0.0, 0.0))),
            angular_velocity_covariance=np.array(_NOT_MEASURED) if rates is None
            else np.zeros(9),
            linear_acceleration=self.vector3(*reading.acceleration),
            linear_acceleration_covariance=np.zeros(9),
        )  # fmt: skip

    def pose_and_twist(self, reading: Reading) -> tuple[Any, Any]:
        import numpy as np

        odo = reading.odometry
        assert odo is not None
        pose = self.make("geometry_msgs/msg/Pose",
                         position=self.make("geometry_msgs/msg/Point", x=odo.x_m, y=odo.y_m, z=0.0),
                         orientation=self.quaternion(odo.theta_rad))  # fmt: skip
        twist = self.make("geometry_msgs/msg/Twist", linear=self.vector3(odo.linear_mps, 0, 0),
                          angular=self.vector3(0.0, 0.0, odo.angular_radps))  # fmt: skip
        return (
            self.make("geometry_msgs/msg/PoseWithCovariance", pose=pose, covariance=np.zeros(36)),
            self.make("geometry_msgs/msg/TwistWithCovariance", twist=twist,
                      covariance=np.zeros(36)),
        )  # fmt: skip

    def odometry(self, reading: Reading) -> Any:
        """``odom``: odom -> base_link (driver.cpp:518-526)."""
        pose, twist = self.pose_and_twist(reading)
        return self.make("nav_msgs/msg/Odometry", header=self.header(reading.stamp_ns, "odom"),
                         child_frame_id="base_link", pose=pose, twist=twist)  # fmt: skip

    def transform(self, stamp_ns: int, parent: str, child: str, x: float, y: float,
                  yaw: float) -> Any:  # fmt: skip
        return self.make(
            "geometry_msgs/msg/TransformStamped", header=self.header(stamp_ns, parent),
            child_frame_id=child,
            transform=self.make("geometry_msgs/msg/Transform",
                                translation=self.vector3(x, y, 0.0),
                                rotation=self.quaternion(yaw)),
        )  # fmt: skip

    def tf(self, reading: Reading) -> Any:
        """``tf``: the odometry's odom -> base_link (driver.cpp:529-537)."""
        odo = reading.odometry
        assert odo is not None
        moved = self.transform(reading.stamp_ns, "odom", "base_link", odo.x_m, odo.y_m,
                               odo.theta_rad)  # fmt: skip
        return self.make("tf2_msgs/msg/TFMessage", transforms=[moved])

    def static_tf(self, stamp_ns: int, with_tof: bool) -> Any:
        """``tf_static``: base_link to the laser, each sensor (driver.cpp:167-235)."""
        d = convert.SENSOR_DIST_FROM_CENTER
        angles = convert.SENSOR_ANGLES_RAD
        frames = [self.transform(stamp_ns, "base_link", "laser_scanner", 0.0, 0.0, 0.0)]
        for i in range(8):
            for kind in ("ps", "ls"):
                frames.append(self.transform(stamp_ns, "base_link", f"{kind}{i}",
                                             d * math.cos(angles[i]), d * math.sin(angles[i]),
                                             angles[i]))  # fmt: skip
        for i in range(3):
            frames.append(self.transform(stamp_ns, "base_link", f"gs{i}", d - 0.005,
                                         0.009 - i * 0.009, angles[i]))  # fmt: skip
        if with_tof:
            frames.append(self.transform(stamp_ns, "base_link", "tof", d, 0.0, 0.0))
        return self.make("tf2_msgs/msg/TFMessage", transforms=frames)

    def joint_states(self, reading: Reading) -> Any:
        """``joint_states``: the wheels' angles and speeds (webots_ros2's joint names)."""
        import numpy as np

        assert reading.wheels_rad is not None and reading.wheels_radps is not None
        return self.make("sensor_msgs/msg/JointState",
                         header=self.header(reading.stamp_ns, ""), name=list(JOINTS),
                         position=np.array(reading.wheels_rad, dtype=np.float64),
                         velocity=np.array(reading.wheels_radps, dtype=np.float64),
                         effort=np.zeros(0))  # fmt: skip

    # -- the camera (epuck_ros2_camera/src/camera.cpp) -----------------------------------

    def image(self, reading: Reading) -> Any:
        """``image_raw``: rgb8, frame ``pipuck_image_raw`` (camera.cpp:139-149)."""
        import numpy as np

        assert reading.image is not None
        height, width = reading.image.shape[:2]
        return self.make("sensor_msgs/msg/Image",
                         header=self.header(reading.stamp_ns, "pipuck_image_raw"),
                         height=height, width=width, encoding="rgb8", is_bigendian=0,
                         step=width * 3,
                         data=np.ascontiguousarray(reading.image).reshape(-1))  # fmt: skip

    def compressed(self, reading: Reading, jpeg: bytes) -> Any:
        """``image_raw/compressed``: JPEG, frame ``pipuck_image_compressed`` (:161-167)."""
        import numpy as np

        return self.make("sensor_msgs/msg/CompressedImage",
                         header=self.header(reading.stamp_ns, "pipuck_image_compressed"),
                         format="jpeg", data=np.frombuffer(jpeg, dtype=np.uint8))  # fmt: skip

    def camera_info(self, reading: Reading) -> Any:
        """``camera_info``, stamped as the image (camera.cpp:129-131). epuck_ros2 loads
        a Pi-puck calibration (camera_info/camera.yaml); ego gives the pinhole its
        image's size and field of view make: no distortion, centred."""
        import numpy as np

        assert reading.image is not None
        height, width = reading.image.shape[:2]
        f = (width / 2) / math.tan(reading.fov_rad / 2)
        cx, cy = width / 2, height / 2
        roi = self.make("sensor_msgs/msg/RegionOfInterest", x_offset=0, y_offset=0,
                        height=0, width=0, do_rectify=False)  # fmt: skip
        return self.make(
            "sensor_msgs/msg/CameraInfo", header=self.header(reading.stamp_ns, "pipuck_image_raw"),
            height=height, width=width, distortion_model="plumb_bob", d=np.zeros(5),
            k=np.array([f, 0, cx, 0, f, cy, 0, 0, 1], dtype=np.float64),
            r=np.array([1, 0, 0, 0, 1, 0, 0, 0, 1], dtype=np.float64),
            p=np.array([f, 0, cx, 0, 0, f, cy, 0, 0, 0, 1, 0], dtype=np.float64),
            binning_x=0, binning_y=0, roi=roi,
        )  # fmt: skip
