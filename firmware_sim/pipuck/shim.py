"""Build ``i2c_shim.c`` into an LD_PRELOAD library with the system's C compiler.

The shim is ``i2c_shim.h`` and three C files (descriptors and framing, ioctl, stat).
The library is cached under ``$XDG_CACHE_HOME/firmware_sim`` (``~/.cache`` without it),
named by a hash of the source and the compiler command, so an edited source is rebuilt
and an unchanged one is not. The build writes a temporary file and renames it into
place, so concurrent builds (test workers) never see half a library.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

__all__ = ["SOCKET_ENV", "SOURCES", "ShimBuildError", "build_shim", "cache_dir"]

_HERE = Path(__file__).parent
#: The shim's C sources; the first is its header, the others are compiled.
SOURCES = (_HERE / "i2c_shim.h", _HERE / "i2c_shim.c", _HERE / "i2c_shim_ioctl.c",
           _HERE / "i2c_shim_stat.c")  # fmt: skip
#: The variable the library reads the emulator's socket path from (i2c_shim.c).
SOCKET_ENV = "FIRMWARE_SIM_I2C_SOCKET"
CFLAGS = ("-shared", "-fPIC", "-O2", "-Wall", "-Wextra", "-Werror")
LIBS = ("-ldl", "-lpthread")


class ShimBuildError(RuntimeError):
    """No C compiler, or the shim did not compile (the compiler's message attached)."""


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "firmware_sim"


def build_shim(
    compiler: str = "gcc", sources: tuple[Path, ...] = SOURCES, cache: Path | None = None
) -> Path:
    """The path of the built library (in ``cache``, default :func:`cache_dir`),
    compiling ``sources`` (a header, then the C files, all in one folder) first if any
    changed."""
    cc = shutil.which(compiler)
    if cc is None:
        raise ShimBuildError(f"no C compiler ({compiler}) to build the I2C shim")
    text = b"".join(path.name.encode() + b"\0" + path.read_bytes() for path in sources)
    digest = hashlib.sha256(text + " ".join((cc, *CFLAGS, *LIBS)).encode()).hexdigest()
    out_dir = cache or cache_dir()
    target = out_dir / f"i2c_shim-{digest[:16]}.so"
    if target.exists():
        return target
    out_dir.mkdir(parents=True, exist_ok=True)
    fd, temp = tempfile.mkstemp(dir=out_dir, prefix=".i2c_shim-", suffix=".so")
    os.close(fd)
    try:
        proc = subprocess.run([cc, *CFLAGS, "-o", temp, *(str(p) for p in sources[1:]), *LIBS],
                              capture_output=True, text=True, check=False)  # fmt: skip
        if proc.returncode != 0:
            raise ShimBuildError(f"the I2C shim did not compile:\n{proc.stderr}")
        os.replace(temp, target)
    finally:
        if os.path.exists(temp):
            os.unlink(temp)
    return target
