"""The camera configuration file: what it sets, and a typed error with the line for each mistake."""

from __future__ import annotations

import textwrap

import pytest
from camera_fakes import ScriptedSource
from hypothesis import given, settings
from hypothesis import strategies as st

from ego.camera import (
    Camera,
    CameraConfiguration,
    ConfigSyntaxError,
    SettingOutOfRangeError,
    UnknownSettingError,
    parse_configuration,
)
from ego.errors import CameraConfigError, OutOfRangeError

THESIS_DEFAULTS = """\
# the thesis' defaults (appendix C.2)
width = 640
height = 480
brightness = 1
contrast = 64
saturation = 64      # trailing comments are fine
auto_white_balance = 0
"""


def test_thesis_defaults_parse_to_their_values():
    assert parse_configuration(THESIS_DEFAULTS) == CameraConfiguration(
        width=640, height=480, brightness=1, contrast=64, saturation=64, auto_white_balance=False
    )


def test_empty_file_sets_nothing():
    assert parse_configuration("\n   \n# only a comment\n") == CameraConfiguration()


@pytest.mark.parametrize(
    ("text", "expected"),
    [("on", True), ("Yes", True), ("1", True), ("off", False), ("FALSE", False), ("no", False)],
)
def test_auto_white_balance_accepts_the_usual_spellings(text, expected):
    config = parse_configuration(f"auto_white_balance = {text}")
    assert config.auto_white_balance is expected


@pytest.mark.parametrize(
    ("text", "line", "message"),
    [
        ("width = 640\nheight 480\n", 2, "expected 'key = value'"),
        ("= 3\n", 1, "missing key"),
        ("# c\n\ncontrast =\n", 3, "missing value for contrast"),
        ("contrast = high\n", 1, "contrast must be an integer, not 'high'"),
        ("contrast = 6.5\n", 1, "must be an integer"),
        ("fov_rad = wide\n", 1, "fov_rad must be a number"),
        ("auto_white_balance = maybe\n", 1, "must be on or off"),
        (
            "contrast = 1\nbrightness = 2\ncontrast = 3\n",
            3,
            "contrast is set twice (first on line 1)",
        ),
    ],
)
def test_malformed_line_is_a_syntax_error_with_its_line(text, line, message):
    with pytest.raises(ConfigSyntaxError) as caught:
        parse_configuration(text, "cam.conf")
    assert caught.value.line_number == line
    assert str(caught.value).startswith(f"cam.conf:{line}: ")
    assert message in str(caught.value)
    assert isinstance(caught.value, CameraConfigError) and isinstance(caught.value, ValueError)


def test_unknown_key_is_refused_listing_the_keys():
    expected = r"cam.conf:2: unknown setting 'brightnes'; the settings are width, height"
    with pytest.raises(UnknownSettingError, match=expected) as caught:
        parse_configuration("width = 64\nbrightnes = 3\n", "cam.conf")
    assert caught.value.line_number == 2


@pytest.mark.parametrize(
    ("text", "line", "message"),
    [
        ("brightness = 256", 1, "brightness 256 is outside 0..255"),
        ("\ncontrast = -1", 2, "contrast -1 is outside 0..255"),
        ("auto_white_balance = 2", 1, "must be on or off"),  # 2 is not a truth value
        ("rotation = 45", 1, "rotation 45 is not one of 0, 90, 180, 270"),
        ("fov_rad = 3.5", 1, "fov_rad 3.5 is outside (0, pi)"),
        ("width = 700", 1, "width 700 is outside 32..640 at rotation 180"),
        ("height = 16", 1, "height 16 is outside 32..480"),
        ("rotation = 90\nwidth = 640", 2, "width 640 is outside 32..480 at rotation 90"),
    ],
)
def test_value_out_of_range_names_the_range_and_line(text, line, message):
    error = ConfigSyntaxError if "on or off" in message else SettingOutOfRangeError
    with pytest.raises(error) as caught:
        parse_configuration(text, "cam.conf")
    assert caught.value.line_number == line
    assert message in str(caught.value)
    if error is SettingOutOfRangeError:
        assert isinstance(caught.value, OutOfRangeError)


def test_rotated_size_ranges_follow_the_camera_when_the_file_has_no_rotation():
    config = parse_configuration("width = 480\nheight = 640", current_rotation=270)
    assert (config.width, config.height) == (480, 640)


def test_load_configuration_applies_every_setting(tmp_path):
    path = tmp_path / "camera.conf"
    path.write_text(
        THESIS_DEFAULTS.replace("640", "160").replace("480", "120")
        + "rotation = 0\nfov_rad = 0.7\n"
    )
    source = ScriptedSource()
    camera = Camera(source=source)
    camera.enable(64)
    camera.load_configuration(path)
    assert (camera.width, camera.height, camera.rotation) == (160, 120, 0)
    assert camera.fov_rad == pytest.approx(0.7)
    assert (camera.brightness, camera.contrast, camera.saturation) == (1, 64, 64)
    assert camera.auto_white_balance is False
    assert source.opened[-1][:2] == (160, 120)
    assert ("auto_white_balance", 0) in source.controls


def test_an_invalid_file_changes_nothing(tmp_path):
    path = tmp_path / "camera.conf"
    path.write_text(
        textwrap.dedent("""\
        width = 160
        height = 120
        contrast = 999
    """)
    )
    camera = Camera(source=ScriptedSource(), width=320, height=240)
    with pytest.raises(SettingOutOfRangeError, match=r"camera.conf:3: contrast 999"):
        camera.load_configuration(path)
    assert (camera.width, camera.height, camera.contrast) == (320, 240, None)


def test_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        Camera(source=ScriptedSource()).load_configuration(tmp_path / "nowhere.conf")


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("=#\n -.0123456789abcdefghiortwxy_\t")), max_size=80))
def test_any_text_parses_or_raises_a_located_config_error(text):
    try:
        config = parse_configuration(text, "fuzz.conf")
    except CameraConfigError as exc:
        assert str(exc).startswith("fuzz.conf:") and exc.line_number >= 1
    else:
        assert isinstance(config, CameraConfiguration)
