"""AllanTools' data conversions and helpers (frequency2phase, phase2frequency, tau_generator,
gradev, psd2allan, ...) with its names, arguments and return values."""

import math

import numpy as np

from . import _checks
from ._allantools import tau_m
from .ci import confidence_interval, edf_simple

__all__ = ["frequency2phase", "phase2frequency", "phase2radians", "frequency2fractional",
           "trim_data", "tau_generator", "tau_reduction", "gradev", "psd2allan"]


def trim_data(x):
    """``x`` without its leading and trailing NaNs.

    Parameters
    ----------
    x : array_like
        Samples.

    Returns
    -------
    numpy.ndarray
        The slice from the first to the last number.

    References
    ----------
    NIST SP1065 sec. 5.4: gaps at the ends shorten the record.
    """
    z = _checks.samples(x, "x")
    valid = np.flatnonzero(~np.isnan(z))
    if len(valid) == 0:
        raise ValueError("x holds no number (empty, or every sample is NaN)")
    return z[valid[0]:valid[-1] + 1]


def frequency2phase(freqdata, rate):
    """Phase (time error, s) from fractional frequency: the cumulative sum of the frequency
    minus its mean, times 1 / rate, with a leading 0 (N frequency points give N + 1 phase
    points). Leading and trailing NaNs are trimmed first.

    Parameters
    ----------
    freqdata : array_like
        Fractional frequency.
    rate : float
        Samples per second.

    Returns
    -------
    numpy.ndarray
        Phase, s.

    References
    ----------
    NIST SP1065 sec. 4.1, eq. (2): x(t) is the integral of y(t).
    """
    y = trim_data(_checks.samples(freqdata, "freqdata"))
    rate = _checks.real(rate, "rate", positive=True)
    return np.concatenate(([0.0], np.cumsum(y - np.nanmean(y)) / rate))


def phase2frequency(phase, rate):
    """Fractional frequency from phase: rate * diff(phase) (N phase points, N - 1 values).

    Parameters
    ----------
    phase : array_like
        Phase, s.
    rate : float
        Samples per second.

    Returns
    -------
    numpy.ndarray

    References
    ----------
    NIST SP1065 sec. 4.1, eq. (3): y_i = (x_(i+1) - x_i) / tau0.
    """
    x = _checks.samples(phase, "phase")
    return _checks.real(rate, "rate", positive=True) * np.diff(x)


def phase2radians(phasedata, v0):
    """Phase in radians from phase in seconds: 2 pi v0 x.

    Parameters
    ----------
    phasedata : array_like
        Phase, s.
    v0 : float
        Nominal frequency, Hz.

    Returns
    -------
    numpy.ndarray

    References
    ----------
    NIST SP1065 sec. 4.1: x(t) = phi(t) / (2 pi v0).
    """
    return 2.0 * math.pi * _checks.real(v0, "v0") * _checks.samples(phasedata, "phasedata")


def frequency2fractional(frequency, mean_frequency=-1):
    """Fractional frequency (f - mu) / mu from frequency in Hz.

    Parameters
    ----------
    frequency : array_like
        Frequency, Hz.
    mean_frequency : float
        The nominal frequency mu, Hz; -1 (the default) takes the mean of ``frequency``.

    Returns
    -------
    numpy.ndarray

    References
    ----------
    NIST SP1065 sec. 4.1, eq. (1): y(t) = (v(t) - v0) / v0.
    """
    f = _checks.samples(frequency, "frequency")
    mu = np.mean(f) if mean_frequency == -1 else _checks.real(mean_frequency, "mean_frequency")
    if mu == 0:
        raise ValueError("the mean frequency is 0: fractional frequency is undefined")
    return (f - mu) / mu


def tau_generator(data, rate, taus=None, v=False, even=False, maximum_m=-1):
    """The averaging factors of a tau list, as every AllanTools statistic chooses them.

    Keywords give m = 1 .. N ("all"), powers of 2 up to N ("octave"), 1, 2, 4, 10, 20, 40, ...
    ("decade") or about 10 per decade ("log10"); None or [] means "octave". Taus in seconds
    become m = round(tau * rate); m <= 0, m >= N, m > maximum_m and repeats are dropped, and
    the rest sorted.

    Parameters
    ----------
    data : array_like
        The data (only its length N is used).
    rate : float
        Samples per second.
    taus : None, str or array_like
        A keyword or taus in seconds.
    v : bool
        Ignored (AllanTools prints the list).
    even : bool
        Keep even m only (Thêo1).
    maximum_m : int
        Largest m (-1: N).

    Returns
    -------
    data : numpy.ndarray
        The data as an array.
    m : numpy.ndarray
        Averaging factors (float, as AllanTools gives them).
    taus : numpy.ndarray
        m / rate, s.

    References
    ----------
    NIST SP1065 sec. 5.2.4: tau = m tau0; Stable32's decade spacing (1, 2, 4).
    """
    data = np.asarray(data)
    rate = _checks.real(rate, "rate", positive=True)
    top = None if maximum_m == -1 else maximum_m
    m = tau_m(len(data), rate, taus, even=even, maximum_m=top).astype(float)
    return data, m, m / rate


def tau_reduction(ms, rate, n_per_decade):
    """At most ``n_per_decade`` averaging factors per decade of an "all" list: m is kept where
    round(n log10 m) differs from that of the next m (the last m is dropped).

    Parameters
    ----------
    ms : array_like of int
        Averaging factors, ascending.
    rate : float
        Samples per second.
    n_per_decade : int
        Factors to keep per decade.

    Returns
    -------
    m : numpy.ndarray
    taus : numpy.ndarray
        m / rate, s.

    References
    ----------
    NIST SP1065 sec. 5.2.4.
    """
    ms = np.asarray(ms, dtype=np.int64)
    k = np.rint(n_per_decade * np.log10(ms))
    ms = ms[:-1][k[1:] != k[:-1]]
    return ms, ms / float(_checks.real(rate, "rate", positive=True))


_GRADEV_ALPHA = {"wp": 2, "fp": 1, "wf": 0, "ff": -1, "rf": -2}


def gradev(data, rate=1.0, data_type="phase", taus=None, ci=0.9, noisetype="wp"):
    """Gap-resistant overlapping Allan deviation: NaN phase points leave out the second
    differences that touch them; the rest are averaged.

    Parameters
    ----------
    data : array_like
        Phase (s) or fractional frequency (integrated to phase first, frequency2phase).
    rate : float
        Samples per second.
    data_type : {"phase", "freq"}
        What data holds.
    taus : None, str or array_like
        As tau_generator.
    ci : float
        Two-sided confidence of the interval.
    noisetype : {"wp", "fp", "wf", "ff", "rf"}
        Noise for the edf (edf_simple: white/flicker PM, white/flicker/random-walk FM); any
        other value gives N - 1 degrees of freedom.

    Returns
    -------
    taus : numpy.ndarray
    devs : numpy.ndarray
    [err_lo, err_hi] : list of two numpy.ndarray
        Distances from dev down to the lower bound and up to the upper one.
    ns : numpy.ndarray
        Number of second differences used (rows with ns <= 1 are dropped).

    References
    ----------
    NIST SP1065 eq. (11) (p. 16), Table 5 (p. 38) and eq. (45);
    D. A. Sullivan et al., NIST TN 1337 (1990), on gaps.
    """
    x = _checks.samples(data, "data")
    rate = _checks.real(rate, "rate", positive=True)
    if data_type == "freq":
        x = frequency2phase(x, rate)
    elif data_type != "phase":
        raise ValueError("data_type must be 'phase' or 'freq', got %r" % (data_type,))
    _, ms, _ = tau_generator(x, rate, taus)
    n_valid = int(np.count_nonzero(~np.isnan(x)))
    alpha = _GRADEV_ALPHA.get(noisetype)
    rows = []
    for m in ms.astype(np.int64):
        d2 = x[2 * m:] - 2.0 * x[m:-m] + x[:-2 * m]
        n = int(np.count_nonzero(~np.isnan(d2)))
        if n <= 1:
            continue
        dev = math.sqrt(np.nansum(d2 * d2) / (2.0 * n)) / m * rate
        edf = edf_simple(n_valid, m, alpha)
        lo, hi = confidence_interval(dev, edf, ci) if edf > 0 else (dev, dev)
        rows.append((m / rate, dev, dev - lo, hi - dev, n))
    if not rows:
        raise ValueError("no tau has two second differences without a gap")
    t, dev, lo, hi, n = (np.array(c) for c in zip(*rows))
    return t, dev, [lo, hi], n.astype(np.int64)


def psd2allan(S_y, f=1.0, kind="adev", base=2):  # noqa: N803
    """Allan or modified Allan deviation from a one-sided fractional-frequency PSD:
    sigma^2(tau) = 2 int_0^inf S_y(f) |sin(pi f tau)^(k+1) / (pi f tau)^k|^2 df, k = 1 (adev)
    or 2 (mdev).

    S_y is given at f = 0, df, 2 df, ... (its first value at f = 0 is not used); it is
    interpolated linearly onto a grid 4 times finer and integrated by the trapezoid rule. The
    taus are m tau0, tau0 = 1 / f_max, m = 1, base, base^2, ... up to (and including)
    n = (len(S_y) - 1) / 2; base <= 1 gives every m below n.

    Parameters
    ----------
    S_y : array_like
        One-sided PSD of the fractional frequency, 1/Hz.
    f : float or array_like
        The frequency step df (Hz), or the frequencies (df = f[1] - f[0]).
    kind : {"adev", "mdev"}
        Which deviation.
    base : float
        Spacing of the taus.

    Returns
    -------
    taus : numpy.ndarray
        s.
    devs : numpy.ndarray

    References
    ----------
    NIST SP1065 eqs. (65)-(66) (p. 73); Benkler et al., Metrologia 52 (2015) 565, eq. (23).
    """
    s = _checks.samples(S_y, "S_y")
    if len(s) < 3:
        raise ValueError("S_y must hold at least 3 values, got %d" % len(s))
    df = float(np.asarray(f, dtype=float)[1] - np.asarray(f, dtype=float)[0]) \
        if np.ndim(f) else _checks.real(f, "f", positive=True)
    if not df > 0:
        raise ValueError("f must increase (df > 0), got df=%r" % df)
    if kind[:1].lower() not in ("a", "m"):
        raise ValueError("kind must be 'adev' or 'mdev', got %r" % (kind,))
    k = 1.0 if kind[:1].lower() == "a" else 2.0
    fine = np.arange(1, 4 * (len(s) - 1) + 1) / 4.0  # in units of df
    sy = np.interp(fine, np.arange(len(s)), s)
    freq = fine * df
    tau0 = 1.0 / freq[-1]
    n = 1.0 / df / tau0 / 2.0
    if base > 1:
        ms = np.unique(np.round(np.append(base ** np.arange(np.floor(np.log(n) / np.log(base))),
                                          n)))
    else:
        ms = np.arange(1, n)
    taus = ms * tau0
    freq0 = np.concatenate(([0.0], freq))
    devs = np.empty(len(taus))
    for i, tau in enumerate(taus):
        u = np.pi * freq * tau
        h = np.concatenate(([0.0], sy * np.abs(np.sin(u) ** (k + 1.0) / u ** k) ** 2))
        devs[i] = math.sqrt(2.0 * np.trapz(h, freq0))
    return taus, devs
