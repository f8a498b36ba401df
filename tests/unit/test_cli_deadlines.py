"""Every ``--*-deadline-ms`` of ``ego`` is read by one parser: the same bounds, the same
refusal, whichever command takes it."""

from __future__ import annotations

import pytest

from ego.app.cli import build_parser
from ego.app.cli_options import MAX_DEADLINE_MS

#: Each command line with a deadline (or ego ros2's period) in it, its value left open.
COMMANDS = {
    "run --supervisor-deadline-ms": ["run", "--supervisor-deadline-ms", "{}", "c.py"],
    "serve --deadline-ms": ["serve", "--deadline-ms", "{}"],
    "ros2 --deadline-ms": ["ros2", "--deadline-ms", "{}"],
    "ros2 --period-ms": ["ros2", "--period-ms", "{}"],
}
DEST = {
    "run --supervisor-deadline-ms": "supervisor_deadline_ms",
    "serve --deadline-ms": "deadline_ms",
    "ros2 --deadline-ms": "deadline_ms",
    "ros2 --period-ms": "period_ms",
}


def parse(name: str, value: str) -> object:
    argv = [word.format(value) for word in COMMANDS[name]]
    return getattr(build_parser().parse_args(argv), DEST[name])


@pytest.mark.parametrize("name", COMMANDS)
@pytest.mark.parametrize("value", ["1", "250", str(MAX_DEADLINE_MS)])
def test_a_whole_number_of_ms_in_range_is_taken(name: str, value: str) -> None:
    assert parse(name, value) == int(value)


@pytest.mark.parametrize("name", COMMANDS)
@pytest.mark.parametrize("value", ["0", str(MAX_DEADLINE_MS + 1), "ten", "1.5", "-3", ""])
def test_anything_else_is_refused_with_one_message(
    name: str, value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exit_:
        parse(name, value)
    assert exit_.value.code == 2
    flag = COMMANDS[name][1]
    expected = f"{flag}: {value!r} is not a whole number of milliseconds within 1..60000"
    assert expected in capsys.readouterr().err
