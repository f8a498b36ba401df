"""A controller whose peak memory ``benchmarks.memory`` measures (run as its own process).

``python -m benchmarks._memory_controller PORT FRAMES WIDTH HEIGHT STEPS FOLDER`` opens the
robot on ``PORT`` (an emulator's pty), enables every sensor the firmware serves at 64 ms
and the camera at WIDTH x HEIGHT (frames replayed from the raw RGB565 file FRAMES), and
saves a JPEG into FOLDER every step for STEPS steps of 64 ms. It prints one JSON line:
peak resident memory (VmHWM, kB) after the imports, after opening the robot, and at the
end, with what it enabled.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

STEP_MS = 64


def peak_kb() -> int:
    """This process' peak resident set (VmHWM) in kB; ru_maxrss where /proc is missing."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:
        pass
    import resource

    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)


def main(argv: list[str]) -> int:
    port, frames, width, height, steps, folder = argv
    w, h, n = int(width), int(height), int(steps)
    import ego
    from ego.camera import FileReplaySource
    from ego.errors import UnsupportedDeviceError

    after_import = peak_kb()
    enabled: list[str] = []
    out = Path(folder) / "frame.jpg"
    with ego.Robot(
        port, camera_source=FileReplaySource(frames, w, h), handle_signals=False
    ) as robot:
        for family in robot.families:
            enable = getattr(family, "enable", None)
            if enable is None:  # actuators
                continue
            try:
                enable(STEP_MS)
            except UnsupportedDeviceError:
                continue
            enabled.append(family.family)
        camera = robot.camera
        camera.set_size(w, h)
        camera.enable(STEP_MS)
        after_open = peak_kb()
        done = 0
        for _ in range(n):
            if robot.step(STEP_MS) == -1:
                break
            camera.save_image(out, quality=90)
            done += 1
        jpeg_bytes = out.stat().st_size if done else 0
    result = {
        "after_import_kb": after_import,
        "after_open_kb": after_open,
        "peak_kb": peak_kb(),
        "steps": done,
        "overruns": robot.overruns,
        "enabled": enabled,
        "jpeg_bytes": jpeg_bytes,
    }
    print(json.dumps(result), flush=True)
    return 0 if done == n else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
