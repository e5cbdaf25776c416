"""Real-time deviations against the batch estimators; the piecewise power-law PSD relations
against NIST SP1065 Table 7 and the Timmer-Koenig generator against its requested PSD."""
import math

import numpy as np
import pytest

import allanlot
from allanlot import realtime

AFS = [1, 2, 3, 7, 40, 333]


def _stream(obj, x):
    for v in x:
        obj.add_phase(v)
    return obj


@pytest.mark.parametrize("cls, batch", [(realtime.oadev_realtime, allanlot.oadev),
                                        (realtime.ohdev_realtime, allanlot.ohdev),
                                        (realtime.tdev_realtime, allanlot.tdev)])
def test_realtime_deviation_equals_the_batch_estimator(cls, batch):
    x = np.cumsum(np.random.default_rng(1).standard_normal(1200)) * 1e-9
    rt = _stream(cls(afs=AFS, tau0=0.25), x)
    taus, devs, _, _ = batch(x, rate=4.0, data_type="phase", taus=np.array(AFS) * 0.25)
    np.testing.assert_allclose(rt.taus(), taus, rtol=1e-15)
    np.testing.assert_allclose(rt.devs(), devs, rtol=1e-12)


def test_realtime_tdev_gives_mdev_and_partial_streams_agree():
    x = np.random.default_rng(2).standard_normal(700)
    rt = realtime.tdev_realtime(afs=AFS, tau0=1.0)
    for n in (100, 700):  # values stay right at every prefix, not only at the end
        _stream(rt, x[len(rt.x):n])
        ready = [m for m in AFS if n >= 3 * m]
        _, mdev, _, _ = allanlot.mdev(x[:n], rate=1.0, taus=ready)
        np.testing.assert_allclose(rt.mdev()[:len(ready)], mdev, rtol=1e-12)
        assert np.all(rt.devs()[len(ready):] == 0)


def test_realtime_auto_factors_and_frequency_input():
    y = np.random.default_rng(3).standard_normal(2000)
    rt = realtime.oadev_realtime(tau0=2.0, auto_afs=True, pts_per_decade=3)
    for v in y:
        rt.add_frequency(v)
    assert list(rt.afs) == [1, 2, 5, 10, 22, 46, 100, 215, 464, 1000]
    x = np.concatenate([[0.0], np.cumsum(y) * 2.0])  # x_{i+1} = x_i + y_i tau0
    np.testing.assert_allclose(rt.x, x, rtol=1e-15)
    taus, devs, _, _ = allanlot.oadev(x, rate=0.5, data_type="phase", taus=rt.taus()[:-1])
    np.testing.assert_allclose(rt.devs()[:-1], devs, rtol=1e-12)
    # m = 1000 has a single second difference, which the batch tau list leaves out
    last = abs(x[2000] - 2 * x[1000] + x[0]) / (math.sqrt(2) * 1000 * 2.0)
    assert rt.devs()[-1] == pytest.approx(last, rel=1e-12)
    with pytest.raises(ValueError, match="averaging factors"):
        realtime.oadev_realtime(afs=[0])


@pytest.mark.parametrize("alpha, var", [(0, lambda h, t: h / (2 * t)),
                                        (-1, lambda h, t: 2 * math.log(2) * h + 0 * t),
                                        (-2, lambda h, t: 2 * math.pi ** 2 / 3 * h * t),
                                        (-0.5, None)])
def test_single_power_law_gives_the_table_7_allan_variance(alpha, var):
    taus = np.array([0.1, 1.0, 100.0])
    adev = allanlot.psd_piecewise_to_adev([3e-22], [alpha], [], taus)
    if var is not None:  # SP1065 Table 7
        np.testing.assert_allclose(adev ** 2, var(3e-22, taus), rtol=1e-9)
    # the slope of sigma^2 is -alpha - 1 for every tau
    np.testing.assert_allclose(np.diff(np.log(adev ** 2)) / np.diff(np.log(taus)),
                               -alpha - 1, rtol=1e-9)


def test_band_limited_white_pm_matches_its_high_frequency_approximation():
    # h2 f^2 up to fh: sigma^2 ~ 3 fh h2 / (4 pi^2 tau^2) when 2 pi fh tau >> 1 (SP1065 Table 7)
    h2, fh, taus = 1e-24, 50.0, np.array([10.0, 100.0])
    adev = allanlot.psd_piecewise_to_adev([h2, 0.0], [2.0, 0.0], [fh], taus)
    np.testing.assert_allclose(adev ** 2, 3 * fh * h2 / (4 * math.pi ** 2 * taus ** 2), rtol=2e-3)
    with pytest.raises(ValueError, match="infinite"):
        allanlot.psd_piecewise_to_adev([h2], [2.0], [], taus)


def test_adev_to_psd_inverts_exact_power_laws_and_is_continuous():
    taus = np.array([1.0, 10.0, 100.0, 1000.0, 1e4])
    h0, hm2 = 4e-22, 1e-30  # white FM then random-walk FM
    true = allanlot.psd_piecewise_to_adev([hm2, h0], [-2.0, 0.0], [1e-3], taus)
    f_nodes, sy_nodes, h, alpha = allanlot.adev2psd_piecewise_approx(
        [math.sqrt(h0 / 2), math.sqrt(h0 / 20)], [1.0, 10.0])
    np.testing.assert_allclose(h, [h0], rtol=1e-12)
    np.testing.assert_allclose(alpha, [0.0], atol=1e-12)
    assert f_nodes.size == 0 and sy_nodes.size == 0
    f_nodes, sy_nodes, h, alpha = allanlot.adev2psd_piecewise_approx(true, taus)
    np.testing.assert_allclose(h[:-1] * f_nodes ** alpha[:-1], h[1:] * f_nodes ** alpha[1:],
                               rtol=1e-12)
    np.testing.assert_allclose(sy_nodes, h[1:] * f_nodes ** alpha[1:], rtol=1e-12)
    # the approximation follows the deviation it came from within the knee's curvature
    back = allanlot.psd_piecewise_to_adev(h, alpha, f_nodes, taus)
    np.testing.assert_allclose(back, true, rtol=0.3)
    np.testing.assert_allclose(back[[0, -1]], true[[0, -1]], rtol=0.05)
    with pytest.raises(ValueError, match="outside"):
        allanlot.adev2psd_piecewise_approx([1.0, 1e3], [1.0, 2.0])


@pytest.mark.parametrize("alpha", [-2.9, -2.5, -2.0, -1.5, -1.0005, -1.0, -0.2, 0.0, 0.5, 0.9])
def test_inversion_recovers_any_single_power_law(alpha):
    # psd_piecewise_to_adev integrates numerically, the inversion uses the closed-form J(mu):
    # they must agree on every exponent of the convergent range
    taus = np.array([2.0, 20.0])
    adev = allanlot.psd_piecewise_to_adev([5e-21], [alpha], [], taus)
    _, _, h, a = allanlot.adev2psd_piecewise_approx(adev, taus)
    np.testing.assert_allclose(h, [5e-21], rtol=1e-10)
    np.testing.assert_allclose(a, [alpha], atol=1e-10)


def test_hadamard_inversion_of_a_single_power_law():
    # Hadamard variance of white FM equals its Allan variance h0 / (2 tau) (SP1065 Table 7)
    _, _, h, alpha = allanlot.adev2psd_piecewise_approx(
        [math.sqrt(1e-20 / 2), math.sqrt(1e-20 / 20)], [1.0, 10.0], vartype="hdev")
    np.testing.assert_allclose(h, [1e-20], rtol=1e-9)


@pytest.mark.parametrize("output", ["freq", "phase"])
def test_timmer_koenig_periodogram_scatters_around_the_requested_psd(output):
    f_nodes, h, alpha, n = [0.01], [1e-24, 1e-22], [-1.0, 0.0], 1 << 16
    x = allanlot.noise.timmer_koenig_from_psd(f_nodes, h, alpha, n * 0.5, 0.5,
                                              output=output, seed=4)
    assert len(x) == n
    f = np.fft.rfftfreq(n, 0.5)[1:-1]
    periodogram = 2 * 0.5 * np.abs(np.fft.rfft(x)[1:-1]) ** 2 / n
    target = np.where(f < 0.01, 1e-24 / f, 1e-22)
    if output == "phase":
        target = target / (2 * math.pi * f) ** 2
    # each bin is target * chi^2_2 / 2 (2 degrees of freedom): the mean ratio over M bins has
    # standard deviation 1/sqrt(M); check below and above the node separately
    for band in (f < 0.01, f >= 0.01):
        ratio = periodogram[band] / target[band]
        assert abs(ratio.mean() - 1) < 5 / math.sqrt(band.sum())
    again = allanlot.noise.timmer_koenig_from_psd(f_nodes, h, alpha, n * 0.5, 0.5,
                                                  output=output, seed=4)
    np.testing.assert_array_equal(x, again)


def test_timmer_koenig_white_fm_has_the_band_limited_allan_deviation():
    h0, n = 2e-20, 1 << 16
    x = allanlot.noise.timmer_koenig_from_psd([], [h0], [0.0], n, 1.0, seed=5)
    taus = np.array([1.0, 10.0])
    _, adev, _, _ = allanlot.oadev(x, rate=1.0, taus=taus)
    # the synthesis stops at Nyquist, so compare with the PSD cut there
    expected = allanlot.psd_piecewise_to_adev([h0, 1e-300], [0.0, 0.0], [0.5], taus)
    edf = [allanlot.edf_simple(n, int(t), 0) for t in taus]
    assert np.all(np.abs(adev / expected - 1) < 4 / np.sqrt(2 * np.asarray(edf)))
    with pytest.raises(ValueError, match="output"):
        allanlot.noise.timmer_koenig_from_psd([], [h0], [0.0], 10, 1.0, output="x")
