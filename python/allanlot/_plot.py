"""allanlot.plot: deviations with their confidence intervals, the eq. (3) fit with each of its
terms, and the PSD, as one matplotlib Figure (matplotlib is imported only here)."""

import math

import numpy as np

_LN2 = math.log(2.0)

# Each term's Allan variance over tau for the value v of eq. (3) (docs/fit-and-psd.md):
# R^2 tau^2 / 2, K^2 tau / 3, B^2 2 ln 2 / pi, N^2 / tau, 3 Q^2 / tau^2.
_TERM_AVAR = {
    "R": lambda v, t: v * v * t * t / 2.0,
    "K": lambda v, t: v * v * t / 3.0,
    "B": lambda v, t: v * v * 2.0 * _LN2 / math.pi * np.ones_like(t),
    "N": lambda v, t: v * v / t,
    "Q": lambda v, t: 3.0 * v * v / (t * t),
}


def _figure(two_panels):
    try:
        from matplotlib.figure import Figure
    except ImportError as e:
        raise RuntimeError("allanlot.plot needs matplotlib (Debian: python3-matplotlib)") from e
    fig = Figure(figsize=(11.0 if two_panels else 6.4, 4.8), layout="constrained")
    axes = fig.subplots(1, 2) if two_panels else [fig.subplots()]
    return fig, axes


def _draw_deviation(ax, d):
    lo, hi = np.asarray(d.dev_lo), np.asarray(d.dev_hi)
    ok = np.isfinite(lo) & np.isfinite(hi)
    if ok.any():
        ax.errorbar(d.tau[ok], d.dev[ok], yerr=[d.dev[ok] - lo[ok], hi[ok] - d.dev[ok]],
                    fmt="o", ms=3, capsize=2, label=d.stat)
        if (~ok).any():
            ax.plot(d.tau[~ok], d.dev[~ok], "o", ms=3)
    else:
        ax.plot(d.tau, d.dev, "o-", ms=3, label=d.stat)


def _draw_fit(ax, fit):
    tau = np.asarray(fit["tau"], dtype=float)
    if len(tau) == 0:
        return
    ax.plot(tau, fit["adev_model"], "k-", lw=1.5, label="eq. (3) fit (%s)" % fit["status"])
    terms = fit.get("terms", {})
    for name, value in zip(terms.get("term", []), np.asarray(terms.get("value", []), float)):
        if name in _TERM_AVAR and value > 0:
            ax.plot(tau, np.sqrt(_TERM_AVAR[name](value, tau)), "--", lw=1,
                    label="%s = %.3g" % (name, value))


def _limit_to_curves(ax, deviations, fit):
    """y range of the measured and fitted curves: a term's line alone (a ramp R at small tau)
    may run decades below them and would squeeze the curves into a corner."""
    values = [np.asarray(d.dev, float) for d in deviations]
    if fit is not None:
        values.append(np.asarray(fit["adev_model"], float))
    v = np.concatenate(values) if values else np.zeros(0)
    v = v[np.isfinite(v) & (v > 0)]
    if len(v):
        ax.set_ylim(v.min() / 3.0, v.max() * 3.0)


def plot(*deviations, fit=None, psd=None, title=None, units=None):
    """Sigma-tau plot of allanlot results, returned as a matplotlib Figure.

    Parameters
    ----------
    *deviations : Deviation
        Results of allanlot.deviation(); each is drawn with its confidence interval as error
        bars (statistics without one, MTIE and TIE rms, as points).
    fit : dict, optional
        allanlot.fit()'s result: the model curve and each non-zero term of eq. (3) alone
        (R tau / sqrt 2, K sqrt(tau / 3), B sqrt(2 ln 2 / pi), N / sqrt(tau), sqrt 3 Q / tau).
    psd : dict, optional
        allanlot.psd()'s result, drawn in a second panel (f against the one-sided PSD).
    title : str, optional
        The figure's title.
    units : str, optional
        The data's units, for the axis labels (default: the first deviation's).

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot: show it with IPython's display, or save it with savefig().

    References
    ----------
    NIST SP1065 sec. 5.2 for sigma-tau plots and eq. (45) for the intervals;
    IEEE Std 952-1997 Annex C for the terms of eq. (3).
    """
    from . import Deviation
    for d in deviations:
        if not isinstance(d, Deviation):
            raise TypeError("deviations must be Deviation results of allanlot.deviation(), got %s"
                            % type(d).__name__)
    if fit is not None and not isinstance(fit, dict):
        raise TypeError("fit must be the dict allanlot.fit() returns, got %s" % type(fit).__name__)
    if psd is not None and not (isinstance(psd, dict) and "f" in psd and "psd" in psd):
        raise TypeError("psd must be the dict allanlot.psd() returns")
    if not deviations and fit is None and psd is None:
        raise ValueError("nothing to plot: give deviations, fit or psd")
    if units is None:
        units = next((d.units for d in deviations if d.units), "")
    fig, axes = _figure(psd is not None and (deviations or fit is not None))
    ax = axes[0]
    if deviations or fit is not None:
        for d in deviations:
            _draw_deviation(ax, d)
        if fit is not None:
            _draw_fit(ax, fit)
        ax.set_xscale("log")
        ax.set_yscale("log")
        _limit_to_curves(ax, deviations, fit)
        ax.set_xlabel("tau (s)")
        ax.set_ylabel("deviation" + (" (%s)" % units if units else ""))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
        ax = axes[-1]
    if psd is not None:
        f, p = np.asarray(psd["f"]), np.asarray(psd["psd"])
        keep = (f > 0) & (p > 0)
        ax.loglog(f[keep], p[keep], "-", lw=1)
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel("PSD" + (" (%s^2/Hz)" % units if units else ""))
        ax.grid(True, which="both", alpha=0.3)
    if title:
        fig.suptitle(title)
    return fig
