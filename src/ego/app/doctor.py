"""``ego doctor``: what the troubleshooting guide asks, checked on the robot's own board.

Each check gives one line: ``ok``, ``note`` (works, but read this) or ``fail`` (a
controller cannot run until it is fixed), each with what to do. The command's status is
0 when no check failed. The firmware probe opens the port as every ego program does
(``V``, then ``C`` and ``b`` on the stock firmware): it moves nothing.
"""

from __future__ import annotations

import argparse
import grp
import importlib.metadata
import math
import os
import re
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, TextIO

Status = Literal["ok", "note", "fail"]

#: ego's own dependencies: import name, distribution names, minimum, how to get it on
#: Debian (the Overo and Pi-puck guides) and from PyPI.
REQUIRED = (
    ("numpy", ("numpy",), "1.24", "apt-get install python3-numpy"),
    ("PIL", ("pillow", "Pillow"), "9.4", "apt-get install python3-pil"),
    ("serial", ("pyserial",), "3.5", "apt-get install python3-serial"),
    ("smbus2", ("smbus2",), "0.4", "apt-get install python3-smbus2"),
)
#: The extras: import name, distribution names, minimum, what they are for, how to get it.
OPTIONAL = (
    ("cv2", ("opencv-python-headless", "opencv-python", "opencv"), "4.6",
     "faster camera (NumPy converts without it)", "apt-get install python3-opencv"),
    ("aiohttp", ("aiohttp",), "3.9", "--dashboard", "pip install 'ego[dashboard]'"),
    ("mcap", ("mcap",), "1.1", "--record, ego replay",
     "apt-get install python3-lz4 python3-zstandard; pip install 'ego[record]'"),
    ("zenoh", ("eclipse-zenoh",), "1.0", "swarms, ego serve --zenoh", "pip install 'ego[zenoh]'"),
)  # fmt: skip
#: Below this much available memory, a camera controller (about 100 MB with Debian's
#: OpenCV on the 32-bit board, docs/guide/overo.md) may not fit.
LOW_MEMORY_MB = 64


@dataclass(frozen=True)
class Line:
    """One check's outcome."""

    status: Status
    what: str
    said: str

    def __str__(self) -> str:
        return f"{self.status:<4}  {self.what}: {self.said}"


def version_tuple(text: str) -> tuple[int, ...]:
    """``"4.6.0+dfsg"`` -> ``(4, 6, 0)``: the leading numbers of a version."""
    return tuple(int(part) for part in re.findall(r"\d+", text.split("+")[0])[:3])


def _dist_version(module: object, names: tuple[str, ...]) -> str:
    for name in names:
        try:
            return importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            continue
    return str(getattr(module, "__version__", "?"))  # Debian's cv2 has no dist-info


def check_python(version: tuple[int, int, int] = sys.version_info[:3]) -> Line:
    shown = ".".join(map(str, version))
    if version < (3, 10):
        return Line("fail", "python", f"{shown}: ego needs 3.10 or later (Debian 12 has 3.11)")
    return Line("ok", "python", shown)


def _import(name: str) -> object | None:
    import importlib

    try:
        return importlib.import_module(name)
    except ImportError:
        return None


def check_required() -> Iterator[Line]:
    for name, dists, least, remedy in REQUIRED:
        module = _import(name)
        if module is None:
            yield Line("fail", dists[0], f"not installed: {remedy}")
            continue
        found = _dist_version(module, dists)
        if version_tuple(found) < version_tuple(least):
            yield Line("fail", dists[0], f"{found} is older than {least}: {remedy}")
        else:
            yield Line("ok", dists[0], found)


def check_optional() -> Iterator[Line]:
    for name, dists, least, purpose, remedy in OPTIONAL:
        module = _import(name)
        if module is None:
            yield Line("note", dists[0], f"not installed (only for {purpose}): {remedy}")
            continue
        found = _dist_version(module, dists)
        if version_tuple(found) < version_tuple(least):
            yield Line("note", dists[0], f"{found} is older than {least}, tested: {remedy}")
        elif name == "cv2":
            yield _check_opencv(found)
        else:
            yield Line("ok", dists[0], f"{found} ({purpose})")
    yield check_flush_to_zero()


def _check_opencv(found: str) -> Line:
    from ego.camera.convert import opencv_is_exact

    if not opencv_is_exact():
        return Line("note", "opencv", f"{found} does not reproduce the thesis' colour tables: "
                    "ego converts with NumPy instead (exact, slower)")  # fmt: skip
    return Line("ok", "opencv", f"{found} (exact; the camera converts with it)")


def check_flush_to_zero() -> Line:
    """Whether the FPU flushes subnormals to zero in this process (after the imports above:
    the armv7 wheel of yarl, which aiohttp imports, sets the mode for the whole process)."""
    if math.ulp(0.0) == 0.0:
        return Line("note", "floats", "flush-to-zero is on (a compiled package set it; on armv7 "
                    "aiohttp's yarl): subnormals read as 0, which ego's arithmetic never needs")
    return Line("ok", "floats", "IEEE subnormals")


def _groups() -> set[str]:
    names = set()
    for gid in {*os.getgroups(), os.getegid()}:
        try:
            names.add(grp.getgrgid(gid).gr_name)
        except KeyError:
            continue
    return names


def _group_remedy(path: Path) -> str:
    try:
        group = grp.getgrgid(path.stat().st_gid).gr_name
    except KeyError:
        group = str(path.stat().st_gid)
    if group in _groups():
        return f"group {group} (yours) cannot read and write it: sudo chmod g+rw {path}"
    return f"not in group {group}: sudo usermod -aG {group} $USER, then log in again"


def holders(path: Path, proc: Path = Path("/proc")) -> list[str]:
    """``"PID NAME"`` of each process (that this user may see) with ``path`` open."""
    target = os.path.realpath(path)
    found = []
    for entry in proc.iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            fds = list((entry / "fd").iterdir())
            if any(os.path.realpath(fd) == target for fd in fds):
                found.append(f"{entry.name} {(entry / 'comm').read_text().strip()}")
        except OSError:
            continue
    return found


def check_port(port: str) -> Line:
    path = Path(port)
    if not path.exists():
        return Line("fail", "serial port", f"{port} does not exist: ls /dev/ttyS* /dev/ttyO*; "
                    "set EGO_PORT or --port (docs/guide/overo.md, section 1)")  # fmt: skip
    if not os.access(path, os.R_OK | os.W_OK):
        return Line("fail", "serial port", f"{port}: {_group_remedy(path)}")
    held = holders(path)
    if held and os.path.realpath(path).startswith("/dev/pts/"):
        # An emulator (ego sim) keeps its own end of the pseudo-terminal open.
        return Line("ok", "serial port", f"{port}, a pseudo-terminal served by {held[0]}")
    if held:
        return Line("fail", "serial port", f"{port} is held by {', '.join(held)}: stop it "
                    "(a getty: systemctl stop serial-getty@...; a controller: its service)")
    return Line("ok", "serial port", f"{port}, readable and writable, held by nobody")


def check_i2c(dev: Path = Path("/dev")) -> Line:
    buses = sorted(dev.glob("i2c-*"))
    if not buses:
        return Line("note", "i2c", "no /dev/i2c-*: the floor sensors and a rev-1.3 accelerometer "
                    "need the kernel's i2c-dev (modprobe i2c-dev)")  # fmt: skip
    names = " ".join(bus.name for bus in buses)
    refused = [bus for bus in buses if not os.access(bus, os.R_OK | os.W_OK)]
    if refused:
        return Line("note", "i2c", f"{names}; {refused[0]}: {_group_remedy(refused[0])}")
    return Line("ok", "i2c", f"{names}, readable and writable")


def check_cameras(dev: Path = Path("/dev")) -> Line:
    cameras = sorted(dev.glob("video*"))
    if not cameras:
        return Line("note", "camera", "no /dev/video*: camera.enable() will raise "
                    "CameraCaptureError (the kernel's driver is missing); all else works")
    return Line("ok", "camera", " ".join(camera.name for camera in cameras))


def check_memory(meminfo: Path = Path("/proc/meminfo")) -> Line:
    try:
        fields = dict(line.split(":", 1) for line in meminfo.read_text().splitlines())
        available = int(fields["MemAvailable"].split()[0]) // 1024
    except (OSError, KeyError, ValueError):
        return Line("note", "memory", f"cannot read {meminfo}")
    if available < LOW_MEMORY_MB:
        return Line("note", "memory", f"{available} MB available: a camera controller needs "
                    "about 100 MB with OpenCV; stop other services")  # fmt: skip
    return Line("ok", "memory", f"{available} MB available")


def check_firmware(port: str) -> Line:
    """Which firmware answers on ``port``: the handshake every ego program does."""
    import ego
    from ego.errors import EgoError

    try:
        with ego.Robot(port) as robot:
            info = robot.channel.info
    except EgoError as exc:
        return Line("fail", "firmware", f"{exc} (docs/guide/troubleshooting.md)")
    selector = "not reported" if info.selector is None else info.selector
    return Line("ok", "firmware", f"{info.firmware.value} ({info.profile.description}), "
                f"version {info.version}, selector {selector}")  # fmt: skip


def diagnose(port: str, probe: bool = True) -> list[Line]:
    """Every check, in the troubleshooting guide's order."""
    lines = [check_python(), *check_required(), *check_optional()]
    lines.append(port_line := check_port(port))
    lines += [check_i2c(), check_cameras(), check_memory()]
    if probe and port_line.status == "ok":
        lines.append(check_firmware(port))
    return lines


def run_doctor(port: str, probe: bool = True, out: TextIO | None = None) -> int:
    """Print each line; 0 when a controller can run, 1 when a check failed."""
    out = out or sys.stdout
    lines = diagnose(port, probe)
    for line in lines:
        print(line, file=out)
    failed = [line for line in lines if line.status == "fail"]
    verdict = "a controller can run" if not failed else f"{len(failed)} to fix first"
    print(f"ego doctor: {verdict}", file=out, flush=True)
    return 1 if failed else 0


def add_doctor_command(sub: Any) -> None:
    """``ego doctor [--port P] [--no-probe]`` on the ego command's subparsers."""
    doctor = sub.add_parser(
        "doctor", help="on the robot: check Python, the packages, the port, I2C, the camera, "
        "the firmware and memory; each line says ok or what to do",
    )  # fmt: skip
    doctor.add_argument("--port", default=None,
                        help="the robot's port (default $EGO_PORT, else /dev/ttyS0)")  # fmt: skip
    doctor.add_argument("--no-probe", action="store_true",
                        help="do not open the port to ask which firmware answers")  # fmt: skip
    doctor.set_defaults(func=_cmd_doctor)


def _cmd_doctor(args: argparse.Namespace) -> int:
    from ego.core.environment import read_environment

    port = args.port or read_environment().port or "/dev/ttyS0"
    return run_doctor(port, probe=not args.no_probe)
