"""Remote control: ``ego serve`` on the robot, and the robot as a channel on the PC.

On the robot (or beside an emulator)::

    ego serve --port /dev/ttyS0 --listen tcp://0.0.0.0:4242 --secret-file ~/.ego-secret

On the PC, the same controller as on the robot::

    with ego.Robot("tcp://robot:4242") as robot:     # or udp://robot:4242
        ...

The network stack is imported only when a tcp:// or udp:// port is opened.
"""

from ego.group import RobotGroup, step_all  # kept here for the controllers that import it so
from ego.remote.client import RemoteChannel, RemoteFrameSource
from ego.remote.server import Server, ServerThread
from ego.remote.session import Session
from ego.remote.wire import DEFAULT_PORT, MAX_PAYLOAD, PROTOCOL_VERSION

__all__ = [
    "DEFAULT_PORT",
    "MAX_PAYLOAD",
    "PROTOCOL_VERSION",
    "RemoteChannel",
    "RemoteFrameSource",
    "RobotGroup",
    "Server",
    "ServerThread",
    "Session",
    "step_all",
]
