#!/usr/bin/env python3
"""Opens a pipescope HTML report in headless Chromium and checks that it drew without errors.

    check_report_in_browser.py REPORT.html --screenshot OUT.png [--chromium PATH]
                               [--min-viewer-state drawn|unavailable]

Runs Chromium twice (software WebGL through SwiftShader, virtual time so the page can finish its work):
once with --dump-dom to read the final DOM and Chromium's console log, once with --screenshot. Fails (exit 1)
with a message unless:
  - <html data-pipescope-status> is "ready" and <pre id="pipescope-errors"> is empty;
  - Chromium's console log shows no uncaught JavaScript error;
  - data-viewer is "drawn" when the report has a point cloud ("unavailable" is accepted only with
    --min-viewer-state unavailable), "none" when it has none;
  - the screenshot is not blank;
  - every distance-ruler label and clock label sits where its value is, within 1.5 CSS px, recomputed from
    the strip geometry in the DOM and the mosaic's scale in the JSON embedded in the report.
Exit 2 for usage problems (no Chromium, unreadable report). Python 3 standard library only.
"""
import argparse
import fcntl
import html.parser
import json
import math
import os
import re
import select
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

TOLERANCE_PX = 1.5
CHROMIUM_NAMES = ["chromium", "chromium-browser", "google-chrome", "google-chrome-stable"]
CHROMIUM_FLAGS = [
    "--headless=new",
    "--no-sandbox",
    "--disable-dev-shm-usage",
    "--use-angle=swiftshader",        # software WebGL (no GPU needed)
    "--enable-unsafe-swiftshader",    # allow WebGL on SwiftShader in recent Chromium
    "--disable-gpu-compositing",      # software compositor: keeps the software GPU free for WebGL (much faster)
    "--hide-scrollbars",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-extensions",
    "--mute-audio",
    "--enable-logging=stderr",
    "--v=0",
]
# Chromium logs page console messages as "...:INFO:CONSOLE:<line>] "<message>", source: <url> (<line>)".
CONSOLE_LINE = re.compile(r":CONSOLE(?::\d+)?\]\s*(.*)")
CONSOLE_ERROR = re.compile(r"Uncaught|Unhandled|\b(?:[A-Z][a-zA-Z]*)?Error\b")


class Failure(Exception):
    pass


# ------------------------------------------------------------------------------------------ report data

def embedded_report_data(html_text):
    """The JSON of <script type="application/json" id="pipescope-data">."""
    match = re.search(r'<script[^>]*\bid="pipescope-data"[^>]*>(.*?)</script>', html_text, re.S)
    if not match:
        raise Failure("the report has no <script id=\"pipescope-data\"> element")
    try:
        return json.loads(match.group(1))
    except json.JSONDecodeError as error:
        raise Failure(f"the embedded report JSON does not parse: {error}")


# ------------------------------------------------------------------------------------------ DOM

class DomCollector(html.parser.HTMLParser):
    """Collects the attributes the check needs from Chromium's DOM dump."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.root_attrs = {}
        self.errors_attrs = None
        self.errors_text = []
        self.in_errors = False
        self.strips = {}          # data-strip -> attrs of the strip image
        self.ruler_labels = []
        self.clock_labels = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        classes = (attrs.get("class") or "").split()
        if tag == "html":
            self.root_attrs = attrs
        elif attrs.get("id") == "pipescope-errors":
            self.errors_attrs = attrs
            self.in_errors = True
        if "wall-strip-image" in classes:
            self.strips[attrs.get("data-strip")] = attrs
        if "ruler-label" in classes:
            self.ruler_labels.append(attrs)
        if "clock-label" in classes:
            self.clock_labels.append(attrs)

    def handle_endtag(self, tag):
        if tag == "pre":
            self.in_errors = False

    def handle_data(self, data):
        if self.in_errors:
            self.errors_text.append(data)


def parse_dom(dom_text):
    # Script bodies (the embedded data and libraries) are large and irrelevant here: drop them first.
    dom_text = re.sub(r"(<script\b[^>]*>).*?(</script>)", r"\1\2", dom_text, flags=re.S)
    collector = DomCollector()
    collector.feed(dom_text)
    collector.close()
    return collector


# ------------------------------------------------------------------------------------------ Chromium

def find_chromium(given):
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)) and not shutil.which(given):
            raise Failure(f"--chromium {given}: not an executable")
        return shutil.which(given) or given
    for name in CHROMIUM_NAMES:
        path = shutil.which(name)
        if path:
            return path
    raise Failure("no Chromium found (tried " + ", ".join(CHROMIUM_NAMES) + "); pass --chromium PATH")


def run_chromium(chromium, extra_args, url, timeout_s):
    """Runs Chromium once in a fresh profile; returns (stdout, stderr, seconds)."""
    with tempfile.TemporaryDirectory(prefix="pipescope-chromium-") as profile:
        command = [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", *extra_args, url]
        start = time.monotonic()
        try:
            done = subprocess.run(command, capture_output=True, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            raise Failure(f"Chromium did not finish within {timeout_s} s: {' '.join(command)}")
        seconds = time.monotonic() - start
    stdout = done.stdout.decode("utf-8", "replace")
    stderr = done.stderr.decode("utf-8", "replace")
    if done.returncode != 0:
        raise Failure(f"Chromium exited with status {done.returncode}:\n{stderr[-3000:]}")
    return stdout, stderr, seconds


def console_errors(stderr):
    found = []
    for line in stderr.splitlines():
        match = CONSOLE_LINE.search(line)
        if match and CONSOLE_ERROR.search(match.group(1)):
            found.append(match.group(1).strip())
    return found


class DevToolsPipe:
    """Minimal DevTools-protocol client over --remote-debugging-pipe (Chromium reads fd 3, writes fd 4)."""

    def __init__(self, chromium, args, timeout_s):
        self.timeout_s = timeout_s
        command_read, self.command_write = os.pipe()
        self.event_read, event_write = os.pipe()

        def child_fds():
            # Move both ends above 10 first, so that placing them on 3 and 4 cannot clobber either.
            high_read = fcntl.fcntl(command_read, fcntl.F_DUPFD, 10)
            high_write = fcntl.fcntl(event_write, fcntl.F_DUPFD, 10)
            os.dup2(high_read, 3)
            os.dup2(high_write, 4)

        self.profile = tempfile.TemporaryDirectory(prefix="pipescope-chromium-")
        self.process = subprocess.Popen(
            [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={self.profile.name}", "--remote-debugging-pipe", *args,
             "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            preexec_fn=child_fds, close_fds=False)
        os.close(command_read)
        os.close(event_write)
        self.buffer = b""
        self.next_id = 0

    def call(self, method, params=None, session=None):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.command_write, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + self.timeout_s
        while True:
            while b"\0" in self.buffer:
                raw, self.buffer = self.buffer.split(b"\0", 1)
                reply = json.loads(raw)
                if reply.get("id") == self.next_id:
                    if "error" in reply:
                        raise Failure(f"DevTools {method}: {reply['error']}")
                    return reply.get("result", {})
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not select.select([self.event_read], [], [], remaining)[0]:
                raise Failure(f"DevTools {method}: no answer within {self.timeout_s} s")
            chunk = os.read(self.event_read, 1 << 20)
            if not chunk:
                raise Failure(f"DevTools {method}: Chromium closed the pipe")
            self.buffer += chunk

    def close(self):
        try:
            self.call("Browser.close")
        except (Failure, OSError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self.command_write)
        os.close(self.event_read)
        self.profile.cleanup()


def measure_ready(chromium, url, window, timeout_s):
    """Real seconds from navigation to data-pipescope-status being set (no virtual time), and the page's own
    performance.now() at that moment in ms. Returns (None, None, reason) if it cannot be measured."""
    try:
        browser = DevToolsPipe(chromium, [window], timeout_s)
    except OSError as error:
        return None, None, str(error)
    try:
        browser.call("Browser.getVersion")
        target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        start = time.monotonic()
        browser.call("Page.navigate", {"url": url}, session)
        while time.monotonic() - start < timeout_s:
            result = browser.call("Runtime.evaluate", {
                "expression": "[document.documentElement.dataset.pipescopeStatus || '', "
                              "document.documentElement.dataset.readyMs || '']",
                "returnByValue": True}, session)
            status, page_ms = (result.get("result", {}).get("value") or ["", ""])
            if status:
                return time.monotonic() - start, page_ms, status
            time.sleep(0.05)
        return None, None, f"not ready within {timeout_s} s"
    except (Failure, OSError) as failure:
        return None, None, str(failure)
    finally:
        browser.close()


# ------------------------------------------------------------------------------------------ PNG

def decode_png(data):
    """Decodes an 8-bit grey/RGB/RGBA (optionally with alpha) non-interlaced PNG: (width, height, channels, rows)."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise Failure("the screenshot is not a PNG file")
    pos, idat, header = 8, [], None
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + length
    if header is None:
        raise Failure("the screenshot PNG has no IHDR chunk")
    width, height, depth, color_type, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(color_type)
    if depth != 8 or channels is None or interlace:
        raise Failure(f"unsupported screenshot PNG (depth {depth}, colour type {color_type}, interlace {interlace})")
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        line = bytearray(raw[start + 1:start + 1 + stride])
        if kind == 1:      # Sub
            for i in range(channels, stride):
                line[i] = (line[i] + line[i - channels]) & 255
        elif kind == 2:    # Up
            line = bytearray((a + b) & 255 for a, b in zip(line, previous))
        elif kind == 3:    # Average
            for i in range(stride):
                left = line[i - channels] if i >= channels else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 255
        elif kind == 4:    # Paeth
            for i in range(stride):
                a = line[i - channels] if i >= channels else 0
                b = previous[i]
                c = previous[i - channels] if i >= channels else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        elif kind != 0:
            raise Failure(f"screenshot PNG: bad filter type {kind} in row {y}")
        rows.append(line)
        previous = line
    return width, height, channels, rows


def screenshot_variation(path):
    """(standard deviation of luminance, share of pixels unlike the commonest colour) over a pixel grid."""
    with open(path, "rb") as file:
        width, height, channels, rows = decode_png(file.read())
    values, colours = [], {}
    step = 4
    for y in range(0, height, step):
        row = rows[y]
        for x in range(0, width, step):
            pixel = tuple(row[x * channels:x * channels + min(channels, 3)])
            colours[pixel] = colours.get(pixel, 0) + 1
            values.append(sum(pixel) / len(pixel))
    mean = sum(values) / len(values)
    deviation = math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))
    share = 1 - max(colours.values()) / len(values)
    return deviation, share, (width, height)


# ------------------------------------------------------------------------------------------ geometry

def number(attrs, key, what):
    try:
        value = float(attrs[key])
    except (KeyError, TypeError, ValueError):
        raise Failure(f"{what}: attribute {key} missing or not a number ({attrs.get(key)!r})")
    if not math.isfinite(value):
        raise Failure(f"{what}: attribute {key} is not finite")
    return value


def check_geometry(dom, report):
    """Returns (ruler labels checked, clock labels checked, worst error in px); raises Failure on a misplaced label."""
    mosaics = report.get("mosaics") or []
    problems, worst = [], 0.0

    def strip_of(label, what):
        strip = dom.strips.get(label.get("data-strip"))
        if strip is None:
            raise Failure(f"{what}: no strip image with data-strip={label.get('data-strip')!r}")
        index = int(number(strip, "data-mosaic", what))
        if not 0 <= index < len(mosaics):
            raise Failure(f"{what}: data-mosaic {index} is not an index into the {len(mosaics)} mosaics")
        return strip, mosaics[index]

    for label in dom.ruler_labels:
        what = f"ruler label {label.get('data-distance-m')} m on strip {label.get('data-strip')}"
        strip, mosaic = strip_of(label, what)
        col0, cols = number(strip, "data-col0", what), number(strip, "data-cols", what)
        width = number(strip, "data-width-css", what)
        x = number(label, "data-x-css", what)
        labelled = number(label, "data-distance-m", what)
        d0, per_col = mosaic.get("distance_m_at_col0"), mosaic.get("distance_m_per_col")
        if not mosaic.get("metric") or not isinstance(d0, (int, float)) or not per_col:
            raise Failure(f"{what}: the mosaic is not metric, yet it has a ruler label")
        px_per_col = width / cols
        column = col0 + x / px_per_col - 0.5          # column whose centre is under the label
        distance = d0 + per_col * column
        error_px = abs(distance - labelled) / abs(per_col) * px_per_col
        worst = max(worst, error_px)
        if error_px > TOLERANCE_PX:
            problems.append(f"{what}: sits at {distance:.5f} m, {error_px:.2f} px from where it belongs")

    for label in dom.clock_labels:
        what = f"clock label {label.get('data-clock-deg')} deg on strip {label.get('data-strip')}"
        strip, mosaic = strip_of(label, what)
        row0, rows = number(strip, "data-row0", what), number(strip, "data-rows", what)
        height = number(strip, "data-height-css", what)
        y = number(label, "data-y-css", what)
        labelled = number(label, "data-clock-deg", what)
        a0, per_row = mosaic.get("clock_deg_at_row0"), mosaic.get("clock_deg_per_row")
        if not isinstance(a0, (int, float)) or not per_row:
            raise Failure(f"{what}: the mosaic has no clock scale, yet it has a clock label")
        px_per_row = height / rows
        row = row0 + y / px_per_row - 0.5
        angle = a0 + per_row * row
        difference = (angle - labelled + 180.0) % 360.0 - 180.0
        error_px = abs(difference) / abs(per_row) * px_per_row
        worst = max(worst, error_px)
        if error_px > TOLERANCE_PX:
            problems.append(f"{what}: sits at {angle % 360:.2f} deg, {error_px:.2f} px from where it belongs")

    # Each mosaic's strips cover its columns once, in order; metric mosaics have ruler labels.
    for index, mosaic in enumerate(mosaics):
        strips = sorted((s for s in dom.strips.values() if s.get("data-mosaic") == str(index)),
                        key=lambda s: float(s.get("data-col0", 0)))
        covered = 0
        for strip in strips:
            col0, cols = int(number(strip, "data-col0", "strip")), int(number(strip, "data-cols", "strip"))
            if col0 != covered:
                problems.append(f"mosaic {index}: strips leave a gap or overlap at column {covered} (next starts at {col0})")
            covered = col0 + cols
        if covered != mosaic.get("width_px"):
            problems.append(f"mosaic {index}: strips cover {covered} of {mosaic.get('width_px')} columns")
        if mosaic.get("metric") and not any(dom.strips.get(l.get("data-strip"), {}).get("data-mosaic") == str(index)
                                            for l in dom.ruler_labels):
            problems.append(f"mosaic {index} is metric but has no ruler label")

    if problems:
        raise Failure("misplaced wall-strip labels:\n  " + "\n  ".join(problems[:20])
                      + (f"\n  ... and {len(problems) - 20} more" if len(problems) > 20 else ""))
    return len(dom.ruler_labels), len(dom.clock_labels), worst


# ------------------------------------------------------------------------------------------ main

def check(args):
    report_path = os.path.abspath(args.report)
    try:
        with open(report_path, encoding="utf-8") as file:
            html_text = file.read()
    except OSError as error:
        raise SystemExit(f"check_report_in_browser: cannot read {args.report}: {error}") from None
    report = embedded_report_data(html_text)
    has_cloud = bool(report.get("cloud") and report["cloud"].get("count"))
    chromium = find_chromium(args.chromium)
    url = "file://" + report_path
    window = f"--window-size={args.window_size}"
    budget = f"--virtual-time-budget={args.budget_ms}"

    dom_text, log, _ = run_chromium(chromium, [window, budget, "--dump-dom"], url, args.timeout)
    if "<html" not in dom_text:
        raise Failure("Chromium printed no DOM:\n" + log[-3000:])
    dom = parse_dom(dom_text)

    failures = []
    status = dom.root_attrs.get("data-pipescope-status")
    viewer = dom.root_attrs.get("data-viewer")
    errors_text = "".join(dom.errors_text).strip()
    if dom.errors_attrs is None:
        failures.append("the page has no <pre id=\"pipescope-errors\"> element")
    if errors_text:
        failures.append("the page collected errors:\n    " + errors_text.replace("\n", "\n    "))
    if status != "ready":
        failures.append(f"page status is {status!r}, not 'ready'"
                        + (" (it never became ready within the virtual time budget)" if status is None else ""))
    js_errors = console_errors(log)
    if js_errors:
        failures.append("Chromium's console log shows JavaScript errors:\n    " + "\n    ".join(js_errors[:10]))
    allowed_viewer = {"drawn"} if args.min_viewer_state == "drawn" else {"drawn", "unavailable"}
    if has_cloud and viewer not in allowed_viewer:
        failures.append(f"the report has a point cloud but data-viewer is {viewer!r} (want {' or '.join(sorted(allowed_viewer))})")
    if not has_cloud and viewer != "none":
        failures.append(f"the report has no point cloud but data-viewer is {viewer!r}, not 'none'")

    try:
        rulers, clocks, worst = check_geometry(dom, report)
    except Failure as failure:
        failures.append(str(failure))
        rulers = clocks = worst = None

    os.makedirs(os.path.dirname(os.path.abspath(args.screenshot)) or ".", exist_ok=True)
    shot = os.path.abspath(args.screenshot)
    if os.path.exists(shot):
        os.remove(shot)
    _, shot_log, _ = run_chromium(chromium, [window, budget, f"--screenshot={shot}"], url, args.timeout)
    if not os.path.exists(shot):
        failures.append("Chromium wrote no screenshot:\n" + shot_log[-2000:])
        deviation = share = None
        size = ("?", "?")
    else:
        deviation, share, size = screenshot_variation(shot)
        if deviation < 8 or share < 0.02:
            failures.append(f"the screenshot looks blank (luminance deviation {deviation:.1f}, "
                            f"{100 * share:.1f} % of pixels unlike the commonest colour)")

    # Time to ready in real time (the runs above use virtual time, whose clock is not the wall clock).
    ready_s, ready_page_ms, ready_note = measure_ready(chromium, url, window, args.timeout)
    if ready_s is None:
        timing = f"time to ready not measured ({ready_note})"
    else:
        timing = f"ready {ready_s:.2f} s after navigation (page clock {ready_page_ms} ms, status {ready_note})"

    size_mb = os.path.getsize(report_path) / 1e6
    summary = (f"{os.path.basename(report_path)}: {size_mb:.1f} MB, status={status}, viewer={viewer}, "
               f"{timing}; "
               f"ruler labels {rulers}, clock labels {clocks}, worst offset "
               f"{'n/a' if worst is None else f'{worst:.2f} px'}; screenshot {size[0]}x{size[1]}, "
               f"deviation {'n/a' if deviation is None else f'{deviation:.1f}'}")
    if failures:
        print("FAIL " + summary)
        for failure in failures:
            print("  - " + failure)
        return 1
    print("OK " + summary)
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[1].strip() or None,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("report", help="the report HTML file")
    parser.add_argument("--screenshot", required=True, help="where to write the screenshot (PNG)")
    parser.add_argument("--chromium", help="Chromium executable (default: chromium, chromium-browser, google-chrome)")
    parser.add_argument("--min-viewer-state", choices=["drawn", "unavailable"], default="drawn",
                        help="'unavailable' also accepts a report whose 3D view found no WebGL (default: drawn)")
    parser.add_argument("--window-size", default="1280,2400", help="browser window in CSS px, W,H (default 1280,2400)")
    parser.add_argument("--budget-ms", type=int, default=20000,
                        help="virtual time the page gets to become ready (default 20000)")
    parser.add_argument("--timeout", type=float, default=300, help="real seconds before giving up on Chromium (default 300)")
    args = parser.parse_args()
    try:
        return check(args)
    except Failure as failure:
        print(f"FAIL {args.report}: {failure}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
