"""AllanTools' calling conventions, written from its documented rules (allantools.py of
AllanTools 2019.9 and later: tau_generator, remove_small_ns and each statistic's docstring), so
that ``import allanlot as allantools`` gives a notebook the same (taus, devs, errs, ns).

What AllanTools does, and this module therefore does:
  - ``data_type="freq"`` data are integrated to phase with their mean removed and a leading 0
    (N frequency points give N + 1 phase points); NaN at either end is trimmed first;
  - ``taus``: None or [] means "octave"; "all", "octave", "decade" and "log10" are keyword
    grids over the length of the phase data; an array is in seconds; each tau becomes
    m = round(tau * rate), and m <= 0, m >= len(data), m above the statistic's largest m and
    repeated m are dropped (sorted ascending);
  - ns is the statistic's own term count (below); rows with ns <= 1 are dropped;
  - errs = devs / sqrt(ns), except where AllanTools defines it otherwise (Thêo1: N - m in the
    root; TIE rms: 0).
The deviations themselves come from allanlot's kernels (the command line's, checked against
Stable32 and long-double references). Differences, documented in docs/python.md: NaN inside the
data is a gap (AllanTools propagates it); totdev has no rows beyond m = (N - 1) / 2.
"""

import numpy as np

from . import _allanlot
from . import _checks


def _phase_length(data, data_type):
    """Length of the phase record AllanTools builds from `data`."""
    if data_type == "phase":
        return len(data)
    if data_type == "freq":
        return len(_trim_nan(data)) + 1
    raise ValueError("unknown data_type: %r (AllanTools accepts 'phase' and 'freq')" % data_type)


def _trim_nan(data):
    if not (np.isnan(data[0]) or np.isnan(data[-1])):
        return data  # the common case, without a pass over the record
    valid = np.flatnonzero(~np.isnan(data))
    if len(valid) == 0:
        raise ValueError("data holds no number (every sample is NaN)")
    return data[valid[0]:valid[-1] + 1]


def tau_m(n_data, rate, taus=None, even=False, maximum_m=None):
    """AllanTools' tau_generator as int averaging factors m for a record of n_data points.

    Parameters
    ----------
    n_data : int
        Number of points.
    rate : float
        Samples per second.
    taus : None, str or array_like
        None or [] ("octave"), "all", "octave", "decade", "log10", or taus in seconds.
    even : bool
        Keep even m only (Thêo1).
    maximum_m : float, optional
        Largest m (default n_data).

    Returns
    -------
    numpy.ndarray of int64
        m = round(tau * rate), 0 < m < n_data, m <= maximum_m, sorted, without repeats.

    References
    ----------
    NIST SP1065 sec. 5.2.4 (tau = m tau0).
    """
    if rate == 0:
        raise ValueError("rate must not be 0")
    rate = float(rate)
    if taus is None or (isinstance(taus, (list, tuple)) and len(taus) == 0):
        taus = "octave"
    if isinstance(taus, str):
        if taus == "all":
            t = (1.0 / rate) * np.linspace(1.0, n_data, n_data)
        elif taus == "octave":
            k = int(np.floor(np.log2(n_data)))
            t = (1.0 / rate) * np.logspace(0, k, k + 1, base=2.0)
        elif taus == "log10":
            top = np.log10(n_data)
            t = (1.0 / rate) * np.logspace(0, top, int(10 * top), base=10.0)
        elif taus == "decade":
            k = int(np.floor(np.log10(n_data)))
            t = np.array([f * (1.0 / rate) * 10.0**j for j in range(k + 1) for f in (1.0, 2.0, 4.0)])
        else:
            raise ValueError("taus must be None, 'all', 'octave', 'decade', 'log10' or an "
                             "array of seconds, got %r" % (taus,))
    else:
        t = np.asarray(taus, dtype=float)
    m = np.round(t * rate)
    top = n_data if maximum_m is None else maximum_m
    m = np.unique(m[(m < n_data) & (m > 0) & (m <= top)])
    if even:
        m = m[m % 2 == 0]
    return m.astype(np.int64)


def _strided(n, start, m):
    """len(x[start::m]) for len(x) == n."""
    return max(0, (n - 1 - start) // m + 1) if n > start else 0


# Each statistic's term count ns as AllanTools reports it, for phase length n (for htotdev: the
# frequency length) and averaging factor m (an array); 0 where its estimator has no term.
_NS = {
    "adev": lambda n, m: np.array([_strided(n, 2 * k, k) for k in m]),
    "oadev": lambda n, m: np.maximum(n - 2 * m, 0),
    "mdev": lambda n, m: np.maximum(n - 3 * m, 0) + 1,
    "tdev": lambda n, m: np.maximum(n - 3 * m, 0) + 1,
    "hdev": lambda n, m: np.array([_strided(n, 3 * k, k) for k in m]),
    "ohdev": lambda n, m: np.maximum(n - 3 * m, 0),
    "totdev": lambda n, m: np.full(len(m), n - 2),
    "mtotdev": lambda n, m: n - 3 * m + 1,
    "ttotdev": lambda n, m: n - 3 * m + 1,
    "htotdev": lambda n, m: np.where(m == 1, n + 1 - 3, n - 3 * m + 1),
    "theo1": lambda n, m: (n - m) * m // 2,
    "theoh": lambda n, m: (n - m) * m // 2,
    "mtie": lambda n, m: n - m,
    "tierms": lambda n, m: n - m,
    "pdev": lambda n, m: np.where(m == 1, np.maximum(n - 2, 0), np.maximum(n - 2 * m, 0)),
}


def allantools_call(stat, data, rate, data_type, taus, threads):
    """(taus, devs, errs, ns) of `stat` with AllanTools' conventions; `threads` as the caller
    gave it (None: every core, one below _checks.SMALL_RECORD samples)."""
    _checks.threads(threads)
    data = _checks.samples(data)
    rate = _checks.real(rate, "rate", positive=True)
    if len(data) < 2:
        raise ValueError("data must hold at least 2 samples, got %d" % len(data))
    if data_type == "freq":
        data = _trim_nan(data)
        if stat in ("mtie", "tierms"):
            # AllanTools integrates frequency with its mean removed; allanlot's time-error
            # kernels keep the offset (a real time error, as Stable32 does), so remove it here.
            data = data - np.nanmean(data)
    n_phase = _phase_length(data, data_type)
    n = n_phase - 1 if stat == "htotdev" else n_phase  # htotdev works on frequency data
    maximum_m = n / 3.0 if stat in ("mtotdev", "ttotdev", "htotdev") else None
    m = tau_m(n, rate, taus, even=stat in ("theo1", "theoh"), maximum_m=maximum_m)
    ns = _NS[stat](n, m).astype(np.int64) if len(m) else np.zeros(0, np.int64)
    keep = ns > 1
    m, ns = m[keep], ns[keep]
    kernel_type = "freq" if data_type == "freq" else "phase"
    r = _allanlot.deviation(data, stat, float(rate), kernel_type, m.tolist(), "", 0.0,
                            _checks.threads_for(threads, len(data)), True)
    got = dict(zip(r["m"].tolist(), r["dev"].tolist()))
    rows = [i for i, k in enumerate(m.tolist()) if k in got]
    m, ns = m[rows], ns[rows]
    devs = np.array([got[k] for k in m.tolist()], dtype=np.float64)
    taus_out = m / float(rate)
    if stat in ("theo1", "theoh"):
        errs = devs / np.sqrt((n - m).astype(np.float64))
    elif stat == "tierms":
        errs = np.zeros_like(devs)
    else:
        errs = devs / np.sqrt(ns.astype(np.float64))
    return taus_out, devs, errs, ns


def gcodev(data_1, data_2, rate=1.0, data_type="phase", taus=None, *, threads=None):
    """Groslambert codeviation of two records measured against the same reference, as
    allantools.gcodev.

    Parameters
    ----------
    data_1, data_2 : array_like
        Phase (s) or fractional frequency of the two records, of equal length.
    rate : float
        Samples per second.
    data_type : {"phase", "freq"}
        What the data hold.
    taus : None, str or array_like
        As tau_generator.
    threads : int, optional
        Keyword only: OpenMP threads (None: every core).

    Returns
    -------
    taus : numpy.ndarray
    devs : numpy.ndarray
        |codeviation|, the square root of the absolute Allan covariance (the sign AllanTools
        drops is kept by the command line's ``allanlot codev``).
    errs : numpy.ndarray
        devs / sqrt(ns).
    ns : numpy.ndarray
        N - 2m.

    References
    ----------
    Vernotte et al., Proc. IFCS 2016: the overlapping form of NIST SP1065 eq. (11) (p. 16) with
    one second difference of each record.
    """
    x = _checks.samples(data_1, "data_1")
    y = _checks.samples(data_2, "data_2")
    rate = _checks.real(rate, "rate", positive=True)
    if min(len(x), len(y)) < 2:
        raise ValueError("data_1 and data_2 must hold at least 2 samples each")
    if data_type == "freq":
        x, y = _trim_nan(x), _trim_nan(y)
    n = _phase_length(x, data_type)
    if _phase_length(y, data_type) != n:
        raise ValueError("data_1 and data_2 must have the same length")
    m = tau_m(n, rate, taus)
    ns = np.maximum(n - 2 * m, 0)
    m = m[ns > 1]
    kernel_type = "freq" if data_type == "freq" else "phase"
    r = _allanlot.gcodev(x, y, rate, kernel_type, m.tolist(),
                         _checks.threads_for(threads, len(x)))
    devs = np.abs(r["dev"])
    ns = r["n"]
    return r["m"] / float(rate), devs, devs / np.sqrt(ns.astype(np.float64)), ns


def three_cornered_hat_phase(phasedata_ab, phasedata_bc, phasedata_ca, rate, taus, function):
    """Clock A's deviation from three pairwise phase records, as
    allantools.three_cornered_hat_phase.

    var_A = (var_AB + var_CA - var_BC) / 2, negative variances set to 0 as AllanTools does (the
    command line's ``allanlot hat`` gives all three clocks with confidence intervals and
    reports negative variances instead).

    Parameters
    ----------
    phasedata_ab, phasedata_bc, phasedata_ca : array_like
        Phase records of the pairs A-B, B-C and C-A, s.
    rate : float
        Samples per second.
    taus : None, str or array_like
        As tau_generator.
    function : callable
        The statistic, e.g. allanlot.oadev.

    Returns
    -------
    taus : numpy.ndarray
    dev_a : numpy.ndarray
    err_a : numpy.ndarray
        dev_a / sqrt(ns_ab).
    ns_ab : numpy.ndarray

    References
    ----------
    J. E. Gray and D. W. Allan, Proc. 28th FCS (1974), eq. (4); the method NIST SP1065 calls
    the three-cornered hat.
    """
    tau_ab, dev_ab, _, ns_ab = function(phasedata_ab, data_type="phase", rate=rate, taus=taus)
    _, dev_bc, _, _ = function(phasedata_bc, data_type="phase", rate=rate, taus=taus)
    _, dev_ca, _, _ = function(phasedata_ca, data_type="phase", rate=rate, taus=taus)
    if not len(dev_ab) == len(dev_bc) == len(dev_ca):
        raise ValueError("the three pairs give different numbers of taus")
    var_a = 0.5 * (dev_ab**2 + dev_ca**2 - dev_bc**2)
    dev_a = np.sqrt(np.maximum(var_a, 0.0))
    return tau_ab, dev_a, dev_a / np.sqrt(np.asarray(ns_ab, dtype=np.float64)), ns_ab


_DOC = """{stat} with AllanTools' arguments and return value, {same}.

Parameters
----------
data : array_like
    Phase in seconds (data_type "phase") or fractional frequency ("freq"), 1-D or (n, 1);
    NaN inside the data is a gap.
rate : float
    Samples per second.
data_type : {{"phase", "freq"}}
    What data holds; frequency is integrated to phase with its mean removed.
taus : None, str or array_like
    None or "octave", "all", "decade", "log10", or taus in seconds (tau_generator).
threads : int, optional
    Keyword only, not in AllanTools: OpenMP threads (None: every core; one for records
    under 65 536 samples, where starting threads costs more than it saves).

Returns
-------
taus : numpy.ndarray
    Averaging times, s.
devs : numpy.ndarray
    The deviations.
errs : numpy.ndarray
    devs / sqrt(ns) (AllanTools' simple error; allanlot.deviation gives chi-square intervals).
ns : numpy.ndarray
    Number of terms of the estimator at each tau.

References
----------
{ref}.
"""


def _make(stat):
    def f(data, rate=1.0, data_type="phase", taus=None, *, threads=None):
        return allantools_call(stat, data, rate, data_type, taus, threads)

    f.__name__ = stat
    f.__qualname__ = stat
    same = ("as allantools.%s(data, rate, data_type, taus)" % stat if stat != "theoh" else
            "in the form of AllanTools' functions (AllanTools has no ThêoH)")
    f.__doc__ = _DOC.format(stat=stat, same=same, ref=_allanlot.stat_reference(stat))
    return f


ALLANTOOLS_STATS = tuple(_NS)
FUNCTIONS = {s: _make(s) for s in ALLANTOOLS_STATS}
FUNCTIONS["gcodev"] = gcodev
FUNCTIONS["three_cornered_hat_phase"] = three_cornered_hat_phase
