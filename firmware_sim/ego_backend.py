"""The ``sim`` backend of ego: the emulator behind a Robot, declared as an entry point.

This module is the one place where the emulator meets the library (it hands ego a
channel on the emulator's pty, the rendered camera, and the emulator itself as ground
truth); every other module of ``firmware_sim`` is written apart from ego, which is what
makes the emulator a check on the library. ego finds it through the ``ego.backends``
entry point group (pyproject.toml) and never imports ``firmware_sim``.
"""

from __future__ import annotations

import errno
from collections.abc import Sequence
from typing import Any

from ego.backends import Opened, open_link
from ego.camera.source import GrantedFormat, PixelFormat, check_control_name
from ego.errors import CameraCaptureError, CameraError
from ego.serial.link import LinkSettings
from ego.serial.protocol import Firmware
from ego.serial.transport import SerialTransport, check_baudrate
from firmware_sim.camera import SimulatedSource
from firmware_sim.cli import main as cli_main
from firmware_sim.server import Emulator

__all__ = ["SimBackend", "SimulatedCamera"]


class SimulatedCamera:
    """The emulator's rendered camera as an ego frame source: ego's types and errors."""

    def __init__(self, source: SimulatedSource) -> None:
        self.source = source

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        try:
            return GrantedFormat(*self.source.open(width, height, pixel_format.value))
        except ValueError as exc:
            raise CameraCaptureError(errno.EINVAL, str(exc)) from exc

    def read_frame(self) -> bytes:
        try:
            return self.source.read_frame()
        except RuntimeError as exc:
            raise CameraError(str(exc)) from exc

    def set_control(self, name: str, value: int) -> int:
        return self.source.set_control(check_control_name(name), value)

    def set_fov_rad(self, fov_rad: float) -> float:
        return self.source.set_fov_rad(fov_rad)

    def close(self) -> None:
        self.source.close()

    def __repr__(self) -> str:
        return repr(self.source)


class SimBackend:
    """``Robot("sim", seed=..., firmware=...)``: a fresh emulator for this robot.

    Options: ``seed`` (the world's), ``world`` (a built-in world's name or a world file:
    firmware_sim.worlds), ``baudrate`` (default: the firmware's line rate),
    ``link_settings``, and any of the Emulator's own (``hardware_version``, ``rev13``,
    ``selector``, ``ground_module``, ``latency_s``).
    """

    def open(
        self,
        port: str,
        *,
        firmware: Firmware | None,
        baudrate: int | None = None,
        seed: int | None = None,
        link_settings: LinkSettings | None = None,
        **emulator_options: Any,
    ) -> Opened:
        name = (firmware or Firmware.WEBOTS).value
        if baudrate is not None:
            baudrate = check_baudrate(baudrate)  # ego's error, before the emulator starts
        emulator = Emulator(name, baud=baudrate, seed=seed, **emulator_options).start()
        try:
            channel = open_link(
                SerialTransport(emulator.path, emulator.baud), firmware, link_settings
            )
        except BaseException:
            emulator.stop()
            raise
        world = emulator.world
        camera = lambda: SimulatedCamera(SimulatedSource(world))  # noqa: E731
        return Opened(channel, camera, emulator, [emulator.stop])

    @staticmethod
    def swarm_worlds(spec: str | None, seeds: Sequence[int | None]) -> list[Any]:
        """One world for each of ``seeds`` (its robot's noise seed), all made from one
        world file (a built-in's name, a path, None for the default arena), joined into
        one crowd: ego swarm's robots, each starting where the file places it, the others
        spread around the centre."""
        from firmware_sim.crowd import Crowd, spread_poses
        from firmware_sim.world import World
        from firmware_sim.worlds import load_world

        worlds: list[World] = [
            load_world(spec, seed) if spec else World(seed=seed) for seed in seeds
        ]
        poses = spread_poses(len(worlds), worlds[0].arena.half_size_m,
                             worlds[0].starts if spec else [])  # fmt: skip
        for world, pose in zip(worlds, poses, strict=True):
            world.start_at(pose)  # before they meet: nobody is in anybody's way yet
        Crowd(worlds)
        return worlds

    @staticmethod
    def main(argv: list[str], prog: str = "ego sim") -> int:
        """``ego sim ARGS``: the emulator's own command line."""
        return cli_main(argv, prog)
