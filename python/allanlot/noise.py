"""Noise generators with AllanTools' names and arguments (``allantools.noise``): white, brown,
violet and pink noise and the periodogram helpers of its examples.

The generators draw from numpy's global generator (``np.random``), as AllanTools does, so that
``np.random.seed(...)`` makes a notebook reproducible. The Kasdin power-law generator is
``allanlot.Noise``; the command line's simulator (Philox streams, the paper's IMU terms) is
``allanlot.simulate``.
"""

import math

import numpy as np

from . import _checks

__all__ = ["white", "brown", "violet", "pink", "numpy_psd", "scipy_psd", "timmer_koenig_from_psd"]


def white(num_points=1024, b0=1.0, fs=1.0):
    """White noise of one-sided PSD ``b0`` up to the Nyquist frequency ``fs/2``.

    Parameters
    ----------
    num_points : int
        Number of samples.
    b0 : float
        One-sided power spectral density, X^2/Hz.
    fs : float
        Sampling frequency, Hz.

    Returns
    -------
    numpy.ndarray
        ``num_points`` Gaussian samples of variance ``b0 * fs / 2``.

    References
    ----------
    NIST SP1065, the power-law model S(f) = h_alpha f^alpha: a white process
    sampled at fs has the variance of its PSD integrated from 0 to fs/2.
    """
    n = _checks.whole(num_points, "num_points", 0)
    b0 = _checks.real(b0, "b0", minimum=0.0)
    fs = _checks.real(fs, "fs", positive=True)
    return math.sqrt(b0 * fs / 2.0) * np.random.randn(n)


def brown(num_points=1024, b_minus2=1.0, fs=1.0):
    """Random-walk (Brownian) noise with one-sided PSD ``b_minus2 * f**-2``.

    The integral (cumulative sum / fs) of white noise of PSD ``(2 pi)^2 b_minus2``: integration
    divides the PSD by (2 pi f)^2.

    Parameters
    ----------
    num_points : int
        Number of samples.
    b_minus2 : float
        PSD coefficient, X^2 Hz.
    fs : float
        Sampling frequency, Hz.

    Returns
    -------
    numpy.ndarray
        ``num_points`` samples.

    References
    ----------
    NIST SP1065 and eq. (66) (p. 73): S_x(f) = S_y(f) / (2 pi f)^2.
    """
    fs = _checks.real(fs, "fs", positive=True)
    b = _checks.real(b_minus2, "b_minus2", minimum=0.0)
    return np.cumsum(white(num_points, b0=b * (2.0 * math.pi) ** 2, fs=fs)) / fs


def violet(num_points=1024, b2=1.0, fs=1.0):
    """Violet noise with one-sided PSD ``b2 * f**2``: the difference (times fs) of white noise
    of PSD ``b2 / (2 pi)^2``.

    Parameters
    ----------
    num_points : int
        Number of samples.
    b2 : float
        PSD coefficient, X^2 / Hz^3.
    fs : float
        Sampling frequency, Hz.

    Returns
    -------
    numpy.ndarray
        ``num_points`` samples.

    References
    ----------
    NIST SP1065 eq. (66) (p. 73): differentiation multiplies the PSD by (2 pi f)^2.
    """
    n = _checks.whole(num_points, "num_points", 0)
    fs = _checks.real(fs, "fs", positive=True)
    b2 = _checks.real(b2, "b2", minimum=0.0)
    return fs * np.diff(white(n + 1, b0=b2 / (2.0 * math.pi) ** 2, fs=fs))


def pink(num_points=1024, depth=80):
    """Pink (flicker, 1/f) noise by the Voss-McCartney algorithm.

    Each sample is the sum of ``depth`` held Gaussian values plus a fresh one; the value of row
    c is redrawn every 2^(c+1) samples (at the samples whose index has c trailing zero bits),
    which gives a PSD close to 1/f over about log2(num_points) octaves. The variance of a sample
    is ``depth + 1``.

    Parameters
    ----------
    num_points : int
        Number of samples.
    depth : int
        Number of held rows (more rows: the 1/f law holds to lower frequencies).

    Returns
    -------
    numpy.ndarray
        ``num_points`` samples.

    References
    ----------
    R. F. Voss and J. Clarke, J. Acoust. Soc. Am. 63 (1978) 258; flicker noise in NIST SP1065
    sec. 6.1 (p. 71, alpha = -1).
    """
    n = _checks.whole(num_points, "num_points", 0)
    depth = _checks.whole(depth, "depth", 1)
    out = np.random.randn(n)
    i = np.arange(n, dtype=np.int64)
    for c in range(depth):
        half = 1 << c
        if half > n:
            out += np.random.randn()  # never redrawn within the record
            continue
        held = (i + half) >> (c + 1)  # which draw of row c is held at sample i
        out += np.random.randn(int(held[-1]) + 1)[held] if n else 0.0
    return out


def numpy_psd(x, f_sample=1.0):
    """One-sided periodogram of ``x``: 2 |rfft(x)|^2 / (N fs), in X^2/Hz.

    Parameters
    ----------
    x : array_like
        Samples.
    f_sample : float
        Sampling frequency, Hz.

    Returns
    -------
    f : numpy.ndarray
        Frequencies from 0 to fs/2 (N // 2 + 1 values, evenly spaced).
    psd : numpy.ndarray
        The periodogram at f.

    References
    ----------
    NIST SP1065, one-sided PSD convention.
    """
    x = _checks.samples(x, "x")
    fs = _checks.real(f_sample, "f_sample", positive=True)
    if len(x) == 0:
        raise ValueError("x must hold at least one sample")
    p = 2.0 / (len(x) * fs) * np.abs(np.fft.rfft(x)) ** 2
    return np.linspace(0.0, fs / 2.0, len(p)), p


def scipy_psd(x, f_sample=1.0, nr_segments=4):
    """Welch PSD of ``x`` (scipy.signal.welch's defaults): Hann window, segments of
    len(x) / nr_segments samples overlapping by half, segment means removed, one-sided density.

    Parameters
    ----------
    x : array_like
        Samples.
    f_sample : float
        Sampling frequency, Hz.
    nr_segments : int
        The segment length is ``int(len(x) / nr_segments)``.

    Returns
    -------
    f : numpy.ndarray
        Frequencies k fs / L, k = 0 .. L // 2 (L the segment length).
    psd : numpy.ndarray
        The averaged one-sided density, X^2/Hz.

    References
    ----------
    P. D. Welch, IEEE Trans. Audio Electroacoust. 15 (1967) 70. allanlot.psd is the command
    line's Welch PSD (log-binned, with degrees of freedom).
    """
    x = _checks.samples(x, "x")
    fs = _checks.real(f_sample, "f_sample", positive=True)
    k = _checks.real(nr_segments, "nr_segments", positive=True)
    seg = int(len(x) / k)
    if seg < 2:
        raise ValueError("nr_segments=%r leaves segments of %d samples (need at least 2)"
                         % (nr_segments, seg))
    step = seg - seg // 2
    window = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(seg) / seg)  # periodic Hann
    starts = range(0, len(x) - seg + 1, step)
    acc = np.zeros(seg // 2 + 1)
    for s in starts:
        part = x[s:s + seg]
        acc += np.abs(np.fft.rfft(window * (part - part.mean()))) ** 2
    p = acc / (len(starts) * fs * np.sum(window ** 2))
    p[1:] *= 2.0
    if seg % 2 == 0:
        p[-1] /= 2.0  # the Nyquist bin has no negative-frequency twin
    return np.arange(len(p)) * fs / seg, p


def _piecewise_psd(f, f_nodes, h, alpha):
    """S(f) = h_i f^alpha_i with segment i between f_nodes[i-1] and f_nodes[i]."""
    seg = np.searchsorted(f_nodes, f, side="right")
    return h[seg] * f ** alpha[seg]


def timmer_koenig_from_psd(f_nodes, h, alpha, duration, timestep, output="phase", seed=None):
    """Gaussian noise with a piecewise power-law fractional-frequency PSD (Fourier synthesis).

    Each positive Fourier frequency f_k = k / (n timestep) gets an independent complex Gaussian
    amplitude of variance n S(f_k) / (2 timestep), so the periodogram
    2 timestep |X_k|^2 / n of the result scatters as S(f_k) chi^2_2 / 2 around the target;
    the inverse real FFT gives n samples (periodic, mean zero).

    Parameters
    ----------
    f_nodes : array_like
        Ascending break frequencies, Hz (``len(h) - 1`` of them, as returned by
        ``adev2psd_piecewise_approx``).
    h : array_like
        Coefficients of S_y(f) = h_i f^alpha_i per segment, lowest frequency first.
    alpha : array_like
        Exponents per segment.
    duration : float
        Length of the series, s; n = round(duration / timestep) samples.
    timestep : float
        Sampling interval, s.
    output : {'phase', 'freq'}
        'phase': phase x in s, PSD S_x = S_y / (2 pi f)^2; 'freq': fractional frequency y.
    seed : int or None
        Seed of the random generator, for a reproducible series.

    Returns
    -------
    numpy.ndarray
        n samples of phase (s) or fractional frequency.

    References
    ----------
    J. Timmer and M. Koenig, "On generating power law noise", Astron. Astrophys. 300,
    707-710 (1995). NIST SP1065, eq. 9 (S_x(f) = S_y(f) / (2 pi f)^2).
    """
    f_nodes = np.atleast_1d(np.asarray(f_nodes, dtype=float))
    h = np.atleast_1d(np.asarray(h, dtype=float))
    alpha = np.atleast_1d(np.asarray(alpha, dtype=float))
    if h.shape != alpha.shape or len(f_nodes) != len(h) - 1:
        raise ValueError("need len(h) == len(alpha) == len(f_nodes) + 1, got %d, %d, %d"
                         % (len(h), len(alpha), len(f_nodes)))
    duration = _checks.real(duration, "duration", positive=True)
    timestep = _checks.real(timestep, "timestep", positive=True)
    if output not in ("phase", "freq"):
        raise ValueError("output must be 'phase' or 'freq', got %r" % (output,))
    n = int(round(duration / timestep))
    if n < 4:
        raise ValueError("duration / timestep = %g: need at least 4 samples" % (n,))
    f = np.arange(1, n // 2 + 1) / (n * timestep)
    s = _piecewise_psd(f, f_nodes, h, alpha)
    if output == "phase":
        s = s / (2.0 * math.pi * f) ** 2
    rng = np.random.default_rng(seed)
    var = n * s / (2.0 * timestep)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[1:] = np.sqrt(var / 2.0) * (rng.standard_normal(len(f))
                                          + 1j * rng.standard_normal(len(f)))
    if n % 2 == 0:  # the Nyquist coefficient is real and carries the whole bin
        spectrum[-1] = math.sqrt(var[-1] * 2.0) * rng.standard_normal()
    return np.fft.irfft(spectrum, n)
