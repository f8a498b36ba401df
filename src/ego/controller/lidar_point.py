"""Webots' ``LidarPoint``: the e-puck has no lidar, so none is ever made."""

__all__ = ["LidarPoint"]


class LidarPoint:
    """A point of Webots' Lidar cloud; the e-puck has no lidar, so none is ever made."""

    def __init__(self) -> None:
        self.x = self.y = self.z = 0.0
        self.layer_id = 0
        self.time = 0.0
