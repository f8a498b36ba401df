"""The link on a scripted transport: exact-length replies, resync, bounded retries, restarts.

protocol.md: "The reply length is the only integrity check there is: read exactly the
expected count with a timeout, and treat a short read, or bytes left over after it, as a
fault (resynchronise, retry a bounded number of times, then raise)."
"""

from __future__ import annotations

import dataclasses
import struct

import pytest
from fakes import INSTANT_LINK, ScriptedTransport

from ego.errors import (
    ExtraBytesError,
    LinkLostError,
    LinkTimeoutError,
    NotAnEpuckError,
    PortNotFoundError,
    ProtocolError,
    RobotResetError,
)
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.link import Link, LinkSettings
from ego.serial.protocol import encode_batch
from firmware_sim import BANNER

SENSORS = [Request(Command((-ord(c)) & 0xFF)) for c in "aEMNOQu"]
REPLY = bytes(range(58))
#: protocol.md: "sending a few zeros is the way to resynchronise"; a newline and a
#: harmless V line then end any ASCII line a desynchronised stream started.
RESYNC = bytes(8) + b"\nV\n"
WEBOTS_V = b"v,Version 1.5.3 November 2016 (Webots)\r\nHW version: FFFF\r\n"
GCTRONIC_V = b"v,Version 1.2.2 August 2008 GCtronic\r\nHW version: FFFF\r\n"
#: Asercom.c, ASCII 'b' on an e-puck older than rev 1.3: the BATT_LOW flag.
OLD_BATTERY = b"b,1\r\n"


def make_link(
    script: list[object] | None = None,
    firmware: str | None = "webots",
    settings: LinkSettings = INSTANT_LINK,
    **transport: object,
) -> tuple[Link, ScriptedTransport]:
    fake = ScriptedTransport(script or [], **transport)  # type: ignore[arg-type]
    return Link(fake, firmware=firmware, settings=settings), fake


def sensor_batch(link: Link):  # type: ignore[no-untyped-def]
    return encode_batch(SENSORS, link.profile)


# -- the good path -------------------------------------------------------------------------------


def test_exchange_returns_exactly_the_reply() -> None:
    link, fake = make_link([REPLY])
    batch = sensor_batch(link)
    assert link.exchange(batch) == REPLY
    assert fake.writes == [bytes.fromhex("9f bb b3 b2 b1 af 8b 00")]
    assert (link.stats.batches, link.stats.bytes_sent, link.stats.bytes_received) == (1, 8, 58)
    assert link.stats.retries == link.stats.resyncs == 0


def test_actuator_only_batch_never_reads() -> None:
    """protocol.md: "A batch that asks for nothing (only D, L, P) gets no reply at all:
    never wait for one"."""
    link, fake = make_link([b"\x55"])  # even a dsPIC that (wrongly) answers is not read
    batch = encode_batch([Request(Command.SET_SPEED, (100, -100))], link.profile)
    assert link.exchange(batch) == b""
    assert fake.events[-1] == ("write", bytes.fromhex("bc 64 00 9c ff 00"))


def test_welcome_banner_is_drained_when_the_link_opens() -> None:
    """protocol.md: "After reset the robot prints a welcome banner: drain input after
    opening the port"."""
    link, fake = make_link([REPLY], incoming=BANNER)
    assert not fake.incoming
    assert link.exchange(sensor_batch(link)) == REPLY
    assert link.stats.restarts == 0


def test_stale_bytes_before_a_batch_are_drained_first() -> None:
    link, fake = make_link([REPLY])
    fake.answer(b"\x01\x02\x03")  # e.g. stray bytes after an earlier silent batch
    assert link.exchange(sensor_batch(link)) == REPLY
    assert link.stats.faults["stale"] == 1
    assert fake.writes == [sensor_batch(link).tx]


# -- faults and recovery ---------------------------------------------------------------------------


def test_short_reply_resyncs_and_retries() -> None:
    link, fake = make_link([REPLY[:-1], b"", REPLY])
    batch = sensor_batch(link)
    assert link.exchange(batch) == REPLY
    assert fake.writes == [batch.tx, RESYNC, batch.tx]
    assert link.stats.faults["LinkTimeoutError"] == 1
    assert (link.stats.retries, link.stats.resyncs) == (1, 1)


def test_overlong_reply_resyncs_and_retries() -> None:
    link, fake = make_link([REPLY + b"\x00", b"", REPLY])
    batch = sensor_batch(link)
    assert link.exchange(batch) == REPLY
    assert fake.writes == [batch.tx, RESYNC, batch.tx]
    assert link.stats.faults["ExtraBytesError"] == 1


def test_resync_drains_what_the_dspic_still_had_to_say() -> None:
    # The dsPIC answers late: the first reply arrives only after the resync began.
    link, fake = make_link([b"", REPLY + WEBOTS_V, REPLY])
    batch = sensor_batch(link)
    assert link.exchange(batch) == REPLY
    assert fake.writes == [batch.tx, RESYNC, batch.tx]
    assert not fake.incoming


def test_resync_sends_eight_zeros_then_ends_any_ascii_line() -> None:
    """Zeros complete pending D/P arguments and end a batch (protocol.md); a stray positive
    byte outside a batch starts an ASCII line that only a newline ends."""
    link, fake = make_link([b""], settings=dataclasses.replace(INSTANT_LINK, retries=0))
    with pytest.raises(LinkTimeoutError):
        link.exchange(sensor_batch(link))
    resync = fake.writes[1]
    assert resync.startswith(bytes(8))
    assert resync.endswith(b"\n")
    assert b"\n" in resync[8:-1], "a newline must end a pending line before the V line"


@pytest.mark.parametrize(
    ("bad_reply", "error"),
    [(REPLY[:-1], LinkTimeoutError), (REPLY + b"\x00", ExtraBytesError), (b"", LinkTimeoutError)],
)
def test_retries_exhausted_raise_the_typed_error(bad_reply: bytes, error: type[Exception]) -> None:
    settings = dataclasses.replace(INSTANT_LINK, retries=2)
    link, fake = make_link([bad_reply, b""] * 3, settings=settings)
    batch = sensor_batch(link)
    with pytest.raises(error):
        link.exchange(batch)
    assert fake.writes == [batch.tx, RESYNC] * 3
    assert link.stats.retries == 2


def test_link_timeout_carries_what_arrived() -> None:
    settings = dataclasses.replace(INSTANT_LINK, retries=0)
    link, _ = make_link([REPLY[:10]], settings=settings)
    with pytest.raises(LinkTimeoutError) as caught:
        link.exchange(sensor_batch(link))
    assert caught.value.partial == REPLY[:10]  # type: ignore[attr-defined]
    assert isinstance(caught.value, TimeoutError)


#: docs/protocol.md, Timing: Webots' firmware reads the ground sensors over I2C, about 3 ms.
M_WORK_S = 0.003


def test_reply_timeout_scales_with_wire_time_firmware_work_and_latency() -> None:
    """docs/protocol.md: 10 bits a byte; the dsPIC's own work per command; a network
    transport adds its own latency."""
    settings = dataclasses.replace(INSTANT_LINK, reply_timeout_s=0.025, wire_factor=3.0)
    link, _ = make_link(settings=settings, firmware="gctronic", latency_s=0.2)
    batch = encode_batch([Request(Command.PROXIMITY), Request(Command.GET_SPEED)], link.profile)
    wire = (len(batch.tx) + batch.reply_size) * 10 / 230400  # 4 bytes out, 24 back
    assert link.timeout_for(batch) == pytest.approx(0.025 + 3 * wire + 0.2)
    slow, _ = make_link(settings=settings, firmware="gctronic", baudrate=57600)
    assert slow.timeout_for(batch) == pytest.approx(0.025 + 3 * wire * 4)


def test_webots_firmware_is_timed_at_its_own_115200_baud_whatever_the_port() -> None:
    """firmware.c: e_init_uart1(), 115200 baud; a pty opened at 230400 carries it all the same,
    and the M it is asked costs its I2C read."""
    settings = dataclasses.replace(INSTANT_LINK, reply_timeout_s=0.0, wire_factor=1.0)
    for baudrate in (230400, None):
        link, _ = make_link(settings=settings, baudrate=baudrate)
        batch = sensor_batch(link)  # 8 bytes out, 58 back, an M among them
        assert link.timeout_for(batch) == pytest.approx(66 * 10 / 115200 + M_WORK_S)


# -- restarts and lost ports -----------------------------------------------------------------------


def test_banner_in_a_reply_raises_robot_reset_after_re_identification() -> None:
    """A dsPIC that restarted has lost its actuator state: the link finds out which firmware
    now answers and tells its owner to re-apply that state."""
    link, fake = make_link(
        [WEBOTS_V, BANNER, GCTRONIC_V, b"c,10\r\n", OLD_BATTERY], firmware=None
    )
    assert link.info.firmware is Firmware.WEBOTS
    batch = sensor_batch(link)
    with pytest.raises(RobotResetError, match="restarted"):
        link.exchange(batch)
    assert fake.writes == [b"V\n", batch.tx, b"V\n", b"C\n", b"b\n"]
    assert link.info.firmware is Firmware.GCTRONIC
    assert link.stats.restarts == 1


@pytest.mark.parametrize("letters", ["E", "Q", "a", "EQ"])
def test_banner_after_a_short_reply_is_still_a_restart(letters: str) -> None:
    """The banner is longer than a short reply: its first bytes fill the reply, the rest
    come as extra bytes and in the resync's drain. It must not pass for a plain glitch."""
    link, _ = make_link([BANNER, b"", bytes(16)])
    batch = encode_batch([Request(Command((-ord(c)) & 0xFF)) for c in letters], link.profile)
    assert batch.reply_size < len(BANNER)
    with pytest.raises(RobotResetError):
        link.exchange(batch)


class LateBanner(ScriptedTransport):
    """The dsPIC resets on the first write: the banner's first ``cut`` bytes come at once,
    the rest only when the link reads again after its trailing guard (a loaded machine)."""

    def __init__(self, cut: int) -> None:
        super().__init__([BANNER[:cut], b"", bytes(16)])  # then the re-detection's
        self.held = BANNER[cut:]
        self.empty_reads = 0

    def read(self, size: int, timeout_s: float) -> bytes:
        if not self.incoming and self.held and self.writes:
            self.empty_reads += 1
            if self.empty_reads == 2:  # the first is the trailing guard's
                self.incoming += self.held
                self.held = b""
        return super().read(size, timeout_s)


def test_a_banner_whose_rest_is_late_after_a_short_reply_is_a_restart_at_once() -> None:
    """Beside the suite and two busy loops, a reset during a 4-byte E gave the step the
    banner's first bytes as speeds (1804, 17751) and was found one batch later, as stale
    bytes. A reply that ends as the banner begins waits for the banner's rest."""
    fake = LateBanner(cut=4)
    link = Link(fake, firmware="webots", settings=INSTANT_LINK)
    batch = encode_batch([Request(Command.GET_SPEED)], link.profile)
    assert batch.reply_size == 4
    with pytest.raises(RobotResetError):
        link.exchange(batch)
    assert link.stats.restarts == 1


def test_a_reply_that_merely_ends_like_the_banner_is_taken() -> None:
    link, _ = make_link([b"\x00\x00\x0c\x07"])  # two bytes of it: too common to wait on
    batch = encode_batch([Request(Command.GET_SPEED)], link.profile)
    assert batch.decode(link.exchange(batch)) == [(0, 0x070C)]


def test_banner_in_a_timed_out_reply_is_a_restart() -> None:
    link, _ = make_link([BANNER])
    batch = encode_batch([Request(Command.MIC_BUFFER)], link.profile)  # 601 bytes > banner
    with pytest.raises(RobotResetError):
        link.exchange(batch)


def test_banner_among_stale_bytes_is_a_restart_and_the_batch_is_not_sent() -> None:
    link, fake = make_link([REPLY])
    fake.answer(BANNER)
    with pytest.raises(RobotResetError):
        link.exchange(sensor_batch(link))
    assert fake.writes == []


def test_banner_in_the_resync_drain_is_a_restart() -> None:
    link, _ = make_link([REPLY[:3], BANNER])
    with pytest.raises(RobotResetError):
        link.exchange(sensor_batch(link))


def test_lost_port_is_reopened_and_reported_as_a_restart() -> None:
    link, fake = make_link([LinkLostError("scripted: read failed")])
    with pytest.raises(RobotResetError, match="reopened"):
        link.exchange(sensor_batch(link))
    assert fake.reopened == 1
    assert not fake.closed
    assert (link.stats.reconnects, link.stats.restarts) == (1, 1)


def test_port_lost_while_resynchronising_is_reopened_not_lost_for_good() -> None:
    """A short reply, then the port vanishes under the resync's own write."""
    link, fake = make_link([REPLY[:3], LinkLostError("scripted: unplugged mid-resync")])
    with pytest.raises(RobotResetError, match="reopened"):
        link.exchange(sensor_batch(link))
    assert fake.reopened == 1
    assert (link.stats.resyncs, link.stats.reconnects, link.stats.restarts) == (1, 1, 1)


def test_port_lost_again_while_the_firmware_is_redetected_is_reopened_again() -> None:
    """A loose connector: the port comes back, then vanishes under the V re-detection."""
    fake = ScriptedTransport([b"v,Version 1.2 ego-emulator\n"])
    link = Link(fake, settings=INSTANT_LINK)
    fake.script.extend([LinkLostError("unplugged"), LinkLostError("unplugged again")])
    with pytest.raises(RobotResetError, match="reopened"):
        link.exchange(sensor_batch(link))
    assert fake.reopened == 2
    assert link.stats.restarts == 1


def test_port_that_comes_back_before_the_deadline_is_reused() -> None:
    gone = [PortNotFoundError("not yet"), LinkLostError("not yet"), None]
    link, fake = make_link([LinkLostError("unplugged")], reopen=gone)
    with pytest.raises(RobotResetError):
        link.exchange(sensor_batch(link))
    assert fake.reopened == 3


def test_port_not_back_by_the_deadline_is_lost_for_good() -> None:
    settings = dataclasses.replace(INSTANT_LINK, reconnect_timeout_s=0.1)
    never = [PortNotFoundError("/dev/ttyS0 is gone")] * 100
    link, fake = make_link([LinkLostError("unplugged")], settings=settings, reopen=never)
    with pytest.raises(LinkLostError, match=r"not back within 0\.1 s") as caught:
        link.exchange(sensor_batch(link))
    assert isinstance(caught.value.__cause__, LinkLostError)
    assert fake.reopened >= 2


def test_transport_that_cannot_reconnect_is_lost_for_good() -> None:
    """Transport.reopen's default: "cannot" (a transport with no way back)."""

    class OneShot(ScriptedTransport):
        def reopen(self) -> None:
            raise LinkLostError("one-shot: this transport cannot reconnect")

    fake = OneShot([LinkLostError("gone")])
    link = Link(
        fake,
        firmware="webots",
        settings=dataclasses.replace(INSTANT_LINK, reconnect_timeout_s=0.05),
    )
    with pytest.raises(LinkLostError):
        link.exchange(sensor_batch(link))


# -- firmware identification -------------------------------------------------------------------


def test_webots_answer_to_v_selects_webots_without_asking_c() -> None:
    link, fake = make_link([WEBOTS_V], firmware=None)
    assert link.info.firmware is Firmware.WEBOTS
    assert link.info.detected
    assert fake.writes == [b"V\n"]


@pytest.mark.parametrize(("selector", "ir_values"), [(10, 10), (3, 8)])
def test_gctronic_answer_to_v_asks_the_selector_and_the_battery(
    selector: int, ir_values: int
) -> None:
    """The selector says Overo mode (10) or Bluetooth; b's form says whether a rev 1.3."""
    script = [GCTRONIC_V, f"c,{selector}\r\n".encode(), OLD_BATTERY]
    link, fake = make_link(script, firmware=None)  # type: ignore[arg-type]
    assert fake.writes == [b"V\n", b"C\n", b"b\n"]
    assert link.info.firmware is Firmware.GCTRONIC
    assert link.info.selector == selector
    assert link.profile.reply_values(Command.PROXIMITY) == ir_values
    assert link.profile.rev13 is False


def test_firmware_silent_to_v_but_answering_e_gets_the_thesis_profile() -> None:
    link, fake = make_link([b"", b"\x00\x00\x00\x00"], firmware=None)
    assert link.info.firmware is Firmware.WEBOTS
    assert link.info.version == ""
    assert fake.writes == [b"V\n", b"\xbb\x00"]


def test_port_silent_to_v_and_to_e_is_reported_as_nothing_there() -> None:
    with pytest.raises(LinkTimeoutError, match="nothing answers on scripted"):
        make_link([], firmware=None)


def test_gctronic_that_does_not_answer_c_is_taken_to_be_in_overo_mode() -> None:
    link, _ = make_link([GCTRONIC_V], firmware=None)
    assert link.info.firmware is Firmware.GCTRONIC
    assert link.info.selector is None
    assert link.profile.line_baud == 230400


def test_robot_switched_on_as_the_port_opens_is_asked_again_after_its_banner() -> None:
    """The banner comes after the open's drain, in place of the answer to V."""
    link, fake = make_link([BANNER, WEBOTS_V], firmware=None)
    assert link.info.detected and link.info.version
    assert fake.writes == [b"V\n", b"V\n"]
    fake.script.append(REPLY)
    assert link.exchange(sensor_batch(link)) == REPLY  # nothing to re-apply at open


def test_restart_during_an_ascii_command_is_told_at_the_next_batch() -> None:
    link, fake = make_link([BANNER, b"s\r\n"])
    assert link.ascii_command("S") == ["s"]
    with pytest.raises(RobotResetError, match="during an ASCII command"):
        link.exchange(sensor_batch(link))
    assert fake.writes == [b"S\n", b"S\n"]  # the batch was not sent to a restarted dsPIC


def test_answer_to_another_command_means_not_an_epuck() -> None:
    with pytest.raises(NotAnEpuckError, match=r"not as an e-puck's dsPIC.*does not start with 'v'"):
        make_link([b"z,Command not found\r\n"], firmware=None)


@pytest.mark.parametrize("firmware", ["webots", Firmware.GCTRONIC, "gctronic"])
def test_forced_firmware_sends_no_probe(firmware: str) -> None:
    link, fake = make_link([WEBOTS_V], firmware=firmware)
    assert link.info.firmware is Firmware(firmware)
    assert not link.info.detected
    assert fake.writes == []


def test_auto_firmware_probes_like_none() -> None:
    link, fake = make_link([WEBOTS_V], firmware="auto")
    assert link.info.detected
    assert fake.writes == [b"V\n"]


def test_unknown_firmware_name_is_refused() -> None:
    with pytest.raises(ValueError, match="'e-puck2'"):
        make_link(firmware="e-puck2")


def test_ascii_command_returns_its_reply_lines() -> None:
    link, fake = make_link([b"k, Starting calibration\r\nk, Calibration finished\r\n"])
    assert link.ascii_command("K", lines=2) == [
        "k, Starting calibration",
        "k, Calibration finished",
    ]
    assert fake.writes == [b"K\n"]


def test_ascii_command_returns_fewer_lines_when_the_firmware_stays_silent() -> None:
    link, _ = make_link([b"k, Starting calibration\r\n"])
    assert link.ascii_command("K", lines=2) == ["k, Starting calibration"]


def test_stop_command_accepts_its_bare_reply() -> None:
    """protocol.md: "S (stop motors, LEDs off; reply s)": no comma, no payload."""
    link, fake = make_link([b"s\r\n"])
    assert link.ascii_command("S") == ["s"]
    assert fake.writes == [b"S\n"]


def test_ascii_reply_to_another_command_is_refused() -> None:
    link, _ = make_link([b"c,10\r\n"])
    with pytest.raises(ProtocolError, match="does not start with 's'"):
        link.ascii_command("S")


def test_closed_link_refuses_to_exchange_rather_than_reopen_its_port() -> None:
    link, fake = make_link()
    link.close()
    assert fake.closed
    with pytest.raises(LinkLostError, match="closed"):
        link.exchange(encode_batch([Request(Command.SET_SPEED, (0, 0))], link.profile))
    assert fake.reopened == 0
    assert fake.closed


def test_default_settings_suit_the_overo_line() -> None:
    """protocol.md numbers the defaults rest on: 230400 baud, 84 us/byte measured."""
    settings = LinkSettings()
    assert settings.retries == 3
    assert settings.wire_factor >= 84.03 / 43.4
    assert settings.resync_quiet_s == pytest.approx(0.1)  # "then drain the input for ~100 ms"


def test_reply_bytes_decode_through_the_link() -> None:
    proximity = tuple(range(100, 900, 100))
    reply = struct.pack("<8h", *proximity)
    link, _ = make_link([reply])
    batch = encode_batch([Request(Command.PROXIMITY)], link.profile)
    assert batch.decode(link.exchange(batch)) == [proximity]
