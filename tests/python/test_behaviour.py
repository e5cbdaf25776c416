"""What numpy users expect of allanlot: any 1-D array-like in (float64 in place, other dtypes
converted once), NaN as gaps, the GIL released during the kernels, threads= honoured with the
same bits for any count, and the command line's errors as ValueError and OSError."""
import shutil
import threading
import time
import tracemalloc

import numpy as np
import pytest

import allanlot

rng = np.random.default_rng(7)
Y = rng.standard_normal(20000)


def test_array_likes_give_the_same_result():
    ref = allanlot.oadev(Y[:500], rate=2.0, data_type="freq")
    for data in (list(Y[:500]), tuple(Y[:500]), Y[:1000:2].copy() * 0 + Y[:500],
                 np.asfortranarray(Y[:500])):
        got = allanlot.oadev(data, rate=2.0, data_type="freq")
        for a, b in zip(ref, got):
            np.testing.assert_array_equal(a, b)
    ints = np.arange(500) % 7
    a = allanlot.oadev(ints, data_type="freq")
    b = allanlot.oadev(ints.astype(np.float64), data_type="freq")
    np.testing.assert_array_equal(a[1], b[1])
    strided = Y[::2]  # a view with a stride: converted once, same numbers
    np.testing.assert_array_equal(allanlot.mdev(strided)[1], allanlot.mdev(strided.copy())[1])


def test_float64_is_used_in_place_and_other_dtypes_copied_once():
    y = rng.standard_normal(1_000_000)  # 8 MB
    allanlot.deviation(y[:1000], "oadev")  # warm up (plans, first allocations)
    tracemalloc.start()
    allanlot.deviation(y, "oadev", confidence=None)
    _, peak64 = tracemalloc.get_traced_memory()
    tracemalloc.reset_peak()
    allanlot.deviation(y.astype(np.float32), "oadev", confidence=None)
    _, peak32 = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    # numpy reports its allocations to tracemalloc: float64 input adds none of 8 MB; float32
    # input is converted to one float64 array (8 MB) besides its own 4 MB.
    assert peak64 < 1_000_000
    assert 8_000_000 <= peak32 < 14_000_000


def test_nan_is_a_gap():
    y = Y.copy()
    y[5000:5100] = np.nan
    r = allanlot.deviation(y, "oadev", rate=10.0, data_type="freq")
    assert r.n_gaps == 100 and np.all(np.isfinite(r.dev))
    full = allanlot.deviation(Y, "oadev", rate=10.0, data_type="freq")
    assert np.all(r.n[: len(full.n)] <= full.n[: len(r.n)])
    with pytest.raises(ValueError, match="gapped"):
        allanlot.deviation(y, "totdev", rate=10.0, data_type="freq")


@pytest.mark.parametrize("stat", allanlot.stats())
def test_same_bits_for_any_thread_count(stat):
    y = Y[:3000] if stat in ("theo1", "theoh", "mtotdev", "ttotdev", "htotdev") else Y
    one = allanlot.deviation(y, stat, rate=5.0, data_type="freq", threads=1)
    two = allanlot.deviation(y, stat, rate=5.0, data_type="freq", threads=2)
    for key in Deviation_arrays():
        np.testing.assert_array_equal(getattr(one, key), getattr(two, key), err_msg=key)


def Deviation_arrays():
    return allanlot.Deviation._ARRAYS


def test_the_gil_is_released_during_the_kernels():
    y = rng.standard_normal(2_000_000)  # about 0.2 s of kernels, 2 s under AddressSanitizer
    call = {}

    def work():
        call["start"] = time.perf_counter()
        allanlot.deviation(y, "oadev", confidence=None, threads=1)
        call["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ran = []  # when this thread ran Python, at most one entry a millisecond
    worker.start()
    while worker.is_alive():
        now = time.perf_counter()
        if not ran or now - ran[-1] > 1e-3:
            ran.append(now)
    worker.join()
    # Held for the whole call, the GIL would let this thread run only at the call's edges: a
    # switch (every 5 ms) between the worker's clock reading and the kernel's start, or between the
    # kernel's return and the next reading. Released, this thread runs throughout. So it must have
    # run in the middle half of the call. What is asserted is when it ran, not how often: a spin
    # count depends on the share of the cores a loaded machine gives this thread.
    quarter = (call["end"] - call["start"]) / 4
    middle = [t for t in ran if call["start"] + quarter < t < call["end"] - quarter]
    assert middle, (f"this thread never ran between {quarter:.3f} s and {3 * quarter:.3f} s "
                    f"into a {4 * quarter:.3f} s call: the GIL was held")


def test_errors_are_value_errors_with_the_reason():
    with pytest.raises(ValueError, match="one-dimensional"):
        allanlot.deviation(np.zeros((3, 3)), "oadev")
    with pytest.raises(ValueError, match="unknown statistic 'foo'.*oadev"):
        allanlot.deviation(Y, "foo")
    with pytest.raises(ValueError, match="data_type"):
        allanlot.deviation(Y, "oadev", data_type="angle")
    with pytest.raises(ValueError, match="rate"):
        allanlot.deviation(Y, "oadev", rate=-1.0)
    with pytest.raises(ValueError, match="confidence"):
        allanlot.deviation(Y, "oadev", confidence=1.5)
    with pytest.raises(ValueError, match="threads"):
        allanlot.deviation(Y, "oadev", threads=0)
    with pytest.raises(ValueError, match="tau"):
        allanlot.deviation(Y, "oadev", taus="weekly")
    with pytest.raises(ValueError):
        allanlot.simulate({"sample_rate_hz": -5, "terms": {"N": 1}}, duration=1)
    with pytest.raises(ValueError, match="edf"):
        allanlot.fit(allanlot.deviation(Y, "oadev", confidence=None))


def test_files_that_cannot_be_read_are_os_errors(tmp_path):
    with pytest.raises(OSError, match="nothing_here.allan.h5"):
        allanlot.read_results(tmp_path / "nothing_here.allan.h5")
    bad = tmp_path / "bad.allan.h5"
    bad.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 600)
    with pytest.raises(OSError, match="bad.allan.h5"):
        allanlot.read_results(bad)
    with pytest.raises(OSError, match="no_model.json"):
        allanlot.simulate(str(tmp_path / "no_model.json"))
    with pytest.raises(OSError):
        allanlot.read_lot_summary(tmp_path)


def test_docstrings_give_the_formula_and_the_allantools_equivalent():
    assert "SP1065" in allanlot.deviation.__doc__ and "AllanTools" in allanlot.deviation.__doc__
    assert "allantools.oadev" in allanlot.oadev.__doc__
    assert "Welch" in allanlot.psd.__doc__
