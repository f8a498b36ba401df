"""What a world's GPS and Compass read, in the world file's own frame: Webots' GPS gives
where the device is (the robot's pose, offset by where the device sits on it:
firmware_sim.wbt_slots), its Compass where north is in the robot's axes. A TOML world's
devices sit at the robot's centre, in an arena at the origin (firmware_sim.frame)."""

from __future__ import annotations

import math

from firmware_sim.world import World

__all__ = ["device_values"]


def device_values(world: World, name: str) -> tuple[float, float, float]:
    """What the world's ``"gps"`` or ``"compass"`` reads now; KeyError for another name or
    a device the world does not declare."""
    if name not in world.declared_devices() or name not in ("gps", "compass"):
        raise KeyError(f"the world declares no {name!r} (it declares "
                       f"{', '.join(sorted(world.declared_devices())) or 'none'})")  # fmt: skip
    pose = world.snapshot()
    frame = world.frame
    if name == "compass":
        return frame.north_in_body(pose.theta_rad)
    ox, oy, oz = world.mounts.get(name, (0.0, 0.0, 0.0))
    c, s = math.cos(pose.theta_rad), math.sin(pose.theta_rad)
    x, y = pose.x_m + c * ox - s * oy, pose.y_m + s * ox + c * oy
    fx, fy, fz, _ = frame.to_file(x, y, oz, pose.theta_rad)
    return (fx, fy, fz)
