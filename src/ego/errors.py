"""Every error and warning ego raises, in one tree.

Each class mixes in the builtin it refines, so ``except ValueError`` or
``except TimeoutError`` in user code keeps working::

    EgoError
    ├── DeviceError
    │   ├── UnknownDeviceError (KeyError)        a name that no device answers to
    │   ├── UnsupportedDeviceError               the connected firmware cannot serve it
    │   └── OutOfRangeError (ValueError)         a speed, LED value, period... outside its range
    ├── LinkError (OSError)
    │   ├── PortNotFoundError (FileNotFoundError) the port or URL does not exist
    │   ├── LinkTimeoutError (TimeoutError)      no (complete) reply within the timeout
    │   ├── LinkLostError                        the port went away and did not come back
    │   │   └── ReplayEndedError                 a replayed recording has no more steps
    │   ├── PortBusyError                        another controller holds the port
    │   └── NotAnEpuckError                      something answered, but not an e-puck
    ├── ProtocolError
    │   ├── ShortReplyError                      fewer bytes than the batch asks for
    │   ├── ExtraBytesError                      bytes left over after the reply
    │   │   └── LineFloodedError                 a line that never goes quiet (a flood)
    │   ├── RobotResetError                      the dsPIC restarted (its banner arrived)
    │   ├── ChecksumError                        a reply whose checksum does not match
    │   └── FirmwareMismatchError                the firmware is not the one we were told
    ├── ThreadLeakError (RuntimeError)           a thread its owner could not end by close
    ├── BackendOptionError (ValueError)          an option a port's backend does not take,
    │                                            or one of the wrong type or value
    ├── BadFileError (ValueError)                not a regular file, or over a bound
    │   ├── RecordingError                       not an ego recording, or cut short
    │   └── WorldFileError                       an emulator world or floor image
    ├── CameraError
    │   ├── CameraConfigError (ValueError)       a camera configuration file line (path:line:)
    │   │   ├── ConfigSyntaxError                not ``key = value``, or a bad value
    │   │   ├── UnknownSettingError              a key the camera does not have
    │   │   └── SettingOutOfRangeError (OutOfRangeError)  a value outside the key's range
    │   ├── CameraCaptureError (OSError)         the V4L2 device refused or failed
    │   │   └── CameraTimeoutError (TimeoutError) no frame arrived within the timeout
    │   ├── UnsupportedControlError (KeyError)   an unknown control, or one the device lacks
    │   ├── FrameSizeError (ValueError)          a raw buffer too short for the frame geometry
    │   └── ImageFormatError (ValueError)        a file extension neither JPEG nor PNG
    └── RemoteError (ConnectionError)
        ├── AuthenticationError                  wrong or missing shared secret
        │   └── SecretRequiredError              the server wants a secret; none was given
        ├── RobotBusyError                       another client already controls the robot
        ├── InsecureSecretError (ValueError)     a secret too short, or a file others can read
        └── FrameError (ValueError)              a malformed or oversized network frame
            └── VersionMismatchError             a frame of another ego protocol version
    ControllerTerminated (SystemExit)            a controller that went on after step()
                                                 returned -1, ended a second later (as in
                                                 the simulator; no ``except Exception``
                                                 catches it, as none survives that kill)
"""

from __future__ import annotations

__all__ = [
    "AuthenticationError",
    "BackendOptionError",
    "BadFileError",
    "CameraCaptureError",
    "CameraConfigError",
    "CameraError",
    "CameraTimeoutError",
    "ChecksumError",
    "ConfigSyntaxError",
    "ControllerError",
    "ControllerTerminated",
    "DeviceError",
    "EgoError",
    "ExtraBytesError",
    "FirmwareMismatchError",
    "FrameError",
    "FrameSizeError",
    "ImageFormatError",
    "InsecureSecretError",
    "LineFloodedError",
    "LinkError",
    "LinkLostError",
    "LinkTimeoutError",
    "NotAnEpuckError",
    "OutOfRangeError",
    "PortBusyError",
    "PortNotFoundError",
    "ProtocolError",
    "RecordingError",
    "RemoteError",
    "ReplayEndedError",
    "RobotBusyError",
    "RobotResetError",
    "SecretRequiredError",
    "SettingOutOfRangeError",
    "ShortReplyError",
    "ThreadLeakError",
    "UnknownDeviceError",
    "UnknownSettingError",
    "UnsupportedControlError",
    "UnsupportedDeviceError",
    "VersionMismatchError",
    "WorldFileError",
]


class EgoError(Exception):
    """Base of every error ego raises on purpose."""


class ControllerError(EgoError):
    """The controller ``ego run`` ran raised an error; its traceback was shown.

    ``traceback`` holds that traceback, the frames of ego itself left out, so that it
    ends in the line of the controller's own file that made the failing call.
    """

    def __init__(self, message: str, traceback: str = "") -> None:
        super().__init__(message)
        self.traceback = traceback


class ControllerTerminated(SystemExit):
    """A controller went on after ``step()`` returned -1 and was ended, as Webots ends it
    ("Controller Termination" in Webots' user guide: the controller is killed about one
    second of real time after its step returned -1).

    A SystemExit, so that the controller's own ``except Exception`` cannot keep it alive;
    ``ego run`` says why in one line and exits with :attr:`code`
    (:data:`ego.faces.termination.TERMINATED_STATUS`).
    """

    def __init__(self, message: str, code: int) -> None:
        super().__init__(code)
        self.message = message

    def __str__(self) -> str:
        return self.message


class DeviceError(EgoError):
    """A device was asked something it cannot do."""


class UnknownDeviceError(DeviceError, KeyError):
    """No device has this name; the message lists the names that exist."""

    def __str__(self) -> str:  # KeyError would quote the whole message
        return str(self.args[0]) if self.args else ""


class UnsupportedDeviceError(DeviceError):
    """The connected firmware cannot serve this device (it never reads zeros instead)."""


class OutOfRangeError(DeviceError, ValueError):
    """A value outside its documented range; ego refuses it rather than clamping."""


class LinkError(EgoError, OSError):
    """The line to the robot failed."""


class PortNotFoundError(LinkError, FileNotFoundError):
    """The serial port, pty or URL does not exist or cannot be opened."""


class LinkTimeoutError(LinkError, TimeoutError):
    """No complete reply arrived in time, after the bounded retries."""


class LinkLostError(LinkError):
    """The port disappeared and did not come back within the reconnect deadline."""


class ReplayEndedError(LinkLostError):
    """A replayed recording has no more steps: the run is over, as it was then, not broken
    (the Robot's step returns -1 and logs it at INFO, where a lost link is an ERROR)."""


class PortBusyError(LinkError):
    """Another process holds the port (ego opens serial ports exclusively, with flock).

    ``holder_pid`` is that process where it could be found, else None.
    """

    def __init__(self, message: str, holder_pid: int | None = None) -> None:
        super().__init__(message)
        self.holder_pid = holder_pid


class NotAnEpuckError(LinkError):
    """The port answers, but not as an e-puck's dsPIC does."""


class ProtocolError(EgoError):
    """Bytes that do not fit the protocol (after the bounded retries)."""


class ShortReplyError(ProtocolError):
    """Fewer reply bytes than the batch asks for."""


class ExtraBytesError(ProtocolError):
    """More reply bytes than the batch asks for: the stream is out of step."""


class LineFloodedError(ExtraBytesError):
    """A serial line still sending when its drain's bound (bytes or time) ran out: a peer
    that never stops; retrying cannot help, so the step fails at once."""


class RobotResetError(ProtocolError):
    """The dsPIC printed its welcome banner mid-stream: it restarted."""


class ChecksumError(ProtocolError):
    """A reply whose checksum does not match its bytes (the Pi-puck's I2C packet)."""


class FirmwareMismatchError(ProtocolError):
    """The firmware answers differently from the profile in use."""


class ThreadLeakError(EgoError, RuntimeError):
    """A thread its owner (an :class:`ego.nursery.Nursery`) told to end was still running
    when the owner's close gave up waiting; the message names the thread and its owner."""


class BackendOptionError(EgoError, ValueError):
    """An option the port's backend does not take (the message names the scheme, the
    option and the options that scheme takes), or one of the wrong type or value."""


class BadFileError(EgoError, ValueError):
    """A file ego refuses to read: not a regular file (a FIFO or a device would hang or
    never end), larger than its documented bound, or holding more than its parser's
    bounds; the message names the file and the reason (docs/bad_input.md lists the
    bounds)."""


class RecordingError(BadFileError):
    """A file that is not an ego recording, one cut short, or one past a recording bound."""


class WorldFileError(BadFileError):
    """An emulator world file (TOML or Webots ``.wbt``), or its floor texture, that the
    emulator cannot use."""


class CameraError(EgoError):
    """The camera could not do what was asked."""


class CameraConfigError(CameraError, ValueError):
    """A camera configuration file line that cannot be used (its line number is given)."""


class _LocatedConfigError(CameraConfigError):
    """A configuration error tied to one line of one file (``path:line:`` leads the message)."""

    def __init__(self, path: str, line_number: int, message: str) -> None:
        super().__init__(f"{path}:{line_number}: {message}")
        self.path = path
        self.line_number = line_number


class ConfigSyntaxError(_LocatedConfigError):
    """A line that is not ``key = value``, a repeated key, or a value of the wrong type."""


class UnknownSettingError(_LocatedConfigError):
    """A key the camera does not have; the message lists the keys that exist."""


class SettingOutOfRangeError(_LocatedConfigError, OutOfRangeError):
    """A value outside the range of its key; the message names the range."""


class CameraCaptureError(CameraError, OSError):
    """The video device refused a request or failed during capture."""


class CameraTimeoutError(CameraCaptureError, TimeoutError):
    """No frame arrived from the video device within the timeout."""


class UnsupportedControlError(CameraError, KeyError):
    """A control (brightness, contrast...) that is unknown or that the device does not offer."""

    def __str__(self) -> str:  # KeyError would quote the whole message
        return str(self.args[0]) if self.args else ""


class FrameSizeError(CameraError, ValueError):
    """A raw frame buffer too short for its width, height and row stride."""


class ImageFormatError(CameraError, ValueError):
    """A file name whose extension names no supported image format (.jpg, .jpeg, .png)."""


class RemoteError(EgoError, ConnectionError):
    """The network link to a remote robot failed or was refused."""


class AuthenticationError(RemoteError):
    """The shared secret was wrong or missing."""


class SecretRequiredError(AuthenticationError):
    """The server wants a shared secret and none was given.

    Its message says how to give one in Python; :meth:`told` says it in another
    interface's words (``ego run`` says "pass --secret-file FILE").
    """

    #: How a Python program gives the secret.
    PYTHON_REMEDY = "pass secret=..., or set EGO_SECRET_FILE or EGO_SECRET"

    def __init__(self, where: str) -> None:
        super().__init__(self.told(where, self.PYTHON_REMEDY))
        self.where = where

    @staticmethod
    def told(where: str, remedy: str) -> str:
        """The message for the robot at ``where``, with ``remedy`` saying how to give one."""
        return f"{where} requires a shared secret: {remedy}"


class RobotBusyError(RemoteError):
    """Another client already controls this robot."""


class InsecureSecretError(RemoteError, ValueError):
    """A shared secret too short to resist guessing, or kept where others can read it."""


class FrameError(RemoteError, ValueError):
    """A network frame that is malformed, oversized or out of sequence."""


class VersionMismatchError(FrameError):
    """A well-formed frame of another protocol version (the peer runs another ego)."""

    def __init__(self, message: str, peer_version: int, seq: int, session: int) -> None:
        super().__init__(message)
        self.peer_version = peer_version
        self.seq = seq
        self.session = session


