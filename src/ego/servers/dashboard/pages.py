"""The dashboard's HTTP side: the Host check, the token login, the files, the headers.

Every response carries a Content-Security-Policy that lets the page run only its own
script and style, talk only to its own server, and never be framed (``frame-ancestors
'none'``, and X-Frame-Options for older browsers), with ``nosniff`` and no Referer: the
page's URL once held the token. The page's files hold no data and are public; the page
itself answers only a logged-in browser, so that one without the token is told why
rather than left on "connecting…". The login is a 303 to the bare page with an HttpOnly,
SameSite=Strict cookie; when the printed URL was clicked on another site's page, the
browser withholds that cookie from the redirect, and the page asks again from its own
origin.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from importlib import resources

from aiohttp import web

from ego.servers.dashboard.access import Gate

__all__ = ["CONTENT_SECURITY_POLICY", "SECURITY_HEADERS", "make_app", "refuse"]

Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]

CONTENT_SECURITY_POLICY = (
    "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
    "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
)
SECURITY_HEADERS = {
    "Content-Security-Policy": CONTENT_SECURITY_POLICY,
    "X-Frame-Options": "DENY",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}
_PUBLIC = {"app.js": "text/javascript", "style.css": "text/css"}
NEEDS_TOKEN = ("this dashboard needs its token: open the URL that ego printed "
               "(it ends in ?token=...)")  # fmt: skip
WRONG_TOKEN = "wrong token: open the URL that ego printed, as printed"
#: A browser sends no SameSite=Strict cookie along a navigation another site started
#: (a link clicked in a web chat), even one it just got at login: this page asks again
#: from the dashboard's own origin, which sends it. Without the cookie, that is a 403.
_ASK_AGAIN = ('<!doctype html><meta http-equiv="refresh" content="0">'
              "<title>ego dashboard</title><p>opening the dashboard…</p>\n")  # fmt: skip


def refuse(status: int, text: str) -> web.Response:
    """A refusal a person reads (in the browser, or a script's error)."""
    return web.Response(status=status, text=text + "\n")


def _file(name: str, content_type: str) -> web.Response:
    static = resources.files("ego.servers.dashboard").joinpath("static")
    text = static.joinpath(name).read_text("utf-8")
    return web.Response(text=text, content_type=content_type)


def make_app(gate: Gate, socket: Handler) -> web.Application:
    """The dashboard's application: the page at /, its files, its WebSocket at /ws."""

    @web.middleware
    async def check_host(request: web.Request, handler: Handler) -> web.StreamResponse:
        if not gate.host_ok(request.headers.get("Host")):
            return refuse(421, f"Host {request.headers.get('Host', '')!r} is not a name of this "
                          "dashboard: open the URL that ego printed")  # fmt: skip
        return await handler(request)

    async def index(request: web.Request) -> web.StreamResponse:
        token = request.query.get("token")
        if token is not None:
            if not gate.token_ok(token):
                return refuse(403, WRONG_TOKEN)
            # Logged in: the cookie from now on, and the token out of the URL bar.
            response = web.Response(status=303, headers={"Location": "./"})
            response.set_cookie(gate.cookie_name, token, path="/", httponly=True,
                                samesite="Strict")  # fmt: skip
            return response
        if not gate.cookie_ok(request.cookies):
            if request.headers.get("Sec-Fetch-Site") == "cross-site":
                return web.Response(text=_ASK_AGAIN, content_type="text/html")
            return refuse(403, NEEDS_TOKEN)
        return _file("index.html", "text/html")

    async def public(request: web.Request) -> web.StreamResponse:
        name = request.path.strip("/")
        return _file(name, _PUBLIC[name])

    async def no_icon(request: web.Request) -> web.StreamResponse:
        return web.Response(status=204)

    async def headers(request: web.Request, response: web.StreamResponse) -> None:
        response.headers.update(SECURITY_HEADERS)

    app = web.Application(middlewares=[check_host])
    app.on_response_prepare.append(headers)
    app.router.add_get("/", index)
    app.router.add_get("/ws", socket)
    for name in _PUBLIC:
        app.router.add_get(f"/{name}", public)
    app.router.add_get("/favicon.ico", no_icon)
    return app
