"""The error tree (one ego.errors): each ego error is also the builtin it refines."""

from __future__ import annotations

import pytest

from ego import errors
from ego.errors import (
    DeviceError,
    EgoError,
    ExtraBytesError,
    FirmwareMismatchError,
    LineFloodedError,
    LinkError,
    LinkLostError,
    LinkTimeoutError,
    NotAnEpuckError,
    OutOfRangeError,
    PortNotFoundError,
    ProtocolError,
    RobotResetError,
    ShortReplyError,
    UnknownDeviceError,
    UnsupportedDeviceError,
)


@pytest.mark.parametrize(
    ("error", "bases"),
    [
        (UnknownDeviceError, (DeviceError, KeyError)),
        (UnsupportedDeviceError, (DeviceError,)),
        (OutOfRangeError, (DeviceError, ValueError)),
        (LinkError, (EgoError, OSError)),
        (PortNotFoundError, (LinkError, FileNotFoundError)),
        (LinkTimeoutError, (LinkError, TimeoutError)),
        (LinkLostError, (LinkError,)),
        (NotAnEpuckError, (LinkError,)),
        (ShortReplyError, (ProtocolError,)),
        (ExtraBytesError, (ProtocolError,)),
        (LineFloodedError, (ExtraBytesError, ProtocolError)),
        (RobotResetError, (ProtocolError,)),
        (FirmwareMismatchError, (ProtocolError,)),
        (ProtocolError, (EgoError,)),
    ],
)
def test_each_error_refines_its_parents(error: type[Exception], bases: tuple[type, ...]) -> None:
    for base in bases:
        assert issubclass(error, base)


def test_builtin_handlers_catch_ego_errors() -> None:
    with pytest.raises(TimeoutError):
        raise LinkTimeoutError("0 of 58 reply bytes")
    with pytest.raises(ValueError):
        raise OutOfRangeError("speed 1200 steps/s is outside +-1000")
    with pytest.raises(FileNotFoundError):
        raise PortNotFoundError("/dev/ttyS9")


def test_unknown_device_message_is_not_quoted_like_a_key() -> None:
    err = UnknownDeviceError("no device 'ps12'; valid names: ps0..ps7")
    assert str(err) == "no device 'ps12'; valid names: ps0..ps7"


def test_every_exported_name_exists_and_is_an_ego_error() -> None:
    # The one exception: a controller ended as Webots ends it must get past the
    # controller's own ``except Exception``, as nothing survives Webots' kill.
    for name in errors.__all__:
        obj = getattr(errors, name)
        allowed = (SystemExit,) if name == "ControllerTerminated" else ()
        assert issubclass(obj, (errors.EgoError, *allowed)), name
    assert not issubclass(errors.ControllerTerminated, Exception)


def _raised_names() -> set[str]:
    """Every name ego (or its emulator) makes an error of, ``X(...)``, or warns with,
    ``warn(message, X)``, outside ego.errors itself."""
    import ast
    from pathlib import Path

    import firmware_sim

    roots = (Path(errors.__file__).parent, Path(firmware_sim.__file__).parent)
    names: set[str] = set()
    for path in (p for root in roots for p in root.rglob("*.py")):
        if path == Path(errors.__file__):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Call):
                continue
            named = [node.func]
            if getattr(node.func, "attr", getattr(node.func, "id", "")) == "warn":
                named += node.args[1:2]
            for name in named:
                if isinstance(name, ast.Name):
                    names.add(name.id)
                elif isinstance(name, ast.Attribute):
                    names.add(name.attr)
    return names


def test_every_leaf_of_the_tree_is_raised_somewhere() -> None:
    classes = [getattr(errors, name) for name in errors.__all__]
    leaves = {
        c.__name__ for c in classes if not any(o is not c and issubclass(o, c) for o in classes)
    }
    assert sorted(leaves - _raised_names()) == []
