# SPDX-License-Identifier: MIT
"""The machine, the build and the code a report measured, and how busy the machine is."""

import hashlib
import os
import platform
import subprocess
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), *[os.pardir] * 4))  # support/tools/python/<pkg>
LSCPU_KEYS = ("Thread(s) per core", "Core(s) per socket", "Socket(s)", "L2 cache", "L3 cache", "Hypervisor vendor")
CACHE_KEYS = ("CMAKE_CXX_COMPILER", "CMAKE_BUILD_TYPE", "CMAKE_CXX_FLAGS_RELEASE", "QUADPHASE_BOX2D_TARBALL",
              "QUADPHASE_BOX2D_SOURCE_DIR")


def _out(cmd):
    try:
        return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout.strip()
    except OSError:
        return ""


def cmake_cache(build_dir):
    cache = {}
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
            for line in f:
                k, _, v = line.strip().partition("=")
                if k.split(":")[0] in CACHE_KEYS:
                    cache[k.split(":")[0]] = v
    except OSError:
        pass
    return cache


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def box2d_checksum(build_dir, cache):
    """sha256 of Box2D's orig tarball when the build tree has one (or was configured with one), else a sha256 over
    the sorted (relative path, sha256 of the contents) of every file of the source directory."""
    in_tree = next((os.path.join(root, name) for root, _, files in os.walk(build_dir) for name in files
                    if name.startswith("box2d_") and name.endswith(".orig.tar.gz")), None)
    configured = cache.get("QUADPHASE_BOX2D_TARBALL")
    for path, where in ((in_tree, "in the build tree"), (configured, "the build was configured with")):
        if path:
            return {"kind": f"sha256 of the orig tarball {where}", "path": path, "sha256": sha256_file(path)}
    src = cache.get("QUADPHASE_BOX2D_SOURCE_DIR", "")
    if not src or not os.path.isdir(src):
        return {"kind": "unknown (no tarball, no source directory found)", "path": "", "sha256": ""}
    h, count = hashlib.sha256(), 0
    for root, dirs, files in os.walk(src):
        dirs.sort()
        for name in sorted(files):
            path = os.path.join(root, name)
            h.update(os.path.relpath(path, src).encode() + b"\0" + sha256_file(path).encode() + b"\n")
            count += 1
    return {"kind": f"sha256 over the sorted (path, sha256 of contents) of the {count} files of the source "
                    "directory (no tarball in the build tree)", "path": src, "sha256": h.hexdigest()}


def describe(build_dir=None):
    """CPU, cores, cache sizes, kernel, load, OpenMP environment, git commit, compiler and (with a build
    directory) its build type, flags and Box2D source checksum."""
    info = {"cpu": platform.processor() or "unknown", "cores": os.cpu_count()}
    try:
        with open("/proc/cpuinfo") as f:
            info["cpu"] = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    for line in _out(["lscpu"]).splitlines():  # "" when lscpu is missing
        k, _, v = line.partition(":")
        if k.strip() in LSCPU_KEYS:
            info[k.strip()] = v.strip()
    head = _out(["git", "-C", REPO, "log", "-1", "--format=%h %s"])
    dirty = _out(["git", "-C", REPO, "status", "--porcelain", "--", "plugin"])
    info["git"] = (head or "unknown") + (" (plus uncommitted changes in plugin/)" if dirty else "")
    info["commit"] = info["git"].split(" ", 1)[0]
    info["compiler"] = (_out(["c++", "--version"]).splitlines() or ["unknown"])[0]
    info["kernel"] = platform.release()
    info["loadavg_start"] = open("/proc/loadavg").read().split()[:3]
    info["omp_env"] = {k: v for k, v in os.environ.items() if k.startswith(("OMP_", "GOMP_"))}
    if build_dir:
        cache = cmake_cache(build_dir)
        info.update({k: v for k, v in cache.items() if k.startswith("CMAKE_")})
        info["box2d"] = box2d_checksum(build_dir, cache)
    return info


def cpus_busy(seconds=0.5):
    """CPUs in use (by anything) over `seconds`, from /proc/stat."""
    def sample():
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        return v[3] + (v[4] if len(v) > 4 else 0), sum(v)
    i0, t0 = sample()
    time.sleep(seconds)
    i1, t1 = sample()
    return (os.cpu_count() or 1) * (1.0 - (i1 - i0) / max(1, t1 - t0))
