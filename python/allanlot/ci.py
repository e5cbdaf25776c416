"""AllanTools' confidence-interval functions (``allantools.ci``): equivalent degrees of freedom,
chi-square intervals and lag-1 autocorrelation noise identification, with AllanTools' names,
arguments and return values. The edf algorithm of Greenhall & Riley and the chi-square
quantiles are the command line's (kernels/uncertainty/), so no scipy is needed."""

import math

import numpy as np

from . import _allanlot
from . import _checks

__all__ = ["ONE_SIGMA_CI", "confidence_interval", "confidence_interval_noiseID", "edf_simple",
           "edf_greenhall", "edf_totdev", "edf_mtotdev", "autocorr_noise_id", "lag1_acf",
           "detrend"]

#: Two-sided confidence of one standard deviation, erf(1 / sqrt(2)) = 0.6827.
ONE_SIGMA_CI = math.erf(1.0 / math.sqrt(2.0))


def confidence_interval(dev, edf, ci=ONE_SIGMA_CI):
    """Chi-square confidence interval (dev_min, dev_max) of a deviation with ``edf`` degrees
    of freedom.

    Parameters
    ----------
    dev : float
        The deviation.
    edf : float
        Equivalent degrees of freedom (> 0).
    ci : float
        Two-sided confidence in (0, 1); as in AllanTools, ci and 1 - ci give the same interval
        (the tails are min(ci, 1 - ci) / 2).

    Returns
    -------
    (dev_min, dev_max) : tuple of float
        dev sqrt(edf / chi2_(1-p)(edf)) and dev sqrt(edf / chi2_p(edf)), p the lower tail.

    References
    ----------
    NIST SP1065 sec. 5.3.3, eq. (45).
    """
    dev = _checks.real(dev, "dev", minimum=0.0)
    edf = _checks.real(edf, "edf", positive=True)
    ci = _checks.real(ci, "ci")
    if not 0.0 < ci < 1.0:
        raise ValueError("ci must be in (0, 1), got %r" % (ci,))
    tail = min(ci, 1.0 - ci) / 2.0
    chi2_lo = _allanlot.chi2_quantile(tail, edf)
    chi2_hi = _allanlot.chi2_quantile(1.0 - tail, edf)
    return (math.sqrt(edf * dev * dev / chi2_hi), math.sqrt(edf * dev * dev / chi2_lo))


_KINDS = {  # dev_type: (d, overlapping, modified), Greenhall & Riley sec. 2
    "adev": (2, False, False), "oadev": (2, True, False), "mdev": (2, True, True),
    "tdev": (2, True, True), "hdev": (3, False, False), "ohdev": (3, True, False),
}


def confidence_interval_noiseID(x, dev, af, dev_type="adev", data_type="phase",  # noqa: N802
                                ci=ONE_SIGMA_CI):
    """Confidence interval of ``dev`` (a deviation of ``x`` at averaging factor ``af``): the
    noise identified by autocorr_noise_id, its Greenhall edf, then confidence_interval.

    Parameters
    ----------
    x : array_like
        Phase (data_type "phase") or fractional frequency ("freq") samples.
    dev : float
        The deviation at tau = af tau0.
    af : int
        Averaging factor m.
    dev_type : {"adev", "oadev", "mdev", "tdev", "hdev", "ohdev"}
        The statistic (Hadamard ones identify noise with up to 3 differences).
    data_type : {"phase", "freq"}
        What x holds.
    ci : float
        Two-sided confidence.

    Returns
    -------
    (dev_min, dev_max) : tuple of float

    References
    ----------
    NIST SP1065 sec. 5.3.3 and 5.5.6 (p. 55); Riley & Greenhall, "Power law noise
    identification using the lag 1 autocorrelation", Proc. EFTF 2004.
    """
    if dev_type not in _KINDS:
        raise ValueError("dev_type must be one of %s, got %r" % (", ".join(_KINDS), dev_type))
    x = _checks.samples(x, "x")
    af = _checks.count(af, "af", 1)
    d, overlapping, modified = _KINDS[dev_type]
    alpha = autocorr_noise_id(x, af, data_type=data_type, dmin=0, dmax=d)[0]
    edf = edf_greenhall(alpha=alpha, d=d, m=af, N=len(x), overlapping=overlapping,
                        modified=modified)
    return confidence_interval(dev, edf, ci)


def edf_greenhall(alpha, d, m, N, overlapping=False, modified=False, verbose=False):  # noqa: N803
    """Equivalent degrees of freedom of a finite-difference variance (Greenhall & Riley's
    combined algorithm).

    Parameters
    ----------
    alpha : int
        Noise exponent of S_y(f) ~ f^alpha, from 2 to -4, with alpha + 2 d > 1.
    d : int
        Order of the phase difference: 1, 2 (Allan family), 3 (Hadamard family).
    m : int
        Averaging factor.
    N : int
        Number of phase points.
    overlapping : bool
        True for oadev and ohdev (stride tau0).
    modified : bool
        True for mdev and tdev.
    verbose : bool
        Ignored (AllanTools prints intermediate values).

    Returns
    -------
    float
        The edf.

    References
    ----------
    C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based on finite
    differences", Proc. 35th PTTI (2003), sec. 3.4-3.6; NIST SP1065 sec. 5.3.3.
    """
    alpha = _checks.count(alpha, "alpha", -4)
    d = _checks.count(d, "d", 1)
    if alpha > 2 or d > 3:
        raise ValueError("alpha must be from -4 to 2 and d from 1 to 3, got alpha=%d, d=%d"
                         % (alpha, d))
    if alpha + 2 * d <= 1:
        raise ValueError("alpha + 2 d must be > 1 (the variance converges), got alpha=%d, d=%d"
                         % (alpha, d))
    return _allanlot.edf_greenhall(alpha, d, _checks.count(m, "m", 1), _checks.count(N, "N", 1),
                                   bool(overlapping), bool(modified))


def edf_simple(N, m, alpha):  # noqa: N803
    """Simple approximate edf of the overlapping Allan variance for the five power-law noises.

    Parameters
    ----------
    N : int
        Number of phase points.
    m : int
        Averaging factor.
    alpha : int
        Noise exponent of S_y(f): 2, 1, 0, -1 or -2; any other value gives N - 1 (independent
        samples), as in AllanTools.

    Returns
    -------
    float

    References
    ----------
    NIST SP1065 sec. 5.3.3, Table 5 (p. 38), after Howe, Allan & Barnes (1981).
    """
    n, m = float(N), float(m)
    if alpha == 2:
        return (n + 1.0) * (n - 2.0 * m) / (2.0 * (n - m))
    if alpha == 1:
        return math.exp(math.sqrt(math.log((n - 1.0) / (2.0 * m))
                                  * math.log((2.0 * m + 1.0) * (n - 1.0) / 4.0)))
    if alpha == 0:
        return ((3.0 * (n - 1.0) / (2.0 * m) - 2.0 * (n - 2.0) / n)
                * 4.0 * m * m / (4.0 * m * m + 5.0))
    if alpha == -1:
        if m == 1:
            return 2.0 * (n - 2.0) / (2.3 * n - 4.9)
        return 5.0 * n * n / (4.0 * m * (n + 3.0 * m))
    if alpha == -2:
        return (n - 2.0) / (m * (n - 3.0) ** 2) * ((n - 1.0) ** 2 - 3.0 * m * (n - 1.0)
                                                   + 4.0 * m * m)
    return n - 1.0


def edf_totdev(N, m, alpha):  # noqa: N803
    """Howe's edf of the total variance, b N / m - c, (b, c) = (1.50, 0), (1.17, 0.22),
    (0.93, 0.36) for alpha = 0, -1, -2; edf_simple for other alpha (AllanTools' T / tau = N / m).

    Parameters
    ----------
    N : int
        Number of phase points.
    m : int
        Averaging factor.
    alpha : int
        Noise exponent of S_y(f).

    Returns
    -------
    float

    References
    ----------
    NIST SP1065 sec. 5.3.3, eq. (47) and Table 7 (p. 41).
    """
    table = {0: (1.50, 0.0), -1: (1.17, 0.22), -2: (0.93, 0.36)}
    if int(alpha) in table:
        b, c = table[int(alpha)]
        return b * float(N) / float(m) - c
    return edf_simple(N, m, alpha)


def edf_mtotdev(N, m, alpha):  # noqa: N803
    """Howe's edf of the modified total variance, b N / m - c, (b, c) = (1.90, 2.10),
    (1.20, 1.40), (1.10, 1.20), (0.85, 0.50), (0.75, 0.31) for alpha = 2, 1, 0, -1, -2.

    Parameters
    ----------
    N : int
        Number of phase points.
    m : int
        Averaging factor.
    alpha : int
        Noise exponent of S_y(f), 2 .. -2.

    Returns
    -------
    float

    References
    ----------
    NIST SP1065 sec. 5.3.3, Table 8 (p. 41).
    """
    table = {2: (1.90, 2.10), 1: (1.20, 1.40), 0: (1.10, 1.20), -1: (0.85, 0.50),
             -2: (0.75, 0.31)}
    if alpha not in table:
        raise ValueError("alpha must be one of 2, 1, 0, -1, -2, got %r" % (alpha,))
    b, c = table[alpha]
    return b * float(N) / float(m) - c


def lag1_acf(x, detrend_deg=1):
    """Lag-1 autocorrelation r1 = sum (x_i - mean)(x_(i+1) - mean) / sum (x_i - mean)^2.

    Parameters
    ----------
    x : array_like
        Samples.
    detrend_deg : int
        Ignored (as in AllanTools: the caller detrends).

    Returns
    -------
    float

    References
    ----------
    Riley & Greenhall, Proc. EFTF 2004, eq. (2); NIST SP1065 sec. 5.5.6.
    """
    z = _checks.samples(x, "x")
    z = z - z.mean()
    return float(np.dot(z[:-1], z[1:]) / np.dot(z, z))


def detrend(x, deg=1):
    """``x`` minus its least-squares polynomial of degree ``deg`` over the sample index.

    Parameters
    ----------
    x : array_like
        Samples.
    deg : int
        Degree of the removed polynomial.

    Returns
    -------
    numpy.ndarray

    References
    ----------
    NIST SP1065 sec. 5.5.6: phase loses its quadratic, frequency its linear drift before
    the lag-1 autocorrelation.
    """
    z = _checks.samples(x, "x")
    t = np.arange(len(z), dtype=float)
    return z - np.polyval(np.polyfit(t, z, _checks.whole(deg, "deg", 0)), t)


def autocorr_noise_id(x, af, data_type="phase", dmin=0, dmax=2):
    """Power-law noise identification by the lag-1 autocorrelation.

    Phase is decimated by ``af`` and loses its quadratic trend; frequency is averaged over
    ``af`` samples and loses its linear trend. The series is differenced until
    rho = r1 / (1 + r1) < 0.25 (at least ``dmin``, at most ``dmax`` times, d times in all);
    then alpha = -2 (rho + d) (+2 for phase) and alpha_int = -round(2 rho) - 2 d (+2 for phase).

    Parameters
    ----------
    x : array_like
        Phase or fractional frequency samples; at least 30 remain after averaging.
    af : int
        Averaging factor.
    data_type : {"phase", "freq"}
        What x holds.
    dmin, dmax : int
        Least and most differences (dmax 2 for the Allan family, 3 for the Hadamard one).

    Returns
    -------
    alpha_int : int
        Identified exponent of S_y(f) ~ f^alpha.
    alpha : float
        The unrounded estimate.
    d : int
        Number of differences taken.
    rho : float
        The last r1 / (1 + r1).

    References
    ----------
    Riley & Greenhall, "Power law noise identification using the lag 1 autocorrelation",
    Proc. EFTF 2004; NIST SP1065 sec. 5.5.6.
    """
    z = _checks.samples(x, "x")
    af = _checks.count(af, "af", 1)
    dmin = _checks.whole(dmin, "dmin", 0)
    dmax = _checks.whole(dmax, "dmax", dmin)
    if data_type == "phase":
        z = detrend(z[::af], deg=2)
        add = 2
    elif data_type == "freq":
        usable = len(z) - len(z) % af
        z = detrend(z[:usable].reshape(-1, af).mean(axis=1), deg=1)
        add = 0
    else:
        raise ValueError("data_type must be 'phase' or 'freq', got %r" % (data_type,))
    if len(z) < 30:
        raise ValueError("x gives %d points at af=%d: noise identification needs at least 30"
                         % (len(z), af))
    d = 0
    while True:
        r1 = lag1_acf(z)
        rho = r1 / (1.0 + r1)
        if d >= dmin and (rho < 0.25 or d >= dmax):
            return int(-round(2.0 * rho) - 2 * d) + add, -2.0 * (rho + d) + add, d, rho
        z = np.diff(z)
        d += 1
