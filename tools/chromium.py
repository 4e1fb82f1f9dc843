"""Headless Chromium over the DevTools protocol, for ``make browser-test``.

Serves a built book from a local ``http.server`` on 127.0.0.1, opens pages in Debian's
Chromium (headless, fresh profile, every host but 127.0.0.1 unresolvable, so the test sees
what an offline reader sees) and reports, per page: JavaScript errors, requests that left
the machine or failed, TeX left unrendered, MathJax errors, images that did not load and
error cells. Uses only the standard library and ``websocket-client``.

Run standalone to check a build and write screenshots::

    .venv/bin/python tools/chromium.py _build/html --screenshots _build/screenshots
"""

from __future__ import annotations

import base64
import contextlib
import functools
import http.server
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
    "--mute-audio",
    "--window-size=1280,900",
    "--remote-allow-origins=*",
    # the network is off: nothing resolves but the local server
    "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
]

# requests a page may attempt and lose offline without harm: the optional ipywidgets
# embed scripts (book/_ext/static/xnav-widgets-loader.js) and thebe, loaded on demand
ALLOWED_EXTERNAL = (
    "https://cdnjs.cloudflare.com/ajax/libs/require.js/",
    "https://cdn.jsdelivr.net/npm/@jupyter-widgets/",
    "https://unpkg.com/thebe@",
)

# console.error messages that are not faults: pydata-sphinx-theme on a fresh profile
BENIGN_CONSOLE = ("Got invalid theme mode",)

_LOCAL = ("http://127.0.0.1", "data:", "blob:", "about:", "chrome:", "devtools:")


def find_chromium():
    """Path of a Chromium binary (``$XNAVLAB_CHROMIUM``, then Debian's), or ``None``."""
    for cand in (os.environ.get("XNAVLAB_CHROMIUM"), "/usr/bin/chromium",
                 shutil.which("chromium"), shutil.which("chromium-browser")):
        if cand and os.access(cand, os.X_OK):
            return cand
    return None


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@contextlib.contextmanager
def serve(root):
    """Serve directory ``root`` on 127.0.0.1 (a free port); yield the base URL."""
    handler = functools.partial(_QuietHandler, directory=str(root))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    finally:
        httpd.shutdown()
        httpd.server_close()


class CDP:
    """A minimal synchronous DevTools-protocol client for one page target."""

    def __init__(self, ws_url):
        import websocket  # websocket-client

        self.ws = websocket.create_connection(ws_url, timeout=60, suppress_origin=True)
        self.events = []
        self._id = 0

    def send(self, method, timeout=60, **params):
        self._id += 1
        msg_id = self._id
        self.ws.send(json.dumps({"id": msg_id, "method": method, "params": params}))
        deadline = time.monotonic() + timeout
        while True:
            msg = self._recv(deadline)
            if msg is None:
                raise TimeoutError(f"no reply to {method} in {timeout} s")
            if msg.get("id") == msg_id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            if "method" in msg:
                self.events.append(msg)

    def wait_event(self, name, timeout=30):
        """Wait for event ``name`` (also among those already received); return it or None."""
        for ev in self.events:
            if ev["method"] == name:
                return ev
        deadline = time.monotonic() + timeout
        while True:
            msg = self._recv(deadline)
            if msg is None:
                return None
            if "method" in msg:
                self.events.append(msg)
                if msg["method"] == name:
                    return msg

    def drain(self, seconds=0.3):
        """Collect the events that arrive within ``seconds``."""
        deadline = time.monotonic() + seconds
        while (msg := self._recv(deadline)) is not None:
            if "method" in msg:
                self.events.append(msg)

    def _recv(self, deadline):
        import websocket

        left = deadline - time.monotonic()
        if left <= 0:
            return None
        self.ws.settimeout(left)
        try:
            return json.loads(self.ws.recv())
        except websocket.WebSocketTimeoutException:
            return None

    def evaluate(self, expression, timeout=60):
        res = self.send("Runtime.evaluate", timeout=timeout, expression=expression,
                        awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in res:
            raise RuntimeError(f"evaluate failed: {res['exceptionDetails']}")
        return res["result"].get("value")

    def close(self):
        with contextlib.suppress(Exception):
            self.ws.close()


class Browser:
    """Headless Chromium with a fresh profile; ``page`` is a :class:`CDP` on its first tab."""

    def __init__(self, binary=None):
        self.binary = binary or find_chromium()
        if not self.binary:
            raise FileNotFoundError("chromium not found (apt-get install chromium)")
        self.profile = tempfile.mkdtemp(prefix="xnav-chromium-")
        self._log = tempfile.TemporaryFile()  # chromium's stderr (a pipe could fill and block)
        self.proc = subprocess.Popen(
            [self.binary, *CHROMIUM_FLAGS, f"--user-data-dir={self.profile}",
             "--remote-debugging-port=0", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=self._log,
        )
        port_file = Path(self.profile) / "DevToolsActivePort"
        deadline = time.monotonic() + 60
        while not (port_file.exists() and port_file.read_text().strip()):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self._log.seek(0)
                err = self._log.read().decode(errors="replace")[-2000:]
                self.close()
                raise RuntimeError(f"chromium did not start:\n{err}")
            time.sleep(0.1)
        port = int(port_file.read_text().split()[0])
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=30) as r:
            targets = json.load(r)
        page = next(t for t in targets if t["type"] == "page")
        self.page = CDP(page["webSocketDebuggerUrl"])
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.page.send(f"{domain}.enable")
        self.page.send("Emulation.setDeviceMetricsOverride", width=1280, height=900,
                       deviceScaleFactor=1, mobile=False)

    def close(self):
        if getattr(self, "page", None):
            self.page.close()
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(10)
        self._log.close()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


# Runs in the page once it has loaded: waits for images, fonts and MathJax, then inspects.
_SETTLE = r"""
(async () => {
  for (const img of document.images) { img.loading = "eager"; }
  const pending = [...document.images].filter(i => !i.complete)
      .map(i => new Promise(r => { i.addEventListener("load", r); i.addEventListener("error", r); }));
  await Promise.race([Promise.all(pending), new Promise(r => setTimeout(r, 10000))]);
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await Promise.race([MathJax.startup.promise, new Promise(r => setTimeout(r, 20000))]);
  }
  if (document.fonts && document.fonts.ready) { await document.fonts.ready; }
  await new Promise(r => setTimeout(r, 300));
  return true;
})()
"""

_INSPECT = r"""
(() => {
  const main = document.querySelector("main") || document.body;
  const prose = main.cloneNode(true);
  prose.querySelectorAll("pre, code, script, style, mjx-container, .xnav-scrubber, "
      + ".cell_input, textarea").forEach(e => e.remove());
  const text = prose.textContent;
  const tex = [];
  const patterns = [/\$\$/, /\\begin\{/, /\\end\{/, /\\\(/, /\\\)/, /\\\[/, /\\\]/,
                    /\$[^$\n]{0,80}[\\^_][^$\n]{0,80}\$/];
  for (const p of patterns) {
    const m = text.match(p);
    if (m) {
      const i = m.index;
      tex.push(text.slice(Math.max(0, i - 40), i + 60).replace(/\s+/g, " "));
    }
  }
  const math = [...document.querySelectorAll(".math")];
  const unrendered = math.filter(e => !e.querySelector("mjx-container"))
      .map(e => e.textContent.slice(0, 80));
  const merrors = [...document.querySelectorAll("mjx-merror")]
      .map(e => (e.getAttribute("data-mjx-error") || e.textContent).slice(0, 120));
  const broken = [...document.images]
      .filter(i => !i.complete || i.naturalWidth === 0).map(i => i.currentSrc || i.src);
  const errorCells = [...document.querySelectorAll(
      ".output.traceback, .output.error, div.cell_output .traceback")]
      .map(e => e.textContent.trim().slice(0, 300));
  for (const o of document.querySelectorAll(".cell_output")) {
    const t = o.textContent;
    if (/Traceback \(most recent call last\)|"ename"\s*:/.test(t) && !errorCells.length) {
      errorCells.push(t.trim().slice(0, 300));
    }
  }
  // a cell that ends in plt.show() (or a bare `fig`) must show a figure; text such as
  // "<Figure size 640x480 with 1 Axes>" means it was not rendered (e.g. MPLBACKEND=Agg)
  const noFigure = [];
  for (const c of document.querySelectorAll("div.cell")) {
    const inp = c.querySelector(".cell_input pre");
    if (!inp) { continue; }
    const lines = inp.textContent.split("\n").map(l => l.trim()).filter(l => l && !l.startsWith("#"));
    const last = lines.length ? lines[lines.length - 1] : "";
    const out = c.querySelector(".cell_output");
    const hasImg = !!(out && out.querySelector("img, svg"));
    const figText = out && /<Figure size \d+(\.\d+)?x\d+(\.\d+)? with \d+ Axes>/.test(out.textContent);
    if (figText || (/^plt\.show\(\)\s*;?$/.test(last) && !hasImg)) {
      noFigure.push(lines.slice(-2).join(" | ").slice(0, 120));
    }
  }
  return {
    noFigure: noFigure.slice(0, 5),
    title: document.title,
    url: location.href,
    nMath: math.length,
    nMathJax: document.querySelectorAll("mjx-container").length,
    mathjaxLoaded: !!(window.MathJax && window.MathJax.startup),
    rawTex: tex,
    unrenderedMath: unrendered.slice(0, 10),
    mathErrors: merrors.slice(0, 10),
    brokenImages: broken,
    nImages: document.images.length,
    errorCells: errorCells.slice(0, 5),
    height: Math.ceil(document.documentElement.scrollHeight),
  };
})()
"""


# Moves every kernel-free scrubber (xnavlab.core.widgets) to its last frame and back.
_SCRUB = r"""
(() => {
  const bad = [];
  const all = document.querySelectorAll(".xnav-scrubber");
  all.forEach((d, n) => {
    try {
      const input = d.querySelector("input[type=range]");
      const img = d.querySelector("img");
      const data = JSON.parse(d.querySelector(".xnav-scrubber-data").textContent);
      const last = data.frames.length - 1, before = input.value;
      input.value = String(last);
      input.dispatchEvent(new Event("input", {bubbles: true}));
      if (img.getAttribute("src") !== data.frames[last]
          || d.querySelector("output").textContent !== data.labels[last]) { bad.push(n); }
      input.value = before;
      input.dispatchEvent(new Event("input", {bubbles: true}));
    } catch (e) { bad.push(n + ": " + e); }
  });
  return {n: all.length, bad: bad};
})()
"""


def _is_local(url):
    return url.startswith(_LOCAL)


def check_page(browser, url, screenshot=None, max_height=16000):
    """Open ``url`` and return a report dict with a list ``problems`` (empty: page is fine).

    ``screenshot`` is a path for a full-page PNG (at most ``max_height`` CSS pixels tall).
    """
    page = browser.page
    page.events.clear()
    page.send("Page.navigate", url=url)
    for _attempt in range(3):  # a redirect page (the root index.html) navigates on load
        if page.wait_event("Page.loadEventFired", timeout=60) is None:
            return {"url": url, "problems": [f"page did not finish loading in 60 s: {url}"]}
        try:
            page.evaluate(_SETTLE, timeout=60)
            break
        except RuntimeError as exc:
            if "navigated" not in str(exc):
                raise
            page.events[:] = [e for e in page.events if e["method"] != "Page.loadEventFired"]
    page.drain(0.3)
    report = page.evaluate(_INSPECT)
    scrub = page.evaluate(_SCRUB)
    report["nScrubbers"] = scrub["n"]
    page.drain(0.1)
    problems = []
    if scrub["bad"]:
        problems.append(f"scrubbers that do not move: {scrub['bad']}")
    for ev in page.events:
        m, p = ev["method"], ev.get("params", {})
        if m == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            desc = d.get("exception", {}).get("description") or d.get("text")
            problems.append(f"JavaScript error: {desc} ({d.get('url', '')}:{d.get('lineNumber')})")
        elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            args = " ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", []))
            if not args.startswith(BENIGN_CONSOLE):
                problems.append(f"console.error: {args[:300]}")
        elif m == "Log.entryAdded":
            e = p.get("entry", {})
            if e.get("level") == "error" and e.get("source") not in ("network",):
                problems.append(f"browser log error ({e.get('source')}): {e.get('text', '')[:300]}")
        elif m == "Network.requestWillBeSent":
            req = p.get("request", {}).get("url", "")
            if not _is_local(req) and not req.startswith(ALLOWED_EXTERNAL):
                problems.append(f"request leaves the machine (offline build must not): {req}")
    failed = {p["params"]["requestId"] for p in page.events
              if p["method"] == "Network.loadingFailed" and not p["params"].get("canceled")}
    urls = {ev["params"]["requestId"]: ev["params"]["request"]["url"] for ev in page.events
            if ev["method"] == "Network.requestWillBeSent"}
    for rid in failed:
        u = urls.get(rid, "?")
        if _is_local(u) and not u.startswith("data:"):
            problems.append(f"failed to load {u}")
    for ev in page.events:
        if ev["method"] == "Network.responseReceived":
            resp = ev["params"]["response"]
            if resp.get("status", 200) >= 400 and not resp["url"].endswith("/favicon.ico"):
                problems.append(f"HTTP {resp['status']} for {resp['url']}")
    if report["rawTex"]:
        problems.append(f"raw TeX visible: {report['rawTex']}")
    if report["unrenderedMath"]:
        problems.append(f"{len(report['unrenderedMath'])}+ math elements not rendered by MathJax: "
                        f"{report['unrenderedMath'][:3]}")
    if report["nMath"] and not report["nMathJax"]:
        problems.append(f"page has {report['nMath']} math elements but no MathJax output "
                        f"(MathJax loaded: {report['mathjaxLoaded']})")
    if report["mathErrors"]:
        problems.append(f"MathJax errors: {report['mathErrors']}")
    if report["noFigure"]:
        problems.append(f"cells that should show a figure but do not: {report['noFigure']}")
    if report["brokenImages"]:
        problems.append(f"images that did not load: {report['brokenImages']}")
    if report["errorCells"]:
        problems.append(f"error cells: {report['errorCells']}")
    if screenshot is not None:
        # grow the viewport to the page (captureBeyondViewport mis-lays-out some pages)
        height = max(900, min(int(report["height"]), max_height))
        page.send("Emulation.setDeviceMetricsOverride", width=1280, height=height,
                  deviceScaleFactor=1, mobile=False)
        try:
            page.evaluate("new Promise(r => requestAnimationFrame(() => setTimeout(r, 300)))")
            shot = page.send("Page.captureScreenshot", timeout=120, format="png")
        finally:
            page.send("Emulation.setDeviceMetricsOverride", width=1280, height=900,
                      deviceScaleFactor=1, mobile=False)
        Path(screenshot).parent.mkdir(parents=True, exist_ok=True)
        Path(screenshot).write_bytes(base64.b64decode(shot["data"]))
        report["screenshot"] = str(screenshot)
    report["problems"] = list(dict.fromkeys(problems))
    return report


def pages(html_root):
    """Every HTML page of a build, relative paths, sorted (assets and sources left out)."""
    root = Path(html_root)
    skip = {"_static", "_sources", "_images", "_downloads", "_panels_static"}
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*.html")
                  if not skip.intersection(p.relative_to(root).parts))


def screenshot_name(rel):
    """``book/01_pulsars.html`` -> ``01_pulsars.png`` (pages outside book/ keep their path)."""
    stem = rel[:-5] if rel.endswith(".html") else rel
    stem = stem[5:] if stem.startswith("book/") else stem
    return stem.replace("/", "__") + ".png"


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description="check a built book in headless Chromium")
    ap.add_argument("html", type=Path, help="the build, e.g. _build/html")
    ap.add_argument("--screenshots", type=Path, help="directory for one PNG per page")
    args = ap.parse_args(argv)
    bad = 0
    with serve(args.html) as base, Browser() as browser:
        for rel in pages(args.html):
            shot = args.screenshots / screenshot_name(rel) if args.screenshots else None
            rep = check_page(browser, base + rel, shot)
            status = "ok" if not rep["problems"] else "FAIL"
            print(f"{status:4s} {rel}  math={rep.get('nMathJax')}/{rep.get('nMath')} "
                  f"images={rep.get('nImages')} scrubbers={rep.get('nScrubbers')}")
            for p in rep["problems"]:
                print(f"     - {p}")
            bad += bool(rep["problems"])
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
