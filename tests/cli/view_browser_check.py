#!/usr/bin/env python3
"""Opens a `hedra view` page in headless Chromium and checks that it works.

One Chromium run loads the page (optionally with a URL fragment such as
'#face=3'), lets it run for a few seconds of virtual time, then dumps the DOM
and takes a screenshot. The page passes when:
  * <html> has data-hedra-ready="true" (the viewer finished its first render);
  * data-hedra-errors is "0" (no uncaught error, rejected promise or
    console.error; the page's error log is printed otherwise);
  * every --expect NAME=VALUE holds for the attribute data-hedra-NAME;
  * the 3D viewport (the screenshot left of the side panel) is not blank: at
    least --min-drawn of its pixels differ from the page background, and
    their brightness varies (standard deviation above --min-stddev).

Exit status: 0 pass, 1 fail (reasons on stderr), 77 Chromium not found
(the caller skips). The PNG reader handles what Chromium writes: 8-bit RGB or
RGBA, non-interlaced, any of the five row filters.
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

SKIP = 77
PANEL_WIDTH = 360  # CSS pixels, see tools/cli/view/viewer.css
BACKGROUND = (0xF3, 0xF4, 0xF6)


def find_chromium():
    override = os.environ.get("HEDRA_CHROMIUM")
    if override:
        return override if shutil.which(override) else None
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def read_png(path):
    """Returns (width, height, rows) with rows a list of bytes objects of RGB(A) pixels."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG file")
    pos, idat, header = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    width, height, depth, color, _, _, interlace = header
    if depth != 8 or color not in (2, 6) or interlace != 0:
        raise ValueError("unsupported PNG (depth %d, colour type %d, interlace %d)" % (depth, color, interlace))
    channels = 3 if color == 2 else 4
    stride = width * channels
    raw = zlib.decompress(b"".join(idat))
    rows, previous = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        line = bytearray(raw[start + 1:start + 1 + stride])
        if kind == 1:
            for i in range(channels, stride):
                line[i] = (line[i] + line[i - channels]) & 0xFF
        elif kind == 2:
            for i in range(stride):
                line[i] = (line[i] + previous[i]) & 0xFF
        elif kind == 3:
            for i in range(stride):
                left = line[i - channels] if i >= channels else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 0xFF
        elif kind == 4:
            for i in range(stride):
                a = line[i - channels] if i >= channels else 0
                b = previous[i]
                c = previous[i - channels] if i >= channels else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                predictor = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + predictor) & 0xFF
        elif kind != 0:
            raise ValueError("bad PNG row filter %d" % kind)
        rows.append(bytes(line))
        previous = line
    return width, height, channels, rows


def viewport_statistics(png, panel_width):
    """Fraction of viewport pixels that differ from the background, and the
    standard deviation of their brightness, sampling every other pixel."""
    width, height, channels, rows = read_png(png)
    right = max(width - panel_width, 1)
    drawn = total = 0
    s = s2 = 0.0
    for y in range(0, height, 2):
        line = rows[y]
        for x in range(0, right, 2):
            i = x * channels
            r, g, b = line[i], line[i + 1], line[i + 2]
            total += 1
            if abs(r - BACKGROUND[0]) + abs(g - BACKGROUND[1]) + abs(b - BACKGROUND[2]) > 12:
                drawn += 1
            v = 0.299 * r + 0.587 * g + 0.114 * b
            s += v
            s2 += v * v
    mean = s / total
    return drawn / total, max(s2 / total - mean * mean, 0.0) ** 0.5


def html_attributes(dom):
    match = re.search(r"<html([^>]*)>", dom)
    if not match:
        return {}
    return dict(re.findall(r'([a-zA-Z0-9_-]+)="([^"]*)"', match.group(1)))


def error_log(dom):
    match = re.search(r'<pre id="hedra-error-log"[^>]*>(.*?)</pre>', dom, re.S)
    return match.group(1).strip() if match else ""


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("html")
    parser.add_argument("--fragment", default="", help="URL fragment, e.g. '#face=3'")
    parser.add_argument("--expect", action="append", default=[], metavar="NAME=VALUE",
                        help="required value of the attribute data-hedra-NAME on <html>")
    parser.add_argument("--screenshot", help="keep the screenshot at this path")
    parser.add_argument("--size", default="1200,800", help="window size in pixels, 'W,H'")
    parser.add_argument("--min-drawn", type=float, default=0.02)
    parser.add_argument("--min-stddev", type=float, default=4.0)
    parser.add_argument("--timeout", type=float, default=90.0, help="seconds before Chromium is given up on")
    args = parser.parse_args()

    chromium = find_chromium()
    if not chromium:
        print("SKIP: Chromium not found (apt-get install chromium, or set HEDRA_CHROMIUM)", file=sys.stderr)
        return SKIP

    failures = []
    with tempfile.TemporaryDirectory(prefix="hedra_view_check_") as work:
        png = args.screenshot or os.path.join(work, "screenshot.png")
        if os.path.exists(png):
            os.remove(png)
        url = "file://" + os.path.abspath(args.html) + args.fragment
        command = [
            chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
            "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-first-run", "--hide-scrollbars",
            "--user-data-dir=" + os.path.join(work, "profile"), "--window-size=" + args.size,
            "--virtual-time-budget=5000", "--screenshot=" + png, "--dump-dom", url,
        ]
        try:
            run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=args.timeout,
                                 check=False)
        except subprocess.TimeoutExpired:
            print("FAIL: Chromium did not finish within %.0f s" % args.timeout, file=sys.stderr)
            return 1
        dom = run.stdout.decode("utf-8", "replace")
        if run.returncode != 0 or not dom:
            tail = run.stderr.decode("utf-8", "replace")[-2000:]
            print("FAIL: Chromium exited with %d and no DOM:\n%s" % (run.returncode, tail), file=sys.stderr)
            return 1

        attributes = html_attributes(dom)
        if attributes.get("data-hedra-ready") != "true":
            failures.append("the page never reported ready (data-hedra-ready=%r)" % attributes.get("data-hedra-ready"))
        errors = attributes.get("data-hedra-errors")
        if errors != "0":
            failures.append("JavaScript errors reported (data-hedra-errors=%r):\n%s" % (errors, error_log(dom)))
        for expectation in args.expect:
            name, _, value = expectation.partition("=")
            actual = attributes.get("data-hedra-" + name)
            if actual != value:
                failures.append("data-hedra-%s is %r, expected %r" % (name, actual, value))

        if not os.path.exists(png):
            failures.append("Chromium wrote no screenshot")
        else:
            width = int(args.size.split(",")[0])
            scale = read_png(png)[0] / width
            drawn, stddev = viewport_statistics(png, int(PANEL_WIDTH * scale))
            print("viewport: %.1f%% of pixels drawn, brightness stddev %.1f" % (100 * drawn, stddev))
            if drawn < args.min_drawn or stddev < args.min_stddev:
                failures.append("the 3D viewport is blank: %.2f%% of pixels drawn (need %.2f%%), brightness "
                                "stddev %.2f (need %.2f)" % (100 * drawn, 100 * args.min_drawn, stddev,
                                                             args.min_stddev))

    for failure in failures:
        print("FAIL: " + failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
