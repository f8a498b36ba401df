"""ego ros2: a robot as a ROS 2 node in rmw_zenoh's formats (docs/ros2.md)."""
