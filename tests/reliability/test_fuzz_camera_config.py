"""The camera configuration file fed random and mutated text: a configuration in range or
a located error, never a hang (the shared settings: ``fuzzing.py``)."""

from __future__ import annotations

import math

from fuzzing import FUZZ
from helpers import SUBNORMALS
from hypothesis import given
from hypothesis import strategies as st

from ego.camera.config import CameraConfiguration, parse_configuration, size_range
from ego.camera.convert import ROTATIONS
from ego.camera.source import CONTROLS
from ego.errors import (
    CameraConfigError,
    ConfigSyntaxError,
    SettingOutOfRangeError,
    UnknownSettingError,
)

# -- the camera configuration file -------------------------------------------------------------

VALID_FILE = """# e-puck camera, as E-GO starts it
width = 640                # pixels
height = 480
rotation = 180
fov_rad = 0.84
brightness = 1
contrast = 64
saturation = 64
auto_white_balance = off
"""


def check_configuration(text: str) -> None:
    """A configuration in range, or a located CameraConfigError of one of its three kinds."""
    try:
        config = parse_configuration(text, "fuzz.conf")
    except CameraConfigError as exc:
        assert type(exc) in (ConfigSyntaxError, UnknownSettingError, SettingOutOfRangeError)
        assert 1 <= exc.line_number <= max(1, len(text.splitlines()))  # type: ignore[attr-defined]
        assert str(exc).startswith(f"fuzz.conf:{exc.line_number}: ")  # type: ignore[attr-defined]
        return
    assert isinstance(config, CameraConfiguration)
    rotation = 180 if config.rotation is None else config.rotation
    assert rotation in ROTATIONS
    low, high = size_range(rotation)
    if config.width is not None:
        assert type(config.width) is int and low[0] <= config.width <= high[0]
    if config.height is not None:
        assert type(config.height) is int and low[1] <= config.height <= high[1]
    if config.fov_rad is not None:
        assert 0.0 < config.fov_rad < math.pi
    for name, value in config.controls().items():
        assert CONTROLS[name].minimum <= value <= CONTROLS[name].maximum
    assert config.auto_white_balance in (None, True, False)


@FUZZ
@given(text=st.text(max_size=200))
def test_any_text_is_a_configuration_in_range_or_a_located_error(text: str) -> None:
    check_configuration(text)


#: A value for each key around the edges of its range, or junk.
VALUES = {
    "width": st.integers(0, 700),
    "height": st.integers(0, 700),
    "rotation": st.sampled_from([0, 45, 90, 180, 270, 360, -90]),
    "fov_rad": st.one_of(
        st.floats(-0.5, 4.5, allow_subnormal=SUBNORMALS),
        st.sampled_from([0.0, 1e-9, 3.1415, 3.1416, 3.5, 4.0]),
    ),
    "brightness": st.integers(-10, 300),
    "contrast": st.integers(-10, 300),
    "saturation": st.integers(-10, 300),
    "auto_white_balance": st.sampled_from(["on", "off", "yes", "no", "1", "0", "2", "maybe"]),
    "zoom": st.integers(0, 9),
}
#: Lines of ``key = value``, every key (and one unknown) with a value near its edges; junk
#: values are the other tests' business.
SETTING_LINES = st.lists(
    st.sampled_from(sorted(VALUES)).flatmap(
        lambda key: VALUES[key].map(lambda value: f"{key} = {value}")
    ),
    max_size=3,
).map("\n".join)


@FUZZ
@given(text=SETTING_LINES)
def test_any_settings_are_a_configuration_in_range_or_a_located_error(text: str) -> None:
    check_configuration(text)


#: Text edits of a valid file: at a position, insert, delete or replace some text.
EDITS = st.lists(
    st.tuples(
        st.integers(0, 3),
        st.integers(0, len(VALID_FILE)),
        st.one_of(
            st.text(max_size=6),
            st.sampled_from(
                ["=", "#", "\n", "-", "9", "0", "_", "e5", "nan", "\uff10", "width = 32\n"]
            ),
        ),
    ),
    min_size=1,
    max_size=5,
)


@FUZZ
@given(edits=EDITS)
def test_a_mutated_valid_file_is_a_configuration_in_range_or_a_located_error(
    edits: list[tuple[int, int, str]],
) -> None:
    text = VALID_FILE
    for kind, position, piece in edits:
        at = position % (len(text) + 1)
        if kind == 0:
            text = text[:at] + piece + text[at:]
        elif kind == 1:
            text = text[:at] + text[at + len(piece) + 1 :]
        elif kind == 2:
            text = text[:at] + piece + text[at + len(piece) :]
        else:  # a line said twice
            lines = text.splitlines(keepends=True)
            if lines:
                line = lines[at % len(lines)]
                text = text + line
    check_configuration(text)
