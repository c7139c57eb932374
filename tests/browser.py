"""Open built HTML pages in headless Chromium and report what a reader
would see go wrong: a page that does not render, an image that does not
load, a video that cannot play, an error on the console.

Chromium is driven over its DevTools protocol (a WebSocket, with the
``websockets`` package the environment already has) rather than through
selenium or playwright: those need a driver or a browser build of their
own, and the protocol calls used here are few. The pages are served by a
local HTTP server (as a reader's web server would), and every host but
the local one is unreachable (``--host-resolver-rules``), so the check is
the same with or without a network; failed loads of third-party resources
(MathJax, require.js from CDNs) are reported apart and do not count as the
book's errors.
"""

from __future__ import annotations

import contextlib
import functools
import http.server
import itertools
import json
import re
import shutil
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "chrome")

# What each page is asked once it has loaded: does it render (a title and
# text in the main area), every image decoded (eager, so lazy images count
# too), every video's metadata readable.
_PAGE_JS = """
(async () => {
  const imgs = Array.from(document.images);
  imgs.forEach(i => { i.loading = 'eager'; });
  const images = await Promise.all(imgs.map(async i => {
    try { await i.decode(); } catch (e) {}
    return {src: i.currentSrc || i.src, ok: i.complete && i.naturalWidth > 0, alt: i.getAttribute('alt')};
  }));
  const videos = await Promise.all(Array.from(document.querySelectorAll('video')).map(v => new Promise(res => {
    const done = () => res({src: v.currentSrc || v.src || (v.querySelector('source') || {}).src,
                            ok: v.readyState >= 1 && !v.error, error: v.error ? v.error.code : null});
    if (v.readyState >= 1 || v.error) return done();
    v.preload = 'metadata';
    v.addEventListener('loadedmetadata', done, {once: true});
    v.addEventListener('error', done, {once: true});
    setTimeout(done, 10000);
    v.load();
  })));
  const main = document.querySelector('main') || document.body;
  return {title: document.title, text: (main.innerText || '').length, images, videos};
})()
"""


def find_chromium() -> str | None:
    """The path of a Chromium-like browser on PATH, or None."""
    for name in CHROMIUM_NAMES:
        path = shutil.which(name)
        if path:
            return path
    return None


@dataclass
class PageReport:
    """What a page showed: its title and main text length, images and
    videos that did not load, console errors (the book's own) and failed
    loads of other hosts' resources (informational)."""

    url: str
    title: str = ""
    text_chars: int = 0
    images: int = 0
    bad_images: list = field(default_factory=list)
    alts: list = field(default_factory=list)
    videos: int = 0
    bad_videos: list = field(default_factory=list)
    errors: list = field(default_factory=list)
    external_failures: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return (
            bool(self.title) and self.text_chars > 0 and not self.bad_images and not self.bad_videos and not self.errors
        )


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):  # no request log on stderr
        pass


@contextlib.contextmanager
def serve(folder: Path):
    """Serve `folder` over HTTP on 127.0.0.1 (a free port); yields the base URL."""
    handler = functools.partial(_QuietHandler, directory=str(folder))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


class Chromium:
    """A headless Chromium and one page target, driven over DevTools."""

    def __init__(self, exe: str | None = None, timeout_s: float = 30.0):
        from websockets.sync.client import connect

        exe = exe or find_chromium()
        if exe is None:
            raise RuntimeError(f"no Chromium on PATH (tried {', '.join(CHROMIUM_NAMES)})")
        self.timeout_s = timeout_s
        self._profile = tempfile.mkdtemp(prefix="mat-hopper-chromium-")
        args = [
            exe,
            "--headless=new",
            "--no-sandbox",  # CI runs as root
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--no-first-run",
            "--remote-debugging-port=0",
            "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1",
            f"--user-data-dir={self._profile}",
            "--autoplay-policy=no-user-gesture-required",
            "about:blank",
        ]
        self._stack = contextlib.ExitStack()
        self.proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        ws_url = self._devtools_url()
        self._stack = contextlib.ExitStack()
        self.ws = self._stack.enter_context(connect(ws_url, max_size=None, open_timeout=timeout_s))
        self._ids = itertools.count(1)
        self._events: list = []
        target = self._call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self._call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            self._call(f"{domain}.enable", session=True)

    def _devtools_url(self) -> str:
        deadline = time.monotonic() + self.timeout_s
        lines = []
        while time.monotonic() < deadline:
            line = self.proc.stderr.readline()
            if not line:
                if self.proc.poll() is not None:
                    break
                continue
            lines.append(line)
            m = re.search(r"DevTools listening on (ws://\S+)", line)
            if m:
                # keep draining stderr so the browser never blocks on a full pipe
                threading.Thread(target=self.proc.stderr.read, daemon=True).start()
                return m.group(1)
        self.close()
        raise RuntimeError("Chromium did not start its DevTools endpoint:\n" + "".join(lines[-20:]))

    def _call(self, method: str, params: dict | None = None, *, session: bool = False) -> dict:
        msg_id = next(self._ids)
        msg = {"id": msg_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = self.session
        self.ws.send(json.dumps(msg))
        deadline = time.monotonic() + self.timeout_s
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"no answer to {method} within {self.timeout_s:g} s")
            reply = json.loads(self.ws.recv(timeout=left))
            if reply.get("id") == msg_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self._events.append(reply)

    def _wait_event(self, method: str) -> dict:
        deadline = time.monotonic() + self.timeout_s
        while True:
            for i, ev in enumerate(self._events):
                if ev.get("method") == method:
                    return self._events.pop(i)
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"no {method} within {self.timeout_s:g} s")
            self._events.append(json.loads(self.ws.recv(timeout=left)))

    def check(self, url: str, local_prefix: str) -> PageReport:
        """Load `url`, wait for its load event, and report (console
        messages from this load only)."""
        self._events.clear()
        self._call("Page.navigate", {"url": url}, session=True)
        self._wait_event("Page.loadEventFired")
        result = self._call(
            "Runtime.evaluate",
            {"expression": _PAGE_JS, "awaitPromise": True, "returnByValue": True},
            session=True,
        )
        if "exceptionDetails" in result:
            raise RuntimeError(f"{url}: the page check raised {result['exceptionDetails']}")
        page = result["result"]["value"]
        time.sleep(0.2)  # late console messages
        with contextlib.suppress(TimeoutError):
            while True:
                self._events.append(json.loads(self.ws.recv(timeout=0.05)))
        rep = PageReport(url, page["title"], page["text"], len(page["images"]), videos=len(page["videos"]))
        rep.bad_images = [i["src"] for i in page["images"] if not i["ok"]]
        rep.alts = [(i["src"], i["alt"]) for i in page["images"]]
        rep.bad_videos = [(v["src"], v["error"]) for v in page["videos"] if not v["ok"]]
        for ev in self._events:
            method, p = ev.get("method"), ev.get("params", {})
            if method == "Runtime.exceptionThrown":
                d = p["exceptionDetails"]
                rep.errors.append(f"exception: {d.get('exception', {}).get('description') or d.get('text')}")
            elif method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                rep.errors.append(
                    "console."
                    + p["type"]
                    + ": "
                    + " ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", []))
                )
            elif method == "Log.entryAdded" and p["entry"].get("level") == "error":
                e = p["entry"]
                src = e.get("url", "")
                if src and not src.startswith(local_prefix):
                    rep.external_failures.append(src)
                else:
                    rep.errors.append(f"{e.get('source')}: {e.get('text')} {src}".strip())
        return rep

    def wait_for_text(self, url: str, needles, timeout_s: float | None = None) -> str:
        """Load `url` and poll its rendered text (``document.body.innerText``)
        until it holds every string of `needles` (a single-page app fills
        the page after its load event); the text, or TimeoutError naming the
        missing strings."""
        self._call("Page.navigate", {"url": url}, session=True)
        self._wait_event("Page.loadEventFired")
        deadline = time.monotonic() + (timeout_s or self.timeout_s)
        while True:
            res = self._call(
                "Runtime.evaluate",
                {"expression": "document.body ? document.body.innerText : ''", "returnByValue": True},
                session=True,
            )
            text = res.get("result", {}).get("value", "") or ""
            missing = [n for n in needles if n not in text]
            if not missing:
                return text
            if time.monotonic() > deadline:
                raise TimeoutError(f"{url}: no {missing} in the rendered page after {timeout_s or self.timeout_s:g} s")
            time.sleep(0.2)

    def close(self) -> None:
        with contextlib.suppress(Exception):
            self._stack.close()
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        shutil.rmtree(self._profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


SKIP_DIRS = ("_static", "_sources", "_images", "_downloads", "reports")


def is_redirect(page: Path) -> bool:
    """A redirect stub (Jupyter Book's root index.html points at the root
    document with a meta refresh): no content of its own."""
    return bool(re.search(r'<meta[^>]+http-equiv="refresh"', page.read_text(encoding="utf-8"), re.I))


def pages(html_dir: Path) -> list[Path]:
    """Every HTML page of a built book (not theme assets or sources, not
    redirect stubs: the page they point at is checked itself)."""
    html_dir = Path(html_dir)
    return sorted(
        p
        for p in html_dir.rglob("*.html")
        if not any(part in SKIP_DIRS for part in p.relative_to(html_dir).parts) and not is_redirect(p)
    )


def check_book(html_dir: Path, exe: str | None = None) -> list[PageReport]:
    """Open every page of the built book in headless Chromium."""
    html_dir = Path(html_dir)
    reports = []
    with serve(html_dir) as base, Chromium(exe) as browser:
        for page in pages(html_dir):
            rel = page.relative_to(html_dir).as_posix()
            reports.append(browser.check(f"{base}/{rel}", base))
    return reports


if __name__ == "__main__":  # python tests/browser.py _build/html
    import sys

    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "_build/html")
    bad = 0
    for r in check_book(folder):
        bad += not r.ok
        print(("ok  " if r.ok else "BAD ") + r.url, r.images, "images", r.videos, "videos")
        for what in ("bad_images", "bad_videos", "errors"):
            for x in getattr(r, what):
                print("    ", what, x)
    sys.exit(1 if bad else 0)
