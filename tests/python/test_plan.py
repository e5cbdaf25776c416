"""plan and watch from Python (allanlot._allanlot.plan, .watch, .look_quantile): the same
answers as the command line's, with its errors as ValueError."""
import json

import numpy as np
import pytest

from allanlot import _allanlot

MODEL = {"units": "deg/s", "sample_rate_hz": 1, "terms": {"N": 0.001, "B": 0.001, "K": 0.0001}}
SPEC = {"confidence": 0.95, "channels": {"gyro_*": {"B": {"max": 0.001, "unit": "deg/s"}}}}


def write(tmp_path, name, obj):
    path = tmp_path / name
    path.write_text(json.dumps(obj))
    return str(path)


def test_plan_gives_the_length_and_its_targets(tmp_path):
    model = write(tmp_path, "model.json", MODEL)
    got = _allanlot.plan(model, {"B": 0.1}, "", 0.2, 0.95, 0, 1, 30 * 86400.0, 1)
    assert got["duration_s"] > 0
    assert got["binding"] == "gyro_x:B"
    tight = _allanlot.plan(model, {"B": 0.05}, "", 0.2, 0.95, 0, 1, 30 * 86400.0, 1)
    # Halving the precision takes about four times the record (sigma ~ 1 / sqrt(length)).
    assert 2.5 < tight["duration_s"] / got["duration_s"] < 6


def test_plan_spec_mode_and_errors(tmp_path):
    model = write(tmp_path, "model.json", MODEL)
    spec = write(tmp_path, "spec.json", SPEC)
    got = _allanlot.plan(model, {}, spec, 0.2, 0, 0, 1, 30 * 86400.0, 1)
    assert "gyro_x:B<=max" in got["per_target"]
    with pytest.raises(ValueError):
        _allanlot.plan(model, {"X": 0.1}, "", 0.2, 0.95, 0, 1, 30 * 86400.0, 1)


def test_look_quantile_spends_the_rate():
    assert _allanlot.look_quantile(0.05, 0, 1, 8) == pytest.approx(2.4977, abs=1e-3)


def test_watch_replays_a_recording(tmp_path):
    spec = write(tmp_path, "spec.json", SPEC)
    rng = np.random.default_rng(3)
    csv = tmp_path / "unit.csv"
    csv.write_text("gyro_x\n" + "\n".join(f"{v:.9g}" for v in 0.001 * rng.standard_normal(8000)))
    status, text = _allanlot.watch(str(csv), spec, 2000.0, 8000.0, True, 0.0, 1.0, 1.0, "deg/s", 1)
    # White noise of N = 0.001 deg/s*s^0.5 has no flicker: B is decided inside the limit.
    assert status == 0, text
    assert "unit passes" in text


def test_public_plan_and_watch_check_their_arguments(tmp_path):
    import allanlot
    model = write(tmp_path, "model.json", MODEL)
    got = allanlot.plan(model, targets={"B": 0.1}, threads=1)
    assert got == _allanlot.plan(model, {"B": 0.1}, "", 0.2, 0.95, 0, 1, 30 * 86400.0, 1)
    with pytest.raises(ValueError, match="either targets or spec"):
        allanlot.plan(model)
    with pytest.raises(ValueError, match="targets"):
        allanlot.plan(model, targets={"B": 10})
    with pytest.raises(ValueError, match="confidence"):
        allanlot.plan(model, targets={"B": 0.1}, confidence=0)
    with pytest.raises(TypeError, match="verify"):
        allanlot.plan(model, targets={"B": 0.1}, verify=1.5)
    with pytest.raises(ValueError, match="interval"):
        allanlot.watch(model, model, interval=-1)
