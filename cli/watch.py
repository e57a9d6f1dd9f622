"""`rustycs watch`: a live preview while a scene is written.

A small HTTP server on 127.0.0.1 serves one page: the HTML player of the latest run of the scene, or,
when the scene does not load, its problems beside the scene's text with those lines marked. The main
thread polls the file; each time it is saved the scene is validated and run again (into a temporary
folder) and the page's version goes up. The page asks for the version twice a second and reloads when
it changed. Ctrl-C stops the server and ends the command.
"""

from __future__ import annotations

import html
import re
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

from .errors import UserError

HOST = "127.0.0.1"  # never another address: the preview is for the person at this machine
POLL_SECONDS = 0.2  # how often the scene file is looked at
RELOAD_SCRIPT = """<script>
(function () {
  const shown = %d;
  setInterval(function () {
    fetch("/version", {cache: "no-store"}).then(function (r) { return r.text(); }).then(function (v) {
      if (Number(v) !== shown) { location.reload(); }
    }).catch(function () {});
  }, 500);
})();
</script>"""
LOCATED = re.compile(r"^.*?:(\d+):(\d+): ")


@dataclass
class Preview:
    """The page shown now and its version (a new version makes open pages reload)."""

    page: str = "<!DOCTYPE html><title>rustycs watch</title><p>running the scene...</p>"
    version: int = 0

    def show(self, page: str) -> None:
        self.page, self.version = page, self.version + 1

    def served(self) -> str:
        """The page with the script that reloads it when a newer version is shown."""
        script = RELOAD_SCRIPT % self.version
        if "</body>" in self.page:
            return self.page.replace("</body>", script + "</body>", 1)
        return self.page + script


def error_page(source: Path, text: str, messages: Sequence[str]) -> str:
    """The problems of a scene, then its text with line numbers, the lines they point at marked."""
    marked = {int(match[1]) for message in messages if (match := LOCATED.match(message))}
    lines = "\n".join(
        f'<span class="{"bad" if number in marked else "ok"}" id="line-{number}">'
        f"{number:4d}  {html.escape(line)}</span>"
        for number, line in enumerate(text.splitlines(), start=1)
    )
    problems = "\n".join(f"<li>{html.escape(message)}</li>" for message in messages)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(source.name)}: problems</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
pre span {{ display: block; }}
.bad {{ background: #fdd; font-weight: bold; }}
li {{ font-family: monospace; color: #a00; }}
</style></head>
<body><h1>{html.escape(source.name)}: the scene does not load</h1>
<ul id="problems">{problems}</ul>
<pre>{lines}</pre>
</body></html>"""


def _handler(preview: Preview) -> type[BaseHTTPRequestHandler]:
    class Handler(BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 (http.server's name)
            if self.path == "/version":
                body, kind = str(preview.version), "text/plain"
            elif self.path in ("/", "/index.html"):
                body, kind = preview.served(), "text/html; charset=utf-8"
            else:
                self.send_error(404)
                return
            data = body.encode("utf-8")
            self.send_response(200)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(data)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(data)

        def log_message(self, *_: object) -> None:  # no line per request on stderr
            return

    return Handler


def _stamp(path: Path) -> tuple[float, int] | None:
    try:
        status = path.stat()
    except OSError:
        return None
    return status.st_mtime_ns, status.st_size


def render_scene(scene: Path, overrides: Sequence[str], ticks: int | None, folder: Path) -> str:
    """Run the scene into `folder` and return its player page, or the page of its problems."""
    from .render.pictures import RenderRequest, render
    from .simulation import load_source, run_scene

    try:
        loaded = load_source(scene, tuple(overrides))
    except UserError as err:
        try:
            text = scene.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            text = ""
        return error_page(scene, text, err.messages)
    run = folder / "preview.h5"
    result = run_scene(loaded, run, ticks, quiet=True)
    if result.status == "interrupted":
        raise KeyboardInterrupt
    page = folder / "preview.html"
    render(RenderRequest(run=run, out=page))
    return page.read_text(encoding="utf-8")


def watch(scene: Path, overrides: Sequence[str], ticks: int | None, port: int,
          say: Callable[[str], None]) -> None:
    """Serve the preview of `scene` until Ctrl-C, running it again on every save."""
    preview = Preview()
    try:
        server = ThreadingHTTPServer((HOST, port), _handler(preview))
    except OSError as err:
        raise UserError(f"--port {port}: cannot listen on {HOST}:{port} ({err.strerror or err})") from None
    serving = threading.Thread(target=server.serve_forever, daemon=True)
    serving.start()
    say(f"watching {scene}: open http://{HOST}:{server.server_address[1]}/ (Ctrl-C stops)")
    try:
        with tempfile.TemporaryDirectory(prefix="rustycs-watch-") as folder:
            seen: tuple[float, int] | None | bool = False
            while True:
                stamp = _stamp(scene)
                if stamp != seen:
                    seen = stamp
                    preview.show(render_scene(scene, overrides, ticks, Path(folder)))
                    say(f"{time.strftime('%H:%M:%S')} shown run {preview.version} of {scene}")
                time.sleep(POLL_SECONDS)
    except KeyboardInterrupt:
        pass
    finally:
        server.shutdown()
        server.server_close()
    say("rustycs watch: stopped")
