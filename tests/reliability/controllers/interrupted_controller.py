"""A controller that drives the robot with every LED on, then waits to be interrupted.

Usage: ego run --port PORT interrupted_controller.py FACE MODE   (FACE: webots, c, overo)
       python interrupted_controller.py plain MODE PORT
It prints "running" once it has stepped with the wheels turning and the LEDs on. MODE
"forever" then steps until the process is killed; MODE "raise" waits for a line on stdin
and raises, as a controller with a bug does.
"""

import sys

TIME_STEP = 32
LEDS = range(10)


def webots_face():
    from controller import Robot

    robot = Robot()
    for side, velocity in (("left", 2.0), ("right", -2.0)):
        motor = robot.getDevice(f"{side} wheel motor")
        motor.setPosition(float("inf"))
        motor.setVelocity(velocity)
    for i in LEDS:
        robot.getDevice(f"led{i}").set(1)
    return lambda: robot.step(TIME_STEP)


def c_face():
    from ego.webots import (
        wb_differential_wheels_set_speed,
        wb_led_set,
        wb_robot_get_device,
        wb_robot_init,
        wb_robot_step,
    )

    wb_robot_init()
    wb_differential_wheels_set_speed(300, -300)
    for i in LEDS:
        wb_led_set(wb_robot_get_device(f"led{i}"), 1)
    return lambda: wb_robot_step(TIME_STEP)


def overo_face():
    from ego.overo import (
        overo_led_set,
        overo_motors_set_speed,
        overo_scheduler_robot_step,
        overo_serial_init,
    )

    overo_serial_init(230400, None)  # None: the port ego run was given
    overo_motors_set_speed("left wheel motor", 300, -300)
    for i in LEDS:
        overo_led_set(f"led{i}", 1)
    return lambda: overo_scheduler_robot_step(TIME_STEP)


def run(step, mode):
    step()
    print("running", flush=True)
    if mode == "raise":
        sys.stdin.readline()
        raise RuntimeError("a bug in the controller")
    while step() != -1:
        pass


face, mode = sys.argv[1], sys.argv[2]
if face == "plain":
    import ego

    with ego.Robot(sys.argv[3]) as robot:
        robot.motors.set_speed(300, -300)
        for i in LEDS:
            robot.leds.set(i, 1)
        run(lambda: robot.step(TIME_STEP), mode)
else:
    run({"webots": webots_face, "c": c_face, "overo": overo_face}[face](), mode)
