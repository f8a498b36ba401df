"""The radio module's WiFi server: ESP:Projects/ESP32_E-Puck_2/main/socket_e-puck2.c,
socket_task, state by state on a real TCP socket (127.0.0.1 here), and the bridge to the
main processor (uart_e-puck2.c), which polls run_asercom2 with ``-0x08 -0x09 <19> 0``.

The loop keeps the firmware's order and its faults: nothing is sent before one valid
0x80 command has arrived whole; a peer that closes first leaves state 3 reading 0 bytes
for ever and the server never accepts again (the wedge); a split first command is never
valid; after a valid one, any packet is applied; the last command is re-applied every
loop; five or more queued commands are flushed to the last; and in states 4 and 6 the
reply is sent before the command reaches the main processor, so a send error loses it.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import logging
import socket
import struct
import termios
import threading
from collections import deque

from firmware_sim.epuck2.asercom2 import Asercom2
from firmware_sim.epuck2.camera import frame_rgb565_be
from firmware_sim.threads import OwnedThread

__all__ = ["ACTUATORS_BUFF_LEN", "DEFAULT_PORT", "Radio"]

log = logging.getLogger(__name__)

#: socket_e-puck2.c:27.
DEFAULT_PORT = 1000
#: socket_e-puck2.h:14.
ACTUATORS_BUFF_LEN = 21
#: socket_e-puck2.c:29-30: the image (160 x 120 RGB565) and the send chunk.
IMAGE_SIZE = 38400
SPI_PACKET_MAX_SIZE = 4092
#: uart_e-puck2.h:14-16.
UART_TX_BUFF_SIZE = 22
UART_RX_BUFF_SIZE = 104
RESPONSE_SIZE = 103
#: socket_e-puck2.c:279, vTaskDelay(10) at CONFIG_FREERTOS_HZ=1000 (sdkconfig:593).
LOOP_DELAY_S = 0.010
#: sdkconfig:682-683, CONFIG_TCP_SND_BUF_DEFAULT and CONFIG_TCP_WND_DEFAULT.
TCP_BUFFER = 5744


class Radio:
    """socket_task + the UART bridge over ``f407`` (a run_asercom2 in selector 15)."""

    def __init__(self, f407: Asercom2, lock: threading.RLock, *, port: int = DEFAULT_PORT,
                 host: str = "127.0.0.1") -> None:  # fmt: skip
        self.f407 = f407
        self._fw_lock = lock
        if not 0 <= port <= 0xFFFF:
            raise ValueError(f"TCP port {port} is outside 0..65535")
        self._server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            self._server.bind((host, port))
            self._server.listen(1)  # socket_e-puck2.c:110
        except OSError as exc:
            self._server.close()
            hint = " (ports below 1024 need privileges; 0 picks a free one)" if port < 1024 else ""
            raise OSError(f"cannot serve the e-puck2's WiFi on {host}:{port}: "
                          f"{exc.strerror}{hint}") from exc  # fmt: skip
        self.address: tuple[str, int] = self._server.getsockname()
        self._client: socket.socket | None = None
        self._stop = threading.Event()
        self._changed = threading.Condition()
        #: conn_state of socket_task (2 accept, 3 read a command, 4 image, 5 sensors,
        #: 6 empty reply); states 0 and 1 (joining the access point, opening the server)
        #: are done by the constructor.
        self.state = 2
        #: Connections accepted so far.
        self.accepted = 0
        #: socket_task's loops so far (ground truth: each is a chance to send or accept).
        self.loops = 0
        self._polls: deque[bytes] = deque(maxlen=10_000)
        self._polls_lock = threading.Lock()
        self._valid = False
        self._buff = bytearray(ACTUATORS_BUFF_LEN)
        self._last = bytearray(ACTUATORS_BUFF_LEN)
        self._tx = bytearray(UART_TX_BUFF_SIZE)
        self._tx[0], self._tx[1] = 0xF8, 0xF7  # uart_e-puck2.c:89-91
        self._filled = bytes(UART_RX_BUFF_SIZE)
        self._filled = self._poll()  # the bridge polls once at boot (uart_e-puck2.c:96)
        self._thread = OwnedThread(self._run, "epuck2-radio", stop=self.close)

    def start(self) -> None:
        self._thread.start()

    def close(self) -> None:
        """Stop socket_task and join it; the sockets are closed. Idempotent."""
        self._stop.set()
        client = self._client
        if client is not None:
            with contextlib.suppress(OSError):
                client.shutdown(socket.SHUT_RDWR)  # unblocks a MSG_WAITALL recv or a send
        with contextlib.suppress(OSError):
            self._server.shutdown(socket.SHUT_RDWR)
        try:
            self._thread.join()
        finally:
            for sock in (client, self._server):
                if sock is not None:
                    sock.close()

    def polls(self) -> list[bytes]:
        """Every 19-byte actuator payload the bridge has sent the main processor, oldest
        first (ground truth; the last 10,000)."""
        with self._polls_lock:
            return list(self._polls)

    def wait_for(self, state: int, timeout_s: float) -> bool:
        """Wait until socket_task is in ``state`` (for tests); whether it got there."""
        with self._changed:
            return self._changed.wait_for(lambda: self.state == state, timeout_s)

    # -- the loop -------------------------------------------------------------------

    def _run(self) -> None:
        steps = {2: self._accept, 3: self._receive, 4: self._send_image,
                 5: self._send_sensors, 6: self._send_empty}  # fmt: skip
        try:
            while not self._stop.is_set():
                steps[self.state]()
                self.loops += 1
                if self._stop.wait(LOOP_DELAY_S):
                    break
        except Exception:
            if not self._stop.is_set():
                log.exception("e-puck2 radio failed")
                raise

    def _go(self, state: int) -> None:
        with self._changed:
            self.state = state
            self._changed.notify_all()

    def _accept(self) -> None:  # state 2, socket_e-puck2.c:118-143
        self._valid = False
        try:
            client, _ = self._server.accept()
        except OSError:
            return  # closing
        client.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, TCP_BUFFER)
        client.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, TCP_BUFFER)
        self._client = client  # the previous one is never closed by the firmware either
        self.accepted += 1
        self._last[:] = bytes(ACTUATORS_BUFF_LEN)
        self._go(3)

    def _pending(self, client: socket.socket) -> int:
        buf = fcntl.ioctl(client.fileno(), termios.FIONREAD, b"\0\0\0\0")
        return int(struct.unpack("i", buf)[0])

    def _flush_queue(self, client: socket.socket) -> None:
        """socket_e-puck2.c:146-162: five or more commands queued: drop all but the last
        whole one (or all whole ones if a new one is arriving)."""
        queued = self._pending(client)
        if queued < ACTUATORS_BUFF_LEN * 5:
            return
        packets = queued // ACTUATORS_BUFF_LEN
        drop = packets - 1 if packets * ACTUATORS_BUFF_LEN == queued else packets
        for _ in range(drop):
            with contextlib.suppress(OSError):
                client.recv_into(self._buff, ACTUATORS_BUFF_LEN, socket.MSG_DONTWAIT)

    def _receive(self) -> None:  # state 3, socket_e-puck2.c:145-197
        client = self._client
        assert client is not None
        self._flush_queue(client)
        try:
            length = client.recv_into(self._buff, ACTUATORS_BUFF_LEN, socket.MSG_DONTWAIT)
        except BlockingIOError:
            length = -1  # error 11: no new command, carry on (166)
        except OSError as exc:
            if exc.errno != errno.EAGAIN:
                self._go(2)
                return
            length = -1
        if length == ACTUATORS_BUFF_LEN and self._buff[0] == 0x80:  # 171-173
            self._valid = True
            self._last[:] = self._buff
        elif length >= 0:  # 174-178: short or wrong id (or 0 at end of stream)
            view = memoryview(self._buff)[length:]
            with contextlib.suppress(OSError):
                client.recv_into(view, ACTUATORS_BUFF_LEN - length, socket.MSG_WAITALL)
            self._last[:] = self._buff
        if self._valid:  # 182-196
            self._tx[2:21] = self._last[2:21]  # uart_set_actuators_state
            request = self._last[1]
            if request == 0:
                self._go(6)
            elif request & 0x01:
                self._go(4)
            elif request & 0x02:
                self._go(5)

    def _send(self, data: bytes) -> bool:
        client = self._client
        assert client is not None
        try:
            client.sendall(data)
        except OSError:
            return False
        return True

    def _send_image(self) -> None:  # state 4, socket_e-puck2.c:199-238
        image = frame_rgb565_be(self.f407.robot.world, 160, 120, 640)  # spi_get_data_ptr(1)
        assert len(image) == IMAGE_SIZE
        if not self._send(b"\x01"):
            self._go(2)
            return
        for start in range(0, IMAGE_SIZE, SPI_PACKET_MAX_SIZE):
            if not self._send(image[start : start + SPI_PACKET_MAX_SIZE]):
                self._go(2)
                return
        if self._buff[1] & 0x02:  # 229: actuators_buff, not the last valid command
            self._go(5)
        else:
            self._uart_get_data_ptr()
            self._go(3)

    def _send_sensors(self) -> None:  # state 5, socket_e-puck2.c:240-264
        sensors = self._uart_get_data_ptr()  # before the send: the command goes through
        if not self._send(b"\x02") or not self._send(sensors):
            self._go(2)
            return
        self._go(3)

    def _send_empty(self) -> None:  # state 6, socket_e-puck2.c:266-276
        if not self._send(b"\x03"):
            self._go(2)  # before uart_get_data_ptr: this command never reaches the F407
            return
        self._uart_get_data_ptr()
        self._go(3)

    # -- the UART bridge (uart_e-puck2.c) ------------------------------------------------

    def _uart_get_data_ptr(self) -> bytes:
        """uart_e-puck2.c:49-71: hand out the buffer the last poll filled, and let the
        bridge poll again (with the actuators as they are now)."""
        filled, self._filled = self._filled, self._poll()
        return filled

    def _poll(self) -> bytes:
        """uart_e-puck2.c:96-154: send the 22-byte request, read 103 bytes, put the
        ESP32's button in byte 102 and the reserved byte after it."""
        payload = bytes(self._tx[2:21])
        with self._fw_lock:
            emissions = self.f407.feed(bytes(self._tx))
        with self._polls_lock:
            self._polls.append(payload)
        reply = b"".join(e.data for e in emissions)
        if len(reply) != RESPONSE_SIZE:
            log.warning("e-puck2 radio: the main processor answered %d bytes", len(reply))
            return self._filled
        button = 1 if self.f407.robot.button else 0
        return reply[:102] + bytes([button, reply[102]])
