"""The compiled evaluation of the ground-motion tables (:func:`colonna.core.ground.kernel_tables`),
one for every solver that reads a record or a vertical motion from them."""

from __future__ import annotations

import numpy as np
from numba import njit

from .jit_cache import ensure_fresh

ensure_fresh()  # cached kernels compiled from other sources are dropped (jit_cache)


@njit(cache=True)
def table_value(t, times, values):
    """Piecewise-linear value of a table (times strictly increasing) at t, zero outside it.

    >>> import numpy as np
    >>> float(table_value(0.25, np.array([0.0, 1.0]), np.array([2.0, 4.0])))
    2.5
    """
    n = times.size
    if n == 0 or t < times[0] or t > times[n - 1]:
        return 0.0
    i = np.searchsorted(times, t)
    if i == 0:
        return values[0]
    w = (t - times[i - 1]) / (times[i] - times[i - 1])
    return values[i - 1] + w * (values[i] - values[i - 1])
