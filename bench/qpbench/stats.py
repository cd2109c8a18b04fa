# SPDX-License-Identifier: MIT
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


def serial_fractions(r):
    """(s as measured, s if the outside work were parallel) of a trace's replay, from r["share"] (m: the work
    outside FindPairs over the whole, at 1 thread) and r["ef"] (e_F: FindPairs' Karp-Flatt fraction):
    s = m + e_F (1 - m)."""
    m = min(max(r["share"], 0.0), 1.0)
    ef = min(max(r["ef"], 0.0), 1.0) if not math.isnan(r["ef"]) else 0.0
    return m + ef * (1.0 - m), ef * (1.0 - m)


def amdahl(s, p):
    s = min(max(s, 0.0), 1.0)
    return 1.0 / (s + (1.0 - s) / p)
