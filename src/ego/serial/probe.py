"""Which firmware answers on a line: ``V``, then for the stock one ``C`` and ``b``.

docs/protocol.md, "Telling the firmwares apart": Webots' firmware and the stock one both
answer ``V``; the stock one's selector (``C``) tells Overo mode from Bluetooth, and the
form of its battery answer (``b``) tells an e-puck rev 1.3. Used by the serial Link when
it opens and after the dsPIC restarted.
"""

from __future__ import annotations

import logging
from typing import Protocol

from ego.errors import LinkTimeoutError, NotAnEpuckError, ProtocolError
from ego.seam.batch import Batch, Request
from ego.seam.channel import FirmwareInfo
from ego.seam.profile import Command, Firmware
from ego.serial.firmware import identify, is_gctronic, line_payload, parse_selector
from ego.serial.profiles import PROFILES
from ego.serial.protocol import encode_batch
from ego.serial.transport import Transport

__all__ = ["Probed", "probe_firmware"]

log = logging.getLogger(__name__)


class Probed(Protocol):
    """What the probe needs of a serial link (ego.serial.link.Link is one)."""

    @property
    def transport(self) -> Transport: ...

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]: ...

    def timeout_for(self, batch: Batch) -> float: ...


def probe_firmware(link: Probed, first: bool = False) -> FirmwareInfo:
    """Ask ``V`` (and ``C``, ``b``) on ``link``: the firmware, its mode and revision.

    At open (``first``), something that answers but not as a dsPIC is the wrong port
    (NotAnEpuckError), and a silent ``V`` is checked with a binary ``E``, which every
    firmware answers: silence to both means nothing is there.
    """
    name = link.transport.name
    try:
        version = link.ascii_command("V", lines=2)
        selector = battery = None
        if version and is_gctronic(line_payload(version[0], "V")):
            answer = link.ascii_command("C", lines=1)
            selector = parse_selector(answer[0]) if answer else None
            battery = _battery_line(link)
    except ProtocolError as exc:
        if not first:
            raise
        raise NotAnEpuckError(f"{name} answers, but not as an e-puck's dsPIC: {exc}") from exc
    if first and not version:
        _probe_silence(link)
    info = identify(version, selector, battery)
    log.info(
        "%s: firmware %s (%s%s)",
        name,
        info.firmware,
        info.version or "no answer to V",
        f", selector {selector}" if selector is not None else "",
    )
    return info


def _battery_line(link: Probed) -> str | None:
    """The stock firmware's answer to ``b``, whose form tells an e-puck rev 1.3.

    docs/protocol.md, "b"; None when it answers something else (an older build).
    """
    try:
        return next(iter(link.ascii_command("b", lines=1)), None)
    except ProtocolError:
        return None


def _probe_silence(link: Probed) -> None:
    probe = encode_batch([Request(Command.GET_SPEED)], PROFILES[Firmware.WEBOTS])
    link.transport.write(probe.tx)
    try:
        link.transport.read_exactly(probe.reply_size, link.timeout_for(probe))
    except LinkTimeoutError as exc:
        raise LinkTimeoutError(
            f"nothing answers on {link.transport.name} (no reply to V, nor to a binary "
            "E): is the robot switched on, and is this its port?"
        ) from exc
