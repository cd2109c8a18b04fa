# SPDX-License-Identifier: MIT
"""Number formats, markdown tables, CSV and JSON files, and the machine section every report starts with."""

import csv
import json
import math

from quadphase_tools.stats import med

DASH = "–"


def _missing(x):
    return x is None or (isinstance(x, float) and (math.isnan(x) or math.isinf(x)))


def num(x, d=2):
    """RESULTS.md style: thousands grouped from 1000, no decimals from 100, else d decimals."""
    if _missing(x):
        return DASH
    if isinstance(x, str):
        return x
    if abs(x) >= 1000:
        return f"{x:,.0f}"
    if abs(x) >= 100:
        return f"{x:.0f}"
    return f"{x:.{d}f}"


def fixed(x, digits=2):
    """parallel.md style: always `digits` decimals."""
    return DASH if _missing(x) else f"{x:.{digits}f}"


def sig(v, digits=3):
    """accuracy.md style: about `digits` significant digits."""
    if _missing(v):
        return DASH
    if isinstance(v, int):
        return str(v)
    if v == 0:
        return "0"
    a = abs(v)
    if a >= 1000:
        return "%.0f" % v
    if a >= 1:
        return ("%." + str(max(0, digits - 1 - int(math.log10(a)))) + "f") % v
    return "%.*g" % (digits, v)


def times(x, d=2):
    """A ratio as "1.23×", or empty when there is none."""
    return f"{num(x, d)}×" if x else ""


def table(header, rows):
    """Markdown lines of a table: the header cells (a list, or one "a | b | c" string), the separator, one line per
    row of cells."""
    header = header.split(" | ") if isinstance(header, str) else header
    out = ["| " + " | ".join(header) + " |", "|---" * len(header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return out


def write_csv(path, rows, fields=None):
    """One row per dict; `fields` defaults to every key, in the order first seen."""
    if fields is None:
        fields = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def write_json(path, data):
    with open(path, "w") as f:
        json.dump(data, f, indent=1)


def read_json(path):
    with open(path) as f:
        return json.load(f)


def write_lines(path, lines):
    with open(path, "w") as f:
        f.write("\n".join(lines).rstrip() + "\n")


def prose(path):
    """The named texts of a report's prose file (bench/prose): a line '@ name' starts one, its lines are joined
    with spaces, a line starting with '- ' starts a new line of it; what precedes the first text is a comment."""
    texts, text = {}, None
    with open(path) as f:
        for line in f.read().splitlines():
            if line.startswith("@ "):
                text = texts.setdefault(line[2:], [])
            elif text is not None and line:
                if line.startswith("- ") or not text:
                    text.append(line)
                else:
                    text[-1] += " " + line
    return {k: "\n".join(v) for k, v in texts.items()}


def machine_section(info, heading="## Machine"):
    """The machine, build, code and load lines of machine.describe() (plus the runner's quiet samples)."""
    L = [heading, ""]
    hw = ", ".join(f"{k}: {info[k]}" for k in ("Socket(s)", "Core(s) per socket", "Thread(s) per core", "L2 cache",
                                                "L3 cache", "Hypervisor vendor") if k in info)
    L.append(f"- CPU: {info.get('cpu')}, {info.get('cores')} CPUs" + (f" ({hw})" if hw else ""))
    L.append(f"- compiler: {info.get('compiler', '?')}; build type {info.get('CMAKE_BUILD_TYPE', '?')}, flags "
             f"`{info.get('CMAKE_CXX_FLAGS_RELEASE', '?')}`" + (f"; tools: {info['tools']}" if info.get("tools") else ""))
    if info.get("box2d"):
        L.append(f"- Box2D 2.4.1 source: `{info['box2d'].get('sha256', '')}` ({info['box2d'].get('kind', '')})")
    L.append(f"- code measured: git {info.get('git', 'unknown')}"
             + (f"; core defaults: {info['default_config']}" if info.get("default_config") else ""))
    L.append(f"- Linux {info.get('kernel', '?')}; OpenMP environment: "
             + (", ".join(f"{k}={v}" for k, v in info.get("omp_env", {}).items()) or "none set (libgomp defaults)"))
    qs = info.get("quiet_samples") or []
    L.append(f"- load: 1/5/15-min load average {' '.join(info.get('loadavg_start', []))} at the start"
             + (f", {' '.join(info['loadavg_end'])} at the end" if info.get("loadavg_end") else "")
             + (f"; CPUs busy with other processes before the rounds: median {med(qs):.2f}, max {max(qs):.2f}"
                if qs else "") + ". The machine is shared: rerun to compare.")
    if qs and med(qs) > 0.5:
        L.append(f"- **The machine was busy during this run** (median {med(qs):.1f} CPUs used by other processes "
                 "before the rounds). All times are inflated, and the 2-thread figures in particular: an OpenMP "
                 "parallel region waits for its second thread, which the other processes keep off the CPU. Rerun "
                 "on a quiet machine before drawing conclusions from the 2-thread columns.")
    return L + [""]
