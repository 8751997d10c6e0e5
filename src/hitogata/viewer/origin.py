"""Only the viewer's own page may talk to it: a request from another web page is refused (HTTP 403).

A browser lets any page it shows open a WebSocket to 127.0.0.1 and sends the
page's address as the `Origin` header; without a check, a site the user visits
could read the scene and drive the viewer. The check, made in the opening
handshake before any of the scene is sent:

- `Origin`, when a browser sends one, must name the same scheme-less address as
  the `Host` the request was sent to (the viewer's own page); a request with no
  `Origin` comes from a program, not a page, and passes;
- a viewer listening on this machine only also requires the `Host` to be a name
  of this machine (localhost, a loopback address): a foreign name resolving to
  127.0.0.1 (DNS rebinding) is refused.

viser builds its websockets server inside its own thread with no hook for this;
`guard(viser_infra)` hands viser's server module a `serve` that puts the check
in front of viser's own request handler.
"""

from __future__ import annotations

import ipaddress
from http import HTTPStatus
from types import ModuleType
from typing import Any
from urllib.parse import urlsplit

LOCAL_NAMES = {"localhost", "localhost.localdomain", "ip6-localhost"}


def is_local_name(host: str) -> bool:
    """Whether `host` (a Host header's name, without the port) names this machine."""
    host = host.strip("[]").lower()
    if host in LOCAL_NAMES or host.endswith(".localhost"):
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def refusal(origin: str | None, host: str | None, listening_locally: bool) -> str | None:
    """Why a request with these headers is refused, or None when it may go on."""
    if not host:
        return "no Host header"
    if listening_locally:
        name = urlsplit(f"//{host}").hostname or ""
        if not is_local_name(name):
            return f"Host {host[:60]!r} does not name this machine"
    if origin is None:
        return None
    parts = urlsplit(origin)
    if parts.scheme not in ("http", "https") or parts.netloc.lower() != host.lower():
        return f"Origin {origin[:60]!r} is not this viewer's page"
    return None


def guard(viser_infra: ModuleType) -> None:
    """Make viser's websockets server (in module `viser_infra`) refuse requests from other pages (once)."""
    websockets = getattr(viser_infra, "websockets")  # noqa: B009 (the module's own import, set again below)
    if isinstance(websockets, _Override):
        return
    real_serve = websockets.asyncio.server.serve

    def serve(*args: Any, process_request: Any = None, **kwargs: Any) -> Any:
        def checked(connection: Any, request: Any) -> Any:
            local = connection.local_address
            listening_locally = bool(local) and is_local_name(str(local[0]))
            why = refusal(request.headers.get("Origin"), request.headers.get("Host"), listening_locally)
            if why is not None:
                return connection.respond(HTTPStatus.FORBIDDEN, f"hitogata viewer: refused: {why}\n")
            return process_request(connection, request) if process_request is not None else None

        return real_serve(*args, process_request=checked, **kwargs)

    server = _Override(websockets.asyncio.server, serve=serve)
    setattr(viser_infra, "websockets", _Override(websockets, asyncio=_Override(websockets.asyncio, server=server)))  # noqa: B010


class _Override:
    """A module seen through: the named attributes replaced, every other one the module's own."""

    def __init__(self, module: Any, **replaced: Any) -> None:
        self._module = module
        self._replaced = replaced

    def __getattr__(self, name: str) -> Any:
        return self._replaced[name] if name in self._replaced else getattr(self._module, name)
