# SPDX-License-Identifier: MIT
"""bench.py's queries section (RESULTS.md 3): qp-query-stock and qp-query-quadtree run QueryAABB, short and long
rays, a mass SetTransform then queries, through b2World; hits checked equal, floors (the output alone) beside."""

from quadphase_tools.stats import med, ratio

from .bench_common import QUADTREES, TEXT, keyed, scaled, section
from .report import num as fmt, table

# The query workload (qp-query-*): 50,000 bodies over a 1 km square, its queries; workloads in report order.
QUERY_ARGS = {"bodies": 50000, "world": 1000, "queries": 2000, "short-rays": 2000, "long-rays": 200,
              "teleport": 37500, "teleport-queries": 2000}
QUERY_WORKLOADS = [("aabb_small", "small QueryAABB (2 m squares)"), ("ray_short_all", "short rays (10 m), all hits"),
                   ("ray_short_closest", "short rays (10 m), closest hit"),
                   ("ray_axis_all", "long rays, axis-aligned, all hits"),
                   ("ray_axis_closest", "long rays, axis-aligned, closest hit"),
                   ("ray_diag_all", "long rays, corner to corner, all hits"),
                   ("ray_diag_closest", "long rays, corner to corner, closest hit"),
                   ("teleport", "SetTransform of {teleported:,} bodies, then {queries:,} small QueryAABBs, together"),
                   ("teleport_step", "the b2World::Step after the teleport")]
QUERY_GOALS = {"ray_diag_all": 2.0, "ray_diag_closest": 2.0, "teleport": 2.0}  # 2x stock; every other workload: >= 1
# Workloads with a floor (qp-query's <workload>_floor: b2World's and the callback's work on the recorded candidates).
QUERY_FLOORS = ("aabb_small", "ray_short_all", "ray_axis_all", "ray_diag_all")


def query_argv(args, runner, label):
    q = dict({k: scaled(v, args) for k, v in QUERY_ARGS.items()}, world=QUERY_ARGS["world"])  # the world unscaled
    return [x for k, v in q.items() for x in (f"--{k}", v)] + ["--seed", args.seed, "--repeats", 5, "--threads",
                                                              "default", "--json", runner.jsonl, "--label", label]


def run_queries(runner, args, u, rnd):
    """One unit = one qp-query run per round: (build, OMP_NUM_THREADS), as the step section's engines."""
    build, omp = u
    runner.run(f"qp-query-{build}", *query_argv(args, runner, f"queries|round={rnd}"),
               env={"OMP_NUM_THREADS": str(omp)})


def query_rows(queries):
    """queries.csv's rows: medians over rounds per (workload, engine), hits compared with stock's."""
    out = []
    names = [w for w, _ in QUERY_WORKLOADS] + [w + "_floor" for w in QUERY_FLOORS]
    ref = {w: queries.get("stock", [{}])[0].get(w + "_hash") for w in names}
    for name, runs in sorted(queries.items()):
        for w in (w for w in names if any(w + "_ns" in r for r in runs)):  # runs before floors existed: none
            hashes = {r.get(w + "_hash") for r in runs}
            out.append({"workload": w, "engine": name, "rounds": len(runs),
                        "ms": med([r[w + "_ns"] * 1e-6 for r in runs if w + "_ns" in r]),
                        "queries": runs[0].get(w + "_queries"), "hits": runs[0].get(w + "_hits"),
                        "hash": ",".join(sorted(h for h in hashes if h)), "same_hits_as_stock": hashes == {ref[w]},
                        "bodies": runs[0]["bodies"], "teleported": runs[0]["teleported"]})
    return out


def floor_ms(q, w):
    """A workload's floor: the lower of the builds' <workload>_floor medians (the same code in both; each build
    records its own candidates), or None."""
    return min([r["ms"] for e in ["stock"] + QUADTREES for r in [q.get((w + "_floor", e))] if r and r["ms"]] or [None])


def query_section(d):
    if not d["queries"]:
        return []
    q = keyed(d["queries"], ("workload", "engine"))
    floors = any(floor_ms(q, w) for w in QUERY_FLOORS)
    L = section("## 3. Queries through b2World", TEXT["queries"].format(bodies=d["queries"][0]["bodies"])
                + ("\n\n" + TEXT["query_floors"] if floors else ""))
    rows = []
    for w, what in QUERY_WORKLOADS:
        a, qs, f = q.get((w, "stock")), [q.get((w, e)) or {} for e in QUADTREES], floor_ms(q, w)
        if a:
            rows.append([what.format(**a), fmt(a["queries"], 0), fmt(a["hits"], 0), fmt(a["ms"], 3)]
                        + [x for r in qs for x in (fmt(r.get("ms"), 3), fmt(ratio(a["ms"], r.get("ms"))))]
                        + ([fmt(f, 3), fmt(ratio(a["ms"], f))] if floors else [])
                        + ["yes" if all(r.get("same_hits_as_stock") for r in qs) else "**NO**"])
    return L + table(["workload", "queries", "hits", "stock ms", "1t ms", "× stock", "2t ms", "× stock"]
                     + (["floor ms", "stock ÷ floor"] if floors else []) + ["same hits"], rows) + [""]
