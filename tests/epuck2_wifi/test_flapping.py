"""Issue 32, item 7: a WiFi radio that keeps dropping (every few packets) was reconnected
for ever: 222 reconnects and 222 WARNING lines in 25 s, the controller never told. Now
the drops are counted, the reconnects back off, the warnings are summarised, and more
than ``DropPolicy.max_drops`` (5) drops within ``window_s`` (30 s) end the link with
LinkLostError: Webots' step returns -1, and the close still sends the stop, once.

Real sockets: the emulated radio behind a relay that cuts each connection after the
robot sent it three sensor packets' worth of bytes."""

from __future__ import annotations

import logging

import pytest
from helpers import wait_until as until
from wifi_relay import Relay

import ego
from ego.backends.epuck2.drops import DropPolicy, DropTally
from firmware_sim.epuck2 import Epuck2Emulator

POLICY = DropPolicy()
#: Three sensor packets (a header byte and 104 bytes each).
EVERY_FEW_PACKETS = 3 * 105


def test_a_link_that_keeps_dropping_is_lost_for_good_and_the_robot_stopped(
    wifi: Epuck2Emulator, relay: Relay, relay_url: str, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING, logger="ego")
    robot = ego.Robot(relay_url)
    try:
        robot.proximity.enable(32)
        robot.motors.set_speed(300, 300)
        assert robot.step(32) == 0
        assert until(lambda: wifi.world.speeds == (300, 300))
        relay.drop_after_bytes = EVERY_FEW_PACKETS
        ended = None
        for step in range(300):  # 10 s of steps: the old code never ended
            if robot.step(32) == -1:
                ended = step
                break
        assert ended is not None, f"still reconnecting after {relay.drops} drops"
        assert robot.channel.stats.reconnects == POLICY.max_drops
        assert relay.drops == POLICY.max_drops + 1
    finally:
        relay.drop_after_bytes = None
        robot.close()
    assert until(lambda: wifi.world.speeds == (0, 0))  # the stop went through at close
    drops = [r for r in caplog.records if "connection lost" in r.getMessage()]
    assert len(drops) == 1 and drops[0].levelno == logging.WARNING  # then summarised
    lost = [r.getMessage() for r in caplog.records if "reconnects do not hold" in r.getMessage()]
    assert lost and f"{relay_url}: the connection dropped 6 times within 30 s" in lost[0]


def test_the_tally_backs_off_gives_up_and_summarises() -> None:
    tally = DropTally(DropPolicy(max_drops=3, window_s=10.0, summary_s=5.0))
    first = tally.dropped(100.0, "reset")
    assert (first.backoff_s, first.give_up) == (0.0, False)
    assert first.warning == "connection lost (reset); reconnecting"
    second, third = tally.dropped(101.0, "reset"), tally.dropped(102.0, "reset")
    assert (second.backoff_s, third.backoff_s) == (0.05, 0.1)
    assert second.warning is None and third.warning is None  # counted, told later
    assert tally.dropped(103.0, "reset").give_up
    assert "dropped 4 times within 10 s (more than 3)" in tally.give_up_message("reset")


def test_drops_further_apart_than_the_window_never_end_the_link() -> None:
    tally = DropTally(DropPolicy(max_drops=2, window_s=10.0, summary_s=30.0))
    verdicts = [tally.dropped(t, "reset") for t in (0.0, 6.0, 17.0, 28.0, 39.0)]
    assert not any(v.give_up for v in verdicts) and tally.total == 5
    assert [v.warning is not None for v in verdicts] == [True, False, False, False, True]
    assert verdicts[4].warning is not None and "(3 more drops since the last" in verdicts[4].warning
    assert max(v.backoff_s for v in verdicts) == 0.05


def test_the_backoff_doubles_up_to_its_cap() -> None:
    tally = DropTally(DropPolicy(max_drops=10, first_backoff_s=0.1, max_backoff_s=0.5))
    backoffs = [tally.dropped(float(t), "x").backoff_s for t in range(7)]
    assert backoffs == [0.0, 0.1, 0.2, 0.4, 0.5, 0.5, 0.5]
