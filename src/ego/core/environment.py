"""The process environment's settings for ego: the one module that reads ``os.environ``.

As python-can's ``load_environment_config``, :func:`read_environment` reads every ``EGO_*``
variable ego honours, once, at the edge (a ``Robot`` opened without one, ``ego run``, ``ego
serve``, a face's context), into an :class:`Environment` that is passed down; the library
below takes parameters and never reads the environment itself. Tests build an
``Environment`` (or hand :func:`read_environment` a mapping) instead of patching
``os.environ``.

=====================  ======================================================================
variable               what it sets
=====================  ======================================================================
``EGO_PORT``           the port a Robot opens when none is named (else ``/dev/ttyS0``)
``EGO_CAMERA``         a serial robot's V4L2 camera device, or ``none`` (else ``/dev/video0``)
``EGO_SYSFS``          where sysfs is mounted, for a Pi-puck's battery ADC (else ``/sys``)
``EGO_SECRET_FILE``    the file holding a served robot's shared secret (wins over EGO_SECRET)
``EGO_SECRET``         the shared secret itself
``EGO_RADIO``          ``none``: robots get no Webots radio (Emitter, Receiver)
``EGO_ZENOH_CONNECT``  Zenoh endpoints to connect to, comma-separated
``EGO_ZENOH_LISTEN``   Zenoh endpoints to listen on, comma-separated
``EGO_ZENOH_CONFIG``   a Zenoh JSON5 configuration file
=====================  ======================================================================

Writing the environment of a child process (``ego swarm``'s controllers, ``ego run``'s
supervised controller) is not reading it, and happens where those processes start.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["VARIABLES", "Environment", "read_environment"]

#: Every environment variable ego reads (here, and nowhere else).
VARIABLES = (
    "EGO_PORT",
    "EGO_CAMERA",
    "EGO_SYSFS",
    "EGO_SECRET_FILE",
    "EGO_SECRET",
    "EGO_RADIO",
    "EGO_ZENOH_CONNECT",
    "EGO_ZENOH_LISTEN",
    "EGO_ZENOH_CONFIG",
)


@dataclass(frozen=True)
class Environment:
    """What the environment says; each field None (or empty) where it says nothing.

    The default ``Environment()`` is an empty environment: what a test or an embedding
    application passes to keep the process's variables out.
    """

    #: ``EGO_PORT``: the port to open when none is named.
    port: str | None = None
    #: ``EGO_CAMERA``: a V4L2 device path, or "none".
    camera: str | None = None
    #: ``EGO_SYSFS``: where sysfs is mounted (a Pi-puck's battery; an emulator's files).
    sysfs: str | None = None
    #: ``EGO_SECRET_FILE``: a path to the shared secret of a served robot.
    secret_file: str | None = None
    #: ``EGO_SECRET``: the shared secret itself (EGO_SECRET_FILE wins when both are set).
    secret: str | None = None
    #: ``EGO_RADIO`` is not "none": robots get a Webots radio (when zenoh is installed).
    radio: bool = True
    #: ``EGO_ZENOH_CONNECT``: endpoints to connect to.
    zenoh_connect: tuple[str, ...] = ()
    #: ``EGO_ZENOH_LISTEN``: endpoints to listen on.
    zenoh_listen: tuple[str, ...] = ()
    #: ``EGO_ZENOH_CONFIG``: a Zenoh configuration file.
    zenoh_config: str | None = None

    def load_secret(self) -> bytes | None:
        """The secret ``EGO_SECRET_FILE`` holds (checked as ``--secret-file`` is), else
        ``EGO_SECRET``'s, else None."""
        from ego.net.auth import coerce_secret, load_secret

        if self.secret_file:
            return load_secret(self.secret_file)
        return coerce_secret(self.secret)


def read_environment(environ: Mapping[str, str] | None = None) -> Environment:
    """The settings in ``environ`` (None: this process's ``os.environ``, read now)."""
    env = os.environ if environ is None else environ
    return Environment(
        port=env.get("EGO_PORT") or None,
        camera=env.get("EGO_CAMERA") or None,
        sysfs=env.get("EGO_SYSFS") or None,
        secret_file=env.get("EGO_SECRET_FILE") or None,
        secret=env.get("EGO_SECRET"),
        radio=env.get("EGO_RADIO") != "none",
        zenoh_connect=_split(env.get("EGO_ZENOH_CONNECT")),
        zenoh_listen=_split(env.get("EGO_ZENOH_LISTEN")),
        zenoh_config=env.get("EGO_ZENOH_CONFIG") or None,
    )


def _split(text: str | None) -> tuple[str, ...]:
    return tuple(part.strip() for part in (text or "").split(",") if part.strip())
