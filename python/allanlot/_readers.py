"""The command line's result files read into numpy: results files, the lot summary and the lot
statistics (regular files only; the checks are in the extension, python/bindings/records.cpp)."""

import os

from . import _allanlot


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
