"""Who may open the dashboard: loopback, or a token derived from the shared secret.

Off loopback the dashboard insists on ``ego serve``'s shared secret, but never puts the
secret itself in a URL: the page's token is an HMAC of the secret, so a leaked URL (a
browser's history, a shoulder) opens that dashboard and nothing else, and changing the
secret revokes it. A WebSocket is also refused when its page came from another site
(the Origin header), so a page on the web cannot drive a robot on loopback through the
browser that visits it.
"""

from __future__ import annotations

import hmac
from hashlib import sha256
from urllib.parse import urlsplit

from ego.errors import InsecureSecretError
from ego.remote.auth import is_loopback

__all__ = ["check_binding", "dashboard_token", "same_origin", "token_matches"]

_LABEL = b"ego dashboard token v1"


def dashboard_token(secret: bytes) -> str:
    """The URL token of a dashboard whose shared secret is ``secret`` (32 hex digits)."""
    return hmac.new(secret, _LABEL, sha256).hexdigest()[:32]


def check_binding(host: str, secret: bytes | None) -> None:
    """Refuse a dashboard off loopback without a secret (InsecureSecretError)."""
    if secret is None and not is_loopback(host):
        raise InsecureSecretError(
            f"a dashboard on {host} (off loopback) needs a shared secret: "
            "--secret-file FILE (make one with 'ego secret'), or listen on 127.0.0.1"
        )


def token_matches(given: str | None, expected: str | None) -> bool:
    """Whether a request's token opens the dashboard (any request, when none is needed)."""
    if expected is None:
        return True
    return given is not None and hmac.compare_digest(given.encode(), expected.encode())


def same_origin(origin: str | None, host: str | None) -> bool:
    """Whether a WebSocket's Origin is the dashboard's own page (no Origin: not a browser
    page, e.g. a script of the user's, which the token or loopback already admits)."""
    if origin is None:
        return True
    if host is None:
        return False
    return urlsplit(origin).netloc.lower() == host.lower()
