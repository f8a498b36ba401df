"""One integer check (ego.seam.validate.check_int) and one rotation check, used everywhere."""

from __future__ import annotations

import numpy as np
import pytest

from ego.camera import convert, device, encode
from ego.camera.convert import ROTATIONS, check_rotation
from ego.devices import base
from ego.errors import OutOfRangeError
from ego.seam.validate import check_int


def test_the_families_and_the_camera_share_the_one_check() -> None:
    assert base.check_int is check_int
    assert vars(device)["check_int"] is check_int
    assert vars(encode)["check_int"] is check_int
    assert vars(device)["check_rotation"] is check_rotation is convert.check_rotation


def test_a_real_number_that_is_whole_is_accepted_and_range_refused() -> None:
    assert check_int("period", 64.0, 1, 100) == 64
    assert check_int("period", np.int16(7), 1, 100) == 7
    assert check_int("speed", 2.6, 0, 5, rounding=True) == 3
    with pytest.raises(OutOfRangeError, match=r"period 0 ms is outside 1\.\.100 ms: refused"):
        check_int("period", 0, 1, 100, " ms")
    with pytest.raises(OutOfRangeError, match=r"not a whole number in 1\.\.100"):
        check_int("period", 2.5, 1, 100)
    with pytest.raises(TypeError, match="period must be a number, not str"):
        check_int("period", "3", 1, 100)


def test_integral_refuses_any_float_and_the_bounds_are_optional() -> None:
    assert check_int("x", 10**12, integral=True) == 10**12
    assert check_int("x", np.uint8(3), integral=True) == 3
    with pytest.raises(TypeError, match=r"^x must be an integer, not 3\.0$"):
        check_int("x", 3.0, integral=True)
    with pytest.raises(TypeError, match=r"quality must be an integer 1\.\.100, not True"):
        check_int("quality", True, 1, 100, integral=True)
    with pytest.raises(OutOfRangeError, match=r"x -1 is outside 0\.\.: refused"):
        check_int("x", -1, 0, integral=True)


@pytest.mark.parametrize("rotation", ROTATIONS)
def test_each_rotation_is_accepted(rotation: int) -> None:
    assert check_rotation(rotation) == rotation


@pytest.mark.parametrize("rotation", [45, -90, 360, True, False, "90", None])
def test_any_other_rotation_is_refused_naming_the_choices(rotation: object) -> None:
    with pytest.raises(OutOfRangeError, match="is not one of 0, 90, 180, 270 degrees"):
        check_rotation(rotation)


def test_the_converters_refuse_a_bool_rotation_as_the_camera_does() -> None:
    frame = bytes(2 * 4 * 4)
    assert convert.rgb565_to_rgb888(frame, 4, 4, rotation=0).shape == (4, 4, 3)
    with pytest.raises(OutOfRangeError, match="rotation False"):
        convert.rgb565_to_rgb888(frame, 4, 4, rotation=False)
