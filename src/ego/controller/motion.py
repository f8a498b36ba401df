"""Webots' ``Motion`` (humanoid ``.motion`` files): the e-puck has no joints to play them."""

from ego.errors import UnsupportedDeviceError

__all__ = ["Motion"]


class Motion:
    """Webots' humanoid motion files (``.motion``): the e-puck has no joints to play them."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        raise UnsupportedDeviceError("Motion plays joint motions, and the e-puck has no joints")
