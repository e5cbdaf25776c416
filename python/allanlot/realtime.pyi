# Type stubs of allanlot.realtime (docstrings in realtime.py).
from typing import Sequence

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]

class dev_realtime:
    afs: npt.NDArray[np.int64]
    dev: Array
    tau0: float
    auto_afs: bool
    def __init__(self, afs: Sequence[int] = ..., tau0: float = ..., auto_afs: bool = ...,
                 pts_per_decade: int = ...) -> None: ...
    @property
    def x(self) -> Array: ...
    def add_phase(self, xnew: float) -> None: ...
    def add_frequency(self, f: float) -> None: ...
    def taus(self) -> Array: ...
    def devs(self) -> Array: ...

class oadev_realtime(dev_realtime):
    S: Array

class ohdev_realtime(dev_realtime):
    S: Array

class tdev_realtime(dev_realtime):
    S: Array
    So: Array
    def mdev(self) -> Array: ...
