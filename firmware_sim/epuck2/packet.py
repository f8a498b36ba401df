"""The two block commands of asercom v2: -0x08 "get all sensors" (a 103-byte reply) and
-0x09 "set all actuators" (a 19-byte payload), MAIN:src/epuck1x/Asercom2.c:296-572.

All multi-byte fields go low byte first (``n & 0xff`` then ``n >> 8``), whatever the
"big endian" comment at Asercom2.c:292 says; floats as their IEEE bits, low byte first.
"""

from __future__ import annotations

import struct

from firmware_sim.epuck2.imu import e_acc_spheric
from firmware_sim.epuck2.motors import uint16
from firmware_sim.epuck2.robot import Epuck2Robot
from firmware_sim.epuck2.state import FirmwareState

__all__ = ["ACTUATORS_SIZE", "ALL_SENSORS_SIZE", "all_sensors", "set_all_actuators"]

ALL_SENSORS_SIZE = 103
ACTUATORS_SIZE = 19


def _u16s(values: list[int] | tuple[int, ...]) -> bytes:
    return b"".join(struct.pack("<H", uint16(v)) for v in values)


def all_sensors(robot: Epuck2Robot) -> bytes:
    """Asercom2.c:296-468, field by field (the line numbers of each are in PROTOCOL_NOTES)."""
    acc = robot.imu.e_get_acc()  # 297-312
    out = bytearray(_u16s(acc))
    out += struct.pack("<3f", *e_acc_spheric(*acc))  # 314-346: magnitude, orientation, incl.
    out += _u16s(robot.imu.gyro())  # 348-364
    out += struct.pack("<3f", *robot.imu.magnetic_field())  # 366-374
    out += struct.pack("<b", robot.imu.temperature())  # 376-381
    out += _u16s(robot.proximity.calibrated())  # 383-388
    out += _u16s(robot.proximity.ambient())  # 390-395
    out += _u16s([robot.tof.distance_mm()])  # 397-405
    out += _u16s(robot.microphones.volumes())  # 407-419: mic0..mic3
    out += _u16s(robot.steps())  # 421-427
    out += _u16s([robot.battery.raw()])  # 429-432
    out.append(1 if robot.sd_card else 0)  # 434-441: !sdio_connect() when a card is in
    out += bytes(robot.rc5)  # 443-446: check, address, data
    out.append(robot.selector & 0xFF)  # 448-450
    out += _u16s(robot.ground.delta()[:3])  # 452-457
    out += _u16s(robot.ground.ambient()[:3])  # 459-464
    out.append(0)  # 466-467: "additional empty byte for future use"
    assert len(out) == ALL_SENSORS_SIZE
    return bytes(out)


def set_all_actuators(robot: Epuck2Robot, state: FirmwareState, payload: bytes) -> None:
    """Asercom2.c:492-571 on ``rx_buff[0..18]``."""
    settings = payload[0]
    if settings & 0x01:  # 493-495: calibrate_ir
        robot.proximity.calibrate()
    robot.obstacle_avoidance = bool(settings & 0x02)  # 496-500
    # 503-504: assembled as unsigned, so E later prints 65336 for -200.
    state.speedl = payload[1] + (payload[2] << 8)
    state.speedr = payload[3] + (payload[4] << 8)
    if settings & 0x04:  # 506-508: set the step counters, leave the speeds
        robot.set_steps(state.speedl, state.speedr)
    else:  # 510-511
        robot.set_speeds(state.speedl, state.speedr)
    leds = payload[5]  # 515-544
    for i in range(4):
        robot.leds.set_led(i, 1 if leds & (1 << i) else 0)
    robot.leds.set_body_led(1 if leds & 0x10 else 0)
    robot.leds.set_front_led(1 if leds & 0x20 else 0)
    for i in range(4):  # 547-550: LED2, 4, 6, 8 as R, G, B
        robot.leds.set_rgb_led(i, *payload[6 + 3 * i : 9 + 3 * i])
    sound = payload[18]  # 553-571: each bit plays; 0x20 stops
    for bit, number in ((0x01, 1), (0x02, 2), (0x04, 3), (0x08, 4), (0x10, 5)):
        if sound & bit:
            robot.play(number)
    if sound & 0x20:
        robot.stop_sound()
