"""A controller written against the E-GO functions of appendix C (``ego.overo``).

It runs until ``ego run --duration`` ends it and writes what it saw as JSON to argv[1], or
to $EGO_TEST_RESULT.
"""

import json
import os
import sys

from ego.overo import (
    overo_distance_sensors_enable,
    overo_distance_sensors_get_value,
    overo_encoders_enable,
    overo_encoders_get_left,
    overo_led_set,
    overo_motors_set_speed,
    overo_scheduler_local_get_time,
    overo_scheduler_robot_step,
    overo_serial_close,
    overo_serial_init,
)

TIME_STEP = 32

overo_serial_init(230400, None)  # None: the port that ego run was given
overo_distance_sensors_enable("ps7", TIME_STEP)
overo_encoders_enable("left wheel sensor", TIME_STEP)
overo_led_set("led1", 1)
overo_motors_set_speed("left wheel motor", 250, 250)

steps = 0
value = encoder = now = float("nan")
while overo_scheduler_robot_step(TIME_STEP) != -1:
    steps += 1
    if steps > 500:  # ego run --duration must end the loop long before
        break
    value = overo_distance_sensors_get_value("ps7")
    encoder = overo_encoders_get_left()
    now = overo_scheduler_local_get_time()
overo_serial_close()

path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump({"steps": steps, "ps7": value, "left_encoder": encoder, "time": now}, out)
