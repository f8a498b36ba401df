"""The Overo's own I2C bus: the e-puck devices the stock firmware leaves to Linux.

In selector 10 GCtronic's firmware lets the Overo be the I2C master (docs/protocol.md,
"The Overo's own I2C bus"): the ground module and a rev 1.3's LSM330 accelerometer are
read over i2c-dev, beside the serial batch. :mod:`ego.i2c.bus` is the seam (the bus as a
small protocol, the real one on ``/dev/i2c-N`` through smbus2), :mod:`ego.i2c.chips` the
chips' registers as data and pure functions, :mod:`ego.i2c.side` the probing and the
per-step reads under one lock.
"""

from ego.i2c.bus import DEFAULT_I2C_BUS, I2CBus, SMBusI2C, i2c_bus_path
from ego.i2c.chips import CHIPS, Chip
from ego.i2c.side import OveroI2C

__all__ = ["CHIPS", "DEFAULT_I2C_BUS", "Chip", "I2CBus", "OveroI2C", "SMBusI2C", "i2c_bus_path"]
