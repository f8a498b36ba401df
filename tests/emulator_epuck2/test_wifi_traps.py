"""The radio's traps, on real loopback sockets (ESP:Projects/ESP32_E-Puck_2/main/
socket_e-puck2.c:118-279): the wedge, the split first command, the wrong-id packet after
a valid one, the second client in the backlog, and the stop lost at close."""

from __future__ import annotations

import fcntl
import socket
import struct
import termios
import time

from epuck2_wire import WifiClient, command
from helpers import wait_for_more, wait_until

from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.epuck2.radio import Radio

ACCEPT, READ = 2, 3


def _unread(sock: socket.socket) -> int:
    """The bytes waiting in ``sock``'s receive queue (FIONREAD)."""
    return int(struct.unpack("i", fcntl.ioctl(sock.fileno(), termios.FIONREAD, b"\0" * 4))[0])


def _unsent(sock: socket.socket) -> int:
    """The bytes ``sock`` has queued to send that its peer has not taken (TIOCOUTQ)."""
    return int(struct.unpack("i", fcntl.ioctl(sock.fileno(), termios.TIOCOUTQ, b"\0" * 4))[0])


def _radio_took_all(radio: Radio) -> bool:
    """Whether the radio has read every byte its client sent so far (ground truth: its
    end of the connection holds none unread)."""
    client = radio._client
    return client is not None and _unread(client) == 0


def test_a_peer_that_leaves_before_a_valid_command_wedges_the_radio(
    wifi: Epuck2Emulator,
) -> None:
    # 164-178: recv returns 0 at the end of the stream, the MSG_WAITALL recv returns 0
    # too, no command is valid, so nothing is ever sent and state 3 never ends.
    radio, address = wifi.radio, wifi.wifi_address
    assert radio is not None and address is not None
    probe = socket.create_connection(address)
    assert radio.wait_for(READ, 5.0)
    probe.close()
    late = WifiClient(address)  # the listen backlog still completes the handshake
    try:
        late.send(command(0))
        # 40 of its loops, each one a chance to answer or to go back to accept().
        assert wait_for_more(lambda: radio.loops, 40), (
            f"the radio stopped looping: state {radio.state}, accepted {radio.accepted}"
        )
        assert late.nothing_pending()
        assert (radio.accepted, radio.state) == (1, READ), "it never goes back to accept()"
    finally:
        late.close()


def test_a_split_first_command_never_counts(wifi: Epuck2Emulator, client: WifiClient) -> None:
    # 174-178: a short read is completed with MSG_WAITALL but valid_cmd_received stays 0.
    packet = command(0, left=300, right=300)
    client.send(packet[:10])
    assert wifi.radio is not None
    assert wait_until(lambda: _radio_took_all(wifi.radio))  # a short read of the first part
    client.send(packet[10:])
    assert wait_for_more(lambda: wifi.radio.loops, 20)  # 20 chances to answer
    assert client.nothing_pending()
    assert wifi.world.speeds == (0, 0)
    client.send(packet)
    assert client.reply() == (0x03, b"")
    client.drain(0.1)
    assert wifi.world.speeds == (300, 300)


def test_after_a_valid_command_a_wrong_id_is_applied(
    wifi: Epuck2Emulator, client: WifiClient
) -> None:
    client.send(command(0))
    client.reply()
    client.send(command(0, left=250, right=-250, packet_id=0x00))
    for _ in range(4):  # read in the next loop, handed on after that loop's reply
        client.reply()
    assert wifi.world.speeds == (250, -250)


def test_a_second_client_waits_in_the_backlog(wifi: Epuck2Emulator, client: WifiClient) -> None:
    address, radio = wifi.wifi_address, wifi.radio
    assert address is not None
    client.send(command(0))
    client.reply()
    second = WifiClient(address)  # not refused: it waits in the backlog
    try:
        second.send(command(0, left=123, right=123))
        assert radio is not None
        assert wait_for_more(lambda: radio.loops, 20)  # 20 chances to take it
        assert second.nothing_pending()
        client.send(command(0))
        client.drain(0.1)
        client.close()
        assert second.reply() == (0x03, b"")
        second.drain(0.1)
        assert wifi.world.speeds == (123, 123)
    finally:
        second.close()


def test_a_stop_sent_just_before_closing_is_lost(wifi: Epuck2Emulator) -> None:
    # 199-276: states 4, 5 and 6 send before the next read, and a send error goes back
    # to accept() without reading; state 6 even sends its 0x03 before
    # uart_get_data_ptr hands a command it has read to the main processor. Whichever
    # state the reset finds, the stop never reaches the motors.
    radio, address = wifi.radio, wifi.wifi_address
    assert radio is not None and address is not None
    for trial in range(4):
        c = WifiClient(address)
        c.send(command(0, left=400 + trial, right=400 + trial))
        c.reply()
        # The 0x03 replies pile up unread: closing resets the connection.
        assert wait_until(lambda c=c: _unread(c.sock) >= 3)
        c.send(command(0))
        c.close()
        assert radio.wait_for(ACCEPT, 5.0)
        assert wifi.world.speeds == (400 + trial, 400 + trial)
        time.sleep(0.013 * trial)  # a pace: meet the radio's 10 ms loop at another phase


def test_a_stop_answered_before_closing_stops_the_robot(wifi: Epuck2Emulator) -> None:
    radio, address = wifi.radio, wifi.wifi_address
    assert radio is not None and address is not None
    c = WifiClient(address)
    c.send(command(0, left=400, right=400))
    c.reply()
    c.send(command(0))
    for _ in range(4):  # answers to loops after the one that read the stop
        c.reply()
    c.close()
    assert radio.wait_for(ACCEPT, 5.0)
    assert wifi.world.speeds == (0, 0)


def test_closing_frees_a_radio_stuck_in_a_split_command() -> None:
    from firmware_sim.world import World

    emu = Epuck2Emulator(World(seed=5), wifi=True, port=0)
    assert emu.radio is not None and emu.wifi_address is not None
    c = WifiClient(emu.wifi_address)
    try:
        c.send(command(0)[:5])  # the radio now blocks in recv(..., MSG_WAITALL)
        assert emu.radio.wait_for(READ, 5.0)
        assert wait_until(lambda: _radio_took_all(emu.radio))  # and read what came
        emu.close()  # must stop and join its thread (the autouse check looks)
    finally:
        c.close()
        emu.close()


def test_closing_frees_a_radio_stuck_sending_to_a_client_that_does_not_read() -> None:
    from firmware_sim.world import World

    emu = Epuck2Emulator(World(seed=6), wifi=True, port=0)
    assert emu.wifi_address is not None
    c = WifiClient(emu.wifi_address)
    try:
        c.send(command(0x01))  # images stream while nobody reads: the send blocks
        assert emu.radio is not None
        # The client's window is full: the radio holds images it cannot hand over.
        assert wait_until(lambda: emu.radio._client is not None
                          and _unsent(emu.radio._client) > 0, 20)  # fmt: skip
        emu.close()
    finally:
        c.close()
        emu.close()
