#!/usr/bin/env python3
"""Renders `allanlot report` in a real browser (headless Chromium) at 1280, 1400 and 1920 px and
checks what a reader would see: nothing clipped, scrolled or overflowing; no table cell broken
inside a number, a unit or a name (the lot judged against a spec, so that its verdict cells,
the longest, are measured too); legends
whole; slope labels off the curves; per channel an Allan deviation panel with OADEV, the fit
and its terms (the other statistics behind tick boxes that work), a TDEV panel, both in the
units of the coefficient table (dimensionless for a clock's phase data), and a collapsible
deviation table; no empty panel and no fit wording when the fit was not computed; lot plots
never pooling channels of different units; and screenshots that are not blank.

Three lots: a simulated IMU lot (lot page and a unit page), a clock's PHASE.DAT beside a GPS
receiver's fractional frequency, both channels named /data, and the IMU lot analysed with
--no-fit --no-psd. The measurements come from measure_report.js, which the test appends to a
copy of each page: Chromium runs it headless and --dump-dom carries its JSON out.

Usage: check_report.py ALLANLOT_BINARY WORK_DIR
Exit status: 0 passed, 1 failed, 77 skipped (no Chromium installed; CTest's SKIP_RETURN_CODE).
Needs only the Python standard library (the PNG is decoded with zlib).
"""
import json
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import time
import zlib

SKIP = 77
HERE = os.path.dirname(os.path.abspath(__file__))
PHASE_DAT = os.path.join(HERE, "..", "data", "stable32", "phasedat", "PHASE.DAT")
WIDTHS = (1280, 1400, 1920)

# A lot small enough to simulate and analyse in seconds, even under ASan: five units of two
# channels at 100 Hz. The accelerometer's sinusoid (a bump of the Allan deviation near 7 s that
# eq. (3) has no term for) makes its fit poor, so that the summary tables carry the longest
# status a real lot shows ("ok (fit: poor fit (chi2/dof = ...))").
MODEL = """{"sample_rate_hz": 100, "lot_spread": {"N": 0.1},
 "channels": {"gyro_x": {"units": "deg/s", "terms": {"N": 0.005, "B": 0.001, "K": 1e-4}},
              "accel_x": {"units": "m/s^2", "terms": {"N": 0.002, "B": 0.0005},
                          "effects": [{"type": "sinusoid", "amplitude": 0.01,
                                       "frequency_hz": 0.05}]}}}"""
UNITS = 5
# Limits the lot straddles (gyro N = 0.005 deg/s*s^0.5 = 0.3 deg/sqrt(h), B = 3.6 deg/h; accel
# N = 0.002 m/s^2*s^0.5 = 0.12 m/s/sqrt(h), B = 0.051 mg; 10 % spread in N): verdicts of every
# kind, each quoting two terms in the spec's units.
SPEC = """{"channels": {
 "gyro_*": {"N": {"max": 0.3, "unit": "deg/sqrt(h)"}, "B": {"max": 5, "unit": "deg/h"}},
 "accel_*": {"N": {"max": 0.12, "unit": "m/s/sqrt(h)"}, "B": {"max": 0.05, "unit": "mg"}}}}"""
CHANNELS = ["accel_x", "gyro_x"]
# analyze's default statistics: OADEV shown, the others behind tick boxes; TDEV on its own.
DEFAULT_STAT = "oadev"
OTHER_STATS = {"mdev", "hdev", "ohdev", "totdev"}
STATS = {"oadev", "mdev", "hdev", "ohdev", "totdev", "tdev"}

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


def chromium_cmd(chromium, profile, width, height=2000):
    return [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
            "--hide-scrollbars", "--user-data-dir=" + profile,
            "--window-size=%d,%d" % (width, height)]


def measure(chromium, profile, page, width):
    """The measurements of measure_report.js on `page` rendered `width` px wide."""
    html = open(page, encoding="utf-8").read()
    script = open(os.path.join(HERE, "measure_report.js"), encoding="utf-8").read()
    # A copy beside the page, so that its relative links and anchors stay as they are.
    probe = os.path.join(os.path.dirname(page), ".probe-" + os.path.basename(page))
    with open(probe, "w", encoding="utf-8") as f:
        f.write(html.replace("</body>", "<script>\n" + script + "</script>\n</body>"))
    dom = run(chromium_cmd(chromium, profile, width) + ["--dump-dom", "file://" + probe]).decode()
    os.remove(probe)
    m = re.search(r'<pre id="allanlot-measure">(.*?)</pre>', dom, re.S)
    if not m:
        raise RuntimeError("%s: the measuring script left no result" % page)
    text = m.group(1).replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"')
    return json.loads(text.replace("&amp;", "&"))


def same_unit(axis, table):
    # The axis prints the table's "1" as "dimensionless".
    return axis == table or (axis == "dimensionless" and table == "1")


def check_clock_model(c, a, t, fail):
    """A clock's section: the power-law model and each detected level's asymptote on the Allan
    panel, the levels' table, and the axes in the clock's own units (docs/clocks.md)."""
    if "power-law model" not in a["visible"]:
        fail("%s: the Allan panel has no power-law model" % c["id"])
    for level in c["detected"]:
        if not any(e.startswith(level + ": slope") for e in a["visible"]):
            fail("%s: no asymptote of the detected level %s" % (c["id"], level))
    if not c["has_coef"]:
        fail("%s: no table of the power-law levels" % c["id"])
    if a["yunit"] != "dimensionless":
        fail("%s: the Allan axis is in %r, not fractional frequency" % (c["id"], a["yunit"]))
    if t and t["yunit"] != "s":
        fail("%s: the TDEV axis is in %r, not s" % (c["id"], t["yunit"]))


def check_channel(c, fit, fail, clock=False):
    """One channel section: the Allan panel (OADEV, the fit and its terms, tick boxes), the
    TDEV panel, both in the table's units, labels off the curves, the deviation tables; for a
    clock the power-law model in place of the fit."""
    a, t = c["adev"], c["tdev"]
    if not a:
        fail("%s: no Allan deviation panel" % c["id"])
        return
    stats = [e.split(" ")[0] for e in a["visible"] if e.split(" ")[0] in STATS]
    if stats != [DEFAULT_STAT]:
        fail("%s: the Allan panel shows %s by default, expected only %s"
             % (c["id"], stats, DEFAULT_STAT))
    if clock:
        check_clock_model(c, a, t, fail)
    elif fit:
        # A poor fit's curve is its model's, labelled "model: eq. (3) + ..." (fit-and-psd.md).
        if not any(e == "eq. (3) fit" or e.startswith("model: eq. (3)") for e in a["visible"]):
            fail("%s: the Allan panel has no eq. (3) fit or model" % c["id"])
        for term in c["detected"]:
            if not any(e.startswith(term + ": slope") for e in a["visible"]):
                fail("%s: no asymptote of the detected term %s" % (c["id"], term))
        if not c["has_coef"]:
            fail("%s: no coefficient table" % c["id"])
    toggled = {b["stat"] for b in a["toggles"]}
    if toggled != OTHER_STATS:
        fail("%s: tick boxes for %s, expected %s" % (c["id"], sorted(toggled), sorted(OTHER_STATS)))
    for b in a["toggles"]:
        if not (b["hidden_before"] and b["shown_after"]):
            fail("%s: the tick box of %s does not show it (hidden before %s, shown after %s)"
                 % (c["id"], b["stat"], b["hidden_before"], b["shown_after"]))
    if a["labels_on_curves"]:
        fail("%s: labels on the curves: %s" % (c["id"], a["labels_on_curves"]))
    if not t:
        fail("%s: no TDEV panel" % c["id"])
    # The plots' units are the table's: B's for a deviation of the rate, Q's for a time error.
    if not clock and (fit or c["has_coef"]):
        if not same_unit(a["yunit"], c["coef_units"].get("B")):
            fail("%s: the Allan axis is in %r, the table's B in %r"
                 % (c["id"], a["yunit"], c["coef_units"].get("B")))
        if t and not same_unit(t["yunit"], c["coef_units"].get("Q")):
            fail("%s: the TDEV axis is in %r, the table's Q in %r"
                 % (c["id"], t["yunit"], c["coef_units"].get("Q")))
    d = c["devtables"]
    if not d:
        fail("%s: no deviation tables" % c["id"])
    else:
        if not d["closed"]:
            fail("%s: the deviation tables are not folded away" % c["id"])
        named = {x.split(" ")[0] for x in d["captions"]}
        if not STATS <= named:
            fail("%s: deviation tables of %s, expected %s" % (c["id"], sorted(named),
                                                              sorted(STATS)))


def check_page(m, label, fail, fit=True, channels=None, dists=None, tables=None, verdicts=False,
               clock=False):
    """The checks every page gets, and the per-channel and lot ones asked for."""
    where = "%s at %d px" % (label, m["width"])
    f = lambda msg: fail("%s: %s" % (where, msg))
    if m["error"]:
        f("the measuring script failed: " + m["error"])
    for o in m["overflow"]:
        f("clipped or overflowing: " + o)
    for o in m["text_out"]:
        f("text outside its plot: " + o)
    for o in m["truncated"]:
        f("legend entry cut: " + o)
    for o in m["empty"]:
        f("empty panel: " + o)
    if not m["probe_caught"]:
        f("the measuring script does not see a token broken over two lines (its probe)")
    if m["cells"] == 0:
        f("no table cell measured")
    for o in m["token_breaks"]:
        f("a table cell breaks inside a token: " + o)
    if not fit:
        for text in m["plot_texts"] + m["headings"]:
            if "eq. (3) fit" in text or "the fit" in text.lower():
                f("fit wording without a fit: %r" % text)
    if channels is not None:
        if len(m["channels"]) != channels:
            f("%d channel sections, expected %d" % (len(m["channels"]), channels))
        for c in m["channels"]:
            check_channel(c, fit, f, clock)
    if dists is not None:
        got = sorted(d["title"] for d in m["dists"])
        if len(got) != len(dists) or any(not g.startswith(e) for g, e in zip(got, sorted(dists))):
            f("distribution plots %s, expected one per channel and units: %s" % (got, dists))
    if verdicts and m["verdict_cells"] == 0:
        f("no spec verdict cell (the lot summary's spec columns)")
    if tables is not None:
        got = sorted(m["summary_tables"])
        if len(got) != len(tables) or any(not g.startswith(e) for g, e in zip(got, sorted(tables))):
            f("summary tables %s, expected one per channel and units: %s" % (got, tables))


def check_screenshot(chromium, profile, page, png, width, fail):
    """Not blank, and the plots' colours are on it (the oadev blue, the fit's black), i.e. the
    SVG was rendered, not just parsed."""
    run(chromium_cmd(chromium, profile, width) + ["--screenshot=" + png, "file://" + page])
    blue, black = (0x1f, 0x77, 0xb4), (0, 0, 0)
    w, h, ink, colours, near = pixel_stats(png, [blue, black])
    print("%s: %dx%d, %.1f %% non-white, %d colours, %d blue, %d black pixels (sampled)"
          % (os.path.basename(png), w, h, 100 * ink, colours, near[blue], near[black]))
    if (w, h) != (width, 2000):
        fail("%s is %dx%d" % (png, w, h))
    if ink < 0.02 or colours < 50:
        fail("%s looks blank (%.2f %% ink, %d colours)" % (png, 100 * ink, colours))
    if near[blue] < 10:
        fail("%s: hardly any plot colour (%d blue pixels)" % (png, near[blue]))


def make_lots(allanlot, work):
    """The three lots' reports: the IMU lot (with unit pages), the clocks, and --no-fit."""
    with open(os.path.join(work, "lot.json"), "w") as f:
        f.write(MODEL)
    run([allanlot, "simulate", "-q", "--model", os.path.join(work, "lot.json"), "--lot",
         str(UNITS), "--duration", "600", "--seed", "5", "-o", os.path.join(work, "lot")])
    results = os.path.join(work, "results")
    # The layout does not depend on which model a poor fit's curve is of; modelling the lot's
    # five accelerometers as diagnose does takes 36 s of CPU against 0.9 s with the release build
    # (minutes under ASan, which CI cannot spare; test_channel_model checks that the report draws
    # a model's curve).
    run([allanlot, "analyze", "-q", "--model-poor-fits", "off", "-o", results,
         os.path.join(work, "lot")])
    with open(os.path.join(work, "spec.json"), "w") as f:
        f.write(SPEC)
    run([allanlot, "summarize", "-q", "--spec", os.path.join(work, "spec.json"), results])
    report = os.path.join(work, "report", "report.html")
    os.makedirs(os.path.dirname(report))
    run([allanlot, "report", "-q", "--unit-pages", "always", results, "-o", report])
    # A clock's phase (PHASE.DAT, time error in s) and a GPS receiver's fractional frequency,
    # both single-column files whose channel is /data.
    clocks = os.path.join(work, "clocks")
    os.makedirs(clocks)
    shutil.copy(PHASE_DAT, os.path.join(clocks, "PHASE.DAT"))
    rng = random.Random(21)
    with open(os.path.join(clocks, "GPS.txt"), "w") as f:
        y = 0.0
        for _ in range(4000):
            y += rng.gauss(0, 2e-13)
            f.write("%.6e\n" % (rng.gauss(0, 3e-11) + y))
    clock_results = os.path.join(work, "clock_results")
    run([allanlot, "analyze", "-q", "-o", clock_results, "--data-type", "phase",
         "--sample-rate", "1", "--units", "s", os.path.join(clocks, "PHASE.DAT")])
    run([allanlot, "analyze", "-q", "-o", clock_results, "--data-type", "rate",
         "--sample-rate", "1", "--units", "1", os.path.join(clocks, "GPS.txt")])
    run([allanlot, "report", "-q", clock_results])
    nofit = os.path.join(work, "nofit_results")
    run([allanlot, "analyze", "-q", "--no-fit", "--no-psd", "-o", nofit, os.path.join(work, "lot")])
    run([allanlot, "report", "-q", nofit])
    return (report, os.path.join(work, "report", "report_units", "unit_0001.html"),
            os.path.join(clock_results, "report.html"), os.path.join(nofit, "report.html"))


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
    lot_page, unit_page, clock_page, nofit_page = make_lots(allanlot, work)
    profile = os.path.join(work, "profile")
    failures = []
    fail = failures.append

    # The links of the lot page to its unit pages, and the plots of a unit page.
    dom = run(chromium_cmd(chromium, profile, 1280) + ["--dump-dom", "file://" + lot_page]).decode()
    for u in range(1, UNITS + 1):
        if 'href="report_units/unit_%04d.html#u-unit_%04d"' % (u, u) not in dom:
            fail("lot page: no link to unit_%04d" % u)
    dom = run(chromium_cmd(chromium, profile, 1280) + ["--dump-dom", "file://" + unit_page]).decode()
    for c in CHANNELS:
        for kind in ("adev", "tdev", "psd", "xc"):
            n = len(re.findall(r'<svg[^>]* id="u-unit_0001-_imu_%s-%s"' % (c, kind), dom))
            if n != 1:
                fail("unit page: %d plots %s-%s, expected 1" % (n, c, kind))

    for width in WIDTHS:
        check_page(measure(chromium, profile, lot_page, width), "lot page", fail,
                   dists=["/imu/accel_x", "/imu/gyro_x"], tables=["/imu/accel_x", "/imu/gyro_x"],
                   verdicts=True)
        check_page(measure(chromium, profile, unit_page, width), "unit page", fail,
                   channels=len(CHANNELS))
        check_page(measure(chromium, profile, clock_page, width), "clock lot", fail,
                   channels=2, dists=[], tables=["/data (1, rate", "/data (s, phase"],
                   clock=True)
        check_page(measure(chromium, profile, nofit_page, width), "--no-fit --no-psd lot", fail,
                   fit=False, channels=UNITS * len(CHANNELS), dists=[],
                   tables=["/imu/accel_x", "/imu/gyro_x"])
        for name, page in (("lot", lot_page), ("unit", unit_page)):
            check_screenshot(chromium, profile, page,
                             os.path.join(work, "%s-%d.png" % (name, width)), width, fail)

    print("browser check took %.1f s" % (time.time() - t0))
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
