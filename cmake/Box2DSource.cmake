# SPDX-License-Identifier: MIT
# Box2DSource.cmake -- obtain the Box2D 2.4.1 source tree at configure time.
#
# Box2D's source is never committed to this repository.  It is located, in
# order of preference, from:
#
#   1. QUADPHASE_BOX2D_SOURCE_DIR  an already unpacked Box2D 2.4.1 source tree
#                                  (must contain include/box2d/b2_broad_phase.h
#                                  and src/collision/b2_broad_phase.cpp);
#   2. QUADPHASE_BOX2D_TARBALL     a local copy of box2d_2.4.1.orig.tar.gz;
#   3. a tarball downloaded by an earlier configure into the build tree
#      (re-used without any network access once its SHA-256 checks out);
#   4. Debian's source package "box2d" (version QUADPHASE_BOX2D_DEBIAN_VERSION,
#      falling back to the unversioned package), fetched with
#      `apt-get source --download-only` through a private, throw-away apt
#      configuration under the build tree (cmake/DebianSource.cmake).  The
#      system apt setup (sources, lists, cache, status, locks) is left alone.
#
# Tarballs (cases 2-4) must have the SHA-256 QUADPHASE_BOX2D_SHA256 and are
# unpacked with file(ARCHIVE_EXTRACT) into the build tree.
#
# After quadphase_resolve_box2d_source() the variable QUADPHASE_BOX2D_SRC (normal
# variable in the caller's scope and an INTERNAL cache entry) holds the absolute
# path of the Box2D source root (the directory containing include/, src/ and
# unit-test/).

include("${CMAKE_CURRENT_LIST_DIR}/DebianSource.cmake")

set(QUADPHASE_BOX2D_VERSION "2.4.1")
set(QUADPHASE_BOX2D_SHA256 "d6b4650ff897ee1ead27cf77a5933ea197cbeef6705638dd181adc2e816b23c2")
set(QUADPHASE_BOX2D_ORIG_TARBALL_NAME "box2d_${QUADPHASE_BOX2D_VERSION}.orig.tar.gz")

set(QUADPHASE_BOX2D_SOURCE_DIR "" CACHE PATH
    "Unpacked Box2D ${QUADPHASE_BOX2D_VERSION} source tree to use instead of downloading one")
set(QUADPHASE_BOX2D_TARBALL "" CACHE FILEPATH
    "Local ${QUADPHASE_BOX2D_ORIG_TARBALL_NAME} to unpack instead of downloading one")
set(QUADPHASE_BOX2D_DEBIAN_VERSION "2.4.1-3" CACHE STRING
    "Debian source package version of box2d fetched with apt-get source")
set(QUADPHASE_BOX2D_DEBIAN_MIRROR "http://deb.debian.org/debian" CACHE STRING
    "Debian mirror used by the private apt configuration that fetches box2d")
set(QUADPHASE_BOX2D_DEBIAN_SUITE "bookworm" CACHE STRING
    "Debian suite used by the private apt configuration that fetches box2d")
set(QUADPHASE_BOX2D_DEBIAN_KEYRING "/usr/share/keyrings/debian-archive-keyring.gpg" CACHE FILEPATH
    "Keyring (signed-by) used to verify the Debian archive when fetching box2d")
mark_as_advanced(QUADPHASE_BOX2D_DEBIAN_VERSION QUADPHASE_BOX2D_DEBIAN_MIRROR
    QUADPHASE_BOX2D_DEBIAN_SUITE QUADPHASE_BOX2D_DEBIAN_KEYRING)

set(_QUADPHASE_BOX2D_HOWTO
"Supply the Box2D ${QUADPHASE_BOX2D_VERSION} source yourself in one of these ways:
  -DQUADPHASE_BOX2D_SOURCE_DIR=/path/to/box2d-${QUADPHASE_BOX2D_VERSION}
       an unpacked source tree containing include/box2d/b2_broad_phase.h and
       src/collision/b2_broad_phase.cpp (e.g. a checkout of tag v${QUADPHASE_BOX2D_VERSION} of
       https://github.com/erincatto/box2d), or
  -DQUADPHASE_BOX2D_TARBALL=/path/to/${QUADPHASE_BOX2D_ORIG_TARBALL_NAME}
       Debian's orig tarball (SHA-256 ${QUADPHASE_BOX2D_SHA256}), as fetched by
       `apt-get source --download-only box2d=${QUADPHASE_BOX2D_DEBIAN_VERSION}`")

# _quadphase_box2d_tree_problem(<dir> <out-var>): set <out-var> to a description of
# what is missing from <dir>, or to "" if it looks like a Box2D 2.4.1 source tree.
function(_quadphase_box2d_tree_problem dir out_var)
    set(problem "")
    foreach(rel include/box2d/b2_broad_phase.h src/collision/b2_broad_phase.cpp)
        if(NOT EXISTS "${dir}/${rel}")
            string(APPEND problem "\n  missing: ${dir}/${rel}")
        endif()
    endforeach()
    set(${out_var} "${problem}" PARENT_SCOPE)
endfunction()

# _quadphase_sha256_ok(<file> <out-var>): TRUE iff <file> exists with the expected hash.
function(_quadphase_sha256_ok file out_var)
    set(ok FALSE)
    if(EXISTS "${file}" AND NOT IS_DIRECTORY "${file}")
        file(SHA256 "${file}" actual)
        if(actual STREQUAL QUADPHASE_BOX2D_SHA256)
            set(ok TRUE)
        endif()
    endif()
    set(${out_var} ${ok} PARENT_SCOPE)
endfunction()

# _quadphase_apt_fetch_box2d(<apt-root> <out-var>): download Debian's box2d source package into <apt-root>/src
# with a private apt configuration (cmake/DebianSource.cmake). Sets <out-var> to the path of the orig tarball, or
# to "" (with a warning explaining why) on failure.
function(_quadphase_apt_fetch_box2d apt_root out_var)
    quadphase_fetch_debian_source(
        PACKAGE box2d
        SPECS "box2d=${QUADPHASE_BOX2D_DEBIAN_VERSION}" box2d
        FILE "${QUADPHASE_BOX2D_ORIG_TARBALL_NAME}"
        APT_ROOT "${apt_root}"
        MIRROR "${QUADPHASE_BOX2D_DEBIAN_MIRROR}"
        SUITE "${QUADPHASE_BOX2D_DEBIAN_SUITE}"
        KEYRING "${QUADPHASE_BOX2D_DEBIAN_KEYRING}"
        OUT_VAR tarball)
    set(${out_var} "${tarball}" PARENT_SCOPE)
endfunction()

# quadphase_resolve_box2d_source(): see the top of this file.
function(quadphase_resolve_box2d_source)
    # -- 1. an unpacked tree supplied by the user ------------------------------
    if(QUADPHASE_BOX2D_SOURCE_DIR)
        get_filename_component(src "${QUADPHASE_BOX2D_SOURCE_DIR}" ABSOLUTE BASE_DIR "${CMAKE_BINARY_DIR}")
        _quadphase_box2d_tree_problem("${src}" problem)
        if(problem)
            message(FATAL_ERROR
                "QUADPHASE_BOX2D_SOURCE_DIR=${QUADPHASE_BOX2D_SOURCE_DIR} is not a Box2D "
                "${QUADPHASE_BOX2D_VERSION} source tree.  Expected the top directory of the unpacked "
                "source (the one holding include/, src/ and unit-test/):${problem}\n${_QUADPHASE_BOX2D_HOWTO}")
        endif()
        if(EXISTS "${src}/CMakeLists.txt")
            file(STRINGS "${src}/CMakeLists.txt" project_line REGEX "project\\(box2d")
            if(NOT project_line MATCHES "VERSION ${QUADPHASE_BOX2D_VERSION}")
                message(WARNING "quadphase: QUADPHASE_BOX2D_SOURCE_DIR=${src} does not look like Box2D "
                                "${QUADPHASE_BOX2D_VERSION} (${src}/CMakeLists.txt: '${project_line}')")
            endif()
        endif()
        message(STATUS "quadphase: using Box2D source from QUADPHASE_BOX2D_SOURCE_DIR: ${src}")
        set(QUADPHASE_BOX2D_SRC "${src}" CACHE INTERNAL "Box2D ${QUADPHASE_BOX2D_VERSION} source root")
        set(QUADPHASE_BOX2D_SRC "${src}" PARENT_SCOPE)
        return()
    endif()

    set(work "${PROJECT_BINARY_DIR}/_box2d")
    set(apt_root "${work}/apt")
    set(unpack_root "${work}/source")
    set(src "${unpack_root}/box2d-${QUADPHASE_BOX2D_VERSION}")
    set(stamp "${unpack_root}/.quadphase-unpacked")

    # -- 2./3./4. find a verified tarball --------------------------------------
    set(tarball "")
    if(QUADPHASE_BOX2D_TARBALL)
        get_filename_component(tarball "${QUADPHASE_BOX2D_TARBALL}" ABSOLUTE BASE_DIR "${CMAKE_BINARY_DIR}")
        if(NOT EXISTS "${tarball}")
            message(FATAL_ERROR "QUADPHASE_BOX2D_TARBALL=${QUADPHASE_BOX2D_TARBALL} does not exist.\n"
                                "${_QUADPHASE_BOX2D_HOWTO}")
        endif()
        set(origin "QUADPHASE_BOX2D_TARBALL")
    else()
        set(cached "${apt_root}/src/${QUADPHASE_BOX2D_ORIG_TARBALL_NAME}")
        _quadphase_sha256_ok("${cached}" cached_ok)
        if(cached_ok)
            set(tarball "${cached}")
            set(origin "previous download")
        elseif(EXISTS "${stamp}")
            # The tarball is gone but an earlier configure verified and unpacked it.
            file(READ "${stamp}" stamp_content)
            string(STRIP "${stamp_content}" stamp_content)
            _quadphase_box2d_tree_problem("${src}" problem)
            if(stamp_content STREQUAL QUADPHASE_BOX2D_SHA256 AND NOT problem)
                message(STATUS "quadphase: using previously unpacked Box2D source ${src}")
                set(QUADPHASE_BOX2D_SRC "${src}" CACHE INTERNAL "Box2D ${QUADPHASE_BOX2D_VERSION} source root")
                set(QUADPHASE_BOX2D_SRC "${src}" PARENT_SCOPE)
                return()
            endif()
        endif()
        if(NOT tarball)
            _quadphase_apt_fetch_box2d("${apt_root}" tarball)
            set(origin "Debian source package box2d")
            if(NOT tarball)
                message(FATAL_ERROR
                    "quadphase: could not obtain the Box2D ${QUADPHASE_BOX2D_VERSION} source from Debian "
                    "(see the warnings above).\n${_QUADPHASE_BOX2D_HOWTO}")
            endif()
        endif()
    endif()

    file(SHA256 "${tarball}" actual)
    if(NOT actual STREQUAL QUADPHASE_BOX2D_SHA256)
        message(FATAL_ERROR
            "quadphase: ${tarball} (${origin}) has SHA-256\n  ${actual}\nbut Box2D "
            "${QUADPHASE_BOX2D_VERSION} (${QUADPHASE_BOX2D_ORIG_TARBALL_NAME}) must have\n  "
            "${QUADPHASE_BOX2D_SHA256}\n${_QUADPHASE_BOX2D_HOWTO}")
    endif()
    message(STATUS "quadphase: Box2D tarball ${tarball} (${origin}), SHA-256 verified")

    # -- unpack (once per verified tarball) ------------------------------------
    set(up_to_date FALSE)
    if(EXISTS "${stamp}")
        file(READ "${stamp}" stamp_content)
        string(STRIP "${stamp_content}" stamp_content)
        _quadphase_box2d_tree_problem("${src}" problem)
        if(stamp_content STREQUAL QUADPHASE_BOX2D_SHA256 AND NOT problem)
            set(up_to_date TRUE)
        endif()
    endif()
    if(NOT up_to_date)
        message(STATUS "quadphase: unpacking Box2D into ${unpack_root}")
        file(REMOVE_RECURSE "${unpack_root}")
        file(MAKE_DIRECTORY "${unpack_root}")
        file(ARCHIVE_EXTRACT INPUT "${tarball}" DESTINATION "${unpack_root}")
        _quadphase_box2d_tree_problem("${src}" problem)
        if(problem)
            message(FATAL_ERROR "quadphase: ${tarball} did not unpack to the expected layout:"
                                "${problem}\n${_QUADPHASE_BOX2D_HOWTO}")
        endif()
        file(WRITE "${stamp}" "${QUADPHASE_BOX2D_SHA256}\n")
    endif()

    message(STATUS "quadphase: using Box2D source ${src}")
    set(QUADPHASE_BOX2D_SRC "${src}" CACHE INTERNAL "Box2D ${QUADPHASE_BOX2D_VERSION} source root")
    set(QUADPHASE_BOX2D_SRC "${src}" PARENT_SCOPE)
endfunction()
