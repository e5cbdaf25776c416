"""AllanTools' ``Noise`` class: Kasdin & Walter's discrete power-law noise generator and the
deviations its parameters predict, with AllanTools' names (``allantools.Noise``)."""

import math

import numpy as np

from . import _checks

_EULER_GAMMA = 0.5772156649015329


class Noise:
    """Discrete power-law noise x[n] with phase PSD S_x(f) = g_b f^b, b in 0 .. -4.

    White noise of variance ``qd`` filtered by the causal filter of Kasdin & Walter,
    h_0 = 1, h_k = h_(k-1) (k - 1 - b/2) / k (the expansion of (1 - z^-1)^(b/2)), convolved
    through zero-padded FFTs. b = 0, -1, -2, -3, -4: white PM, flicker PM, white FM, flicker FM
    and random-walk FM.

    Parameters
    ----------
    nr : int
        Number of samples (AllanTools asks for a power of two; any length works).
    qd : float
        Discrete variance of the driving white noise.
    b : int
        Exponent of the phase PSD.

    Attributes
    ----------
    time_series : numpy.ndarray
        The samples, after generateNoise().

    References
    ----------
    N. J. Kasdin and T. Walter, "Discrete simulation of power law noise", Proc. 1992 IEEE
    Frequency Control Symposium, pp. 274-283, eqs. (30) and (39); the deviations of each
    noise: Dawkins, McFerran & Luiten, IEEE Trans. UFFC 54 (2007) 918, Table I;
    NIST SP1065 sec. 5.2 (the slopes of each deviation for each noise).
    """

    def __init__(self, nr=2, qd=1.0, b=0):
        self.set_input(nr, qd, b)
        self.time_series = np.array([])

    def set_input(self, nr=2, qd=1.0, b=0):
        """Set the length ``nr``, the variance ``qd`` and the phase-PSD exponent ``b``.

        Parameters
        ----------
        nr : int
            Number of samples.
        qd : float
            Discrete variance of the driving white noise (>= 0).
        b : int or float
            Exponent of the phase PSD, from 0 (white PM) to -4 (random-walk FM).

        Returns
        -------
        None
        """
        self.nr = _checks.whole(nr, "nr", 1)
        self.qd = _checks.real(qd, "qd", minimum=0.0)
        self.b = _checks.real(b, "b")

    def generateNoise(self):  # noqa: N802 (AllanTools' name)
        """Draw ``nr`` samples into ``time_series``.

        Returns
        -------
        None
            The samples are in ``self.time_series``.
        """
        n = self.nr
        h = np.ones(n)
        k = np.arange(1, n)
        h[1:] = np.cumprod((k - 1 - self.b / 2.0) / k)
        w = np.random.normal(0.0, math.sqrt(self.qd), n)
        size = 2 * n
        x = np.fft.irfft(np.fft.rfft(w, size) * np.fft.rfft(h, size), size)[:n]
        self.time_series = x

    def phase_psd_from_qd(self, tau0=1.0):
        """The coefficient g_b of the phase PSD S_x(f) = g_b f^b of these samples at spacing
        ``tau0``: g_b = 2 qd (2 pi)^b tau0^(b + 1) (Kasdin & Walter eq. (39)).

        Parameters
        ----------
        tau0 : float
            Sample interval, s.

        Returns
        -------
        float
        """
        return self.qd * 2.0 * (2.0 * math.pi) ** self.b * tau0 ** (self.b + 1.0)

    def frequency_psd_from_qd(self, tau0=1.0):
        """The coefficient h_a of the fractional-frequency PSD S_y(f) = h_a f^a, a = b + 2:
        h_a = 2 qd (2 pi)^a tau0^(a - 1) (S_y = (2 pi f)^2 S_x, SP1065 eq. (66)).

        Parameters
        ----------
        tau0 : float
            Sample interval, s.

        Returns
        -------
        float
        """
        a = self.b + 2.0
        return self.qd * 2.0 * (2.0 * math.pi) ** a * tau0 ** (a - 1.0)

    def c_avar(self):
        """Exponent c of tau in AVAR = prefactor^2 tau^c for this noise (NIST SP1065 sec. 5.2).

        Returns
        -------
        float
        """
        return {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -2.0}[int(self.b)]

    def c_mvar(self):
        """Exponent c of tau in MVAR = prefactor^2 tau^c (NIST SP1065 sec. 5.2).

        Returns
        -------
        float
        """
        return {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -3.0}[int(self.b)]

    def adev_from_qd(self, tau0=1.0, tau=1.0):
        """sqrt(K h_a), with AVAR = K h_a tau^c: K = 3 f_h / (4 pi^2) (white PM),
        (1.038 + 3 ln(2 pi f_h tau)) / (4 pi^2) (flicker PM), 1/2 (white FM), 2 ln 2 (flicker
        FM), 2 pi^2 / 3 (random-walk FM), f_h = 1 / (2 tau0).

        Parameters
        ----------
        tau0 : float
            Sample interval, s.
        tau : float
            Averaging time, s (used by flicker PM only).

        Returns
        -------
        float

        References
        ----------
        Dawkins et al., IEEE Trans. UFFC 54 (2007) 918, Table I; the flicker PM
        constant 3 gamma - ln 2 = 1.038.
        """
        f_h = 0.5 / tau0
        k = {0: 3.0 * f_h / (4.0 * math.pi ** 2),
             -2: 0.5, -3: 2.0 * math.log(2.0), -4: 2.0 * math.pi ** 2 / 3.0}
        b = int(self.b)
        if b == -1:
            coeff = ((3.0 * _EULER_GAMMA - math.log(2.0) + 3.0 * np.log(2.0 * math.pi * f_h * tau))
                     / (4.0 * math.pi ** 2))
        else:
            coeff = k[b]
        return np.sqrt(coeff * self.frequency_psd_from_qd(tau0))

    def mdev_from_qd(self, tau0=1.0, tau=1.0):
        """sqrt(K h_a), with MVAR = K h_a tau^c: K = 3 / (8 pi^2) (white PM),
        (24 ln 2 - 9 ln 3) / (8 pi^2) (flicker PM), 1/4 (white FM), 27 ln 2 / 20 (flicker FM),
        11 pi^2 / 20 (random-walk FM).

        Parameters
        ----------
        tau0 : float
            Sample interval, s.
        tau : float
            Averaging time, s (unused: every MVAR law here is a pure power of tau).

        Returns
        -------
        float

        References
        ----------
        Dawkins et al., IEEE Trans. UFFC 54 (2007) 918, Table I; Benkler et al.,
        Metrologia 52 (2015) 565, Table 1.
        """
        k = {0: 3.0 / (8.0 * math.pi ** 2),
             -1: (24.0 * math.log(2.0) - 9.0 * math.log(3.0)) / (8.0 * math.pi ** 2),
             -2: 0.25, -3: 27.0 / 20.0 * math.log(2.0), -4: 11.0 / 20.0 * math.pi ** 2}
        return np.sqrt(k[int(self.b)] * self.frequency_psd_from_qd(tau0))

    def adev(self, tau0, tau):
        """The Allan deviation these samples should show at ``tau`` (tau0 their spacing).

        Parameters
        ----------
        tau0 : float
            Sample interval, s.
        tau : float or array_like
            Averaging times, s.

        Returns
        -------
        float or numpy.ndarray

        References
        ----------
        Dawkins et al., IEEE Trans. UFFC 54 (2007) 918, Table I.
        """
        return np.sqrt(self.adev_from_qd(tau0, tau) ** 2 * np.power(tau, self.c_avar()))

    def mdev(self, tau0, tau):
        """The modified Allan deviation these samples should show at ``tau``.

        Parameters
        ----------
        tau0 : float
            Sample interval, s.
        tau : float or array_like
            Averaging times, s.

        Returns
        -------
        float or numpy.ndarray

        References
        ----------
        Dawkins et al., IEEE Trans. UFFC 54 (2007) 918, Table I.
        """
        return np.sqrt(self.mdev_from_qd(tau0, tau) ** 2 * np.power(tau, self.c_mvar()))
