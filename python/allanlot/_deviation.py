"""allanlot.deviation and its result: one Allan-family statistic with confidence intervals and
noise identification, as ``allanlot analyze`` computes it."""

import numpy as np

from . import _allanlot
from . import _checks

#: The confidence of the command line's intervals: one standard deviation, two-sided.
DEFAULT_CONFIDENCE = 0.683


class Deviation:
    """One statistic of one record, as the command line writes it to allan/<stat>/.

    Attributes
    ----------
    m, tau, dev, n, edf, dev_lo, dev_hi, alpha : numpy.ndarray
        One entry per tau: averaging factor, tau (s; Thêo1: 0.75 m tau0), deviation, terms in
        the estimator, equivalent degrees of freedom, the confidence interval (NaN for
        statistics without one), identified power-law exponent of the rate PSD (S_y ~ f^alpha).
    stat : str
    confidence : float
    tau0 : float
        Sample interval, s.
    n_points : int
        Phase points.
    n_gaps : int
        Missing samples.
    units : str
        As given to deviation().

    References
    ----------
    NIST SP1065 sec. 5.2 (eqs. (7)-(32)) for the statistics, sec. 5.3.3 and eq. (45) for the
    intervals; docs/statistics.md.
    """

    _ARRAYS = ("m", "tau", "dev", "n", "edf", "dev_lo", "dev_hi", "alpha")

    def __init__(self, d, units=""):
        for k in self._ARRAYS:
            setattr(self, k, d[k])
        self.stat = d["stat"]
        self.confidence = d["confidence"]
        self.tau0 = d["tau0"]
        self.n_points = d["n_points"]
        self.n_gaps = d["n_gaps"]
        self.units = units

    def __len__(self):
        return len(self.m)

    def as_dict(self):
        """The arrays by name, as read_results() gives allan/<stat>/.

        Returns
        -------
        dict of str to numpy.ndarray
        """
        return {k: getattr(self, k) for k in self._ARRAYS}

    def __repr__(self):
        return "<allanlot.Deviation %s: %d taus from %g s to %g s>" % (
            self.stat, len(self), self.tau[0] if len(self) else float("nan"),
            self.tau[-1] if len(self) else float("nan"))


def deviation(data, stat="oadev", rate=1.0, data_type="phase", taus=None,
              confidence=DEFAULT_CONFIDENCE, threads=None, units=""):
    """One Allan-family statistic with its confidence interval, as ``allanlot analyze``
    computes it.

    Parameters
    ----------
    data : array_like
        Samples, 1-D or (n, 1) (float64 used in place; other dtypes converted once); NaN is a gap.
    stat : str
        One of stats().
    rate : float
        Samples per second.
    data_type : {"phase", "freq", "rate"}
        Phase, or fractional frequency or any rate such as deg/s ("freq" and "rate" alike).
    taus : None, str or array_like
        None (the command line's default grid, "log:16"), a grid name ("octave", "decade",
        "all", "stable32", "log:K", "m:1,2,5"), or taus in seconds (rounded to the nearest m).
        The taus run to Stable32's largest m for the statistic, as on the command line.
    confidence : float or None
        Two-sided level of dev_lo/dev_hi, in (0, 1); None: no intervals.
    threads : int, optional
        OpenMP threads (None: every core, capped as on the command line).
    units : str
        The data's units, kept for fit() and plot().

    Returns
    -------
    Deviation

    References
    ----------
    NIST SP1065 eqs. (7)-(32) as cited in docs/statistics.md; intervals: chi-square (eq. (45))
    with Greenhall & Riley's edf (sec. 5.3.3). AllanTools equivalent: allanlot.<stat>(...).
    """
    data = _checks.samples(data)
    rate = _checks.real(rate, "rate", positive=True)
    conf = _checks.confidence(confidence)
    if not isinstance(stat, str):
        raise TypeError("stat must be a statistic's name (allanlot.stats()), got %r" % (stat,))
    m_list, grid = None, "log:16"
    if taus is None:
        pass
    elif isinstance(taus, str):
        grid = taus
    else:
        t = np.atleast_1d(np.asarray(taus, dtype=float))
        m = np.round(t * float(rate))
        m_list = np.unique(m[m >= 1]).astype(np.int64).tolist()
        if not m_list:
            raise ValueError("no tau of %r is at least one sample interval" % (taus,))
    d = _allanlot.deviation(data, stat, float(rate), data_type, m_list, grid, conf,
                            _checks.threads_for(threads, len(data)), False)
    return Deviation(d, units)
