"""How Robot(port) finds its backend: the core's registry names no concrete backend, the
built-in ones register themselves by name when ``ego`` is imported (the composition
root), and each is imported only when a port of its scheme is first opened."""

from __future__ import annotations

import subprocess
import sys

import pytest

from ego.core import registry
from ego.errors import PortNotFoundError


def run_python(code: str) -> str:
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=60, check=True)  # fmt: skip
    return result.stdout.strip()


def test_importing_the_core_registers_the_built_in_backends_without_importing_them() -> None:
    out = run_python(
        "import sys\n"
        "from ego.core.registry import registered\n"
        "print(' '.join(registered()))\n"
        "print(any(m.startswith('ego.backends.') for m in sys.modules))"
    )
    schemes, imported = out.splitlines()
    assert {"serial", "tcp", "udp", "unix", "replay", "zenoh", "epuck2"} <= set(schemes.split())
    assert imported == "False"


def test_a_backend_registered_by_name_is_imported_at_first_use() -> None:
    out = run_python(
        "import sys\n"
        "from ego.core.registry import find_backend\n"
        "backend = find_backend('serial')\n"
        "print(type(backend).__module__, 'ego.backends.zenoh_remote' in sys.modules)"
    )
    assert out == "ego.backends.serial_line False"


def test_an_unknown_scheme_lists_the_known_ones() -> None:
    with pytest.raises(PortNotFoundError, match=r"no backend serves 'nowhere' ports.*serial"):
        registry.find_backend("nowhere")


def test_register_by_name_or_factory_replaces_the_other() -> None:
    # In a process of its own: the registry is the process's.
    out = run_python(
        "from ego.core import registry\n"
        "registry.register('extra', 'ego.backends.serial_line:SerialBackend')\n"
        "by_name = registry.find_backend('extra')\n"
        "registry.register('extra', lambda: by_name)\n"
        "print(registry.scheme_of('extra://x'), type(by_name).__name__,\n"
        "      registry.find_backend('extra') is by_name)"
    )
    assert out == "extra SerialBackend True"
