"""run_asercom2's static variables (MAIN:src/epuck1x/Asercom2.c:77-95), shared by its
binary and ASCII halves, and the tiny ``sscanf`` its ASCII commands parse with."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["CAM_DEFAULT", "IMAGE_MAX_SIZE", "Emission", "FirmwareState", "sscanf_ints"]

#: Asercom2.c:133-138: RGB565 (mode 1), 40 x 40, zoom 8.
CAM_DEFAULT = (1, 40, 40, 8)
#: MAIN:src/epuck1x/memory.h:5-7 and Asercom2.c:9: BUFFER_SIZE (52*39*2+3+80) less the
#: 3-byte image header.
IMAGE_MAX_SIZE = 52 * 39 * 2 + 3 + 80 - 3


@dataclass(frozen=True, slots=True)
class Emission:
    """What the firmware does next: spend ``work_s`` of its own time (not reading the
    line meanwhile), then send ``data`` (possibly nothing)."""

    data: bytes
    work_s: float = 0.0


@dataclass(slots=True)
class FirmwareState:
    """The statics: E reports ``speedl``/``speedr`` as last *stored*, which the binary
    commands store unsigned (Asercom2.c:503-504, 801, 811) and ASCII D signed (1135)."""

    speedl: int = 0
    speedr: int = 0
    positionl: int = 0
    positionr: int = 0
    led_nbr: int = 0
    led_action: int = 0
    sound: int = 0
    sound_ready: bool = False  # `first`: e_init_sound done
    cam_mode: int = CAM_DEFAULT[0]
    cam_width: int = CAM_DEFAULT[1]
    cam_height: int = CAM_DEFAULT[2]
    cam_zoom: int = CAM_DEFAULT[3]

    @property
    def cam_size(self) -> int:
        """Asercom2.c:138 and 1328-1331: one byte a pixel in grey, two in RGB565."""
        per_pixel = 1 if self.cam_mode == 0 else 2
        return self.cam_width * self.cam_height * per_pixel


def _int32(value: int) -> int:
    return ((value + 0x8000_0000) & 0xFFFF_FFFF) - 0x8000_0000


def sscanf_ints(text: str, fmt: str) -> list[int]:
    """C's ``sscanf(text, fmt, ...)`` for formats of literals and ``%d``: the values
    converted, in order, up to the first mismatch (the variables after it keep their
    old values). Whitespace in ``fmt`` matches any run of whitespace, even none."""
    values: list[int] = []
    i = 0
    f = 0
    while f < len(fmt):
        token = fmt[f]
        if token == "%" and fmt[f + 1 : f + 2] == "d":
            f += 2
            while i < len(text) and text[i] in " \t\r\n\v\f":
                i += 1
            start = i
            if i < len(text) and text[i] in "+-":
                i += 1
            digits = i
            while i < len(text) and text[i].isdigit() and text[i].isascii():
                i += 1
            if i == digits:
                return values
            values.append(_int32(int(text[start:i])))
        elif token in " \t\r\n\v\f":
            f += 1
            while i < len(text) and text[i] in " \t\r\n\v\f":
                i += 1
        else:
            if i >= len(text) or text[i] != token:
                return values
            i += 1
            f += 1
    return values
