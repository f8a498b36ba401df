"""An emulated GCtronic e-puck2 in a firmware_sim world: its main processor's asercom v2
on a pty (USB, selector 8; Bluetooth, selector 3) or its radio's WiFi server on a TCP
port (selector 15). Written from the firmware sources (see sources.py), apart from ego.

>>> with Epuck2Emulator(world="arena", seed=1) as emu:  # doctest: +SKIP
...     serial.Serial(emu.pty_path)
>>> with Epuck2Emulator(wifi=True, port=0) as emu:  # doctest: +SKIP
...     socket.create_connection(emu.wifi_address)
"""

from __future__ import annotations

import threading
from types import TracebackType

from firmware_sim.epuck2.asercom2 import Asercom2
from firmware_sim.epuck2.radio import DEFAULT_PORT, Radio
from firmware_sim.epuck2.robot import Epuck2Robot
from firmware_sim.epuck2.serial_port import SerialPort
from firmware_sim.world import World

__all__ = ["BLUETOOTH_SELECTOR", "USB_SELECTOR", "WIFI_SELECTOR", "Epuck2Emulator"]

#: MAIN:src/main.c:214 (3: asercom v2 over Bluetooth), 541 (8: over USB), 836 (15: WiFi).
BLUETOOTH_SELECTOR = 3
USB_SELECTOR = 8
WIFI_SELECTOR = 15
#: MAIN:src/serial_comm.c:44-45: the F407's UART to the radio module.
UART_BAUD = 115200


class Epuck2Emulator:
    """An e-puck2 in ``world`` (a World, a built-in world's name or a world file).

    ``wifi``: serve the radio's TCP protocol on ``host``:``port`` (0 picks a free port;
    :attr:`wifi_address` says which) instead of a serial port; else ``bluetooth``
    chooses the Bluetooth link (paced at the UART's 115200 baud, plus ``latency_s`` each
    way) over USB (unpaced). The robot starts with its selector where the mode needs it.
    Every thread is started here and stopped and joined by :meth:`close`.
    """

    def __init__(
        self,
        world: World | str | None = None,
        *,
        seed: int | None = None,
        wifi: bool = False,
        bluetooth: bool = False,
        port: int = DEFAULT_PORT,
        host: str = "127.0.0.1",
        latency_s: float = 0.0,
        ground_module: bool = False,
        sd_card: bool = False,
        battery_v: float = 3.9,
    ) -> None:
        if wifi and bluetooth:
            raise ValueError("an e-puck2 runs WiFi (selector 15) or Bluetooth (3), not both")
        if isinstance(world, str):
            from firmware_sim.worlds import load_world

            world = load_world(world, seed)
        self.world = world or World(seed=seed)
        selector = WIFI_SELECTOR if wifi else BLUETOOTH_SELECTOR if bluetooth else USB_SELECTOR
        self.robot = Epuck2Robot(self.world, seed=seed, selector=selector,
                                 ground_module=ground_module, sd_card=sd_card,
                                 battery_v=battery_v)  # fmt: skip
        # Asercom2.c:104-108: the UART to the radio (use_bt) in 3 and 15, USB in 8.
        self.firmware = Asercom2(self.robot, use_bt=selector != USB_SELECTOR)
        self._lock = threading.RLock()
        self.radio: Radio | None = None
        self.serial: SerialPort | None = None
        if wifi:
            self.robot.imu.magnetometer_on = True  # main.c:852, before run_asercom2
            self.radio = Radio(self.firmware, self._lock, port=port, host=host)
            self.radio.start()
        else:
            baud = UART_BAUD if bluetooth else None
            self.serial = SerialPort(self.firmware, self._lock, baud=baud, latency_s=latency_s,
                                     blocking_writes=not bluetooth)  # fmt: skip
            self.serial.start()
        self._closed = False

    @property
    def pty_path(self) -> str | None:
        """The serial port's path (USB or Bluetooth), None in WiFi mode."""
        return self.serial.path if self.serial is not None else None

    @property
    def wifi_address(self) -> tuple[str, int] | None:
        """(host, port) of the radio's TCP server, None in a serial mode."""
        return self.radio.address if self.radio is not None else None

    def remote_key(self, data: int, address: int = 0) -> None:
        """A TV remote's RC5 key reaches the IR receiver; it is reported, it does not
        drive (see Asercom2.rc5)."""
        with self._lock:
            self.firmware.rc5(address, data)

    def close(self) -> None:
        """Stop and join every thread, close the port or socket; idempotent."""
        if self._closed:
            return
        self._closed = True
        if self.radio is not None:
            self.radio.close()
        if self.serial is not None:
            self.serial.close()

    def __enter__(self) -> Epuck2Emulator:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def serve_forever(self, stop: threading.Event) -> None:
        """Block until ``stop`` is set (the command line's main thread)."""
        stop.wait()
