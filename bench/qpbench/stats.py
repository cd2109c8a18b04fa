"""Per-round ratios and the two laws of parallel speed-up the reports use (medians and ratios: quadphase_tools.stats)."""

import math


def round_ratios(num, den, field):
    """Per-round ratios num/den of two lists of runs (dicts with "rep_round"): rounds pair up because every
    round ran both."""
    a, b = ({(r["rep_round"], r.get("rep", 0)): r[field] for r in runs if "rep_round" in r} for runs in (num, den))
    return [a[k] / b[k] for k in sorted(a) if k in b and b[k] > 0]


def karp_flatt(speedup, p=2):
    """Experimentally determined serial fraction: e = (1/S - 1/p) / (1 - 1/p)."""
    if not speedup or speedup <= 0 or math.isnan(speedup):
        return float("nan")
    return (1.0 / speedup - 1.0 / p) / (1.0 - 1.0 / p)


def amdahl(s, p):
    s = min(max(s, 0.0), 1.0)
    return 1.0 / (s + (1.0 - s) / p)
