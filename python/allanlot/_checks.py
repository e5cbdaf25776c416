"""The checks of the module's arguments, in one place: each bad argument is a TypeError (wrong
kind: complex data, a fractional seed, a tuple where a Deviation is expected) or a ValueError
(right kind, bad value: a rate <= 0, a confidence outside (0, 1), too many threads), and the
message names the argument, as the command line names its option."""

import math
import numbers

import numpy as np

from . import _allanlot


def samples(data, name="data"):
    """`data` as a 1-D float64 array (converted once): a column (n, 1) or a row (1, n) is
    flattened as AllanTools does; complex, non-numeric and empty data are refused."""
    a = np.asarray(data)
    if np.iscomplexobj(a):
        raise TypeError("%s must be real numbers, got complex values" % name)
    if a.dtype.kind not in "biuf":
        raise TypeError("%s must be numbers, got an array of %s" % (name, a.dtype))
    if a.ndim == 2 and 1 in a.shape:
        a = a.reshape(-1)
    if a.ndim != 1:
        raise ValueError("%s must be one-dimensional (or one column), got shape %s"
                         % (name, a.shape))
    if a.size == 0:
        raise ValueError("%s is empty" % name)
    return np.ascontiguousarray(a, dtype=np.float64)


def whole(value, name, minimum=None, maximum=None):
    """`value` as an int: a whole number (bool and 1.5 refused) within [minimum, maximum]."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError("%s must be a whole number, got %r" % (name, value))
    v = int(value)
    if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
        low = "" if minimum is None else "from %d " % minimum
        high = "" if maximum is None else "to %d" % maximum
        raise ValueError("%s must be a whole number %s%s, got %d" % (name, low, high, v))
    return v


def real(value, name, positive=False, minimum=None):
    """`value` as a finite float (> 0 when `positive`, >= minimum when given)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError("%s must be a real number, got %r" % (name, value))
    v = float(value)
    if not math.isfinite(v) or (positive and v <= 0) or (minimum is not None and v < minimum):
        need = "> 0" if positive else ">= %g" % minimum if minimum is not None else "finite"
        raise ValueError("%s must be a finite number %s, got %r" % (name, need, value))
    return v


def threads(value):
    """The kernels' thread count: None (0 to the kernels: OMP_NUM_THREADS or every core, capped
    as on the command line) or 1 .. max_threads."""
    if value is None:
        return 0
    return whole(value, "threads", 1, _allanlot.max_threads)


def confidence(value):
    """A confidence level in (0, 1), or None (no intervals)."""
    if value is None:
        return 0.0
    v = real(value, "confidence")
    if not 0.0 < v < 1.0:
        raise ValueError("confidence must be in (0, 1) (None: no intervals), got %r" % (value,))
    return v


def count(value, name, minimum=None):
    """`value` as an int where AllanTools passes counts as floats (m = tau * rate, 4.0): a whole
    number or an integral float; 1.5, bool and NaN refused."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError("%s must be a whole number, got %r" % (name, value))
    if not isinstance(value, numbers.Integral):
        if not math.isfinite(float(value)) or float(value) != math.floor(float(value)):
            raise TypeError("%s must be a whole number, got %r" % (name, value))
    return whole(int(value), name, minimum)


#: Below this many samples `threads=None` runs on one thread: starting and joining an OpenMP
#: team costs tens of microseconds (milliseconds on a loaded machine), more than the kernels
#: take on such a record. Results are the same bits for any thread count.
SMALL_RECORD = 1 << 16


def threads_for(value, n_samples):
    """threads(value), with None meaning one thread for records below SMALL_RECORD samples."""
    if value is None and n_samples < SMALL_RECORD:
        return 1
    return threads(value)
