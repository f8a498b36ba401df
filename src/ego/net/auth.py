"""The shared-secret handshake: HMAC-SHA256 challenge-response, the secret never on the wire.

The client sends a fresh nonce in HELLO; the server answers with its own nonce and a
session id. The client proves it knows the secret with
``HMAC(secret, "ego-remote-v1 client" | server nonce | client nonce | session)``, and the
server proves it too (a robot impostor cannot fake the reply) with the same MAC over
``"ego-remote-v1 server" | client nonce | server nonce | session``. Both nonces are
fresh for every connection, so a recorded handshake cannot be replayed, and proofs are
compared with :func:`hmac.compare_digest`.
"""

from __future__ import annotations

import hashlib
import hmac
import ipaddress
import logging
import os
import secrets
import stat

from ego.errors import InsecureSecretError

__all__ = [
    "NONCE_SIZE",
    "FailureThrottle",
    "check_proof",
    "client_proof",
    "coerce_secret",
    "is_loopback",
    "load_secret",
    "new_nonce",
    "new_secret",
    "server_proof",
    "write_secret",
]

log = logging.getLogger(__name__)

NONCE_SIZE = 32
_CLIENT = b"ego-remote-v1 client"
_SERVER = b"ego-remote-v1 server"


def new_nonce() -> bytes:
    return secrets.token_bytes(NONCE_SIZE)


def _mac(secret: bytes, label: bytes, first: bytes, second: bytes, session: int) -> bytes:
    message = label + first + second + session.to_bytes(4, "little")
    return hmac.new(secret, message, hashlib.sha256).digest()


def client_proof(secret: bytes, server_nonce: bytes, client_nonce: bytes, session: int) -> bytes:
    """What the client sends to show it knows ``secret``."""
    return _mac(secret, _CLIENT, server_nonce, client_nonce, session)


def server_proof(secret: bytes, client_nonce: bytes, server_nonce: bytes, session: int) -> bytes:
    """What the server sends back to show it knows ``secret`` too."""
    return _mac(secret, _SERVER, client_nonce, server_nonce, session)


def check_proof(expected: bytes, received: bytes) -> bool:
    """Constant-time comparison, so the time taken leaks nothing of the MAC."""
    return hmac.compare_digest(expected, received)


#: The shortest secret accepted: 128 bits of a random one resist any online guessing.
MIN_SECRET_BYTES = 16


def coerce_secret(secret: str | bytes | None) -> bytes | None:
    """The secret as bytes (text is UTF-8); None or empty means no secret.

    A secret shorter than MIN_SECRET_BYTES is refused (InsecureSecretError).
    """
    if secret is None:
        return None
    raw = secret.encode() if isinstance(secret, str) else bytes(secret)
    if raw and len(raw) < MIN_SECRET_BYTES:
        raise InsecureSecretError(
            f"a shared secret of {len(raw)} bytes is too short: use at least "
            f"{MIN_SECRET_BYTES} ('ego secret' makes one)"
        )
    return raw or None


def load_secret(path: str) -> bytes:
    """The secret in file ``path``, without its trailing newline.

    As ssh does with its keys, a file other users may read or write is refused, and so
    is anything but a regular file (a FIFO would hang the start-up, a directory is a
    slip of the path): ValueError for an empty file, InsecureSecretError for the rest.
    """
    # O_NONBLOCK: opening a FIFO must not wait for a writer before it can be refused.
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    if stat.S_ISDIR(os.fstat(fd).st_mode):
        os.close(fd)  # fdopen would say "Is a directory: 3", naming the descriptor
        raise InsecureSecretError(f"{path}: is a directory, not a secret file")
    with os.fdopen(fd, "rb") as f:
        info = os.fstat(f.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise InsecureSecretError(f"secret file {path!r} is not a regular file")
        if info.st_mode & (stat.S_IRWXG | stat.S_IRWXO):
            raise InsecureSecretError(
                f"secret file {path!r} is accessible by other users "
                f"(mode {stat.S_IMODE(info.st_mode):03o}): chmod 600 it"
            )
        raw = f.read(4096).strip()
    if not raw:
        raise ValueError(f"secret file {path!r} is empty")
    secret = coerce_secret(raw)
    assert secret is not None
    return secret


def new_secret() -> str:
    """A fresh random secret: 32 bytes from the system's generator, URL-safe text."""
    return secrets.token_urlsafe(32)


def write_secret(path: str) -> str:
    """Write a new secret to ``path`` (created with mode 600, never overwritten); it."""
    secret = new_secret()
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "w") as f:
        f.write(secret + "\n")
    return secret


def is_loopback(host: str) -> bool:
    """Whether ``host`` only reaches this machine (127.0.0.0/8, ::1, "localhost")."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False  # a name that may resolve anywhere: treat it as off loopback


class FailureThrottle:
    """How long a wrong proof's answer waits: the brake on online guessing (no I/O).

    Each source host's recent failures double its delay (``base_s``, then 2x, 4x...,
    at most ``max_s``), forgotten after ``window_s`` without one; the server answers
    failures one at a time, so that parallel connections cannot add their guesses up:
    at most ``1 / base_s`` wrong proofs a second in all, far fewer from any one host.
    A correct proof is never delayed.
    """

    def __init__(self, base_s: float = 0.2, max_s: float = 5.0, window_s: float = 60.0) -> None:
        self.base_s = base_s
        self.max_s = max_s
        self.window_s = window_s
        self._recent: dict[str, tuple[int, float]] = {}  # host -> (failures, last one)
        #: When the failure answered last is answered: the next one waits its turn.
        self._free_at = 0.0

    def failed(self, host: str, now_s: float) -> float:
        """Record a wrong proof from ``host``; how long to wait before answering it.

        Failures are answered one after the other: each waits for the one before it,
        then its own delay.
        """
        count, last = self._recent.get(host, (0, now_s))
        count = 1 if now_s - last > self.window_s else count + 1
        self._recent[host] = (count, now_s)
        if len(self._recent) > 4096:  # many hosts: forget the ones quiet for a window
            self._recent = {h: v for h, v in self._recent.items() if now_s - v[1] <= self.window_s}
        own = min(self.max_s, self.base_s * 2 ** (count - 1)) if self.base_s else 0.0
        self._free_at = max(now_s, self._free_at) + own
        return self._free_at - now_s
