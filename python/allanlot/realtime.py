"""Deviations updated sample by sample from a stream of phase or frequency data.

Each class keeps, per averaging factor m, the running sum of squared differences of the
Dobrogowski and Kasznia recursions, so adding a sample costs O(number of averaging factors)
instead of recomputing the whole statistic. The results equal the batch overlapping
estimators (``allanlot.oadev``, ``ohdev``, ``tdev``, ``mdev``) on the same data.
"""

import numpy as np

__all__ = ["dev_realtime", "oadev_realtime", "ohdev_realtime", "tdev_realtime"]


class dev_realtime:  # noqa: N801  (AllanTools' class name)
    """Common state of the real-time deviations: the phase history and the averaging factors.

    Parameters
    ----------
    afs : sequence of int
        Averaging factors m (tau = m * tau0). Ignored when ``auto_afs`` is true.
    tau0 : float
        Sampling interval, s.
    auto_afs : bool
        Start with m = 1 and add ``pts_per_decade`` log-spaced factors per decade as soon as
        enough samples have arrived for each.
    pts_per_decade : int
        Averaging factors per decade in ``auto_afs`` mode.

    References
    ----------
    A. Dobrogowski and M. Kasznia, "Real-time assessment of Allan deviation and time
    deviation", Proc. IEEE IFCS-EFTF 2007, pp. 853-858 (recursions (9)-(14)).
    NIST SP1065, sections 5.2.4, 5.2.5 and 5.2.6 (the batch estimators they equal).
    """

    _order = 2  # difference order: a factor m is usable once order*m + 1 samples exist

    def __init__(self, afs=(1,), tau0=1.0, auto_afs=False, pts_per_decade=4):
        if tau0 <= 0:
            raise ValueError("tau0 must be positive, got %r" % (tau0,))
        if int(pts_per_decade) < 1:
            raise ValueError("pts_per_decade must be at least 1, got %r" % (pts_per_decade,))
        self.tau0 = float(tau0)
        self.auto_afs = bool(auto_afs)
        self._x = np.empty(1024)
        self._n = 0
        self._candidates = np.logspace(0, 1, int(pts_per_decade) + 1)[:-1]
        self._next = 1  # index of the next candidate factor in auto mode
        self.afs = np.zeros(0, dtype=np.int64)
        self.dev = np.zeros(0)
        self._reset_state(0)
        first = [1] if self.auto_afs else list(afs)
        for m in first:
            if int(m) < 1:
                raise ValueError("averaging factors must be >= 1, got %r" % (m,))
            self._append_af(int(m))

    @property
    def x(self):
        """The phase samples received so far, s."""
        return self._x[:self._n]

    def _append_af(self, m):
        self.afs = np.append(self.afs, m)
        self.dev = np.append(self.dev, 0.0)
        self._grow_state()
        self._catch_up(len(self.afs) - 1)

    def _auto_factor(self, k):
        decade, idx = divmod(k, len(self._candidates))
        return int(np.round(10.0 ** decade * self._candidates[idx]))

    def _update_afs(self):
        while self._n >= self._order * self._auto_factor(self._next) + 1:
            self._append_af(self._auto_factor(self._next))
            self._next += 1

    def add_phase(self, xnew):
        """Append one phase sample and update every deviation.

        Parameters
        ----------
        xnew : float
            Phase (time error) sample, s.

        Returns
        -------
        None
        """
        if self._n == len(self._x):
            self._x = np.concatenate([self._x, np.empty(len(self._x))])
        self._x[self._n] = float(xnew)
        self._n += 1
        self._step()
        if self.auto_afs:
            self._update_afs()

    def add_frequency(self, f):
        """Append one fractional-frequency sample, integrated to phase.

        Parameters
        ----------
        f : float
            Fractional frequency averaged over the last interval tau0.

        Returns
        -------
        None

        Notes
        -----
        The first call also stores a starting phase of 0, as x_{i+1} = x_i + y_i tau0
        (NIST SP1065 eq. 7) needs an origin.
        """
        if self._n == 0:
            self.add_phase(0.0)
        self.add_phase(self._x[self._n - 1] + float(f) * self.tau0)

    def taus(self):
        """Averaging times tau = m tau0.

        Returns
        -------
        numpy.ndarray
            One tau per averaging factor, s.
        """
        return self.tau0 * np.asarray(self.afs, dtype=float)

    def devs(self):
        """Current deviation per averaging factor (0 until enough samples exist).

        Returns
        -------
        numpy.ndarray
            One deviation per averaging factor.
        """
        return self.dev


def _ready(obj, order):
    """Indices of the factors whose last `order`-th difference exists."""
    return np.nonzero(obj._n >= order * obj.afs + 1)[0]


class _SumOfSquares(dev_realtime):
    """Variance S / (norm (m tau0)^2 (N - order m)) from the running sum S of squared
    order-th differences sum_j coeffs[j] x_{i - j m}."""

    _coeffs = (1.0, -2.0, 1.0)
    _norm = 2.0

    def _reset_state(self, k):
        self.S = np.zeros(k)

    def _grow_state(self):
        self.S = np.append(self.S, 0.0)

    def _catch_up(self, j):
        m, x, k = int(self.afs[j]), self.x, self._order
        if len(x) >= k * m + 1:
            d = sum(c * x[(k - i) * m:len(x) - i * m] for i, c in enumerate(self._coeffs))
            self.S[j] = np.dot(d, d)
            self._finish(np.array([j]))

    def _finish(self, idx):
        m = self.afs[idx].astype(float)
        self.dev[idx] = np.sqrt(self.S[idx] / (self._norm * (m * self.tau0) ** 2
                                               * (self._n - self._order * m)))

    def _step(self):
        idx = _ready(self, self._order)
        if len(idx):
            i, m, x = self._n - 1, self.afs[idx], self._x
            d = sum(c * x[i - k * m] for k, c in enumerate(self._coeffs))
            self.S[idx] += d * d
            self._finish(idx)


class oadev_realtime(_SumOfSquares):  # noqa: N801
    """Overlapping Allan deviation updated per sample (parameters as `dev_realtime`).

    sigma^2(m tau0) = S / (2 (m tau0)^2 (N - 2m)), S the running sum of
    (x_i - 2 x_{i-m} + x_{i-2m})^2.

    References
    ----------
    A. Dobrogowski and M. Kasznia, IEEE IFCS-EFTF 2007, eq. (9).
    NIST SP1065, eq. 11 (overlapping Allan variance).
    """


class ohdev_realtime(_SumOfSquares):  # noqa: N801
    """Overlapping Hadamard deviation updated per sample (parameters as `dev_realtime`).

    H^2(m tau0) = S / (6 (m tau0)^2 (N - 3m)), S the running sum of
    (x_i - 3 x_{i-m} + 3 x_{i-2m} - x_{i-3m})^2.

    References
    ----------
    A. Dobrogowski and M. Kasznia, IEEE IFCS-EFTF 2007 (third-difference analogue of eq. 9).
    NIST SP1065, eq. 20 (overlapping Hadamard variance).
    """

    _order = 3
    _coeffs = (1.0, -3.0, 3.0, -1.0)
    _norm = 6.0


class tdev_realtime(dev_realtime):  # noqa: N801
    """Time deviation (and modified Allan deviation) updated per sample.

    S holds the current inner sum of m second differences; each new sample moves the window by
    one through the third difference x_i - 3 x_{i-m} + 3 x_{i-2m} - x_{i-3m}, and So
    accumulates S^2: TDEV^2 = So / (6 m^2 (N - 3m + 1)). Parameters as `dev_realtime`.

    References
    ----------
    A. Dobrogowski and M. Kasznia, IEEE IFCS-EFTF 2007, eqs. (11)-(14).
    NIST SP1065, eqs. 14-15 (modified Allan variance and time variance).
    """

    def _reset_state(self, k):
        self.S = np.zeros(k)
        self.So = np.zeros(k)

    def _grow_state(self):
        self.S = np.append(self.S, 0.0)
        self.So = np.append(self.So, 0.0)

    def _catch_up(self, j):
        m, x = int(self.afs[j]), self.x
        if len(x) < 2 * m + 1:
            return
        d = x[2 * m:] - 2 * x[m:-m] + x[:-2 * m]
        c = np.concatenate([[0.0], np.cumsum(d)])
        if len(d) < m:  # the first window is still filling
            self.S[j] = c[-1]
            return
        sums = c[m:] - c[:-m]
        self.S[j] = sums[-1]
        self.So[j] = np.dot(sums, sums)
        self._finish(np.array([j]))

    def _finish(self, idx):
        m = self.afs[idx].astype(float)
        self.dev[idx] = np.sqrt(self.So[idx] / (6.0 * m * m * (self._n - 3 * m + 1)))

    def _step(self):
        i, x = self._n - 1, self._x
        full = np.nonzero(self._n >= 3 * self.afs + 1)[0]
        if len(full):
            m = self.afs[full]
            self.S[full] += x[i] - 3 * x[i - m] + 3 * x[i - 2 * m] - x[i - 3 * m]
            self.So[full] += self.S[full] ** 2
            self._finish(full)
        filling = np.nonzero((self._n >= 2 * self.afs + 1) & (self._n <= 3 * self.afs))[0]
        if len(filling):
            m = self.afs[filling]
            self.S[filling] += x[i] - 2 * x[i - m] + x[i - 2 * m]
            done = filling[self._n == 3 * self.afs[filling]]
            self.So[done] = self.S[done] ** 2
            self._finish(done)

    def mdev(self):
        """Modified Allan deviation, MDEV = sqrt(3) TDEV / tau.

        Returns
        -------
        numpy.ndarray
            One MDEV per averaging factor.
        """
        return self.dev * np.sqrt(3.0) / (self.afs * self.tau0)
