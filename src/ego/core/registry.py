"""How ``Robot(port)`` finds its backend: by the port's URL scheme, in a registry that
names no concrete backend.

The built-in backends register themselves by name (``ego.backends``, which the package
``ego`` imports first, as the composition root); another package declares its own under
the ``ego.backends`` entry point group (the emulator's ``sim``), found on first use.
Choosing a concrete backend is so left to the packages that provide them, and the core
imports none. A port's options are bound and checked here, in :func:`bind_options`.
"""

from __future__ import annotations

import dataclasses
import importlib
import types
import typing
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, Union, get_args, get_origin

from ego.core.backend import Backend, BackendOptions, Opened
from ego.errors import BackendOptionError, PortNotFoundError

if TYPE_CHECKING:
    from importlib.metadata import EntryPoint

    from ego.core.environment import Environment

__all__ = [
    "ENTRY_POINT_GROUP",
    "Backend",
    "BackendOptions",
    "Opened",
    "bind_options",
    "find_backend",
    "open_port",
    "option_names",
    "register",
    "registered",
    "scheme_of",
    "takes_option",
]

#: Where packages declare backends: ``[project.entry-points."ego.backends"] sim = ...``.
ENTRY_POINT_GROUP = "ego.backends"

_REGISTRY: dict[str, Callable[[], Backend]] = {}
#: Backends registered by name (``"package.module:Class"``), imported when first used.
_NAMED: dict[str, str] = {}


def register(scheme: str, factory: Callable[[], Backend] | str) -> None:
    """Serve ``scheme://...`` ports with the backend ``factory()`` makes; ``factory`` may
    be ``"module:Class"``, imported only when a port of that scheme is first opened (so
    that zenoh or mcap load only for their own ports)."""
    if isinstance(factory, str):
        _REGISTRY.pop(scheme, None)
        _NAMED[scheme] = factory
    else:
        _NAMED.pop(scheme, None)
        _REGISTRY[scheme] = factory


def registered() -> tuple[str, ...]:
    """The schemes registered in this process (the built-in ones once ``ego`` is imported)."""
    return tuple(sorted({*_REGISTRY, *_NAMED}))


def scheme_of(port: str) -> str:
    """The backend scheme of a port: ``sim``, ``tcp``, ``udp``... or ``serial``."""
    if port in _REGISTRY or port in _NAMED or port == "sim":  # a bare name: "sim"
        return port
    if port.isidentifier() and _declared(port) is not None:  # "pipuck", declared
        return port
    scheme, sep, _ = port.partition("://")
    if sep and (scheme in _REGISTRY or scheme in _NAMED or _declared(scheme) is not None):
        return scheme
    return "serial"  # a path, or a URL pyserial handles (socket://, loop://, spy://)


def _declared(scheme: str) -> EntryPoint | None:
    # Imported here: importlib.metadata costs the Overo ~4 MB and is needed only for a
    # scheme that is not built in.
    from importlib.metadata import entry_points

    found = entry_points(group=ENTRY_POINT_GROUP, name=scheme)
    return next(iter(found), None)


def find_backend(scheme: str) -> Backend:
    """The backend for ``scheme``: built in, registered, or declared by an installed package."""
    factory = _REGISTRY.get(scheme)
    if factory is None:
        if scheme in _NAMED:
            module, _, name = _NAMED[scheme].partition(":")
            factory = getattr(importlib.import_module(module), name)
        else:
            declared = _declared(scheme)
            if declared is None:
                known = registered()
                raise PortNotFoundError(
                    f"no backend serves {scheme!r} ports: is the package that provides it "
                    f"installed? (known: {', '.join(known)})"
                )
            factory = declared.load()
        _REGISTRY[scheme] = factory
    return factory()


def option_names(port: str) -> tuple[str, ...]:
    """The options the backend of ``port`` declares, in its declaration's order."""
    return tuple(f.name for f in dataclasses.fields(find_backend(scheme_of(port)).options))


def takes_option(port: str, name: str) -> bool:
    """Whether the backend of ``port`` declares the option ``name`` (a served robot's
    backend takes ``secret``; the emulator's and a serial port's do not)."""
    return name in option_names(port)


def bind_options(
    port: str, given: Mapping[str, object], environment: Environment | None = None
) -> BackendOptions:
    """The options of ``port``'s backend, bound from ``given`` and checked, the
    environment's defaults filled in: the one place a port's options are checked.

    An option the backend does not declare raises BackendOptionError naming the scheme,
    the option and the options the scheme takes; a value of the wrong type raises
    BackendOptionError too (or the option's own checker's error: a baud rate's). A value
    of None is the backend's default, for every option, as if it were not given.
    """
    return _bind(scheme_of(port), find_backend(scheme_of(port)), given, environment)


def _bind(
    scheme: str, backend: Backend, given: Mapping[str, object], environment: Environment | None
) -> BackendOptions:
    declared = backend.options
    fields = {f.name: f for f in dataclasses.fields(declared)}
    unknown = sorted(set(given) - set(fields))
    if unknown:
        raise BackendOptionError(
            f"{scheme} ports take no option {unknown[0]!r} (they take: {', '.join(fields)})"
        )
    hints = _hints(declared)
    values: dict[str, Any] = {}  # each checked against its field's type above
    for name, value in given.items():
        if value is None:
            continue  # the backend's default
        checker = fields[name].metadata.get("check")
        if checker is not None:
            value = checker(value)  # its own error; the value to bind (a name's Firmware)
        elif not _fits(value, hints[name]):
            raise BackendOptionError(
                f"{scheme} option {name}={value!r} must be {_shown(hints[name])}, "
                f"not {type(value).__name__}"
            )
        values[name] = value
    if environment is None:
        from ego.core.environment import read_environment

        environment = read_environment()
    return declared(**values).with_environment(environment)


_HINTS: dict[str, dict[str, object]] = {}


def _hints(declared: type[BackendOptions]) -> dict[str, object]:
    """The resolved type of each option of ``declared`` (resolved once a class)."""
    key = f"{declared.__module__}.{declared.__qualname__}"
    if key not in _HINTS:
        _HINTS[key] = typing.get_type_hints(declared)
    return _HINTS[key]


def _fits(value: object, hint: object) -> bool:
    """Whether ``value`` is of the type ``hint`` names (the types options are declared
    with: classes, unions, Literal, sequences of a type)."""
    origin = get_origin(hint)
    if hint is Any or hint is object:
        return True
    if origin in (Union, types.UnionType):
        return any(_fits(value, arg) for arg in get_args(hint))
    if origin is typing.Literal:
        return value in get_args(hint)
    if origin is not None and isinstance(origin, type) and issubclass(origin, Sequence):
        if isinstance(value, str | bytes) or not isinstance(value, Sequence):
            return False
        args = [a for a in get_args(hint) if a is not Ellipsis]
        return all(_fits(item, args[0]) for item in value) if args else True
    if hint is float:
        return isinstance(value, int | float) and not isinstance(value, bool)
    if hint is int:
        return isinstance(value, int) and not isinstance(value, bool)
    return isinstance(value, hint) if isinstance(hint, type) else True


def _shown(hint: object) -> str:
    if isinstance(hint, type):
        return hint.__name__
    return str(hint).replace("typing.", "").replace("collections.abc.", "")


def open_port(port: str, *, environment: Environment | None = None, **options: object) -> Opened:
    """Open ``port`` with the backend its scheme names, with ``options`` bound and checked
    by :func:`bind_options` (``firmware`` for every backend: a Firmware, None to detect
    it). ``environment`` None: the process's (:func:`ego.core.environment.read_environment`).
    """
    scheme = scheme_of(port)
    backend = find_backend(scheme)
    return backend.open(port, _bind(scheme, backend, options, environment))
