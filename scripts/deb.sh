#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Debian packages of quadphase's libbox2d, standing in for Debian's libbox2d2 and libbox2d-dev:
#
#   scripts/deb.sh [OUTDIR]      # default build/deb
#
# writes into OUTDIR (replacing the .deb files there)
#   libbox2d2-quadphase_<version>_<arch>.deb      /usr/lib/<triplet>/libbox2d.so.2.4.1 and libbox2d.so.2,
#                                                 /usr/bin/quadphase-which; Provides, Conflicts, Replaces libbox2d2
#   libbox2d-quadphase-dev_<version>_<arch>.deb   headers, libbox2d.so, libbox2d.a, box2d.pc, box2dConfig.cmake;
#                                                 Provides, Conflicts, Replaces libbox2d-dev
#   lintian.txt                                   lintian's report on both (it fails the script on any error)
# with debhelper (scripts/debian/, docs/packaging.md): dpkg-buildpackage -b in OUTDIR/work, on a copy of
# CMakeLists.txt, cmake/ and plugin/ with scripts/debian/ as its debian/. <version> is
# 2.4.1+quadphase<project version>-<n>, from scripts/debian/changelog, whose upstream part must match
# CMakeLists.txt's project version.
# Environment: QUADPHASE_BOX2D_SOURCE_DIR or QUADPHASE_BOX2D_TARBALL (Box2D 2.4.1's source, else fetched and
# checked by CMake), QUADPHASE_SKIP_DEPS=1 (no scripts/install-deps.sh), JOBS (parallel jobs, default nproc).
# Install: apt install ./OUTDIR/*.deb; back to stock: apt install libbox2d2 (README "Install system-wide").
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"

case "${1:-}" in -h | --help) sed -n '2,/^source /{/^# SPDX-License-Identifier: MIT$/!p}' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;; esac
[[ $# -le 1 ]] || { echo "deb: at most one argument, OUTDIR (see --help)" >&2; exit 2; }
out=${1:-build/deb}

qp_deps scripts/install-deps.sh --for deb

project_version=$(sed -n 's/^ *VERSION \([0-9.]*\)$/\1/p' CMakeLists.txt | head -1)
version=$(dpkg-parsechangelog -l scripts/debian/changelog -S Version)
[[ "$version" == "2.4.1+quadphase${project_version}-"* ]] ||
    { echo "deb: scripts/debian/changelog's version $version is not 2.4.1+quadphase${project_version}-N (CMakeLists.txt)" >&2; exit 1; }

mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$out/work
stage=$work/quadphase-$version
rm -rf "$work" "$out"/*.deb "$out/lintian.txt"
mkdir -p "$stage"
# The source tree the package is built from: what the libraries' build reads (examples, tests, benchmarks off).
cp -r CMakeLists.txt LICENSE cmake plugin "$stage/"
cp -r scripts/debian "$stage/debian"

echo "deb: dpkg-buildpackage -b in $stage (log $work/build.log)"
start=$(date +%s)
(cd "$stage" && DEB_BUILD_OPTIONS="parallel=$QP_JOBS ${DEB_BUILD_OPTIONS:-}" dpkg-buildpackage -b -us -uc) \
    >"$work/build.log" 2>&1 || { tail -n 40 "$work/build.log" >&2; echo "deb: dpkg-buildpackage failed (full log $work/build.log)" >&2; exit 1; }
mv "$work"/*.deb "$out/"
echo "deb: built in $(($(date +%s) - start)) s:"
for deb in "$out"/*.deb; do
    echo "  $deb"
    dpkg-deb -f "$deb" Package Version Depends Provides Conflicts Replaces | sed 's/^/    /'
done

# lintian on the two binary packages; --fail-on error: errors fail, warnings stay (each has its reason in
# docs/packaging.md).
status=0
lintian --fail-on error --display-info "$out"/*.deb >"$out/lintian.txt" 2>&1 || status=$?
echo "deb: lintian ($out/lintian.txt):"
sed 's/^/  /' "$out/lintian.txt"
[[ $status -eq 0 ]] || { echo "deb: lintian reports errors (status $status)" >&2; exit 1; }
echo "deb: done"
