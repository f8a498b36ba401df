"""The error tree (one ego.errors): each ego error is also the builtin it refines."""

from __future__ import annotations

import pytest

from ego import errors
from ego.errors import (
    DeviceError,
    EgoError,
    ExtraBytesError,
    FirmwareMismatchError,
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


def test_every_exported_name_exists_and_is_an_ego_error_or_warning() -> None:
    for name in errors.__all__:
        obj = getattr(errors, name)
        assert issubclass(obj, (errors.EgoError, errors.EgoWarning)), name
