#!/usr/bin/env python3
"""Renders `allanlot report` in a real browser (headless Chromium) and checks what a reader
would see: the screenshots are not blank and carry the plots' colours, and the DOM the browser
built holds the expected plots.

Usage: check_report.py ALLANLOT_BINARY WORK_DIR
Exit status: 0 passed, 1 failed, 77 skipped (no Chromium installed; CTest's SKIP_RETURN_CODE).
Needs only the Python standard library (the PNG is decoded with zlib).
"""
import os
import re
import shutil
import struct
import subprocess
import sys
import time
import zlib

SKIP = 77

# A lot small enough to simulate and analyse in seconds, even under ASan: three units of two
# channels at 100 Hz.
MODEL = """{"sample_rate_hz": 100, "lot_spread": {"N": 0.1},
 "channels": {"gyro_x": {"units": "deg/s", "terms": {"N": 0.005, "B": 0.001, "K": 1e-4}},
              "accel_x": {"units": "m/s^2", "terms": {"N": 0.002, "B": 0.0005}}}}"""
UNITS = 3
CHANNELS = ["accel_x", "gyro_x"]


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def run(cmd, **kw):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=240, **kw)
    if proc.returncode != 0:
        raise RuntimeError("%s failed (%d):\n%s\n%s" % (" ".join(cmd), proc.returncode,
                                                       proc.stdout.decode(errors="replace"),
                                                       proc.stderr.decode(errors="replace")))
    return proc.stdout


def decode_png(path):
    """Returns (width, height, channels, rows) for an 8-bit RGB or RGBA PNG, rows as bytes."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    pos, idat, width = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or color not in (2, 6) or interlace != 0:
                raise ValueError("unsupported PNG: depth %d colour type %d" % (depth, color))
            channels = 3 if color == 2 else 4
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + length
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        ftype, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        if ftype == 1:
            for i in range(channels, stride):
                line[i] = (line[i] + line[i - channels]) & 255
        elif ftype == 2:
            line = bytearray((a + b) & 255 for a, b in zip(line, prev))
        elif ftype == 3:
            for i in range(stride):
                left = line[i - channels] if i >= channels else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif ftype == 4:
            for i in range(stride):
                a = line[i - channels] if i >= channels else 0
                b = prev[i]
                c = prev[i - channels] if i >= channels else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def pixel_stats(path, colours):
    """Fraction of non-white pixels, number of distinct colours, and per colour of `colours`
    (RGB tuples) the number of pixels within a small distance of it (anti-aliasing)."""
    width, height, ch, rows = decode_png(path)
    non_white, distinct = 0, set()
    near = {c: 0 for c in colours}
    for row in rows:
        for x in range(0, width * ch, ch * 2):  # every second pixel: plenty, and twice as fast
            px = (row[x], row[x + 1], row[x + 2])
            if px != (255, 255, 255):
                non_white += 1
                distinct.add(px)
                for c in colours:
                    if abs(px[0] - c[0]) + abs(px[1] - c[1]) + abs(px[2] - c[2]) < 40:
                        near[c] += 1
    return width, height, non_white / (width * height / 2), len(distinct), near


def chromium_cmd(chromium, profile):
    return [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
            "--hide-scrollbars", "--user-data-dir=" + profile, "--window-size=1400,2000"]


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 1
    allanlot, work = sys.argv[1], os.path.abspath(sys.argv[2])
    chromium = find_chromium()
    if not chromium:
        print("skipped: no chromium (apt-get install chromium)")
        return SKIP
    t0 = time.time()
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(os.path.join(work, "lot.json"), "w") as f:
        f.write(MODEL)
    run([allanlot, "simulate", "-q", "--model", os.path.join(work, "lot.json"), "--lot",
         str(UNITS), "--duration", "600", "--seed", "5", "-o", os.path.join(work, "lot")])
    results = os.path.join(work, "results")
    run([allanlot, "analyze", "-q", "-o", results, os.path.join(work, "lot")])
    report = os.path.join(work, "report", "report.html")
    os.makedirs(os.path.dirname(report))
    run([allanlot, "report", "-q", "--unit-pages", "always", results, "-o", report])
    unit_page = os.path.join(work, "report", "report_units", "unit_0001.html")
    profile = os.path.join(work, "profile")
    failures = []

    # 1. The DOM Chromium built: every plot is an <svg> element with its id.
    dom = run(chromium_cmd(chromium, profile) + ["--dump-dom", "file://" + report]).decode()
    dists = re.findall(r'<svg[^>]* id="dist-[^"]*"', dom)
    if len(dists) != len(CHANNELS):
        failures.append("lot page: %d distribution plots, expected %d" % (len(dists),
                                                                          len(CHANNELS)))
    for u in range(1, UNITS + 1):
        if 'href="report_units/unit_%04d.html#u-unit_%04d"' % (u, u) not in dom:
            failures.append("lot page: no link to unit_%04d" % u)
    dom = run(chromium_cmd(chromium, profile) + ["--dump-dom", "file://" + unit_page]).decode()
    for c in CHANNELS:
        for kind in ("adev", "psd", "xc"):
            n = len(re.findall(r'<svg[^>]* id="u-unit_0001-_imu_%s-%s"' % (c, kind), dom))
            if n != 1:
                failures.append("unit page: %d plots %s-%s, expected 1" % (n, c, kind))

    # 2. Screenshots: not blank, and the plots' colours are on them (the oadev blue, the fit's
    # black, the grid), i.e. the SVG was rendered, not just parsed.
    blue, black = (0x1f, 0x77, 0xb4), (0, 0, 0)
    for name, page in (("lot", report), ("unit", unit_page)):
        png = os.path.join(work, name + ".png")
        run(chromium_cmd(chromium, profile) + ["--screenshot=" + png, "file://" + page])
        w, h, ink, colours, near = pixel_stats(png, [blue, black])
        print("%s.png: %dx%d, %.1f %% non-white, %d colours, %d blue, %d black pixels (sampled)"
              % (name, w, h, 100 * ink, colours, near[blue], near[black]))
        if (w, h) != (1400, 2000):
            failures.append("%s.png is %dx%d" % (name, w, h))
        if ink < 0.02 or colours < 50:
            failures.append("%s.png looks blank (%.2f %% ink, %d colours)" % (name, 100 * ink,
                                                                          colours))
        # The lot page's plots are small strip plots; a unit page is mostly curves.
        if near[blue] < (10 if name == "lot" else 200):
            failures.append("%s.png: hardly any plot colour (%d blue pixels)" % (name, near[blue]))
        if name == "unit" and near[black] < 200:
            failures.append("unit.png: no fit curve or text (%d black pixels)" % near[black])

    print("browser check took %.1f s" % (time.time() - t0))
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
