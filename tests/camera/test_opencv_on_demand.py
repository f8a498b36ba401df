"""OpenCV is imported at first need: about 70 MB of a 256 MB board (Debian's build on the
emulated Overo), which ego's command line, its serial backend and a controller that never
converts a frame paid at start before (issue 34: every `ego run` imported it through the
parser's `ego serve` options)."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

from ego.camera.convert import opencv


def _modules_after(program: str) -> set[str]:
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(program)
                           + "\nimport sys\nprint(' '.join(sorted(sys.modules)))"],
                          capture_output=True, text=True, timeout=120, check=True)  # fmt: skip
    return set(done.stdout.split())


def test_the_command_line_and_a_controller_that_never_converts_a_frame_import_no_opencv() -> None:
    modules = _modules_after("""
        import ego
        from ego.app.cli import build_parser

        build_parser().parse_args(["run", "--port", "sim", "controller.py"])
        with ego.Robot("sim", seed=1, handle_signals=False) as robot:
            robot.proximity.enable(32)
            robot.step(32)
    """)
    assert "ego.camera" in modules  # the camera's modules are there, OpenCV is not
    assert "cv2" not in modules


@pytest.mark.skipif(opencv() is None, reason="OpenCV is not installed (ego[opencv])")
def test_the_first_conversion_imports_it() -> None:
    modules = _modules_after("""
        import ego.camera as camera
        assert "cv2" not in __import__("sys").modules
        camera.rgb565_to_rgb888(bytes(2 * 160 * 120), 160, 120)
    """)
    assert "cv2" in modules
