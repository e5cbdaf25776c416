"""Production time: how long to record a unit (``allanlot plan``) and deciding a unit while it
records (``allanlot watch``), as the command line runs them (docs/production.md)."""

import os

from . import _allanlot
from . import _checks


def _path(value, name):
    """A file's path as str; None as the empty string (the command's 'not given')."""
    if value is None:
        return ""
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError("%s must be a path, got %r" % (name, value))
    return os.fspath(value)


def _targets(value):
    """{"B": 0.1, ...}: relative precisions in (0, 1) keyed by the eq. (3) term."""
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise TypeError("targets must be a dict such as {'B': 0.1}, got %r" % (value,))
    out = {}
    for term, precision in value.items():
        if not isinstance(term, str):
            raise TypeError("targets' keys must be term names such as 'B', got %r" % (term,))
        p = _checks.real(precision, "targets[%r]" % term, positive=True)
        if p >= 1.0:
            raise ValueError("targets[%r] must be a relative precision below 1 (0.1 is 10 %%), "
                             "got %r" % (term, precision))
        out[term] = p
    return out


def plan(model=None, targets=None, spec=None, margin=0.2, confidence=0.95, verify=0, seed=1,
         max_duration=30 * 86400.0, threads=None):
    """The recording length at which each target is met: ``allanlot plan --json`` as a dict.

    Parameters
    ----------
    model : str or os.PathLike, optional
        A model file (docs/formats.md "Model files"); None: the paper's six-channel unit.
    targets : dict, optional
        Relative precision per eq. (3) term at `confidence`, e.g. ``{"B": 0.1, "N": 0.02}``.
        Give either targets or spec.
    spec : str or os.PathLike, optional
        A spec file: the length at which a unit `margin` inside each limit is decided.
    margin : float
        With spec: the unit's relative distance inside each limit.
    confidence : float
        Of the targets' intervals, in (0, 1); with spec, the spec's own is used.
    verify : int
        Simulated recordings of the planned length fitted to check it (0: none).
    seed : int
        Random seed of the verification.
    max_duration : float
        The longest record searched, s.
    threads : int, optional
        OpenMP threads (None: every core); the answer does not depend on it.

    Returns
    -------
    dict
        ``duration_s`` (the binding length), ``binding`` (channel:target), ``per_target``
        (length, deciding taus and, with verify, the share of simulations within target).

    References
    ----------
    The length comes from the eq. (3) fit's covariance on the expected Allan variance of a
    record of each length, with the edf of each tau (NIST SP1065 sec. 5.3, pp. 38-41).
    """
    t = _targets(targets)
    s = _path(spec, "spec")
    if bool(t) == bool(s):
        raise ValueError("give either targets or spec")
    c = 0.0 if s else _checks.confidence(confidence)
    return _allanlot.plan(_path(model, "model"), t, s, _checks.real(margin, "margin", positive=True),
                          c, _checks.whole(verify, "verify", 0), _checks.whole(seed, "seed", 0),
                          _checks.real(max_duration, "max_duration", positive=True),
                          _checks.threads(threads))


def watch(recording, spec, interval=600.0, max_duration=0.0, replay=False, poll=5.0,
          idle_timeout=3600.0, sample_rate=0.0, units=None, threads=None):
    """Follow a growing recording and decide its verdicts as they firm up (``allanlot watch``).

    Parameters
    ----------
    recording : str or os.PathLike
        A CSV being appended or an HDF5 file extended by a SWMR writer.
    spec : str or os.PathLike
        The spec whose limits are decided.
    interval : float
        Seconds of recording between looks.
    max_duration : float
        The last look, s of recording (0: the spec's planned length).
    replay : bool
        The recording is complete: look at it as it grew, faster than real time.
    poll : float
        Wall seconds between checks for new data.
    idle_timeout : float
        Wall seconds without new data before giving up.
    sample_rate : float
        Hz, for a text recording without a time column (0: from the file).
    units : str, optional
        As ``--units`` (``[GLOB=]UNIT``).
    threads : int, optional
        OpenMP threads (None: every core).

    Returns
    -------
    tuple of (int, str)
        The exit status (0 every limit decided pass, 1 one decided fail, 3 undecided at
        max_duration) and the text the command prints.

    References
    ----------
    Linear alpha spending over the planned looks (Lan & DeMets, Biometrika 70(3), 1983), each
    look a one-sided interval of the eq. (3) fit (docs/production.md).
    """
    return _allanlot.watch(_path(recording, "recording"), _path(spec, "spec"),
                           _checks.real(interval, "interval", positive=True),
                           _checks.real(max_duration, "max_duration", minimum=0.0), bool(replay),
                           _checks.real(poll, "poll", positive=True),
                           _checks.real(idle_timeout, "idle_timeout", positive=True),
                           _checks.real(sample_rate, "sample_rate", minimum=0.0), units or "",
                           _checks.threads(threads))
