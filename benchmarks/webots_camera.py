"""The Webots face's camera calls: getImageArray and getImage at 52x39 (Webots' e-puck size),
160x120 and 640x480, on the emulator's rendered camera, interleaved in one run.

Targets (issue 13): getImageArray under 1 ms at 52x39 and under 20 ms at 640x480.
"""

from __future__ import annotations

import argparse
import sys

from benchmarks.common import Table, interleaved, print_and_save

__all__ = ["main", "run"]

SIZES = ((52, 39), (160, 120), (640, 480))


def table(repeats: int) -> Table:
    from ego.controller import Robot
    from ego.faces import default_robot, runtime

    result = Table(
        key="webots_camera",
        title=f"Webots face camera calls, {repeats} calls each, interleaved (one frame per size)",
        columns=["size", "call", "median [ms]", "min", "max", "target [ms]"],
    )
    for width, height in SIZES:
        options = runtime.RunOptions(port="sim", seed=1, camera_size=(width, height))
        with default_robot.activate(default_robot.FaceContext(options)):
            robot = Robot()
            try:
                camera = robot.getDevice("camera")
                assert camera is not None
                camera.enable(32)
                robot.step(32)
                stats = interleaved(
                    {"getImageArray": camera.getImageArray, "getImage": camera.getImage},
                    repeats=repeats,
                )
            finally:
                robot.cleanup()
        target = {52: 1.0, 640: 20.0}.get(width, "-")
        for call, s in stats.items():
            result.rows.append(
                [f"{width}x{height}", call, s.median * 1e3, s.low * 1e3, s.high * 1e3,
                 target if call == "getImageArray" else "-"]
            )  # fmt: skip
    return result


def run(quick: bool = False) -> list[Table]:
    return [table(20 if quick else 200)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run: few calls")
    args = parser.parse_args(argv)
    print_and_save(run(quick=args.quick), args.quick)
    return 0


if __name__ == "__main__":
    sys.exit(main())
