"""Every delay the emulator models can be turned off (issue 27: benchmarks credit it to ego).

The dsPIC's modelled firmware time (M's I2C read, A's float maths, K's calibration) is
on by default, as the firmware spends it; ``Emulator(dspic_work=False)`` and ``ego sim
--no-dspic-work`` turn it off, so that a benchmark can tell ego's cost from the model's.
"""

from __future__ import annotations

import argparse
from typing import Any

import pytest

from ego.seam.batch import Request
from ego.seam.profile import Firmware
from ego.serial import Command, Link, SerialTransport
from ego.serial.profiles import PROFILES
from ego.serial.protocol import encode_batch
from firmware_sim import Dspic, Emulator, World
from firmware_sim.cli import add_arguments
from firmware_sim.dspic import WORK_S


def neg(letter: str) -> int:
    return (-ord(letter)) & 0xFF


def feed_batch(dspic: Dspic, *letters: str) -> float:
    """The modelled work of one batch of argument-less commands, from its record."""
    dspic.feed(bytes(neg(c) for c in letters) + b"\0")
    assert dspic.last_record is not None
    return dspic.last_record.work_s


def make(**variant: Any) -> Dspic:
    return Dspic(World(seed=3, noise=False), "webots", **variant)


def test_m_and_a_carry_their_modelled_work_by_default() -> None:
    assert feed_batch(make(), "M", "A", "N") == pytest.approx(WORK_S["M"] + WORK_S["A"])


def test_work_off_answers_m_and_a_with_no_modelled_time() -> None:
    assert feed_batch(make(work=False), "M", "A", "N") == 0.0


@pytest.mark.parametrize(("work", "deaf"), [(True, 1.5), (False, 0.0)])
def test_calibration_time_follows_the_switch(work: bool, deaf: float) -> None:
    emissions = make(work=work).feed(b"K\n")
    assert [e.deaf_s for e in emissions if e.deaf_s or e.after_s] == ([deaf] if deaf else [])


def test_emulator_option_reaches_the_dspic_and_its_history() -> None:
    requests = [Request(Command(neg(c))) for c in "MN"]
    batch = encode_batch(requests, PROFILES[Firmware.WEBOTS])
    with Emulator("webots", seed=1, dspic_work=False) as emu:
        link = Link(SerialTransport(emu.path), firmware="webots")
        try:
            link.exchange(batch)
        finally:
            link.close()
        assert emu.dspic.work is False
        assert [r.work_s for r in emu.history] == [0.0]


def test_sim_flag_turns_the_work_off() -> None:
    parser = argparse.ArgumentParser()
    add_arguments(parser)
    assert parser.parse_args([]).dspic_work is True
    assert parser.parse_args(["--no-dspic-work"]).dspic_work is False
