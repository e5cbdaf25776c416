"""The Python API and the command line agree: simulate gives the recording's samples bit for
bit, deviation() and fit() give what `analyze` wrote, read_results()/read_lot_summary() read
back what the command line wrote (strings as str), and diagnose() returns diagnose --json."""
import csv
import json
import math

import numpy as np
import pytest

import allanlot
from conftest import run

MODEL = {"sample_rate_hz": 100, "units": "deg/s",
         "terms": {"N": 0.01, "B": 0.002, "K": 2e-4, "Q": 1e-4}}
DURATION = 300  # 30 000 samples: seconds of work even under AddressSanitizer


@pytest.fixture(scope="module")
def lot(tmp_path_factory, binary):
    d = tmp_path_factory.mktemp("cli")
    model = d / "model.json"
    model.write_text(json.dumps(MODEL))
    rec = d / "unit.h5"
    run(binary, "simulate", "--model", model, "--duration", DURATION, "--seed", 5, "-o", rec)
    out = d / "results"
    run(binary, "analyze", "-q", "-o", out, rec)
    return {"dir": d, "model": model, "recording": rec, "results": out / "unit.allan.h5",
            "outdir": out}


def test_simulate_equals_the_recording(lot):
    h5py = pytest.importorskip("h5py")
    sim = allanlot.simulate(lot["model"], duration=DURATION, seed=5)
    with h5py.File(lot["recording"], "r") as f:
        paths = []
        f.visititems(lambda name, obj: paths.append(name) if isinstance(obj, h5py.Dataset) else None)
        (path,) = paths
        np.testing.assert_array_equal(f[path][...], sim["gyro_x"])
    assert sim.rate == 100 and sim.units == {"gyro_x": "deg/s"}


def test_deviations_and_fit_equal_the_results_file(lot):
    res = allanlot.read_results(lot["results"])
    assert isinstance(res["device_id"], str) and res["device_id"] == "unit"
    (ch,) = res["channels"].values()
    assert ch["units"] == "deg/s" and ch["data_type"] == "rate"
    y = allanlot.simulate(lot["model"], duration=DURATION, seed=5)["gyro_x"]
    assert set(ch["allan"]) >= {"oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"}
    for stat, written in ch["allan"].items():
        r = allanlot.deviation(y, stat, rate=100.0, data_type="freq", threads=1)
        for key in ("m", "tau", "dev", "n", "edf", "dev_lo", "dev_hi", "alpha"):
            np.testing.assert_array_equal(getattr(r, key), written[key], err_msg=stat + " " + key)
    oadev = allanlot.deviation(y, "oadev", rate=100.0, data_type="freq", units="deg/s")
    f = allanlot.fit(oadev)
    assert f["status"] == ch["fit"]["status"]
    assert list(f["terms"]["term"]) == list(ch["fit"]["terms"]["term"])
    np.testing.assert_allclose(f["terms"]["value"], ch["fit"]["terms"]["value"], rtol=1e-12)
    np.testing.assert_allclose(f["terms"]["value_datasheet"],
                               ch["fit"]["terms"]["value_datasheet"], rtol=1e-12)
    assert list(f["readouts"]["name"]) == list(ch["fit"]["readouts"]["name"])


def test_lot_summary_columns_equal_the_csv(lot):
    cols = allanlot.read_lot_summary(lot["outdir"])
    with open(lot["outdir"] / "lot_summary.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert list(cols) == header
    for j, name in enumerate(header):
        for i, row in enumerate(body):
            got = cols[name][i]
            if isinstance(got, str):
                assert got == row[j], name
            elif row[j] == "":
                assert math.isnan(got), name
            else:  # the CSV prints each column to its own number of significant digits
                digits = len(row[j].split("e")[0].replace("-", "").replace(".", "").lstrip("0"))
                assert float(row[j]) == float("%.*g" % (max(digits, 1), got)), name
    stats = allanlot.read_lot_statistics(lot["outdir"])
    with open(lot["outdir"] / "lot_statistics.csv", newline="", encoding="utf-8") as f:
        assert list(stats) == next(csv.reader(f))


def test_diagnose_returns_diagnose_json(lot, binary):
    cli = json.loads(run(binary, "diagnose", lot["recording"], "--model", lot["model"],
                         "--json", "--replicas", 4, "--seed", 3).stdout)
    y = allanlot.simulate(lot["model"], duration=DURATION, seed=5)["gyro_x"]
    py = allanlot.diagnose(y, 100.0, lot["model"], replicas=4, seed=3)
    assert py["channel"] == "gyro_x"
    cli.pop("channel")
    py.pop("channel")
    assert py == cli
    capped = json.loads(run(binary, "diagnose", lot["recording"], "--model", lot["model"],
                            "--json", "--replicas", 0, "--max-effects", 1).stdout)
    capped.pop("channel")
    py_capped = allanlot.diagnose(y, 100.0, lot["model"], replicas=0, max_effects=1)
    py_capped.pop("channel")
    assert py_capped == capped
    with pytest.raises(ValueError, match="max_effects"):
        allanlot.diagnose(y, 100.0, lot["model"], replicas=0, max_effects=0)
