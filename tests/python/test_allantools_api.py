"""`import allanlot as allantools`, beyond the statistics: AllanTools' noise generators, Kasdin's
Noise, the conversions, tau_generator, gradev, psd2allan, the edf and interval functions,
Dataset and Plot. Each is checked against its defining formula (written out here) or against
theory on simulated noise; AllanTools' own behaviour (argument names, return forms, grids) is
kept as facts, not by importing AllanTools."""
import math

import numpy as np
import pytest

import allanlot as allantools


def test_the_readme_example_of_allantools_runs():
    np.random.seed(1)
    x = allantools.noise.white(10000)  # phase, s
    taus, adevs, errors, ns = allantools.oadev(x)
    np.testing.assert_array_equal(taus, 2.0 ** np.arange(13))  # octave up to N/2
    t = np.logspace(0, 3, 50)
    y = allantools.noise.white(10000)
    t2, ad, ade, adn = allantools.oadev(y, rate=12.3, data_type="freq", taus=t)
    assert len(t2) == len(ad) == len(ade) == len(adn) > 30
    a = allantools.Dataset(data=np.random.rand(1000))
    result = a.compute("mdev")
    assert set(result) == {"taus", "stat", "stat_err", "stat_n"} and a.out["stat_id"] == "mdev"


def test_white_brown_violet_have_their_psd_levels():
    np.random.seed(3)
    n, fs = 200_000, 10.0
    w = allantools.noise.white(n, b0=2.0, fs=fs)
    # variance of white noise of one-sided PSD b0 up to fs/2: b0 fs / 2 (5 sigma of the estimate)
    assert abs(np.var(w) / (2.0 * fs / 2) - 1) < 5 * math.sqrt(2.0 / n)
    np.random.seed(4)
    b = allantools.noise.brown(n, b_minus2=3.0, fs=fs)
    steps = np.diff(b) * fs  # the white noise integrated: PSD (2 pi)^2 b_minus2
    assert abs(np.var(steps) / ((2 * math.pi) ** 2 * 3.0 * fs / 2) - 1) < 5 * math.sqrt(2.0 / n)
    np.random.seed(5)
    v = allantools.noise.violet(n, b2=4.0, fs=fs)
    assert len(v) == n
    # the difference of white noise of PSD b2/(2 pi)^2: variance 2 fs^2 (b2/(2 pi)^2) fs / 2
    expected = 2 * fs ** 2 * (4.0 / (2 * math.pi) ** 2) * fs / 2
    assert abs(np.var(v) / expected - 1) < 10 * math.sqrt(2.0 / n)
    np.random.seed(6)
    again = allantools.noise.white(n, b0=2.0, fs=fs)
    np.random.seed(3)
    np.testing.assert_array_equal(allantools.noise.white(n, b0=2.0, fs=fs), w)  # np.random.seed
    assert not np.array_equal(again, w)


def test_pink_noise_has_a_one_over_f_spectrum():
    np.random.seed(7)
    # each sample: depth held rows plus a fresh value, all of unit variance (over realisations)
    power = np.mean([allantools.noise.pink(32, depth=20) ** 2 for _ in range(400)])
    assert abs(power / 21 - 1) < 0.2
    x = allantools.noise.pink(2 ** 16, depth=20)
    f, p = allantools.noise.scipy_psd(x, f_sample=1.0, nr_segments=16)
    band = (f > 1e-3) & (f < 1e-1)
    slope = np.polyfit(np.log10(f[band]), np.log10(p[band]), 1)[0]
    assert -1.2 < slope < -0.8


def test_periodograms_follow_their_definitions():
    x = np.random.default_rng(8).standard_normal(64)
    f, p = allantools.noise.numpy_psd(x, f_sample=4.0)
    np.testing.assert_allclose(p, 2.0 / (64 * 4.0) * np.abs(np.fft.rfft(x)) ** 2)
    np.testing.assert_allclose(f, np.linspace(0, 2.0, 33))
    # Welch, one segment of all samples, Hann window: the windowed periodogram
    f, p = allantools.noise.scipy_psd(x, f_sample=4.0, nr_segments=1)
    w = 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(64) / 64)
    direct = np.abs(np.fft.rfft(w * (x - x.mean()))) ** 2 / (4.0 * np.sum(w * w))
    direct[1:-1] *= 2
    np.testing.assert_allclose(p, direct, rtol=1e-12)
    np.testing.assert_allclose(f, np.arange(33) * 4.0 / 64)
    # white noise: the Welch average sits at b0 = 2 var / fs
    y = np.random.default_rng(9).standard_normal(2 ** 16)
    _, p = allantools.noise.scipy_psd(y, f_sample=2.0, nr_segments=64)
    assert abs(np.mean(p[1:-1]) / (2.0 / 2.0) - 1) < 0.02


def test_kasdin_filter_and_its_predictions():
    # b = 0: the white draws themselves; b = -2 (white FM): their running sum (h_k = 1).
    for b, expect in ((0, lambda w: w), (-2, np.cumsum)):
        np.random.seed(10)
        ng = allantools.Noise(1024, 2.0, b)
        ng.generateNoise()
        np.random.seed(10)
        w = np.random.normal(0, math.sqrt(2.0), 1024)
        np.testing.assert_allclose(ng.time_series, expect(w), atol=1e-9)
    ng = allantools.Noise()
    ng.set_input(nr=2 ** 16, qd=1e-20, b=-2)
    np.random.seed(11)
    ng.generateNoise()
    assert len(ng.time_series) == 2 ** 16
    # Kasdin & Walter eq. (39): g_b = 2 qd (2 pi)^b tau0^(b+1); h_a with a = b + 2
    assert ng.phase_psd_from_qd(0.5) == pytest.approx(2e-20 * (2 * math.pi) ** -2 * 0.5 ** -1)
    assert ng.frequency_psd_from_qd(0.5) == pytest.approx(2e-20 * 0.5 ** -1)
    # white FM: AVAR = h0 / (2 tau), MVAR = h0 / (4 tau)
    h0 = ng.frequency_psd_from_qd(1.0)
    assert ng.adev(1.0, 10.0) == pytest.approx(math.sqrt(h0 / 20))
    assert ng.mdev(1.0, 10.0) == pytest.approx(math.sqrt(h0 / 40))
    taus, devs, _, _ = allantools.oadev(ng.time_series, taus=[1, 4, 16])
    np.testing.assert_allclose(devs, ng.adev(1.0, taus), rtol=0.1)


@pytest.mark.parametrize("b", [0, -1, -2, -3, -4])
def test_kasdin_noise_has_the_predicted_adev(b):
    np.random.seed(20 + b)
    ng = allantools.Noise(2 ** 15, 1e-18, b)
    ng.generateNoise()
    taus, devs, _, _ = allantools.oadev(ng.time_series, taus=[8.0])
    # one realisation: within a factor 1.6 (flicker and random walk carry few degrees of freedom)
    assert 1 / 1.6 < devs[0] / ng.adev(1.0, 8.0) < 1.6


def test_conversions_follow_their_definitions():
    with pytest.raises(ValueError):
        allantools.frequency2phase(np.array([np.nan, np.nan]), 1.0)
    y = np.array([np.nan, 1.0, 3.0, 2.0, 6.0, np.nan])
    x = allantools.frequency2phase(y, 2.0)
    np.testing.assert_allclose(x, [0, -2 / 2, -2 / 2 + 0, -2 / 2 + 0 - 1 / 2, 0])  # mean 3
    np.testing.assert_allclose(allantools.phase2frequency(x, 2.0), [1 - 3, 3 - 3, 2 - 3, 6 - 3])
    np.testing.assert_allclose(allantools.frequency2fractional([9.0, 11.0]), [-0.1, 0.1])
    np.testing.assert_allclose(allantools.frequency2fractional([9.0, 11.0], 9.0), [0, 2 / 9])
    np.testing.assert_allclose(allantools.phase2radians([1e-9], 10e6), [2 * math.pi * 1e-2])
    np.testing.assert_array_equal(allantools.trim_data(np.array([np.nan, 1.0, np.nan, 2.0])),
                                  [1.0, np.nan, 2.0])


def test_tau_generator_gives_allantools_grids():
    data = np.zeros(1000)
    d, m, taus = allantools.tau_generator(data, 2.0)
    np.testing.assert_array_equal(m, 2.0 ** np.arange(10))  # octave: 1 .. 512 < 1000
    assert m.dtype == np.float64 and d is not None
    np.testing.assert_array_equal(taus, m / 2.0)
    _, m, _ = allantools.tau_generator(data, 1.0, "decade")
    np.testing.assert_array_equal(m, [1, 2, 4, 10, 20, 40, 100, 200, 400])
    _, m, _ = allantools.tau_generator(data, 1.0, "all", maximum_m=5)
    np.testing.assert_array_equal(m, [1, 2, 3, 4, 5])
    _, m, _ = allantools.tau_generator(data, 1.0, [1, 2, 3, 4, 5, 6, 2000], even=True)
    np.testing.assert_array_equal(m, [2, 4, 6])
    m, taus = allantools.tau_reduction(np.arange(1, 1001), 10.0, 5)
    assert len(m) < 20 and np.all(np.diff(m) > 0)
    np.testing.assert_allclose(taus, m / 10.0)


def test_gradev_is_oadev_without_gaps_and_skips_them():
    x = np.cumsum(np.random.default_rng(12).standard_normal(1000))
    t, d, (lo, hi), ns = allantools.gradev(x, rate=1.0, taus="octave")
    t2, d2, _, ns2 = allantools.oadev(x, rate=1.0, taus="octave")
    np.testing.assert_array_equal(t, t2)
    np.testing.assert_allclose(d, d2, rtol=1e-12)
    np.testing.assert_array_equal(ns, ns2)
    assert np.all(lo > 0) and np.all(hi > 0) and np.all(lo < d)
    g = x.copy()
    g[400:600] = np.nan
    t, d, _, ns = allantools.gradev(g, rate=1.0, taus=[1.0, 10.0])
    direct = []
    for m in (1, 10):
        d2 = g[2 * m:] - 2 * g[m:-m] + g[:-2 * m]
        ok = ~np.isnan(d2)
        direct.append(math.sqrt(np.sum(d2[ok] ** 2) / (2 * ok.sum())) / m)
        assert ns[len(direct) - 1] == ok.sum()
    np.testing.assert_allclose(d, direct, rtol=1e-12)


def test_psd2allan_is_the_transfer_function_integral():
    h0, df = 2e-20, 1.0
    s = np.full(1001, h0)
    taus, ad = allantools.psd2allan(s, f=df)
    tau0 = 1 / 1000.0
    # AllanTools' grid: base^k for k < floor(log_base n), then n = (len - 1) / 2 itself
    np.testing.assert_allclose(taus / tau0, [1, 2, 4, 8, 16, 32, 64, 128, 500])
    # the definition, 2 int_0^fmax S_y |H|^2 df, on a fine grid (white FM cut at 1000 Hz)
    f = np.linspace(1e-6, 1000.0, 400_001)
    for k, devs in ((1, ad), (2, allantools.psd2allan(s, f=np.arange(1001.0), kind="mdev")[1])):
        direct = [math.sqrt(2 * np.trapz(h0 * np.abs(np.sin(np.pi * f * t) ** (k + 1)
                                                     / (np.pi * f * t) ** k) ** 2, f))
                  for t in taus]
        np.testing.assert_allclose(devs, direct, rtol=2e-3)
    # and the white FM laws h0 / (2 tau), h0 / (4 tau) where the band limit no longer matters
    np.testing.assert_allclose(ad[3:], np.sqrt(h0 / (2 * taus[3:])), rtol=0.02)


def chi2_exp_quantile(p):
    """Quantile of chi-square with 2 degrees of freedom (an exponential of mean 2)."""
    return -2.0 * math.log(1.0 - p)


def test_confidence_interval_is_the_chi_square_interval():
    lo, hi = allantools.confidence_interval(dev=3.0, edf=2.0, ci=0.9)
    assert lo == pytest.approx(3.0 * math.sqrt(2.0 / chi2_exp_quantile(0.95)), rel=1e-10)
    assert hi == pytest.approx(3.0 * math.sqrt(2.0 / chi2_exp_quantile(0.05)), rel=1e-10)
    assert allantools.confidence_interval(3.0, 2.0, 0.1) == pytest.approx((lo, hi))
    lo1, hi1 = allantools.confidence_interval(1.0, 1000.0)  # one sigma: about 1 -+ 1/sqrt(2 edf)
    assert lo1 == pytest.approx(1 - 1 / math.sqrt(2000), abs=2e-3)
    assert hi1 == pytest.approx(1 + 1 / math.sqrt(2000), abs=2e-3)
    assert allantools.ci.ONE_SIGMA_CI == pytest.approx(0.6826894921370859)


def test_edf_formulas():
    n, m = 1001, 4
    assert allantools.edf_simple(n, m, 2) == pytest.approx((n + 1) * (n - 2 * m) / (2 * (n - m)))
    assert allantools.edf_simple(n, m, 0) == pytest.approx(
        (3 * (n - 1) / (2 * m) - 2 * (n - 2) / n) * 4 * m * m / (4 * m * m + 5))
    assert allantools.edf_simple(n, m, -1) == pytest.approx(5 * n * n / (4 * m * (n + 3 * m)))
    assert allantools.edf_simple(n, 1, -1) == pytest.approx(2 * (n - 2) / (2.3 * n - 4.9))
    assert allantools.edf_simple(n, m, None) == n - 1
    assert allantools.edf_totdev(n, m, -1) == pytest.approx(1.17 * n / m - 0.22)
    assert allantools.edf_totdev(n, m, 2) == allantools.edf_simple(n, m, 2)
    assert allantools.edf_mtotdev(n, m, 1) == pytest.approx(1.20 * n / m - 1.40)
    with pytest.raises(ValueError, match="alpha"):
        allantools.edf_mtotdev(n, m, -3)
    with pytest.raises(ValueError, match="alpha"):
        allantools.edf_greenhall(alpha=-1, d=1, m=1, N=100)


def test_edf_greenhall_is_the_edf_of_the_intervals():
    # deviation()'s oadev and mdev rows carry the Greenhall edf of their identified noise.
    x = np.cumsum(np.random.default_rng(13).standard_normal(3000))
    for stat, kind in (("oadev", dict(d=2, overlapping=True, modified=False)),
                       ("mdev", dict(d=2, overlapping=True, modified=True)),
                       ("ohdev", dict(d=3, overlapping=True, modified=False))):
        r = allantools.deviation(x, stat, taus="octave")
        for m, edf, alpha in zip(r.m, r.edf, r.alpha):
            got = allantools.edf_greenhall(alpha=int(alpha), m=float(m), N=len(x), **kind)
            assert got == pytest.approx(edf, rel=1e-12), (stat, m)
    # the white FM value Stable32 uses for OADEV at m = 1 on 1001 points (docs/statistics.md)
    assert allantools.edf_greenhall(0, 2, 1, 1001, overlapping=True) == pytest.approx(782, abs=1)


def test_autocorr_noise_id_names_the_power_laws():
    rng = np.random.default_rng(14)
    white = rng.standard_normal(5000)
    assert allantools.autocorr_noise_id(white, 1, data_type="phase")[0] == 2  # white PM
    assert allantools.autocorr_noise_id(white, 4, data_type="freq")[0] == 0  # white FM
    assert allantools.autocorr_noise_id(np.cumsum(white), 1)[0] == 0  # phase of white FM
    walk = np.cumsum(np.cumsum(white))
    a_int, a, d, rho = allantools.autocorr_noise_id(walk, 2, dmax=3)
    assert a_int == -2 and d >= 1 and rho < 0.25 + 1e-12
    # r1 of the definition, on the decimated, detrended series (phase loses a quadratic)
    z = white[::3]
    t = np.arange(len(z))
    z = z - np.polyval(np.polyfit(t, z, 2), t)
    z = z - z.mean()
    r1 = np.dot(z[:-1], z[1:]) / np.dot(z, z)
    _, _, d, rho = allantools.autocorr_noise_id(white, 3, dmax=0)
    assert d == 0 and rho == pytest.approx(r1 / (1 + r1), rel=1e-10)
    with pytest.raises(ValueError, match="30"):
        allantools.autocorr_noise_id(white[:100], 10)


def test_confidence_interval_noise_id():
    x = np.cumsum(np.random.default_rng(15).standard_normal(4000))
    taus, devs, _, _ = allantools.oadev(x, taus=[8.0])
    lo, hi = allantools.confidence_interval_noiseID(x, devs[0], 8, dev_type="oadev")
    edf = allantools.edf_greenhall(0, 2, 8, len(x), overlapping=True)
    assert (lo, hi) == pytest.approx(allantools.confidence_interval(devs[0], edf))
    assert lo < devs[0] < hi
    with pytest.raises(ValueError, match="dev_type"):
        allantools.confidence_interval_noiseID(x, devs[0], 8, dev_type="totdev")


def test_dataset_writes_its_results(tmp_path):
    a = allantools.Dataset(data=np.cumsum(np.random.default_rng(16).standard_normal(1000)),
                           rate=2.0)
    r = a.compute("oadev")
    np.testing.assert_array_equal(r["stat"], allantools.oadev(a.inp["data"], rate=2.0)[1])
    out = tmp_path / "output.dat"
    a.write_results(out, digits=4, header_params={"clock": "test"})
    lines = out.read_text().splitlines()
    assert lines[0].startswith("# Generated by allanlot ")
    assert "# clock: test" in lines and lines[4].split()[:4] == ["AF", "Tau", "N", "alpha"]
    rows = [l.split() for l in lines[5:]]
    assert len(rows) == len(r["taus"]) and rows[1][0] == "2"
    assert float(rows[1][5]) == pytest.approx(r["stat"][1], rel=1e-3)
    with pytest.raises(ValueError, match="function"):
        a.compute("frequency2phase")


def test_allantools_plot_class():
    pytest.importorskip("matplotlib")
    a = allantools.Dataset(data=np.random.default_rng(17).random(1000))
    a.compute("mdev")
    b = allantools.Plot(no_display=True)
    b.plot(a, errorbars=True, grid=True)
    b.ax.set_xlabel("Tau (s)")
    assert b.ax.get_xscale() == "log" and b.ax.get_ylabel() == "mdev"
    assert len(b.ax.containers) == 1  # the error bars


def test_column_arrays_are_accepted_and_empty_ones_named():
    x = np.cumsum(np.random.default_rng(18).standard_normal(500))
    for a, b in zip(allantools.oadev(x[:, None]), allantools.oadev(x)):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(allantools.deviation(x[None, :], "mdev").dev,
                                  allantools.deviation(x, "mdev").dev)
    for call in (lambda: allantools.deviation([], "oadev"), lambda: allantools.oadev([]),
                 lambda: allantools.psd(np.zeros((0, 1))),
                 lambda: allantools.frequency2phase([], 1.0)):
        with pytest.raises(ValueError, match="empty"):
            call()
