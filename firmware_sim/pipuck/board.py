"""The Pi-puck board's own side: its bus numbering, the devices on its bus, and the
battery ADC as the kernel's drivers show it in sysfs.

* The Pi's bus 1 carries a PCA9548 mux at 0x70 whose channel 0 holds the board's
  devices, channel 1 the e-puck's, channels 2-7 the sensor boards
  (yorkrobotlab/pi-puck@9cb1a25 device-tree/pi-puck.dts:92-161). The kernel numbers the
  channels 11, 12, ... on the RPi Zero 2 era kernels and 3, 4, ... on the older ones
  (YPP python-library/pipuck/epuck.py:7-8; gctronic/Pi-puck@73b8913
  e-puck2/e-puck2_test.py:5-6; battery/read-battery.py:4-9 for 11-0048 and 3-0048)
  [channels 2-7 as 13-18 and 5-10: inferred from the same order].
* On the board's bus: the FT903 at 0x1C (spec section 2.1) and the ADS1015 ADC at 0x48,
  bound to the kernel's ads1015 driver (pi-puck.dts:104-119), so ``I2C_SLAVE`` on it is
  EBUSY. The mux at 0x70 is bound to its driver too.
* The battery: ADC channel 4 (AIN0) is the e-puck's battery through a halving divider,
  channel 5 (AIN1) an auxiliary battery, both at gain 1 (+-4.096 V, 2 mV a count;
  pi-puck.dts:109-118). Current kernels' iio driver shows
  ``/sys/bus/i2c/devices/11-0048/iio:device0/in_voltage{0,1}_{raw,scale}``, the older
  hwmon driver ``/sys/bus/i2c/drivers/ads1015/3-0048/in{4,5}_input`` in millivolts; a
  reader computes volts = raw * scale / 500 (read-battery.py:4-9, 40-48)
  [scale text "2.000000000": inferred from the iio driver's fractional-log2 format].
"""

from __future__ import annotations

from pathlib import Path

from firmware_sim.pipuck.registers import RegisterTarget

__all__ = ["BATTERY_SCALE_MV", "BUS_BASES", "Ft903", "battery_files", "channel_bus"]

#: Channel 0's bus number per numbering: "current" (RPi Zero 2 era), "legacy".
BUS_BASES = {"current": 11, "legacy": 3}
PI_BUS = 1
MUX_ADDRESS = 0x70
FT903_ADDRESS = 0x1C
ADC_ADDRESS = 0x48
#: mV a count at the ADS1015's gain 1 (4.096 V over 2048 counts).
BATTERY_SCALE_MV = 2.0


def channel_bus(numbering: str, channel: int) -> int:
    """The bus number of the mux's ``channel`` (0 board, 1 e-puck, 2-7 sensor boards)."""
    return BUS_BASES[numbering] + channel


class Ft903(RegisterTarget):
    """The FT903 microcontroller's I2C slave: registers that read back what was written
    [inferred: its register map is not modelled]."""


def battery_files(numbering: str, epuck_v: float, aux_v: float) -> dict[str, str]:
    """The sysfs files (relative paths) and their text for the two batteries."""
    adc_in = [volts / 2 for volts in (epuck_v, aux_v)]  # the divider halves it
    if numbering == "legacy":
        base = f"sys/bus/i2c/drivers/ads1015/{channel_bus(numbering, 0)}-0048"
        return {f"{base}/in{4 + i}_input": f"{round(v * 1000)}\n" for i, v in enumerate(adc_in)}
    base = f"sys/bus/i2c/devices/{channel_bus(numbering, 0)}-0048/iio:device0"
    files = {}
    for i, v in enumerate(adc_in):
        raw = max(-2048, min(2047, round(v * 1000 / BATTERY_SCALE_MV)))
        files[f"{base}/in_voltage{i}_raw"] = f"{raw}\n"
        files[f"{base}/in_voltage{i}_scale"] = f"{BATTERY_SCALE_MV:.9f}\n"
    return files


def write_battery(root: Path, numbering: str, epuck_v: float, aux_v: float) -> None:
    """Write the files under ``root`` (each replaced whole, never seen half written)."""
    for relative, text in battery_files(numbering, epuck_v, aux_v).items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        temp = path.with_name(path.name + ".new")
        temp.write_text(text)
        temp.replace(path)
