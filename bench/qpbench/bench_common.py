# SPDX-License-Identifier: MIT
"""What bench.py's section modules share: the report's prose, sizes under --scale, the headline engines and how a
row names them, rows keyed by case and engine, ratios over stock, and a section's head."""

import os

from quadphase_tools.stats import ratio

from . import report

TEXT = report.prose(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "prose", "bench.md"))
PARTS = ("step", "phases", "replay", "queries", "circles")  # bench.py --parts: the sections a run may choose
HEADLINE_ENGINES = ["stock", "quadtree-1t", "quadtree-2t"]  # what further optimisation levels replay
QUADTREES = HEADLINE_ENGINES[1:]  # quadphase at 1 and 2 threads
LABELS = {"stock": "Box2D b2DynamicTree (stock)", "quadtree-1t": "quadphase, 1 thread",
          "quadtree-2t": "quadphase, 2 threads"}  # the replay's ENGINE_LABEL adds the other engines


def scaled(size, args, lo=1):
    return max(lo, int(round(size * args.scale)))


def engine_name(r):
    """stock, or quadtree-Nt with N = OMP_NUM_THREADS of the run (the tools print it)."""
    return "stock" if r["variant"] == "stock" else f"quadtree-{r.get('omp_num_threads') or r.get('threads')}t"


def threads(engine):
    return engine.replace("quadtree-", "")


def keyed(rows, fields=("scene", "size", "engine")):
    return {tuple(r[f] for f in fields): r for r in rows}


def x_stock(by, case, engine, field):
    """Stock's `field` ÷ the engine's on a case (a key of `by` without its engine): > 1 when the engine is faster."""
    return ratio((by.get(case + ("stock",)) or {}).get(field), (by.get(case + (engine,)) or {}).get(field))


def section(title, intro, plots=(), key=None, alt=None):
    """A section's title, its plot (when drawn) and its introduction."""
    return [title, ""] + ([f"![{alt}]({plots[key]})", ""] if key in plots else []) + [intro, ""]
