"""Stray bytes (the ``extra`` fault) reach the host with the byte before them and the
reply's tail, in one piece, however the emulator paces the rest of the reply: a dsPIC
sends its reply without a pause, so a host's trailing guard of a few bytes' time sees
them. Before, a reply went out in 4-byte writes, and an emulator thread held up between
two of them let the link take a stray byte for the reply's (firmware_sim.faults.Mangled).

The line runs at 9600 baud here, so that each 4-byte write is 4 ms apart and a reader
sees where the writes fall."""

from __future__ import annotations

import os
import select
import time

from firmware_sim import Emulator
from firmware_sim.dspic import BANNER

#: N (the eight proximity sensors): 16 bytes of reply.
PROXIMITY = bytes([(-ord("N")) & 0xFF, 0])
REPLY_SIZE = 16
#: Quiet this long after the last byte: the reply, at 9600 baud, is over.
QUIET_S = 0.2


def read_pieces(fd: int, wanted: int) -> list[bytes]:
    """What arrives on ``fd``, one entry per read, until ``wanted`` bytes and a quiet line."""
    pieces: list[bytes] = []
    got = 0
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        ready, _, _ = select.select([fd], [], [], QUIET_S)
        if not ready:
            if got >= wanted:
                return pieces
            continue
        piece = os.read(fd, 4096)
        pieces.append(piece)
        got += len(piece)
    raise AssertionError(f"{got} of at least {wanted} bytes in 10 s: {pieces!r}")


def test_stray_bytes_arrive_in_one_piece_with_the_replys_tail() -> None:
    for seed in range(1, 9):  # several draws of where the stray bytes fall
        with Emulator("webots", seed=seed, baud=9600) as emu:
            fd = os.open(emu.path, os.O_RDWR | os.O_NOCTTY)
            try:
                read_pieces(fd, len(BANNER))  # the welcome banner, whole
                emu.inject("extra", batch=emu.batches + 1)
                os.write(fd, PROXIMITY)
                pieces = read_pieces(fd, REPLY_SIZE + 1)
            finally:
                os.close(fd)
            received = b"".join(pieces)
            truth = emu.history[-1].reply
            assert emu.history[-1].faults == ["extra"] and len(truth) == REPLY_SIZE
            stray = len(received) - len(truth)
            assert 1 <= stray <= 4, received
            # Where the stray bytes start: the first byte that is not the reply's (or
            # the end, where they follow it).
            start = next((i for i in range(len(truth)) if received[i] != truth[i]), len(truth))
            ends = [sum(len(p) for p in pieces[: k + 1]) for k in range(len(pieces))]
            inside = [end for end in ends if max(0, start - 1) < end < len(received)]
            assert not inside, f"seed {seed}: reads ended at {ends}, stray bytes from {start}"
