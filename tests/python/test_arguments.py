"""The module's arguments (python/allanlot/_checks.py): every bad argument is a TypeError or a
ValueError naming it, thread counts are capped as on the command line (also from
OMP_NUM_THREADS), and the readers open regular files only."""
import os
import subprocess
import sys

import numpy as np
import pytest

import allanlot

Y = np.random.default_rng(3).normal(size=2000)


def test_thread_counts_beyond_the_cap_are_refused_or_capped():
    with pytest.raises(ValueError, match="threads"):
        allanlot.deviation(Y, "oadev", threads=100000)
    with pytest.raises(ValueError, match="threads"):
        allanlot.oadev(Y, threads=100000)
    with pytest.raises(TypeError, match="threads"):
        allanlot.deviation(Y, "oadev", threads=1.5)
    one = allanlot.deviation(Y, "oadev", threads=1)
    capped = allanlot.deviation(Y, "oadev", threads=allanlot._allanlot.max_threads)
    np.testing.assert_array_equal(one.dev, capped.dev)


def test_omp_num_threads_far_beyond_the_machine_is_capped():
    code = ("import numpy as np, allanlot\n"
            "y = np.random.default_rng(1).normal(size=5000)\n"
            "for s in allanlot.stats():\n"
            "    allanlot.deviation(y, s, data_type='freq')\n"
            "allanlot.oadev(y)\n"
            "allanlot.psd(y, rate=10.0)\n"
            "print('ok')\n")
    env = dict(os.environ, OMP_NUM_THREADS="100000")
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "ok"


@pytest.mark.parametrize("call, error, name", [
    (lambda: allanlot.deviation(Y, "oadev", confidence=0), ValueError, "confidence"),
    (lambda: allanlot.deviation(Y, "oadev", confidence="high"), TypeError, "confidence"),
    (lambda: allanlot.deviation(Y + 1j, "oadev"), TypeError, "data"),
    (lambda: allanlot.deviation(["a", "b", "c"], "oadev"), TypeError, "data"),
    (lambda: allanlot.deviation(Y, "oadev", rate=0), ValueError, "rate"),
    (lambda: allanlot.deviation(Y, "oadev", rate=float("nan")), ValueError, "rate"),
    (lambda: allanlot.oadev(Y + 1j), TypeError, "data"),
    (lambda: allanlot.oadev([]), ValueError, "data"),
    (lambda: allanlot.oadev([1.0]), ValueError, "data"),
    (lambda: allanlot.oadev(Y, rate=-1), ValueError, "rate"),
    (lambda: allanlot.gcodev([], []), ValueError, "data_1"),
    (lambda: allanlot.psd(Y, bins_per_decade=-1), ValueError, "bins_per_decade"),
    (lambda: allanlot.psd(Y, rate=-5), ValueError, "rate"),
    (lambda: allanlot.psd(Y, segments=2.5), TypeError, "segments"),
    (lambda: allanlot.simulate(seed=1.5, duration=1), TypeError, "seed"),
    (lambda: allanlot.simulate(seed=-1, duration=1), ValueError, "seed"),
    (lambda: allanlot.simulate(duration=-1), ValueError, "duration"),
    (lambda: allanlot.fit((Y, Y)), TypeError, "result"),
    (lambda: allanlot.diagnose(Y, rate=10.0, model={"sample_rate_hz": 10, "terms": {"N": 1}},
                               replicas=-1), ValueError, "replicas"),
])
def test_each_bad_argument_is_named(call, error, name):
    with pytest.raises(error, match=name):
        call()


def test_readers_open_regular_files_only(tmp_path):
    for read in (allanlot.read_results, allanlot.read_lot_summary,
                 allanlot.read_lot_statistics):
        with pytest.raises(OSError, match="no such file"):
            read(tmp_path / "missing.allan.h5")
    with pytest.raises(OSError, match="is a directory"):
        allanlot.read_results(tmp_path)
    fifo = tmp_path / "pipe.allan.h5"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="FIFO"):
        allanlot.read_results(fifo)  # refused, never opened (open(2) would wait for a writer)
    (tmp_path / "out").mkdir()
    os.mkfifo(tmp_path / "out" / "lot_summary.h5")
    with pytest.raises(OSError, match="FIFO"):
        allanlot.read_lot_summary(tmp_path / "out")


def test_devices_are_refused_as_not_regular_files(tmp_path):
    # /dev/zero never ends: reading it would grow until memory runs out
    with pytest.raises(OSError, match="not a regular file"):
        allanlot.read_results("/dev/zero")
    (tmp_path / "out").mkdir()
    os.symlink("/dev/zero", tmp_path / "out" / "lot_summary.h5")
    with pytest.raises(OSError, match="not a regular file"):
        allanlot.read_lot_summary(tmp_path / "out")


@pytest.mark.parametrize("call, error, name", [
    (lambda: allanlot.noise.white(-1), ValueError, "num_points"),
    (lambda: allanlot.noise.white(10, fs=0), ValueError, "fs"),
    (lambda: allanlot.noise.pink(10.5), TypeError, "num_points"),
    (lambda: allanlot.Noise(nr=0), ValueError, "nr"),
    (lambda: allanlot.confidence_interval(1.0, 10, ci=0), ValueError, "ci"),
    (lambda: allanlot.confidence_interval(1.0, 0), ValueError, "edf"),
    (lambda: allanlot.edf_greenhall(0, 2, 1.5, 100), TypeError, "m"),
    (lambda: allanlot.edf_greenhall(0, 4, 1, 100), ValueError, "d"),
    (lambda: allanlot.frequency2phase(Y + 1j, 1.0), TypeError, "freqdata"),
    (lambda: allanlot.phase2frequency(Y, rate=0), ValueError, "rate"),
    (lambda: allanlot.gradev(Y, data_type="angle"), ValueError, "data_type"),
    (lambda: allanlot.psd2allan(np.ones(10), f=-1.0), ValueError, "f"),
    (lambda: allanlot.autocorr_noise_id(Y, 0), ValueError, "af"),
    (lambda: allanlot.fit(allanlot.deviation(Y, "oadev"), lowpass=3), TypeError, "lowpass"),
    (lambda: allanlot.deviation(Y, 3), TypeError, "stat"),
])
def test_each_bad_argument_of_the_allantools_api_is_named(call, error, name):
    with pytest.raises(error, match=name):
        call()
