"""Webots' ``RadarTarget``: the e-puck has no radar, so none is ever made."""

__all__ = ["RadarTarget"]


class RadarTarget:
    """A target of Webots' Radar; the e-puck has no radar, so none is ever made."""

    def __init__(self) -> None:
        self.distance = self.received_power = self.speed = self.azimuth = 0.0
