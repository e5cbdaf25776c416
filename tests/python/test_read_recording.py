"""allanlot.read_recording: every format the command line reads, as numpy arrays (the MCAP
samples of tests/data/mcap, written by the official MCAP writer, against their CSV)."""
import os

import numpy as np
import pytest

import allanlot
from conftest import DATA

AXES = ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]


def test_mcap_topic_as_six_channels_with_its_dropped_messages_as_nan():
    csv = np.loadtxt(DATA / "mcap" / "imu.csv", delimiter=",")
    rec = allanlot.read_recording(DATA / "mcap" / "imu_zstd.mcap", topics="/imu")
    assert sorted(rec["channels"]) == sorted("/imu/" + a for a in AXES)
    for k, axis in enumerate(AXES):
        ch = rec["channels"]["/imu/" + axis]
        assert ch["sample_rate_hz"] == pytest.approx(200.0, rel=1e-12)
        assert ch["units"] == ("rad/s" if axis.startswith("gyro") else "m/s^2")
        s = ch["samples"]
        # rows 60..69 were dropped: ten NaN in the time axis, every other sample as written.
        assert len(s) == len(csv) + 10
        assert np.isnan(s[60:70]).all()
        np.testing.assert_array_equal(np.concatenate([s[:60], s[70:]]), csv[:, k + 1])


def test_channel_globs_and_a_second_topic():
    rec = allanlot.read_recording(DATA / "mcap" / "imu_lz4.mcap", channels=["*/gyro_*"])
    assert sorted(rec["channels"]) == sorted(t + "/gyro_" + a for t in ("/imu", "/imu2")
                                             for a in "xyz")
    assert rec["channels"]["/imu2/gyro_x"]["sample_rate_hz"] == pytest.approx(100.0)


def test_missing_file_fifo_and_bad_arguments(tmp_path):
    with pytest.raises(OSError, match="no such file"):
        allanlot.read_recording(tmp_path / "none.mcap")
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="not a regular file"):
        allanlot.read_recording(fifo)
    with pytest.raises(TypeError, match="topics"):
        allanlot.read_recording(DATA / "mcap" / "imu_zstd.mcap", topics=[1])
    with pytest.raises(ValueError, match="sample_rate"):
        allanlot.read_recording(DATA / "mcap" / "imu_zstd.mcap", sample_rate=-1)
