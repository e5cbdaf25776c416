"""The command line's analyses beyond the deviations: the eq. (3) noise fit, the Welch PSD, the
simulator and diagnose."""

import json

import numpy as np

from . import _allanlot
from . import _checks
from ._deviation import Deviation


def fit(result, units=None, tau0=None, n_samples=None, lowpass="auto"):
    """The eq. (3) fit (R, K, B, N, Q) of an overlapping Allan deviation curve.

    Parameters
    ----------
    result : Deviation or dict
        A Deviation of stat "oadev" with its edf (confidence not None), or a dict with arrays
        m, tau, dev, n, edf and the keys tau0 and n_samples.
    units : str, optional
        The channel's units ("deg/s", "m/s^2", ...; default the Deviation's): they give the
        datasheet units of the terms and read-outs.
    tau0 : float, optional
        Sample interval, s (default the Deviation's).
    n_samples : int, optional
        Samples in the record (default the Deviation's).
    lowpass : str
        The sensor's filter, as analyze --lowpass: "auto", "none", "cutoff_hz=X" or "taps=X"
        (docs/fit-and-psd.md "The sensor's filter").

    Returns
    -------
    dict
        The fit/ group of a results file: status, status_text, chi2_dof, rank, terms (columns
        term, value, sigma, upper, detected, unit, value_datasheet, ...), readouts (N at 1 s,
        bias instability, K at 3 s), tau and adev_model.

    References
    ----------
    IEEE Std 952-1997 Annex C (the terms of eq. (3)); NIST SP1065 eq. (11) (p. 16) for OAVAR;
    the method: docs/fit-and-psd.md. AllanTools has no equivalent.
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
    missing = [k for k in ("m", "tau", "dev", "n", "edf") if k not in arrays]
    if missing:
        raise ValueError("result lacks the arrays %s" % ", ".join(missing))
    edf = np.asarray(arrays["edf"], dtype=float)
    if np.any(~np.isfinite(edf)):
        raise ValueError("fit needs the edf of every tau: compute the deviation with a confidence")
    if not isinstance(lowpass, str):
        raise TypeError("lowpass must be a string ('auto', 'none', 'cutoff_hz=X', 'taps=X')")
    return _allanlot.fit(np.asarray(arrays["m"], np.int64).tolist(),
                         np.asarray(arrays["tau"], float).tolist(),
                         np.asarray(arrays["dev"], float).tolist(),
                         np.asarray(arrays["n"], np.int64).tolist(), edf.tolist(),
                         _checks.real(tau0, "tau0", positive=True),
                         _checks.count(n_samples, "n_samples", 1), units or "", lowpass)


def psd(data, rate=1.0, segments=16, bins_per_decade=10, threads=None):
    """Welch PSD (Hann window, 50 % overlap, segment means removed), one-sided, u^2/Hz.

    Parameters
    ----------
    data : array_like
        Rate samples, 1-D or (n, 1) (NaN: a segment touching it is skipped).
    rate : float
        Samples per second.
    segments : int
        At least this many segments (the segment length is the largest power of two that
        allows it).
    bins_per_decade : int
        Average into log-spaced bins as the results file's psd/ group (0: every Welch bin).
    threads : int, optional
        OpenMP threads (None: every core).

    Returns
    -------
    dict
        f (Hz), psd, edf (chi-square degrees of freedom of each value), n_avg (Welch bins per
        value, binned only), df, segment_length, n_segments, n_skipped.

    References
    ----------
    P. D. Welch, IEEE Trans. Audio Electroacoust. 15 (1967) 70; NIST SP1065 eqs. (65)-(66)
    (p. 73) relate it to the Allan variance. scipy equivalent: scipy.signal.welch.
    """
    return _allanlot.psd(_checks.samples(data), _checks.real(rate, "rate", positive=True),
                         _checks.whole(segments, "segments", 1),
                         _checks.whole(bins_per_decade, "bins_per_decade", 0),
                         _checks.threads(threads))


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
    """A simulated unit: rate (samples per second), channels {name: samples}, units
    {name: units}; ``sim[name]`` is a channel's samples."""

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

    Parameters
    ----------
    model : None, dict, str or os.PathLike
        A model file's path, its JSON text or a dict (docs/formats.md "Model files"); None:
        the paper's six-channel unit.
    duration : float
        Seconds.
    seed : int
        The random seed, 0 .. 2^64 - 1.
    threads : int, optional
        OpenMP threads (None: every core); the samples do not depend on it.

    Returns
    -------
    Simulation

    References
    ----------
    White terms from Philox streams; flicker by Kasdin's filter (Proc. IEEE 83(5), 1995);
    the terms of eq. (3) as IEEE Std 952-1997 Annex C defines them. AllanTools equivalent:
    allanlot.noise.* and allanlot.Noise, one process at a time.
    """
    text, source = _model_text(model)
    rate, channels = _allanlot.simulate(text, source,
                                        _checks.real(duration, "duration", positive=True),
                                        _checks.whole(seed, "seed", 0, 2**64 - 1),
                                        _checks.threads(threads))
    return Simulation(rate, channels)


def diagnose(data, rate, model, channel=None, data_type="freq", replicas=30, seed=7,
             threads=None, max_effects=8):
    """What the noise model misses: the dict ``allanlot diagnose --json`` prints.

    Parameters
    ----------
    data : array_like
        The channel's samples (rate, or phase with data_type="phase").
    rate : float
        Samples per second.
    model : dict, str or os.PathLike
        As for simulate().
    channel : str, optional
        The model's channel when it has several.
    data_type : {"freq", "phase"}
        What data holds.
    replicas : int
        Monte Carlo replicas of the band (docs/diagnose.md).
    seed : int
        Their random seed.
    threads : int, optional
        OpenMP threads (None: every core).
    max_effects : int
        At most this many effects are named (as --max-effects).

    Returns
    -------
    dict

    References
    ----------
    docs/diagnose.md; NIST SP1065 eq. (11) (p. 16). AllanTools has no equivalent.
    """
    text, source = _model_text(model)
    if not text:
        raise ValueError("diagnose needs a model (a file, JSON text or a dict)")
    out = _allanlot.diagnose(_checks.samples(data), _checks.real(rate, "rate", positive=True),
                             data_type, text, source, channel or "",
                             _checks.whole(replicas, "replicas", 0),
                             _checks.whole(seed, "seed", 0, 2**64 - 1), _checks.threads(threads),
                             _checks.whole(max_effects, "max_effects", 1))
    return json.loads(out)
