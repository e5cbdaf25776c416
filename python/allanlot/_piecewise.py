"""Piecewise power-law PSD S_y(f) = h_i f^alpha_i <-> Allan/Hadamard deviation.

The Allan variance of a one-sided fractional-frequency PSD is (NIST SP1065 eq. 65)
    sigma^2(tau) = 2 int_0^inf S_y(f) sin^4(pi f tau) / (pi f tau)^2 df,
so with z = pi f tau a segment h f^alpha on [f_a, f_b) adds
    2 h (pi tau)^(-alpha-1) int_{pi tau f_a}^{pi tau f_b} sin^4(z) z^(alpha-2) dz.
The Hadamard variance has the extra factor (4/3) sin^2(z) (IEEE 1139, Table 7 of SP1065).
"""

import math

import numpy as np

# sin^4 z = sum_k c_k (1 - cos(k z)) and (4/3) sin^6 z likewise: the constant terms balance,
# so int_0^inf of each weighted sum converges where the z^-s tail and z->0 limit allow.
_COS_SERIES = {"adev": ((2, 4.0 / 8), (4, -1.0 / 8)),
               "hdev": ((2, 4.0 / 3 * 15 / 32), (4, -4.0 / 3 * 6 / 32), (6, 4.0 / 3 / 32))}
_X_ASYMPTOTIC = 2000.0  # beyond it the integral of sin^4 z z^-s uses its asymptotic expansion


def _one_minus_cos_integral(a, s):
    """int_0^inf (1 - cos(a z)) z^-s dz = a^(s-1) pi / (2 Gamma(s) sin(pi (s-1)/2)), 1<s<3
    (Gradshteyn & Ryzhik 3.823); analytically continued for the balanced sums above."""
    return a ** (s - 1) * math.pi / (2.0 * math.gamma(s) * math.sin(math.pi * (s - 1) / 2))


def _full_integral(s, vartype):
    """J = int_0^inf q(z) sin^4(z) z^-s dz in closed form; removable poles at odd integers s
    are bridged by the polynomial through six points around them (J is analytic there, and
    the points are far enough from the pole for the cancellation to cost only ~1e-13)."""
    def value(t):
        return sum(c * _one_minus_cos_integral(a, t) for a, c in _COS_SERIES[vartype])

    pole = round(s)
    if abs(s - pole) < 1e-3 and pole % 2 == 1:
        offsets = np.array([-3e-3, -2e-3, -1e-3, 1e-3, 2e-3, 3e-3])
        coef = np.polynomial.polynomial.polyfit(offsets, [value(pole + d) for d in offsets], 5)
        return float(np.polynomial.polynomial.polyval(s - pole, coef))
    return value(s)


def _sin4_antiderivative_tail(x, s):
    """Antiderivative of sin^4(z) z^-s for large z: 3/8 z^-s minus the cosines, each
    integrated by parts twice (error O(x^-s-3))."""
    main = math.log(x) if abs(s - 1) < 1e-12 else x ** (1 - s) / (1 - s)
    out = 3.0 / 8 * main
    for a, c in ((2, -0.5), (4, 0.125)):
        out += c * (math.sin(a * x) * x ** -s / a - s * math.cos(a * x) * x ** (-s - 1) / a ** 2
                    - s * (s + 1) * math.sin(a * x) * x ** (-s - 2) / a ** 3)
    return out


def _sin4_integral(lo, hi, s):
    """int_lo^hi sin^4(z) z^-s dz for 0 <= lo < hi <= inf."""
    if hi == math.inf and s <= 1:
        raise ValueError("S_y(f) = h f^alpha with alpha >= 1 up to infinite frequency has an "
                         "infinite Allan variance: give a finite last node")
    if lo == 0 and s >= 5:
        raise ValueError("S_y(f) = h f^alpha with alpha <= -3 down to f = 0 has an infinite "
                         "Allan variance: give a first node above 0")
    total = 0.0
    top = min(hi, _X_ASYMPTOTIC)
    if lo < top:
        total += _quadrature(lo, top, s)
    if hi > _X_ASYMPTOTIC:
        start = max(lo, _X_ASYMPTOTIC)
        end = 0.0 if hi == math.inf else _sin4_antiderivative_tail(hi, s)
        total += end - _sin4_antiderivative_tail(start, s)
    return total


def _quadrature(lo, hi, s):
    """Gauss-Legendre in ln z up to z = 1, then on panels of width pi/8; below z = 0.05 the
    Taylor series
    sin^4 z = z^4 - 2 z^6/3 + z^8/5 - 34 z^10/945 integrated exactly (handles z^(4-s))."""
    total = 0.0
    z0 = 0.05
    if lo < z0:
        b = min(hi, z0)
        for k, c in ((4, 1.0), (6, -2.0 / 3), (8, 1.0 / 5), (10, -34.0 / 945)):
            p = k - s + 1
            total += c * (b ** p - lo ** p) / p
        lo = b
    nodes, weights = np.polynomial.legendre.leggauss(12)
    if lo < 1.0:  # z^(4-s) is steep near 0: integrate in u = ln z, where it is smooth
        b = min(hi, 1.0)
        edges = np.linspace(math.log(lo), math.log(b), 5)
        half = 0.5 * np.diff(edges)[:, None]
        z = np.exp(0.5 * (edges[:-1] + edges[1:])[:, None] + half * nodes[None, :])
        total += float(np.sum(half * weights[None, :] * np.sin(z) ** 4 * z ** (1.0 - s)))
        lo = b
    if lo >= hi:
        return total
    panels = max(1, int(math.ceil((hi - lo) / (math.pi / 8))))
    edges = np.linspace(lo, hi, panels + 1)
    half = 0.5 * np.diff(edges)[:, None]
    z = 0.5 * (edges[:-1] + edges[1:])[:, None] + half * nodes[None, :]
    return total + float(np.sum(half * weights[None, :] * np.sin(z) ** 4 * z ** -s))


def psd_piecewise_to_adev(h, alpha, f_nodes, taus):
    """Allan deviation of a piecewise power-law fractional-frequency PSD.

    Parameters
    ----------
    h : array_like
        Coefficient h_i of each segment S_y(f) = h_i f^alpha_i, 1/Hz^(alpha_i+1).
    alpha : array_like
        Exponent alpha_i of each segment (same length as ``h``).
    f_nodes : array_like
        Ascending break frequencies, Hz, ``len(h) - 1`` of them: segment 0 spans
        [0, f_nodes[0]), the last [f_nodes[-1], inf).
    taus : array_like
        Averaging times, s.

    Returns
    -------
    numpy.ndarray
        Allan deviation at each tau.

    References
    ----------
    NIST SP1065, eq. 65 (Allan variance from S_y(f)) and Table 7 (its power-law terms).
    """
    h, alpha = np.atleast_1d(np.asarray(h, float)), np.atleast_1d(np.asarray(alpha, float))
    f_nodes = np.atleast_1d(np.asarray(f_nodes, float))
    taus = np.asarray(taus, float)
    if h.shape != alpha.shape or h.ndim != 1 or len(f_nodes) != len(h) - 1:
        raise ValueError("need len(h) == len(alpha) == len(f_nodes) + 1, got %d, %d, %d"
                         % (len(h), len(alpha), len(f_nodes)))
    if np.any(np.diff(f_nodes) <= 0) or np.any(f_nodes <= 0):
        raise ValueError("f_nodes must be positive and strictly increasing")
    if np.any(taus <= 0):
        raise ValueError("taus must be positive")
    edges = np.concatenate([[0.0], f_nodes, [np.inf]])
    out = np.empty(taus.shape)
    for k, tau in np.ndenumerate(taus):
        var = 0.0
        for i in range(len(h)):
            z = math.pi * tau
            integral = _sin4_integral(z * edges[i], z * edges[i + 1], 2.0 - alpha[i])
            var += 2.0 * h[i] * z ** (-alpha[i] - 1.0) * integral
        out[k] = math.sqrt(var)
    return out


def _local_slopes(adev, taus, mu_tol):
    """Slopes mu of sigma^2 ~ tau^mu between nodes, merging neighbours closer than mu_tol."""
    mus, kept = [], [0]
    for i in range(1, len(adev)):
        mu = 2.0 * math.log(adev[i] / adev[i - 1]) / math.log(taus[i] / taus[i - 1])
        if mus and abs(mu - mus[-1]) <= mu_tol:
            kept[-1] = i
        else:
            mus.append(mu)
            kept.append(i)
    return np.array(mus), np.array(kept)


def adev2psd_piecewise_approx(adev, taus, vartype="adev", mu_tol=1e-5):
    """Piecewise power-law PSD S_y(f) whose Allan (or Hadamard) deviation follows given points.

    Between consecutive nodes sigma^2 = B_i tau^mu_i; the exact integral relation turns each
    power law into S_y = h_i f^alpha_i with alpha_i = -mu_i - 1 and
    h_i = B_i / (2 J(mu_i) pi^mu_i), J(mu) = int_0^inf q(z) sin^4(z) z^-(3+mu) dz
    (q = 1 for ADEV, (4/3) sin^2 z for HDEV). Break frequencies are where neighbouring PSD
    segments meet, so the PSD is continuous.

    Parameters
    ----------
    adev : array_like
        Deviations at ``taus`` (at least two, positive).
    taus : array_like
        Strictly increasing averaging times, s.
    vartype : {'adev', 'hdev'}
        Whether ``adev`` holds Allan or Hadamard deviations.
    mu_tol : float
        Neighbouring slopes closer than this merge into one segment.

    Returns
    -------
    f_nodes : numpy.ndarray
        Ascending break frequencies, Hz (one fewer than segments).
    Sy_nodes : numpy.ndarray
        S_y at each break frequency, 1/Hz.
    h : numpy.ndarray
        Coefficients, lowest-frequency segment first.
    alpha : numpy.ndarray
        Exponents, lowest-frequency segment first.

    References
    ----------
    F. De Marchi, M. K. Plumaris, E. A. Burt and L. Iess, "An algorithm to estimate the power
    spectral density from Allan deviation", IEEE Trans. UFFC 71(4), 506-515 (2024).
    NIST SP1065, eq. 65 and Table 7 (power-law Allan and Hadamard variances).
    """
    adev, taus = np.asarray(adev, float), np.asarray(taus, float)
    if adev.ndim != 1 or adev.shape != taus.shape or len(adev) < 2:
        raise ValueError("adev and taus must be 1-D of equal length >= 2")
    if np.any(adev <= 0) or np.any(taus <= 0) or np.any(np.diff(taus) <= 0):
        raise ValueError("adev and taus must be positive and taus strictly increasing")
    vt = str(vartype).lower()
    if vt not in _COS_SERIES:
        raise ValueError("vartype must be 'adev' or 'hdev', got %r" % (vartype,))
    mus, kept = _local_slopes(adev, taus, mu_tol)
    upper = 2.0 if vt == "adev" else 4.0
    for i, mu in enumerate(mus):
        if not -2.0 < mu < upper:
            raise ValueError("%s slope %.3g between tau = %g s and %g s is outside (-2, %g): "
                             "no power-law PSD gives it" % (vt.upper(), mu, taus[kept[i]],
                                                            taus[kept[i + 1]], upper))
    ends = kept[1:]
    b = adev[ends] ** 2 * taus[ends] ** -mus
    j = np.array([_full_integral(3.0 + mu, vt) for mu in mus])
    h = (b / (2.0 * j * math.pi ** mus))[::-1]
    alpha = (-mus - 1.0)[::-1]
    # segments i and i+1 meet where h_i f^alpha_i = h_{i+1} f^alpha_{i+1}
    f_nodes = (h[:-1] / h[1:]) ** (1.0 / (alpha[1:] - alpha[:-1]))
    return f_nodes, h[:-1] * f_nodes ** alpha[:-1], h, alpha
