"""The composer's HTTP server: the page and a small JSON API over a :class:`~jaxmotion.composer.app.Composer`, on the
standard library's threaded server (each request its own thread; generation itself one request at a time).

* ``GET /`` and ``GET /static/<file>``: the page (``static/``: HTML, JavaScript, CSS; no library, no CDN).
* ``GET /api/model``: the model's facts (:meth:`~jaxmotion.composer.app.Composer.model`).
* ``GET /api/body``: the body model's mesh, when the server has one (:meth:`~jaxmotion.composer.app.Composer.body`).
* ``POST /api/generate``: a request (:mod:`jaxmotion.composer.app`) -> a stream of JSON lines
  (``application/x-ndjson``): ``{"event": "queued"}`` when another request goes first, ``{"event": "warning",
  "message"}`` per tag pair never seen in training, ``{"event": "action", "index", "of", "shadowed", "revised"}``
  per action done, then ``{"event": "done", "motion"}`` or ``{"event": "error", "message"}``.
* ``GET /api/motions/<id>/<file>``: a generated motion as ``motion.bvh``, ``motion.npz`` (AMASS layout),
  ``motion.npy`` (joints) or ``segments.json``.

Bad requests get a 4xx with ``{"error": message}`` naming the field (400: not JSON, a bad program; 404: an unknown
path or motion; 405: another method; 411: no length; 413: a body over :data:`MAX_BODY`), and the server goes on
serving. It binds to 127.0.0.1 by default; ``--host 0.0.0.0`` exposes it to the network, with no authentication and
no TLS: put it behind a reverse proxy that provides them.
"""

from __future__ import annotations

import json
import re
import sys
import traceback
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

from jaxmotion.composer.app import Composer, RequestError, read_request

#: The largest request body read (a program of a hundred actions with drawn paths is a few tens of kB).
MAX_BODY = 1 << 20
STATIC = Path(__file__).parent / "static"
_TYPES = {".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
          ".css": "text/css; charset=utf-8", ".png": "image/png", ".svg": "image/svg+xml"}
_DOWNLOAD = re.compile(r"^/api/motions/(?P<id>[\w-]+)/(?P<name>[\w.-]+)$")


class ComposerHandler(BaseHTTPRequestHandler):
    """One request: routes as the module docstring's table."""

    server_version = "jaxmotion-composer"
    composer: Composer  # set on the subclass :func:`make_server` builds
    quiet = True

    def do_GET(self) -> None:  # noqa: N802 (the standard library's name)
        self._answer(self._get)

    def do_POST(self) -> None:  # noqa: N802
        self._answer(self._post)

    def _refuse(self) -> None:
        self._json({"error": f"{self.command} {self.path}: expected GET (the page, the model, downloads) or POST "
                             f"/api/generate"}, HTTPStatus.METHOD_NOT_ALLOWED)

    do_PUT = do_DELETE = do_PATCH = _refuse  # noqa: N815

    def _answer(self, route) -> None:
        try:
            route(self.path.split("?", 1)[0])
        except RequestError as error:
            self._json({"error": str(error)}, error.status)
        except (BrokenPipeError, ConnectionResetError):  # the page went away mid-answer
            pass
        except Exception as error:  # a bug: say so, log it, keep serving
            traceback.print_exc(file=sys.stderr)
            self._json({"error": f"internal error: {type(error).__name__}: {error}"}, HTTPStatus.INTERNAL_SERVER_ERROR)

    def _get(self, path: str) -> None:
        if path in ("/", "/index.html"):
            return self._file(STATIC / "index.html")
        if path.startswith("/static/"):
            name = path[len("/static/"):]
            if re.fullmatch(r"[\w-]+\.\w+", name) and (STATIC / name).is_file():
                return self._file(STATIC / name)
        elif path == "/api/model":
            return self._json(self.composer.model())
        elif path == "/api/body":
            return self._json(self.composer.body())
        elif match := _DOWNLOAD.match(path):
            data, content_type = self.composer.download(match["id"], match["name"])
            return self._send(data, content_type, {"Content-Disposition": f'attachment; filename="{match["name"]}"'})
        raise RequestError(f"GET {path}: not found", HTTPStatus.NOT_FOUND)

    def _post(self, path: str) -> None:
        if path != "/api/generate":
            raise RequestError(f"POST {path}: not found (POST /api/generate generates)", HTTPStatus.NOT_FOUND)
        request = read_request(self._body(), self.composer.generator)
        self.composer.check(request)
        self.send_response(HTTPStatus.OK)
        self.send_header("Content-Type", "application/x-ndjson")
        self.send_header("Cache-Control", "no-store")
        self.end_headers()  # HTTP/1.0: the stream ends when the connection closes
        count = len(request.program.actions)

        def send(event: dict) -> None:
            self.wfile.write(json.dumps(event).encode() + b"\n")
            self.wfile.flush()

        for warning in self.composer.warnings(request):
            send({"event": "warning", "message": warning})
        try:
            motion = self.composer.generate(
                request, on_wait=lambda: send({"event": "queued"}),
                on_action=lambda a, shadowed, revised: send({"event": "action", "index": a, "of": count,
                                                             "shadowed": shadowed, "revised": revised}))
        except (BrokenPipeError, ConnectionResetError):
            raise
        except Exception as error:  # the status line is sent: the stream says what went wrong
            traceback.print_exc(file=sys.stderr)
            return send({"event": "error", "message": f"{type(error).__name__}: {error}"})
        send({"event": "done", "motion": motion})

    def _body(self):
        length = self.headers.get("Content-Length")
        if length is None or not length.isdigit():
            raise RequestError("request: expected a Content-Length header", HTTPStatus.LENGTH_REQUIRED)
        length = int(length)
        if length > MAX_BODY:
            self._discard(length)
            raise RequestError(f"request: the body is {length} bytes; expected at most {MAX_BODY}",
                               HTTPStatus.REQUEST_ENTITY_TOO_LARGE)
        try:
            return json.loads(self.rfile.read(length))
        except (UnicodeDecodeError, json.JSONDecodeError) as error:
            raise RequestError(f"request: the body is not JSON ({error})") from None

    def _discard(self, length: int) -> None:
        """Read what the client sends (up to 16 MiB) before refusing it, so that it reads the answer."""
        left = min(length, 16 * MAX_BODY)
        while left > 0:
            chunk = self.rfile.read(min(left, 1 << 16))
            if not chunk:
                break
            left -= len(chunk)

    def _file(self, path: Path) -> None:
        self._send(path.read_bytes(), _TYPES.get(path.suffix, "application/octet-stream"))

    def _json(self, value, status: int = HTTPStatus.OK) -> None:
        self._send(json.dumps(value).encode(), "application/json", status=status)

    def _send(self, data: bytes, content_type: str, headers: dict | None = None, status: int = HTTPStatus.OK) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        for name, value in (headers or {}).items():
            self.send_header(name, value)
        self.end_headers()
        self.wfile.write(data)

    def log_message(self, format: str, *args) -> None:  # noqa: A002 (the standard library's signature)
        if not self.quiet:
            super().log_message(format, *args)


def make_server(composer: Composer, host: str = "127.0.0.1", port: int = 8000, *, quiet: bool = True
                ) -> ThreadingHTTPServer:
    """A server of ``composer`` bound to ``host:port`` (port 0: a free one; ``server.server_address`` says which),
    not yet serving: call ``serve_forever()``."""
    handler = type("Handler", (ComposerHandler,), {"composer": composer, "quiet": quiet})
    server = ThreadingHTTPServer((host, port), handler)
    server.daemon_threads = True
    return server
