"""A ROS 2 topic from an ego controller: read it and publish to it in rmw_zenoh's formats.

``Topic(owner, name, type_name)`` joins the ROS 2 graph as a node of its own and reads
or writes one topic, whatever face the controller uses. ``owner`` is a Zenoh session,
an :class:`ego.Robot`, or a face's robot (``ego.controller.Robot``, the Webots face,
whose ``core`` is the Robot): with a robot, the topics of that robot share one node
(``ego_controller`` unless ``node`` says otherwise) on a session opened for them (to
``router``, else the EGO_ZENOH_CONNECT endpoints, as every ego Zenoh session), closed
when the robot closes.

Usage (a Webots controller run by ``ego run``)::

    from controller import Robot
    from ego.ros2.topic import Topic

    robot = Robot()
    cmd = Topic(robot, "/cmd_vel", "geometry_msgs/msg/Twist", router="tcp/127.0.0.1:7447")
    scan = Topic(robot, "/scan", "sensor_msgs/msg/LaserScan", router="tcp/127.0.0.1:7447")
    while robot.step(64) != -1:
        latest = scan.latest()                      # None until one came
        cmd.publish(cmd.message(linear=cmd.field("linear", x=0.05)))
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from ego.ros2.attachment import Attachment
from ego.ros2.distros import Distro
from ego.ros2.participant import Participant, Publisher, Subscription
from ego.ros2.qos import QoS

__all__ = ["Topic"]

#: rclcpp's ``create_publisher(name, 10)``, what most ROS 2 examples use.
DEFAULT_TOPIC_QOS = QoS(depth=10)
_NODES: dict[int, Participant] = {}
_NODES_LOCK = threading.Lock()


def _robot_of(owner: Any) -> Any | None:
    """The core robot of ``owner`` (a Robot, or a face's robot), or None (a session)."""
    from ego.core.robot import Robot

    core = getattr(owner, "core", owner)
    return core if isinstance(core, Robot) else None


def _node_for(robot: Any, node: str, namespace: str, domain_id: int, distro: Distro | str,
              router: str | None) -> Participant:  # fmt: skip
    """The one node of ``robot``'s topics, made (with its session) at first need."""
    from ego.core.environment import read_environment
    from ego.zenoh_net.sessions import ZenohSettings, open_session

    with _NODES_LOCK:
        found = _NODES.get(id(robot))
        if found is not None:
            return found
        settings = ZenohSettings.from_environment(
            read_environment(), connect=[router] if router else None
        )
        session: Any = open_session(settings)
        try:
            made = Participant(session, node, namespace=namespace, domain_id=domain_id,
                               distro=distro)  # fmt: skip
        except BaseException:
            session.close()
            raise
        _NODES[id(robot)] = made

        def close() -> None:
            with _NODES_LOCK:
                _NODES.pop(id(robot), None)
            made.close()
            session.close()

        robot.add_closer(close)
        return made


class Topic:
    """One ROS 2 topic, read (:meth:`latest`, :meth:`on_message`) and written
    (:meth:`publish`) by an ego controller (see the module's doc)."""

    def __init__(
        self, owner: Any, name: str, type_name: str, *, distro: Distro | str = Distro.JAZZY,
        domain_id: int = 0, namespace: str = "/", node: str = "ego_controller",
        qos: QoS = DEFAULT_TOPIC_QOS, router: str | None = None,
        callback: Callable[[Any], None] | None = None,
    ) -> None:  # fmt: skip
        robot = _robot_of(owner)
        if robot is not None:
            self.node = _node_for(robot, node, namespace, domain_id, distro, router)
            self._own_node = False
        else:
            self.node = Participant(owner, node, namespace=namespace, domain_id=domain_id,
                                    distro=distro)  # fmt: skip
            self._own_node = True
        self.name, self.type_name, self.qos = self.node.resolve(name), type_name, qos
        self._lock = threading.Lock()
        self._latest: Any = None
        self._callbacks: list[Callable[[Any], None]] = [callback] if callback else []
        self._publisher: Publisher | None = None
        self._subscription: Subscription = self.node.subscription(
            self.name, type_name, qos, self._on_message
        )

    def _on_message(self, message: Any, _: Attachment) -> None:
        with self._lock:
            self._latest = message
            callbacks = list(self._callbacks)
        for callback in callbacks:
            callback(message)

    @property
    def dropped(self) -> int:
        """Samples this topic dropped (no attachment, not decodable, a callback raised);
        each reason is logged once, then summarised every 10 s."""
        return self._subscription.dropped

    def latest(self) -> Any:
        """The last message that came (a rosbags dataclass), or None."""
        with self._lock:
            return self._latest

    def on_message(self, callback: Callable[[Any], None]) -> None:
        """Call ``callback(message)`` for every message that comes (on the subscription's
        own thread, never Zenoh's: a slow callback delays only this topic)."""
        with self._lock:
            self._callbacks.append(callback)

    def message(self, **fields: Any) -> Any:
        """A message of this topic's type with ``fields`` (every field must be given)."""
        from ego.ros2.messages import message_class

        return message_class(self.type_name, self.node.distro)(**fields)

    def field(self, name: str, **fields: Any) -> Any:
        """A nested message for field ``name`` of this topic's type, zero but ``fields``:
        ``twist.field("linear", x=0.1)`` is a Vector3."""
        from ego.ros2.messages import message_class

        nested = message_class(self.type_name, self.node.distro).__dataclass_fields__[name]
        cls = message_class(_type_name(nested.type), self.node.distro)
        zero = {key: 0.0 for key in cls.__dataclass_fields__ if not key.startswith("__")}
        return cls(**{**zero, **fields})

    def publish(self, message: Any) -> None:
        """Publish ``message`` (the publisher is declared at the first call)."""
        if self._publisher is None:
            self._publisher = self.node.publisher(self.name, self.type_name, self.qos)
        self._publisher.publish(message)

    def close(self) -> None:
        """Withdraw this topic's publisher and subscription (its own node, if it has one)."""
        if self._own_node:
            self.node.close()
            return
        for entity in (self._publisher, self._subscription):
            if entity is not None:
                self.node.withdraw(entity)
        self._publisher = None


def _type_name(annotation: Any) -> str:
    """``pkg/msg/Name`` of a rosbags field annotation (``geometry_msgs__msg__Vector3``)."""
    text = str(getattr(annotation, "__name__", annotation)).rsplit(".", 1)[-1]
    pkg, _, name = text.partition("__msg__")
    return f"{pkg}/msg/{name}"
