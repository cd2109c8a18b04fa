# SPDX-License-Identifier: MIT
"""bench.py's outputs from its raw results (the tools' JSON lines of every level): each level's rows sorted out by
section, then results/*.csv, bench.json, the PNG plots and RESULTS.md (summary.py)."""

import os

from . import paper, plot, report
from .bench_common import engine_name
from .circles import circles_figure, circles_rows
from .phases import FAIR_FIELDS, PHASE_FIELDS, phase_rows
from .queries import query_rows
from .replay import REPLAY_CSV, peers_floors, replay_figure, replay_phase_rows, replay_table
from .step import STEP_CSV, STEP_FIELDS, step_figure, step_rows
from .summary import REFERENCE, markdown

# The CSVs of every level (with an "opt" column) and their columns (None: every field, in the order first seen);
# queries.csv and circles.csv are the first level's.
LEVEL_CSVS = {
    "step": ["opt", "scene", "size", "engine", "rounds", "bodies", "proxies", "continuous"] + STEP_CSV,
    "phases": ["opt", "scene", "size", "steps", "engine", "rounds", "continuous"] + PHASE_FIELDS + FAIR_FIELDS,
    "replay_phases": None, "peers": None,
    "replay": REPLAY_CSV,
}


def aggregate(rows):
    """A level's raw rows by what they measured: qp-step runs by (part, scene, size, steps, engine), replay runs and
    checks by (trace, engine), the paper's checks by trace, circles searches by (engine, threads, depth), query runs
    by engine, and the triads' bandwidths."""
    groups, replay, checks, paper_checks, circles, queries, triads = {}, {}, {}, {}, {}, {}, []
    for r in rows:
        tool, kind = r.get("tool"), r.get("kind")
        if tool == "qp-step":
            part = r["label"].split()[0] if r.get("label", "").startswith("phases") else "step"
            groups.setdefault((part, r["scene"], r["size"], r["steps"], engine_name(r)), []).append(r)
        elif tool == "qp-query":
            queries.setdefault(engine_name(r), []).append(r)
        elif tool == "qp-replay" and kind == "triad":
            triads.append(r["bytes_per_s"])
        elif tool == "qp-replay" and kind in ("run", "check", "paper_check"):
            e = r.get("engine", "quadtree")
            key = (r["trace"], f"quadtree-{r.get('threads')}t" if e == "quadtree" else e)
            if kind == "run":
                replay.setdefault(key, []).append(r)
            elif kind == "check":
                checks[key] = r
            else:
                paper_checks[r["trace"]] = r
        elif tool == "qp-circles" and kind == "result":
            circles[(r["engine"], r["threads"], r["depth"])] = r
    return groups, replay, checks, paper_checks, circles, queries, triads


def level_data(rows, traces):
    """One level's raw rows as the rows of its CSVs."""
    groups, replay, checks, paper_checks, circles, queries, triads = aggregate(rows)
    replay_rows = replay_table(replay, checks, paper_checks, traces)
    return dict(step=step_rows(groups, "step", STEP_FIELDS), phases=phase_rows(groups),
                replay=replay_rows, replay_phases=replay_phase_rows(replay, traces),
                peers=peers_floors(replay_rows, checks, triads, traces), queries=query_rows(queries),
                circles=circles_rows(circles))


def write_outputs(args, info, rows_by_level, frame_goals=()):
    res, levels = args.results, [lv for lv, _ in info["levels"]]
    data = {lv: level_data(rows_by_level[lv], info.get("traces", [])) for lv in levels}
    for name, fields in LEVEL_CSVS.items():
        report.write_csv(os.path.join(res, name + ".csv"), [dict(r, opt=lv) for lv in levels for r in data[lv][name]],
                         fields)
    for name in ("queries", "circles"):
        report.write_csv(os.path.join(res, name + ".csv"), data[levels[0]][name])
    report.write_json(os.path.join(res, "bench.json"), {
        "machine": info, "levels": data, "paper_published": paper.TABLES, "reference_this_machine": REFERENCE})
    report.write_lines(args.summary, markdown(info, data, levels, figures(res, data[levels[0]]), frame_goals))


def figures(res, d):
    """The first level's plots (step ratios, replay scaling, the paper's table): {section: path} of those drawn."""
    plt = plot.pyplot("bench.py")
    plots = {}
    if plt is not None:
        for figure in (step_figure, replay_figure, circles_figure):
            figure(plt, res, d, plots)
    return plots
