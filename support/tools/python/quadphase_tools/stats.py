# SPDX-License-Identifier: MIT
"""Medians and ratios, as the reports and the demo take them."""

import math
import statistics


def med(values, empty=None):
    """Median of the values that are not None (or NaN); `empty` when there are none."""
    v = [x for x in values if x is not None and not (isinstance(x, float) and math.isnan(x))]
    return statistics.median(v) if v else empty


def ratio(a, b):
    """a / b, or None when either is missing or zero."""
    return a / b if a and b else None
