"""`import allanlot as allantools`: AllanTools' conventions, hand-coded here from its documented
rules (no AllanTools in the tests): which taus a keyword or an array gives, the number of terms
ns, errs = devs / sqrt(ns) (Thêo1: N - m; TIE rms: 0), and rows with ns <= 1 dropped; and each
deviation against a direct numpy implementation of its SP1065 formula."""
import numpy as np
import pytest

import allanlot as allantools

RATE = 4.0
rng = np.random.default_rng(2026)
PHASE = np.cumsum(rng.standard_normal(301)) * 1e-9 + 2e-7 * np.arange(301)
FREQ = rng.standard_normal(300) * 1e-3 + 3.0


def test_octave_decade_all_and_arrays():
    n = len(PHASE)  # 301 phase points
    taus, _, _, _ = allantools.oadev(PHASE, rate=RATE)  # octave: 2^k < n, and ns = n - 2m > 1
    np.testing.assert_allclose(taus * RATE, [1, 2, 4, 8, 16, 32, 64, 128])
    taus, _, _, _ = allantools.oadev(PHASE, rate=RATE, taus="decade")
    np.testing.assert_allclose(taus * RATE, [1, 2, 4, 10, 20, 40, 100])
    taus, _, _, ns = allantools.oadev(PHASE, rate=RATE, taus="all")
    np.testing.assert_allclose(taus * RATE, np.arange(1, (n - 2) // 2 + 1))
    np.testing.assert_array_equal(ns, n - 2 * np.arange(1, (n - 2) // 2 + 1))
    # Seconds rounded to m, sorted, duplicates and m <= 0 or m >= n dropped.
    taus, _, _, _ = allantools.oadev(PHASE, rate=RATE, taus=[3.0, 0.26, 0.25, 0.1, 1e5, 1.13])
    np.testing.assert_allclose(taus * RATE, [1, 5, 12])


def test_frequency_data_give_one_more_phase_point():
    _, _, _, ns = allantools.oadev(FREQ, rate=RATE, data_type="freq", taus=[0.25])
    assert ns[0] == len(FREQ) + 1 - 2
    # NaN at the ends is trimmed (AllanTools' trim_data).
    padded = np.concatenate([[np.nan, np.nan], FREQ, [np.nan]])
    a = allantools.oadev(padded, rate=RATE, data_type="freq")
    b = allantools.oadev(FREQ, rate=RATE, data_type="freq")
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)


def second_diffs(x, m, stride=1):
    return (x[2 * m:] - 2 * x[m:-m] + x[:-2 * m])[::stride]


def direct(stat, x, m, tau0):
    """SP1065's formulas, written out plainly in long double."""
    x = x.astype(np.longdouble)
    n = len(x)
    tau = m * tau0
    if stat in ("adev", "oadev"):
        d = second_diffs(x, m, m if stat == "adev" else 1)
        return np.sqrt(np.sum(d * d) / (2 * len(d) * tau * tau)), len(d)
    if stat in ("hdev", "ohdev"):
        d = (x[3 * m:] - 3 * x[2 * m:n - m] + 3 * x[m:n - 2 * m] - x[:n - 3 * m])
        d = d[::m] if stat == "hdev" else d
        return np.sqrt(np.sum(d * d) / (6 * len(d) * tau * tau)), len(d)
    if stat == "mdev":
        terms = [np.sum(x[j + 2 * m:j + 3 * m] - 2 * x[j + m:j + 2 * m] + x[j:j + m])
                 for j in range(n - 3 * m + 1)]
        t = np.array(terms) / m
        return np.sqrt(np.sum(t * t) / (2 * len(t) * tau * tau)), len(t)
    if stat == "totdev":
        ext = lambda k: 2 * x[0] - x[-k] if k < 0 else (2 * x[-1] - x[2 * (n - 1) - k] if k > n - 1 else x[k])
        d = np.array([ext(i - m) - 2 * x[i] + ext(i + m) for i in range(1, n - 1)])
        return np.sqrt(np.sum(d * d) / (2 * (n - 2) * tau * tau)), n - 2
    if stat == "mtie":
        return max(np.ptp(x[i:i + m + 1]) for i in range(n - m)), n - m
    if stat == "tierms":
        d = x[m:] - x[:-m]
        return np.sqrt(np.mean(d * d)), n - m
    if stat == "theo1":
        s = sum((x[i] - x[i - d + m // 2] + x[i + m] - x[i + d + m // 2]) ** 2 / (m / 2 - d)
                for i in range(n - m) for d in range(m // 2))
        return np.sqrt(s / (0.75 * (n - m) * tau * tau)), (n - m) * m // 2
    raise AssertionError(stat)


@pytest.mark.parametrize("stat", ["adev", "oadev", "mdev", "hdev", "ohdev", "totdev", "mtie",
                                  "tierms", "theo1"])
def test_deviations_ns_and_errs_against_direct_formulas(stat):
    taus, devs, errs, ns = getattr(allantools, stat)(PHASE, rate=RATE, taus="all")
    assert len(taus) > 0
    n = len(PHASE)
    for tau, dev, err, k in list(zip(taus, devs, errs, ns))[::7]:
        m = int(round(tau * RATE))
        want, terms = direct(stat, PHASE, m, 1.0 / RATE)
        assert k == terms, (stat, m)
        assert dev == pytest.approx(float(want), rel=1e-9), (stat, m)
        if stat == "theo1":
            assert err == pytest.approx(dev / np.sqrt(n - m))
        elif stat == "tierms":
            assert err == 0
        else:
            assert err == pytest.approx(dev / np.sqrt(k))
    assert np.all(ns > 1)


def test_ranges_end_where_allantools_ends():
    n = len(PHASE)
    last = lambda f, **kw: int(round(f(PHASE, rate=RATE, taus="all", **kw)[0][-1] * RATE))
    assert last(allantools.adev) == (n - 1) // 3  # two non-overlapping pairs at least
    assert last(allantools.oadev) == (n - 2) // 2
    assert last(allantools.mdev) == (n - 1) // 3
    assert last(allantools.hdev) == (n - 1) // 4
    assert last(allantools.totdev) == n - 1  # reflected: every m < n
    assert last(allantools.mtotdev) == n // 3
    assert last(allantools.theo1) == (n - 1) - (n - 1) % 2
    assert last(allantools.mtie) == n - 2


def test_tdev_ttotdev_and_theo1_taus():
    taus, md, _, ns = allantools.mdev(PHASE, rate=RATE)
    t2, td, te, ns2 = allantools.tdev(PHASE, rate=RATE)
    np.testing.assert_allclose(td, t2 * md / np.sqrt(3.0), rtol=1e-12)
    np.testing.assert_allclose(te, td / np.sqrt(ns2), rtol=1e-12)
    taus, mt, _, _ = allantools.mtotdev(PHASE, rate=RATE)
    t3, tt, _, _ = allantools.ttotdev(PHASE, rate=RATE)
    np.testing.assert_allclose(tt, t3 * mt / np.sqrt(3.0), rtol=1e-12)
    # Thêo1: AllanTools reports tau = m tau0 (allanlot.deviation and Stable32: 0.75 m tau0).
    taus, _, _, _ = allantools.theo1(PHASE, rate=RATE, taus=[1.0, 2.0])
    np.testing.assert_allclose(taus, [1.0, 2.0])
    assert allanlot_deviation_tau(PHASE, 10) == pytest.approx(0.75 * 10 / RATE)


def allanlot_deviation_tau(x, m):
    return allantools.deviation(x, "theo1", RATE, "phase", "m:%d" % m, confidence=None).tau[0]


def test_time_errors_of_frequency_data_have_the_mean_frequency_removed():
    # AllanTools integrates frequency with its mean removed: MTIE of a constant frequency is 0.
    _, devs, _, _ = allantools.mtie(np.full(100, 5.0), rate=1.0, data_type="freq")
    np.testing.assert_allclose(devs, 0.0, atol=1e-12)


def test_gcodev_is_the_magnitude_of_the_allan_covariance():
    other = np.cumsum(rng.standard_normal(len(PHASE))) * 1e-9
    taus, devs, errs, ns = allantools.gcodev(PHASE, other, rate=RATE, taus="all")
    n = len(PHASE)
    for tau, dev, err, k in list(zip(taus, devs, errs, ns))[::9]:
        m = int(round(tau * RATE))
        x = PHASE.astype(np.longdouble)
        y = other.astype(np.longdouble)
        dx = x[2 * m:] - 2 * x[m:-m] + x[:-2 * m]
        dy = y[2 * m:] - 2 * y[m:-m] + y[:-2 * m]
        cov = np.sum(dx * dy) / (2 * (n - 2 * m) * (m / RATE) ** 2)
        assert k == n - 2 * m
        assert dev == pytest.approx(float(np.sqrt(abs(cov))), rel=1e-9)
        assert err == pytest.approx(dev / np.sqrt(k))
    # With itself it is the overlapping Allan deviation.
    a = allantools.gcodev(PHASE, PHASE, rate=RATE)
    b = allantools.oadev(PHASE, rate=RATE)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_allclose(a[1], b[1], rtol=1e-12)


def test_three_cornered_hat_combines_the_pairs_and_clips_negative_variances():
    ab = np.cumsum(rng.standard_normal(len(PHASE)))
    bc = np.cumsum(rng.standard_normal(len(PHASE))) * 3.0
    ca = np.cumsum(rng.standard_normal(len(PHASE)))
    taus, dev_a, err_a, ns = allantools.three_cornered_hat_phase(ab, bc, ca, RATE, "octave",
                                                                 allantools.oadev)
    _, d_ab, _, n_ab = allantools.oadev(ab, rate=RATE)
    _, d_bc, _, _ = allantools.oadev(bc, rate=RATE)
    _, d_ca, _, _ = allantools.oadev(ca, rate=RATE)
    var = 0.5 * (d_ab**2 + d_ca**2 - d_bc**2)
    assert np.any(var < 0)  # BC noisier than AB and CA together: A's estimate goes negative
    np.testing.assert_allclose(dev_a, np.sqrt(np.maximum(var, 0)), rtol=1e-12)
    np.testing.assert_array_equal(ns, n_ab)
    np.testing.assert_allclose(err_a, dev_a / np.sqrt(n_ab))
