"""Render the verification report in headless Chromium and check it; exit ≠ 0 on a problem.

    python -m verification.render_check reports/index.html [--screenshot PATH] [--chromium PATH]
                                        [--mode cdp|cli] [--full-page] [--timeout S]

Checks: no console errors or uncaught exceptions, no failed resource loads,
no resource fetched over the network (the page must be self-contained), the
summary table has at least one row, every <img> loaded with a non-zero size
and every figure <svg> has content and a non-zero box. Writes a screenshot
(default: next to the page, `screenshot.png`, 1280×2000 CSS px, top of the page).

Mode "cdp" (default) drives Chromium over the DevTools protocol on a pipe
(`--remote-debugging-pipe`, no sockets, no extra packages): console and log
events, DOM checks by script, screenshot. Mode "cli" (fallback, used
automatically if cdp fails to start) uses `--dump-dom`, `--screenshot` and
`--enable-logging=stderr --v=0`, and scans the log for console errors
("Uncaught", "ERROR:CONSOLE", "Failed to load resource"; newer Chromium logs
every console message as INFO:CONSOLE, so "console.error" text is not
distinguishable there) and the DOM for the summary rows and empty images.

Needs: `apt-get install -y chromium` (Debian/Ubuntu; /usr/bin/chromium).
"""

from __future__ import annotations

import argparse
import fcntl
import json
import os
import re
import select
import shutil
import subprocess
import sys
import tempfile
import time
from html.parser import HTMLParser
from pathlib import Path

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--mute-audio"]
WIDTH, HEIGHT = 1280, 2000

# evaluated in the page: everything the checks need, as one JSON-able object
PAGE_PROBE = r"""
(() => {
  const rows = [...document.querySelectorAll('#summary-table tbody tr')]
      .filter(r => r.querySelectorAll('td').length >= 7);
  const imgs = [...document.images].map(i => ({src: (i.getAttribute('src') || '').slice(0, 60),
      ok: i.complete && i.naturalWidth > 0 && i.naturalHeight > 0}));
  const svgs = [...document.querySelectorAll('figure svg')].map(s => {
      const b = s.getBoundingClientRect();
      return {w: b.width, h: b.height, children: s.querySelectorAll('path,use,line,text,rect').length}; });
  const resources = performance.getEntriesByType('resource').map(e => e.name);
  return {title: document.title, summary_rows: rows.length, figures: document.querySelectorAll('figure').length,
          imgs, svgs, resources, height: document.documentElement.scrollHeight};
})()
"""


def find_chromium(explicit=None):
    for c in [explicit, os.environ.get("CHROMIUM"), "/usr/bin/chromium", "chromium", "chromium-browser",
              "google-chrome", "google-chrome-stable"]:
        if c and (Path(c).is_file() or shutil.which(c)):
            return shutil.which(c) or c
    return None


# --------------------------------------------------------------------------- CDP over a pipe
class CDP:
    """Minimal DevTools-protocol client over --remote-debugging-pipe (fd 3 in, fd 4 out of Chromium)."""

    def __init__(self, chromium, user_data_dir, timeout):
        to_child_r, self._w = os.pipe()
        self._r, from_child_w = os.pipe()

        def wire():  # in the child: its fd 3 reads our commands, fd 4 writes replies
            a = fcntl.fcntl(to_child_r, fcntl.F_DUPFD, 10)  # move out of the way of 3 and 4 first
            b = fcntl.fcntl(from_child_w, fcntl.F_DUPFD, 10)
            os.dup2(a, 3)
            os.dup2(b, 4)
            os.set_inheritable(3, True)
            os.set_inheritable(4, True)

        self.log = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(
            [chromium, *FLAGS, f"--user-data-dir={user_data_dir}", "--remote-debugging-pipe",
             f"--window-size={WIDTH},{HEIGHT}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=self.log, stderr=subprocess.STDOUT, preexec_fn=wire, close_fds=False)
        os.close(to_child_r)
        os.close(from_child_w)
        self.timeout = timeout
        self._buf = b""
        self._id = 0
        self.events = []

    def _read_message(self, deadline):
        while b"\0" not in self._buf:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no answer from Chromium over the DevTools pipe")
            ready, _, _ = select.select([self._r], [], [], left)
            if ready:
                chunk = os.read(self._r, 1 << 20)
                if not chunk:
                    raise ConnectionError("Chromium closed the DevTools pipe")
                self._buf += chunk
        msg, self._buf = self._buf.split(b"\0", 1)
        return json.loads(msg)

    def send(self, method, params=None, session=None):
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            m = self._read_message(deadline)
            if m.get("id") == self._id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            self.events.append(m)

    def wait_event(self, method, seconds):
        deadline = time.monotonic() + seconds
        for e in self.events:
            if e.get("method") == method:
                return e
        while True:
            m = self._read_message(deadline)
            self.events.append(m)
            if m.get("method") == method:
                return m

    def drain(self, seconds):
        deadline = time.monotonic() + seconds
        try:
            while True:
                self.events.append(self._read_message(deadline))
        except TimeoutError:
            pass

    def close(self):
        try:
            self.send("Browser.close")
        except Exception:  # noqa: BLE001 - closing anyway
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        for fd in (self._r, self._w):
            try:
                os.close(fd)
            except OSError:
                pass


def check_cdp(page, screenshot, chromium, timeout, full_page=False):
    """(problems, facts) via the DevTools protocol."""
    problems = []
    with tempfile.TemporaryDirectory(prefix="render-check-") as profile:
        cdp = CDP(chromium, profile, timeout)
        try:
            targets = cdp.send("Target.getTargets")["targetInfos"]
            target = next((t["targetId"] for t in targets if t["type"] == "page"), None)
            if target is None:
                target = cdp.send("Target.createTarget", {"url": "about:blank"})["targetId"]
            sid = cdp.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
            for domain in ("Page", "Runtime", "Log"):
                cdp.send(f"{domain}.enable", session=sid)
            cdp.send("Emulation.setDeviceMetricsOverride",
                     {"width": WIDTH, "height": HEIGHT, "deviceScaleFactor": 1, "mobile": False}, session=sid)
            cdp.events.clear()
            nav = cdp.send("Page.navigate", {"url": page.resolve().as_uri()}, session=sid)
            if nav.get("errorText"):
                problems.append(f"navigation failed: {nav['errorText']}")
            cdp.wait_event("Page.loadEventFired", timeout)
            cdp.drain(0.5)
            probe = cdp.send("Runtime.evaluate", {"expression": PAGE_PROBE, "returnByValue": True},
                             session=sid)["result"]["value"]
            params = {"format": "png"}
            if full_page:
                params.update(captureBeyondViewport=True, clip={"x": 0, "y": 0, "width": WIDTH, "scale": 1,
                                                                "height": min(int(probe["height"]), 30000)})
            shot = cdp.send("Page.captureScreenshot", params, session=sid)["data"]
            import base64
            Path(screenshot).write_bytes(base64.b64decode(shot))
        finally:
            cdp.close()
    for e in cdp.events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.exceptionThrown":
            d = params.get("exceptionDetails", {})
            problems.append(f"uncaught exception: {d.get('exception', {}).get('description') or d.get('text')}")
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            args = " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", []))
            problems.append(f"console.{params['type']}: {args}")
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            entry = params["entry"]
            problems.append(f"log error ({entry.get('source')}): {entry.get('text')} {entry.get('url', '')}")
    problems += probe_problems(probe)
    return problems, probe


def probe_problems(probe):
    problems = []
    if probe["summary_rows"] < 1:
        problems.append("summary table (#summary-table) has no rows")
    bad_imgs = [i["src"] for i in probe["imgs"] if not i["ok"]]
    if bad_imgs:
        problems.append(f"{len(bad_imgs)} <img> not loaded: {bad_imgs[:5]}")
    empty = [k for k, s in enumerate(probe["svgs"]) if not (s["w"] > 0 and s["h"] > 0 and s["children"] > 0)]
    if empty:
        problems.append(f"{len(empty)} of {len(probe['svgs'])} figure <svg> empty or zero-sized: #{empty[:10]}")
    remote = [r for r in probe.get("resources", []) if not r.startswith(("data:", "file:", "about:"))]
    if remote:
        problems.append(f"page fetched {len(remote)} non-local resources (must be self-contained): {remote[:5]}")
    return problems


# --------------------------------------------------------------------------- CLI fallback
class _DomProbe(HTMLParser):
    def __init__(self):
        super().__init__()
        self.stack, self.summary_rows, self.imgs, self.svgs = [], 0, [], []
        self._in_summary = self._in_tbody = False
        self._row_tds = 0
        self._svg_depth = 0
        self._svg_children = 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "table" and a.get("id") == "summary-table":
            self._in_summary = True
        elif tag == "tbody" and self._in_summary:
            self._in_tbody = True
        elif tag == "tr" and self._in_tbody:
            self._row_tds = 0
        elif tag == "td" and self._in_tbody:
            self._row_tds += 1
        elif tag == "img":
            self.imgs.append(a.get("src") or "")
        if tag == "svg":
            if self._svg_depth == 0:
                self._svg_children = 0
            self._svg_depth += 1
        elif self._svg_depth and tag in ("path", "use", "line", "text", "rect"):
            self._svg_children += 1

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        if tag == "svg":
            self.handle_endtag(tag)

    def handle_endtag(self, tag):
        if tag == "tr" and self._in_tbody and self._row_tds >= 7:
            self.summary_rows += 1
        elif tag == "tbody":
            self._in_tbody = False
        elif tag == "table" and self._in_summary and not self._in_tbody:
            self._in_summary = False
        elif tag == "svg" and self._svg_depth:
            self._svg_depth -= 1
            if self._svg_depth == 0:
                self.svgs.append({"w": 1, "h": 1, "children": self._svg_children})


def check_cli(page, screenshot, chromium, timeout, full_page=False):
    problems = []
    url = page.resolve().as_uri()
    with tempfile.TemporaryDirectory(prefix="render-check-") as profile:
        base = [chromium, *FLAGS, f"--user-data-dir={profile}", "--enable-logging=stderr", "--v=0"]
        dom = subprocess.run(base + ["--dump-dom", url], capture_output=True, text=True, timeout=timeout)
        shot = subprocess.run(base + [f"--screenshot={Path(screenshot).resolve()}", f"--window-size={WIDTH},{HEIGHT}",
                                      url], capture_output=True, text=True, timeout=timeout)
    log = dom.stderr + shot.stderr
    for line in log.splitlines():
        if re.search(r"Uncaught|ERROR:CONSOLE|Failed to load resource|console\.error", line):
            problems.append(f"console: {line.strip()[:300]}")
    if dom.returncode != 0 or not dom.stdout.strip():
        problems.append(f"--dump-dom failed (exit {dom.returncode})")
    if not Path(screenshot).is_file():
        problems.append(f"no screenshot written (exit {shot.returncode})")
    p = _DomProbe()
    p.feed(dom.stdout)
    imgs = [{"src": s[:60], "ok": s.startswith("data:") and len(s) > 30} for s in p.imgs]
    probe = {"summary_rows": p.summary_rows, "imgs": imgs, "svgs": p.svgs, "resources": [],
             "figures": dom.stdout.count("<figure")}
    return problems + probe_problems(probe), probe


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m verification.render_check", description=__doc__.split("\n")[0])
    ap.add_argument("page", type=Path, help="the report page, e.g. reports/index.html")
    ap.add_argument("--screenshot", type=Path, default=None, help="PNG path (default: screenshot.png beside page)")
    ap.add_argument("--chromium", default=None, help="browser executable (default /usr/bin/chromium, $CHROMIUM)")
    ap.add_argument("--mode", choices=("cdp", "cli"), default="cdp")
    ap.add_argument("--full-page", action="store_true", help="screenshot the whole page, not the first 2000 px "
                    "(cdp mode only)")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per browser operation")
    args = ap.parse_args(argv)
    if not args.page.is_file():
        print(f"render_check: FAIL: {args.page} does not exist", file=sys.stderr)
        return 2
    chromium = find_chromium(args.chromium)
    if chromium is None:
        print("render_check: FAIL: no Chromium found (apt-get install -y chromium, or --chromium PATH)",
              file=sys.stderr)
        return 3
    screenshot = args.screenshot or args.page.with_name("screenshot.png")
    mode = args.mode
    try:
        problems, probe = (check_cdp if mode == "cdp" else check_cli)(args.page, screenshot, chromium, args.timeout,
                                                                     args.full_page)
    except (OSError, TimeoutError, ConnectionError, RuntimeError, KeyError, subprocess.SubprocessError) as exc:
        if mode != "cdp":
            raise
        print(f"render_check: DevTools pipe failed ({type(exc).__name__}: {exc}); falling back to --mode cli",
              file=sys.stderr)
        mode = "cli"
        problems, probe = check_cli(args.page, screenshot, chromium, args.timeout,
                                                                     args.full_page)
    print(f"render_check ({mode}, {chromium}): {args.page}: {probe.get('summary_rows')} summary rows, "
          f"{probe.get('figures')} figures, {len(probe.get('svgs', []))} svg, {len(probe.get('imgs', []))} img; "
          f"screenshot {screenshot}")
    if problems:
        for p in problems:
            print(f"render_check: FAIL: {p}", file=sys.stderr)
        return 1
    print("render_check: OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
