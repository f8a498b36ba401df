"""The terminal colours Webots names (``controller.ansi_codes``): ``ego run`` prints to a real
terminal, where the standard ANSI escape sequences apply."""

__all__ = ["AnsiCodes"]


def _sgr(code: int) -> str:
    return f"\x1b[{code}m"


class AnsiCodes:
    """The ANSI escape sequences Webots names (SGR codes 0, 1, 4, 30-37, 40-47; 2J)."""

    RESET = _sgr(0)
    BOLD = _sgr(1)
    UNDERLINE = _sgr(4)
    BLACK_FOREGROUND, RED_FOREGROUND, GREEN_FOREGROUND, YELLOW_FOREGROUND = (
        _sgr(30), _sgr(31), _sgr(32), _sgr(33),
    )  # fmt: skip
    BLUE_FOREGROUND, MAGENTA_FOREGROUND, CYAN_FOREGROUND, WHITE_FOREGROUND = (
        _sgr(34), _sgr(35), _sgr(36), _sgr(37),
    )  # fmt: skip
    BLACK_BACKGROUND, RED_BACKGROUND, GREEN_BACKGROUND, YELLOW_BACKGROUND = (
        _sgr(40), _sgr(41), _sgr(42), _sgr(43),
    )  # fmt: skip
    BLUE_BACKGROUND, MAGENTA_BACKGROUND, CYAN_BACKGROUND, WHITE_BACKGROUND = (
        _sgr(44), _sgr(45), _sgr(46), _sgr(47),
    )  # fmt: skip
    CLEAR_SCREEN = "\x1b[2J"
