"""Which firmware answers on a port: the first thing to run on a new robot or a new line.

    python examples/which_firmware.py /dev/ttyS0       # on the Overo
    python examples/which_firmware.py /dev/rfcomm0     # over Bluetooth

It opens the port as every ego program does (ego asks the dsPIC ``V``, then ``C`` and
``b`` on the stock firmware) and prints what answered, the selector, and the sensors
this firmware can serve on this line. It moves nothing.
"""

import sys

import ego
from ego.errors import UnsupportedDeviceError

port = sys.argv[1] if len(sys.argv) > 1 else None  # None: $EGO_PORT, else /dev/ttyS0
with ego.Robot(port) as robot:
    info = robot.channel.info
    print(f"port:     {robot.port}")
    print(f"firmware: {info.firmware.value} ({info.profile.description})")
    print(f"version:  {info.version}")
    print(f"selector: {'not reported' if info.selector is None else info.selector}")
    sensors = [robot.proximity, robot.light, robot.floor, robot.accelerometer]
    sensors += [robot.microphones, robot.battery]
    served, refused = [], []
    for family in sensors:
        try:
            family.enable(64)
        except UnsupportedDeviceError as exc:
            refused.append(f"{family.family}: {exc}")
        else:
            served.append(family.family)
    print(f"serves:   {', '.join(served)}")
    for line in refused:
        print(f"refuses:  {line}")
