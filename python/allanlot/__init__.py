"""allanlot for Python: the Allan-variance family, the eq. (3) noise fit, the Welch PSD, the
simulator and diagnose, on the command line's kernels, with numpy arrays in and out.

Two faces (docs/python.md):

- AllanTools' API, so that ``import allanlot as allantools`` runs a notebook written for
  AllanTools unchanged: the statistics ``oadev(data, rate=1.0, data_type="phase", taus=None)
  -> (taus, devs, errs, ns)`` and adev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev,
  htotdev, theo1, mtie, tierms, pdev, gcodev, three_cornered_hat_phase (and theoh); ``noise``
  and ``Noise`` (Kasdin); ``Dataset`` and ``Plot``; the conversions, ``tau_generator``,
  ``gradev``, ``psd2allan``; the edf and confidence-interval functions (``ci``);
- the richer API of the command line: ``deviation`` (confidence intervals, noise
  identification, Stable32's tau grids), ``fit``, ``psd``, ``plot``, ``simulate``,
  ``diagnose``, ``plan``, ``watch``, ``read_recording``, ``read_results``, ``read_lot_summary``,
  ``read_lot_statistics``.

Errors are ValueError or TypeError naming the bad argument (the command line's exit status 2)
and OSError (files that cannot be read or are damaged; exit status 1). The kernels run without
the GIL on ``threads`` OpenMP threads (None: all) and give the same bits for any thread count.
"""

from . import _allanlot
from . import ci
from . import noise
from . import realtime
from ._allantools import FUNCTIONS as _FUNCTIONS
from ._allantools import tau_m
from ._analysis import Simulation, diagnose, fit, psd, simulate
from ._conversions import (frequency2fractional, frequency2phase, gradev, phase2frequency,
                           phase2radians, psd2allan, tau_generator, tau_reduction, trim_data)
from ._dataset import Dataset, Plot
from ._deviation import DEFAULT_CONFIDENCE, Deviation, deviation
from ._kasdin import Noise
from ._piecewise import adev2psd_piecewise_approx, psd_piecewise_to_adev
from ._plot import plot
from ._production import plan, watch
from ._readers import (read_lot_statistics, read_lot_summary, read_recording, read_results,
                       stats)
from .ci import (autocorr_noise_id, confidence_interval, confidence_interval_noiseID,
                 edf_greenhall, edf_mtotdev, edf_simple, edf_totdev)

#: The project's version (CMakeLists.txt), as ``allanlot --version`` prints it.
__version__ = _allanlot.version

# adev, oadev, ... as module functions.
globals().update(_FUNCTIONS)

__all__ = [
    "Deviation", "Simulation", "deviation", "fit", "psd", "plot", "simulate", "diagnose",
    "read_recording", "read_results", "read_lot_summary", "read_lot_statistics", "stats",
    "tau_m", "plan", "watch",
    "DEFAULT_CONFIDENCE", "noise", "ci", "Noise", "Dataset", "Plot", "frequency2phase",
    "phase2frequency", "phase2radians", "frequency2fractional", "trim_data", "tau_generator",
    "tau_reduction", "gradev", "psd2allan", "edf_simple", "edf_greenhall", "edf_totdev",
    "edf_mtotdev", "confidence_interval", "confidence_interval_noiseID", "autocorr_noise_id",
    "realtime", "adev2psd_piecewise_approx", "psd_piecewise_to_adev",
] + list(_FUNCTIONS)
