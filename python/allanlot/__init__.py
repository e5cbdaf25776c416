"""allanlot for Python: the Allan-variance family, the eq. (3) noise fit, the Welch PSD, the
simulator and diagnose, on the command line's kernels, with numpy arrays in and out.

Two faces (docs/python.md):

- AllanTools' functions with AllanTools' arguments and return values, so that
  ``import allanlot as allantools`` runs a notebook written for AllanTools unchanged:
  ``oadev(data, rate=1.0, data_type="phase", taus=None) -> (taus, devs, errs, ns)``, and
  likewise adev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev, htotdev, theo1, mtie,
  tierms, pdev, gcodev, three_cornered_hat_phase (and theoh);
- the richer API of the command line: ``deviation`` (confidence intervals, noise
  identification, Stable32's tau grids and ranges), ``fit``, ``psd``, ``simulate``,
  ``diagnose``, ``read_results``, ``read_lot_summary``.

Errors are ValueError (bad arguments, models, data; the command line's exit status 2) and
OSError (files that cannot be read or are damaged; exit status 1), with the command line's
messages. The kernels run without the GIL, on ``threads`` OpenMP threads (None: all), and give
the same bits for any thread count.
"""

import json
import os

import numpy as np

from . import _allanlot
from . import _checks
from ._allantools import FUNCTIONS as _FUNCTIONS
from ._allantools import tau_m

__all__ = [
    "Deviation", "Simulation", "deviation", "fit", "psd", "simulate", "diagnose",
    "read_results", "read_lot_summary", "read_lot_statistics", "stats", "tau_m",
] + list(_FUNCTIONS)

#: The confidence of the command line's intervals: one standard deviation, two-sided.
DEFAULT_CONFIDENCE = 0.683

# adev, oadev, ... as module functions.
globals().update(_FUNCTIONS)


def stats():
    """The statistics this build computes (names as in AllanTools and the results files)."""
    return list(_allanlot.stats())


class Deviation:
    """One statistic of one record, as the command line writes it to allan/<stat>/.

    Arrays (one entry per tau): m (averaging factor), tau (s; Thêo1: 0.75 m tau0), dev, n (terms
    in the estimator), edf (equivalent degrees of freedom), dev_lo and dev_hi (the confidence
    interval; NaN for statistics without one), alpha (identified power-law exponent of the
    rate PSD, S_y ~ f^alpha). Scalars: stat, confidence, tau0 (s), n_points (phase points),
    n_gaps (missing samples), units (as given to deviation()).
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
        """The arrays by name, as read_results() gives allan/<stat>/."""
        return {k: getattr(self, k) for k in self._ARRAYS}

    def __repr__(self):
        return "<allanlot.Deviation %s: %d taus from %g s to %g s>" % (
            self.stat, len(self), self.tau[0] if len(self) else float("nan"),
            self.tau[-1] if len(self) else float("nan"))


_threads = _checks.threads


def deviation(data, stat="oadev", rate=1.0, data_type="phase", taus=None,
              confidence=DEFAULT_CONFIDENCE, threads=None, units=""):
    """One Allan-family statistic with its confidence interval, as ``allanlot analyze`` computes it.

    data: 1-D array-like (float64 used in place; other dtypes converted once); NaN is a gap.
    stat: one of stats(). rate: samples per second. data_type: "phase" or "freq" (fractional
    frequency, or any rate such as deg/s; "rate" is accepted too).
    taus: None (the command line's default grid, "log:16"), a grid name ("octave", "decade",
    "all", "stable32", "log:K", "m:1,2,5"), or an array of taus in seconds (rounded to the
    nearest m). The taus run to Stable32's largest m for the statistic (max_m), as on the
    command line. confidence: two-sided level of dev_lo/dev_hi, in (0, 1) (None: no intervals).

    Formulas: NIST SP1065 (eqs. 7-32) as cited in docs/statistics.md; intervals are chi-square
    with Greenhall-Riley edf (SP1065 sec. 5.3). AllanTools equivalent: allanlot.<stat>(...), or
    allantools.<stat>(...) with its errs = dev/sqrt(n) in place of dev_lo/dev_hi.
    """
    data = _checks.samples(data)
    rate = _checks.real(rate, "rate", positive=True)
    conf = _checks.confidence(confidence)
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
                            _threads(threads), False)
    return Deviation(d, units)


def fit(result, units=None, tau0=None, n_samples=None, lowpass="auto"):
    """The eq. (3) fit (R, K, B, N, Q) of an overlapping Allan deviation curve.

    result: a Deviation of stat "oadev" (with its edf: confidence not None), or a dict with
    arrays m, tau, dev, n, edf and the keys tau0 and n_samples (also accepted as arguments).
    units: the channel's units ("deg/s", "m/s^2", ...; default the Deviation's), which give the
    datasheet units of the terms and read-outs.
    lowpass: the sensor's filter, as analyze --lowpass: "auto" (named from the curve, the taus
    it biases left out), "none" (every tau), "cutoff_hz=X" or "taps=X" (docs/fit-and-psd.md
    "The sensor's filter").

    Returns the fit/ group of a results file as a dict: status ("ok", "poor fit", ...),
    status_text, chi2_dof, rank, terms (columns term, value, sigma, upper, detected, unit,
    value_datasheet, ...), readouts (N at 1 s, bias instability, K at 3 s), tau and adev_model.
    Method: docs/fit-and-psd.md (weighted NNLS on the squared coefficients, uncertainties from the
    covariance of the OAVAR estimates). AllanTools has no equivalent.
    """
    if not isinstance(result, (Deviation, dict)):
        raise TypeError("result must be a Deviation (stat 'oadev') or a dict of arrays m, tau, "
                        "dev, n, edf, got %s" % type(result).__name__)
    if isinstance(result, Deviation):
        if result.stat != "oadev":
            raise ValueError("fit needs the oadev curve, got %s" % result.stat)
        arrays = result.as_dict()
        tau0 = result.tau0 if tau0 is None else tau0
        n_samples = result.n_points - 1 if n_samples is None else n_samples
        units = result.units if units is None else units
    else:
        arrays = result
        tau0 = arrays.get("tau0") if tau0 is None else tau0
        n_samples = arrays.get("n_samples") if n_samples is None else n_samples
    if tau0 is None or n_samples is None:
        raise ValueError("fit needs tau0 and n_samples with plain arrays")
    edf = np.asarray(arrays["edf"], dtype=float)
    if np.any(~np.isfinite(edf)):
        raise ValueError("fit needs the edf of every tau: compute the deviation with a confidence")
    return _allanlot.fit(np.asarray(arrays["m"], np.int64).tolist(),
                         np.asarray(arrays["tau"], float).tolist(),
                         np.asarray(arrays["dev"], float).tolist(),
                         np.asarray(arrays["n"], np.int64).tolist(), edf.tolist(),
                         float(tau0), int(n_samples), units or "", str(lowpass))


def psd(data, rate=1.0, segments=16, bins_per_decade=10, threads=None):
    """Welch PSD (Hann window, 50 % overlap, segment means removed), one-sided, u^2/Hz.

    data: rate samples (NaN: a segment touching it is skipped). segments: at least this many
    segments (the segment length is the largest power of two that allows it). bins_per_decade:
    average into log-spaced bins as the results file's psd/ group (0: every Welch bin).
    Returns a dict: f (Hz), psd, edf (chi-square degrees of freedom of each value), n_avg (Welch
    bins per value, binned only), df, segment_length, n_segments, n_skipped.
    AllanTools/scipy equivalent: scipy.signal.welch(data, fs=rate, window="hann").
    """
    return _allanlot.psd(_checks.samples(data), _checks.real(rate, "rate", positive=True),
                         _checks.whole(segments, "segments", 1),
                         _checks.whole(bins_per_decade, "bins_per_decade", 0), _threads(threads))


def _model_text(model):
    """(JSON text, name for messages) of a model: None, a dict, JSON text or a file path."""
    if model is None:
        return "", "the default model"
    if isinstance(model, dict):
        return json.dumps(model), "model"
    text = str(model)
    if text.lstrip().startswith("{"):
        return text, "model"
    try:
        with open(text, encoding="utf-8") as f:
            return f.read(), text
    except OSError as e:
        raise OSError("%s: cannot read the model file: %s" % (text, e.strerror)) from e


class Simulation:
    """A simulated unit: rate (samples per second), channels {name: samples}, units {name: units}."""

    def __init__(self, rate, channels):
        self.rate = rate
        self.channels = {name: a for name, _, a in channels}
        self.units = {name: u for name, u, _ in channels}

    def __getitem__(self, name):
        return self.channels[name]

    def __repr__(self):
        return "<allanlot.Simulation %d channel(s) at %g Hz>" % (len(self.channels), self.rate)


def simulate(model=None, duration=60.0, seed=1, threads=None):
    """Simulated recordings of one unit, bit for bit those of ``allanlot simulate -o FILE``.

    model: a model file's path, its JSON text or a dict (docs/formats.md "Model files"); None:
    the paper's six-channel unit. duration: seconds. seed: the random seed.
    Noise generation: white terms from Philox streams, flicker by Kasdin's filter (Proc. IEEE
    83(5), 1995). AllanTools equivalent: allantools.noise.* one process at a time.
    """
    text, source = _model_text(model)
    rate, channels = _allanlot.simulate(text, source,
                                        _checks.real(duration, "duration", positive=True),
                                        _checks.whole(seed, "seed", 0, 2**64 - 1),
                                        _threads(threads))
    return Simulation(rate, channels)


def diagnose(data, rate, model, channel=None, data_type="freq", replicas=30, seed=7,
             threads=None, max_effects=8):
    """What the noise model misses: the dict ``allanlot diagnose --json`` prints.

    data: the channel's samples (rate, or phase with data_type="phase"). model: as for
    simulate(); channel: the model's channel when it has several. replicas and seed: the Monte
    Carlo band of docs/diagnose.md; max_effects: at most this many effects are named (as
    --max-effects). AllanTools has no equivalent.
    """
    text, source = _model_text(model)
    if not text:
        raise ValueError("diagnose needs a model (a file, JSON text or a dict)")
    out = _allanlot.diagnose(_checks.samples(data), _checks.real(rate, "rate", positive=True),
                             data_type, text, source, channel or "",
                             _checks.whole(replicas, "replicas", 0),
                             _checks.whole(seed, "seed", 0, 2**64 - 1), _threads(threads),
                             _checks.whole(max_effects, "max_effects", 1))
    return json.loads(out)


def read_results(path):
    """A results file (<device_id>.allan.h5) as nested dicts: the root attributes, "attributes"
    (analysis options), and "channels" {path: {attributes, "allan": {stat: arrays}, "fit",
    "psd_fit", "psd", "crosscheck", "quality", "diagnosis"}}, with the names of docs/formats.md;
    numbers as numpy arrays, strings as str. The file's seal is checked first (OSError when
    damaged)."""
    return _allanlot.read_results(os.fspath(path))


def read_lot_summary(outdir):
    """The lot summary (OUTDIR or its lot_summary.h5) as {column: array}; the columns of
    lot_summary.csv, numbers as float arrays (NaN where the CSV is empty), text as lists."""
    return _allanlot.read_lot_summary(os.fspath(outdir))


def read_lot_statistics(outdir):
    """The lot statistics (lot_statistics.csv's columns) as {column: array}."""
    return _allanlot.read_lot_statistics(os.fspath(outdir))
