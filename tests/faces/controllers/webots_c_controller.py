"""A controller written against the Webots C API names (appendix B), with integer tags.

It runs until ``ego run --duration`` ends it and writes what it saw as JSON to argv[1], or
to $EGO_TEST_RESULT.
"""

import json
import os
import sys

from ego.webots import wb_differential_wheel_enable_encoders as enable_encoders
from ego.webots import (
    wb_differential_wheels_get_left_encoder,
    wb_differential_wheels_set_speed,
    wb_distance_sensor_enable,
    wb_distance_sensor_get_value,
    wb_led_set,
    wb_robot_cleanup,
    wb_robot_get_device,
    wb_robot_init,
    wb_robot_step,
)

TIME_STEP = 32

wb_robot_init()
ps0 = wb_robot_get_device("ps0")
led = wb_robot_get_device("led3")
wb_distance_sensor_enable(ps0, TIME_STEP)
enable_encoders(TIME_STEP)
wb_led_set(led, 1)
wb_differential_wheels_set_speed(200, 200)

steps = 0
value = encoder = float("nan")
while wb_robot_step(TIME_STEP) != -1:
    steps += 1
    if steps > 500:  # ego run --duration must end the loop long before
        break
    value = wb_distance_sensor_get_value(ps0)
    encoder = wb_differential_wheels_get_left_encoder()
wb_robot_cleanup()

path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump({"steps": steps, "ps0": value, "left_encoder": encoder, "tags": [ps0, led]}, out)
