"""The handshake of ``ego serve``, both sides, without I/O: cookies, proofs, the session key.

One exchange (docs/architecture.md, "Remote"):

1. The client says HELLO with a fresh nonce. Over UDP, a server that has not seen the
   client's address answers with a COOKIE only, keeping no state: a MAC of the address,
   the nonce and the time, under a key of its own (as DTLS does). The client says HELLO
   again with it. A forged source address never sees the cookie, so it can neither fill
   the server's table of pending handshakes nor use the server as an amplifier (a COOKIE
   is smaller than the HELLO that asked for it).
2. The server answers with its own nonce, a session id and, when it has a secret, its
   proof over both nonces: the client checks that proof *before* it proves anything
   itself, so an impostor that does not know the secret learns no proof from the client.
   A client that holds a secret refuses a server that offers no proof.
3. The client sends its proof; the server checks it (constant time) and welcomes the
   client in the first sealed frame.

Both sides then derive the session key with HKDF-SHA256 (RFC 5869): the secret as input
keying material, both nonces as salt, the session id in the info. Each frame of the
session is sealed with it (:class:`ego.net.frames.FrameKey`).
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
from dataclasses import dataclass, field

from ego.errors import AuthenticationError, FrameError, SecretRequiredError
from ego.net.auth import NONCE_SIZE, check_proof, client_proof, new_nonce, server_proof
from ego.net.frames import FrameKey
from ego.net.payloads import pack_json, unpack_json

__all__ = [
    "COOKIE_LIFETIME_S",
    "ClientHandshake",
    "CookieJar",
    "Hello",
    "parse_hello",
    "session_key",
]

#: How long a COOKIE stays good: long enough for a slow link's second HELLO.
COOKIE_LIFETIME_S = 10.0
_COOKIE_SIZE = 16


def session_key(secret: bytes, client_nonce: bytes, server_nonce: bytes, session: int) -> bytes:
    """HKDF-SHA256 (RFC 5869) of the secret, salted with both nonces, bound to the session."""
    prk = hmac.new(client_nonce + server_nonce, secret, hashlib.sha256).digest()
    info = b"ego-remote-v2 session key" + session.to_bytes(4, "little")
    return hmac.new(prk, info + b"\x01", hashlib.sha256).digest()


class CookieJar:
    """Stateless proof that a UDP client receives at its address."""

    def __init__(self, lifetime_s: float = COOKIE_LIFETIME_S) -> None:
        self._key = secrets.token_bytes(32)
        self.lifetime_s = lifetime_s

    def _cookie(self, address: str, nonce: bytes, epoch: int) -> bytes:
        message = address.encode() + b"|" + nonce + epoch.to_bytes(8, "little", signed=True)
        return hmac.new(self._key, message, hashlib.sha256).digest()[:_COOKIE_SIZE]

    def make(self, address: str, nonce: bytes, now_s: float) -> bytes:
        return self._cookie(address, nonce, int(now_s // self.lifetime_s))

    def check(self, cookie: bytes, address: str, nonce: bytes, now_s: float) -> bool:
        """Whether ``cookie`` was made for this address and nonce, this epoch or the last."""
        epoch = int(now_s // self.lifetime_s)
        return any(
            hmac.compare_digest(cookie, self._cookie(address, nonce, e)) for e in (epoch, epoch - 1)
        )


@dataclass(frozen=True, slots=True)
class Hello:
    nonce: bytes
    cookie: bytes = b""
    client: str = ""


def _hex(obj: dict[str, object], name: str, size: int | None = None) -> bytes:
    try:
        value = bytes.fromhex(str(obj.get(name, "")))
    except ValueError as exc:
        raise FrameError(f"field {name!r} is not hexadecimal: {exc}") from exc
    if size is not None and len(value) != size:
        raise FrameError(f"field {name!r} of {len(value)} bytes, expected {size}")
    return value


def parse_hello(payload: bytes) -> Hello:
    """A HELLO's nonce, cookie and client name; FrameError when malformed."""
    obj = unpack_json(payload)
    return Hello(_hex(obj, "nonce", NONCE_SIZE), _hex(obj, "cookie"), str(obj.get("client", "")))


def challenge(secret: bytes | None, hello: Hello, server_nonce: bytes, session: int,
              **extra: object) -> bytes:  # fmt: skip
    """The server's answer to HELLO: its nonce and, with a secret, its proof."""
    proof = server_proof(secret, hello.nonce, server_nonce, session) if secret else b""
    return pack_json(
        {"nonce": server_nonce.hex(), "auth": secret is not None, "proof": proof.hex(), **extra}
    )


def auth_proof(payload: bytes) -> bytes:
    """The proof an AUTH carries; FrameError when malformed."""
    return _hex(unpack_json(payload), "proof")


def client_proved(secret: bytes, hello: Hello, server_nonce: bytes, session: int,
                  proof: bytes) -> bool:  # fmt: skip
    return check_proof(client_proof(secret, server_nonce, hello.nonce, session), proof)


@dataclass
class ClientHandshake:
    """The client's side: HELLO, then checking the server's proof before giving its own."""

    secret: bytes | None
    where: str
    client: str = "ego"
    nonce: bytes = field(default_factory=new_nonce)
    cookie: bytes = b""
    #: What the server said in its challenge (deadline_s, server version...).
    offered: dict[str, object] = field(default_factory=dict)
    key: FrameKey | None = None

    def hello(self) -> bytes:
        fields: dict[str, object] = {"client": self.client, "nonce": self.nonce.hex()}
        if self.cookie:
            fields["cookie"] = self.cookie.hex()
        return pack_json(fields)

    def take_cookie(self, payload: bytes) -> None:
        self.cookie = _hex(unpack_json(payload), "cookie")
        if not self.cookie:
            raise FrameError(f"{self.where}: an empty cookie")

    def answer(self, payload: bytes, session: int) -> bytes:
        """The AUTH payload for the server's challenge; AuthenticationError for a server
        that does not prove it knows our secret, or that wants one we do not have."""
        obj = unpack_json(payload)
        server_nonce = _hex(obj, "nonce", NONCE_SIZE)
        wants = bool(obj.get("auth"))
        self.offered = obj
        if self.secret is None:
            if wants:
                raise SecretRequiredError(self.where)
            return pack_json({"proof": ""})
        expected = server_proof(self.secret, self.nonce, server_nonce, session)
        if not wants or not check_proof(expected, _hex(obj, "proof")):
            raise AuthenticationError(
                f"{self.where} could not prove it knows our shared secret: a different "
                "secret there (wrong shared secret?), or not our robot"
            )
        key = session_key(self.secret, self.nonce, server_nonce, session)
        self.key = FrameKey(key, server=False)
        return pack_json(
            {"proof": client_proof(self.secret, server_nonce, self.nonce, session).hex()}
        )
