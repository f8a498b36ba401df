"""Webots' Supervisor for the e-puck: on the emulator (and an emulated swarm's robots and
bodiless supervisors, over Zenoh), the subset learning and experiment controllers use,
served from the emulated world (as GPS and compass are); on a real
robot, which has no simulation to supervise, each such call says so."""

from __future__ import annotations

import math

from ego.controller.field import Field
from ego.controller.motor import Motor
from ego.controller.node import Node, no_simulation
from ego.controller.robot import Robot
from ego.core.scene import ROBOT, Scene
from ego.errors import OutOfRangeError, UnsupportedDeviceError

__all__ = ["SceneField", "SceneNode", "Supervisor"]


def _vector(value: object, size: int, what: str) -> list[float]:
    if not isinstance(value, list | tuple) or len(value) != size:
        raise TypeError(f"{what} takes a list of {size} numbers, not {value!r}")
    numbers = [float(v) for v in value]
    if not all(math.isfinite(v) for v in numbers):
        raise OutOfRangeError(f"{what} takes finite numbers, not {value!r}")
    return numbers


def _turn_matrix(axis: tuple[float, float, float], angle: float) -> list[float]:
    """The 3x3 matrix, row by row, of a turn of ``angle`` about the unit ``axis``
    (Rodrigues' formula): the world's vertical, ENU's z or NUE's y."""
    c, s = math.cos(angle), math.sin(angle)
    x, y, z = axis
    t = 1.0 - c
    return [
        t * x * x + c, t * x * y - z * s, t * x * z + y * s,
        t * x * y + z * s, t * y * y + c, t * y * z - x * s,
        t * x * z - y * s, t * y * z + x * s, t * z * z + c,
    ]  # fmt: skip


class SceneField(Field):
    """A node's ``translation`` or ``rotation`` field (SFVec3f, SFRotation)."""

    SF_VEC3F = 5
    SF_ROTATION = 6

    def __init__(self, scene: Scene, solid: str, name: str) -> None:
        self._scene, self._solid, self._name = scene, solid, name

    def getName(self) -> str:
        return self._name

    def getType(self) -> int:
        return self.SF_VEC3F if self._name == "translation" else self.SF_ROTATION

    def getSFVec3f(self) -> list[float]:
        self._expect("translation")
        x, y, z, _ = self._scene.pose(self._solid)
        return [x, y, z]

    def setSFVec3f(self, values: list[float]) -> None:
        """Move the solid (in the world file's frame); its height is the floor's (the
        emulated world is flat)."""
        self._expect("translation")
        x, y, z = _vector(values, 3, "setSFVec3f")
        self._scene.set_pose(self._solid, (x, y, z), self._scene.pose(self._solid)[3])

    def getSFRotation(self) -> list[float]:
        self._expect("rotation")
        return [*self._scene.vertical, self._scene.pose(self._solid)[3]]

    def setSFRotation(self, values: list[float]) -> None:
        """Turn the solid about the world's vertical (z, or y in an NUE world); an axis
        that tilts is refused."""
        self._expect("rotation")
        ax, ay, az, angle = _vector(values, 4, "setSFRotation")
        norm = math.sqrt(ax * ax + ay * ay + az * az)
        vx, vy, vz = self._scene.vertical
        along = (ax * vx + ay * vy + az * vz) / norm if norm else 0.0
        if abs(abs(along) - 1.0) > 1e-6:
            raise UnsupportedDeviceError(
                f"rotation about {values[:3]} tilts the solid; the emulated world is flat"
            )
        x, y, z, _ = self._scene.pose(self._solid)
        self._scene.set_pose(self._solid, (x, y, z), angle * math.copysign(1.0, along))

    def _expect(self, name: str) -> None:
        if self._name != name:
            raise TypeError(f"the {self._name!r} field is not the {name!r} field")


class SceneNode(Node):
    """A solid of the emulated world: the robot (``getSelf``) or a box with a DEF name."""

    def __init__(self, scene: Scene, name: str) -> None:
        self._scene, self._name = scene, name

    def getDef(self) -> str:
        return self._scene.robot_name or "" if self._name == ROBOT else self._name

    def getTypeName(self) -> str:
        return self._scene.kind(self._name)

    def getBaseTypeName(self) -> str:
        return "Robot" if self._scene.kind(self._name) in ("E-puck", "Robot") else "Solid"

    def getPosition(self) -> list[float]:
        """x, y, z in metres, in the world's frame."""
        x, y, z, _ = self._scene.pose(self._name)
        return [x, y, z]

    def getOrientation(self) -> list[float]:
        """The 3x3 rotation matrix, row by row, in the world's frame (a turn about the
        vertical)."""
        return _turn_matrix(self._scene.vertical, self._scene.pose(self._name)[3])

    def getPose(self) -> list[float]:
        """The 4x4 homogeneous transform, row by row."""
        x, y, z = self.getPosition()
        m = self.getOrientation()
        return [*m[0:3], x, *m[3:6], y, *m[6:9], z, 0.0, 0.0, 0.0, 1.0]

    def getVelocity(self) -> list[float]:
        """Linear (m/s) then angular (rad/s) velocity in the world's frame."""
        return list(self._scene.velocity(self._name))

    def getField(self, name: str) -> SceneField | None:
        """``translation`` or ``rotation``; another field: None, as Webots for no such field."""
        return (
            SceneField(self._scene, self._name, name)
            if name in ("translation", "rotation")
            else None
        )

    def resetPhysics(self) -> None:
        """Nothing to do: the emulated bodies keep no momentum beyond their wheels."""

    def __repr__(self) -> str:
        return f"<Node {self.getDef() or self.getTypeName()}>"


class Supervisor(Robot):
    """Webots' Supervisor. On ``--port sim`` and in ``ego swarm`` (whose nodes serve their
    world's scene over Zenoh): ``getSelf``, ``getFromDef``, the nodes' poses and
    velocities, their ``translation``/``rotation`` fields, ``resetPhysics``,
    ``simulationReset``, ``simulationSetMode``, ``getTime``. On a real robot the robot's
    API works and the simulation's raises UnsupportedDeviceError."""

    SIMULATION_MODE_PAUSE = 0
    SIMULATION_MODE_REAL_TIME = 1
    SIMULATION_MODE_FAST = 2

    def _scene(self, what: str) -> Scene:
        scene = self._core.scene
        if scene is None:
            no_simulation(what)
        return scene

    def getSupervisor(self) -> bool:
        return self._core.scene is not None

    def getSelf(self) -> SceneNode:
        return SceneNode(self._scene("Supervisor.getSelf"), ROBOT)

    def getFromDef(self, name: str) -> SceneNode | None:
        """The solid with that DEF name (a box's, or the robot's); None if none has it."""
        scene = self._scene("Supervisor.getFromDef")
        return SceneNode(scene, name) if name in scene.names() else None

    def getRoot(self) -> Node:
        no_simulation("Supervisor.getRoot (the emulated world has no scene tree)")

    def getFromId(self, id: int) -> Node:
        no_simulation("Supervisor.getFromId (the emulated world has no node ids)")

    def simulationReset(self) -> None:
        """Every solid back where the world began, the robot standing still; the
        controller runs on.

        The motors are left as Webots' ``WbMotor::reset`` leaves them: each wheel held at
        its position (the counters back at 0, so 0 rad), its velocity back at
        maxVelocity. So the step a learning loop takes after resetting (deepbots'
        ``reset()`` takes one) does not replay the last action: the episode starts
        where the world began. The LEDs go off, as at the start of the run.
        """
        self._scene("Supervisor.simulationReset").reset()
        core = self._core
        for device in self._devices.values():
            if isinstance(device, Motor):
                device.reset()
        core.motors.set_speed(0, 0)
        core.encoders.set(0, 0)
        leds = core.leds
        for index in (*leds.profile.leds, *leds.rgb):
            leds.set(index, 0)

    def simulationResetPhysics(self) -> None:
        """Nothing to reset beyond the poses: the emulated bodies keep no momentum."""
        self._scene("Supervisor.simulationResetPhysics")

    def simulationGetMode(self) -> int:
        self._scene("Supervisor.simulationGetMode")
        return getattr(self, "_simulation_mode", self.SIMULATION_MODE_REAL_TIME)

    def simulationSetMode(self, mode: int) -> None:
        """REAL_TIME or FAST is recorded; the pace is the run's (``ego run --fast`` runs in
        virtual time). PAUSE is refused: a paused world would never end this step."""
        self._scene("Supervisor.simulationSetMode")
        if mode not in (self.SIMULATION_MODE_REAL_TIME, self.SIMULATION_MODE_FAST):
            raise UnsupportedDeviceError(
                f"simulation mode {mode!r}: the emulator runs (REAL_TIME or FAST), never pauses"
            )
        self._simulation_mode = mode

    def simulationQuit(self, status: int) -> None:
        no_simulation("Supervisor.simulationQuit (end the controller instead)")

    def worldReload(self) -> None:
        no_simulation("Supervisor.worldReload (restart ego run instead)")

    simulation_mode = property(
        lambda self: self.simulationGetMode(), lambda self, m: self.simulationSetMode(m)
    )
