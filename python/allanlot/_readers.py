"""The command line's result files read into numpy: results files, the lot summary and the lot
statistics (regular files only; the checks are in the extension, python/bindings/records.cpp)."""

import os

from . import _allanlot
from . import _checks


def stats():
    """The statistics this build computes.

    Returns
    -------
    list of str
        Names as in AllanTools and the results files.
    """
    return list(_allanlot.stats())


def read_results(path):
    """A results file (<device_id>.allan.h5) as nested dicts.

    Parameters
    ----------
    path : str or os.PathLike
        The file; its seal is checked first.

    Returns
    -------
    dict
        The root attributes, "attributes" (analysis options), and "channels" {path:
        {attributes, "allan": {stat: arrays}, "fit", "psd_fit", "psd", "crosscheck",
        "quality", "diagnosis"}}, with the names of docs/formats.md; numbers as numpy arrays,
        strings as str.

    Raises
    ------
    OSError
        No such file, not a regular file (a directory, a FIFO, a device), or damaged.
    """
    return _allanlot.read_results(os.fspath(path))


def read_lot_summary(outdir):
    """The lot summary of an analysed lot.

    Parameters
    ----------
    outdir : str or os.PathLike
        OUTDIR, or its lot_summary.h5.

    Returns
    -------
    dict
        {column: array}: the columns of lot_summary.csv, numbers as float arrays (NaN where
        the CSV is empty), text as lists.
    """
    return _allanlot.read_lot_summary(os.fspath(outdir))


def read_lot_statistics(outdir):
    """The lot statistics of an analysed lot.

    Parameters
    ----------
    outdir : str or os.PathLike
        OUTDIR.

    Returns
    -------
    dict
        {column: array}, the columns of lot_statistics.csv.
    """
    return _allanlot.read_lot_statistics(os.fspath(outdir))


def _globs(value, name):
    """None, one glob or a list of globs, as a list of str."""
    if value is None:
        return []
    if isinstance(value, str):
        return [value]
    if not all(isinstance(v, str) for v in value):
        raise TypeError("%s must be a glob or a list of globs, got %r" % (name, value))
    return list(value)


def read_recording(path, channels=None, topics=None, receive_time=False, sample_rate=None):
    """A recording's channels as the command line reads them, in any of its formats.

    Parameters
    ----------
    path : str or os.PathLike
        An HDF5 recording, a CSV/TSV (plain or gzip), a ROS 1 bag, an MCAP file, or a ROS 2 bag
        (its folder or one .db3) (docs/formats.md "Input recordings", docs/robotics.md).
    channels : str or list of str, optional
        Globs of the channels to read (as ``--channels``; default every channel).
    topics : str or list of str, optional
        Globs of the sensor_msgs/Imu topics of a bag or MCAP file (as ``--topic``; default every
        Imu topic). Each topic gives ``<topic>/gyro_x|y|z`` in rad/s and
        ``<topic>/accel_x|y|z`` in m/s^2.
    receive_time : bool
        Time a bag's messages by when they were recorded, not by their header stamps.
    sample_rate : float, optional
        Hz, for a text recording without a time column (as ``--sample-rate``).

    Returns
    -------
    dict
        ``device_id``, ``channels`` ({path: {"samples": array, "sample_rate_hz", "units",
        "data_type"}}; dropped samples are NaN), ``problems`` ({path: reason} of datasets that
        look like channels but cannot be read) and ``notes``.

    Raises
    ------
    OSError
        No such file, a FIFO or device, or a file that cannot be read (named with the reason).
    """
    p = os.fspath(path)
    if not os.path.exists(p):
        raise OSError("%s: no such file" % p)
    if not (os.path.isfile(p) or os.path.isdir(p)):
        raise OSError("%s: not a regular file or folder" % p)
    rate = 0.0 if sample_rate is None else _checks.real(sample_rate, "sample_rate", positive=True)
    return _allanlot.read_recording(p, _globs(channels, "channels"), _globs(topics, "topics"),
                                    bool(receive_time), rate)
