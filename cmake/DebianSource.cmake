# SPDX-License-Identifier: MIT
# DebianSource.cmake -- download a file of a Debian source package (typically its orig tarball) with
# `apt-get source --download-only` through a private, throw-away apt configuration: its own sources.list (deb-src
# lines only), lists, cache, status file and no locking, all under one directory. The system's apt setup (sources,
# lists, cache, status, locks) is left alone, and nothing needs root.
#
# Two uses:
#   include(DebianSource) then quadphase_fetch_debian_source(...)   (cmake/Box2DSource.cmake, at configure time)
#   cmake -D PACKAGE=caveexpress -D VERSION=2.5.2-1 -D FILE=caveexpress_2.5.2.orig.tar.xz -D SHA256=<hex>
#         -D APT_ROOT=<dir> [-D SUITE=bookworm] [-D MIRROR=<url>] [-D KEYRING=<file>] -P cmake/DebianSource.cmake
#       (scripts/real-game.sh): fetches FILE into APT_ROOT/src and checks its SHA256 (fails otherwise). A FILE
#       already there with the right SHA256 is reused without any network access.
#
# Only FILE has to arrive: apt-get source exits non-zero when any part of the package fails to download (the
# archive here serves caveexpress's orig tarball but not its debian.tar.xz), and that is accepted as long as FILE
# was fetched. The caller checks FILE's hash (the script mode does when SHA256 is given).

set(QUADPHASE_DEBIAN_DEFAULT_MIRROR "http://deb.debian.org/debian")
set(QUADPHASE_DEBIAN_DEFAULT_SUITE "bookworm")
set(QUADPHASE_DEBIAN_DEFAULT_KEYRING "/usr/share/keyrings/debian-archive-keyring.gpg")

# quadphase_fetch_debian_source(PACKAGE <name> SPECS <spec>... FILE <file> APT_ROOT <dir> OUT_VAR <var>
#                               [MIRROR <url>] [SUITE <suite>] [KEYRING <file>])
# Tries each SPEC in order (e.g. "box2d=2.4.1-3" then "box2d") until FILE is in <dir>/src. Sets <var> to FILE's
# path, or to "" (after a warning saying why) on failure. <dir> is wiped first.
function(quadphase_fetch_debian_source)
    cmake_parse_arguments(arg "" "PACKAGE;FILE;APT_ROOT;OUT_VAR;MIRROR;SUITE;KEYRING" "SPECS" ${ARGN})
    foreach(required PACKAGE FILE APT_ROOT OUT_VAR)
        if(NOT arg_${required})
            message(FATAL_ERROR "quadphase_fetch_debian_source: ${required} is required")
        endif()
    endforeach()
    if(NOT arg_SPECS)
        set(arg_SPECS "${arg_PACKAGE}")
    endif()
    foreach(opt MIRROR SUITE KEYRING)
        if(NOT arg_${opt})
            set(arg_${opt} "${QUADPHASE_DEBIAN_DEFAULT_${opt}}")
        endif()
    endforeach()
    set(${arg_OUT_VAR} "" PARENT_SCOPE)
    set(apt_root "${arg_APT_ROOT}")

    find_program(QUADPHASE_APT_GET_EXECUTABLE apt-get)
    mark_as_advanced(QUADPHASE_APT_GET_EXECUTABLE)
    if(NOT QUADPHASE_APT_GET_EXECUTABLE)
        message(WARNING "quadphase: apt-get not found; cannot download Debian's ${arg_PACKAGE} source package.")
        return()
    endif()
    if(NOT EXISTS "${arg_KEYRING}")
        message(WARNING "quadphase: Debian archive keyring ${arg_KEYRING} not found (package "
                        "debian-archive-keyring); cannot verify Debian's ${arg_PACKAGE} source package.")
        return()
    endif()

    # Fresh private apt state for every attempt.
    file(REMOVE_RECURSE "${apt_root}")
    file(MAKE_DIRECTORY
        "${apt_root}/lists/partial"
        "${apt_root}/cache/archives/partial"
        "${apt_root}/etc"
        "${apt_root}/src")
    file(TOUCH "${apt_root}/status")
    file(WRITE "${apt_root}/etc/sources.list"
        "deb-src [signed-by=${arg_KEYRING}] ${arg_MIRROR} ${arg_SUITE} main\n")

    set(apt_opts
        -o "Dir::Etc::SourceList=${apt_root}/etc/sources.list"
        -o "Dir::Etc::SourceParts=/dev/null"
        -o "Dir::State::Lists=${apt_root}/lists"
        -o "Dir::Cache=${apt_root}/cache"
        -o "Dir::State::status=${apt_root}/status"
        -o "Debug::NoLocking=1")

    message(STATUS "quadphase: fetching Debian source package ${arg_PACKAGE} (${arg_SUITE}) with a private apt "
                   "configuration in ${apt_root}")
    execute_process(
        COMMAND "${QUADPHASE_APT_GET_EXECUTABLE}" ${apt_opts} update
        WORKING_DIRECTORY "${apt_root}"
        RESULT_VARIABLE rc
        OUTPUT_VARIABLE out
        ERROR_VARIABLE out)
    if(NOT rc EQUAL 0)
        message(WARNING "quadphase: private `apt-get update` failed (${rc}):\n${out}")
        return()
    endif()
    # apt-get update exits 0 even when the mirror is unreachable; check for an index.
    file(GLOB sources_index "${apt_root}/lists/*_Sources*")
    if(NOT sources_index)
        message(WARNING "quadphase: private `apt-get update` fetched no Sources index from "
                        "${arg_MIRROR} (${arg_SUITE}); no network?\n${out}")
        return()
    endif()

    set(wanted "${apt_root}/src/${arg_FILE}")
    foreach(spec IN LISTS arg_SPECS)
        message(STATUS "quadphase: apt-get source --download-only ${spec}")
        execute_process(
            COMMAND "${QUADPHASE_APT_GET_EXECUTABLE}" ${apt_opts} source --download-only "${spec}"
            WORKING_DIRECTORY "${apt_root}/src"
            RESULT_VARIABLE rc
            OUTPUT_VARIABLE out
            ERROR_VARIABLE out)
        if(EXISTS "${wanted}")
            if(NOT rc EQUAL 0)
                message(STATUS "quadphase: apt-get source ${spec} fetched ${arg_FILE} but not all of the "
                               "package (${rc}):\n${out}")
            endif()
            set(${arg_OUT_VAR} "${wanted}" PARENT_SCOPE)
            return()
        endif()
        message(STATUS "quadphase: apt-get source ${spec} did not fetch ${arg_FILE} (${rc}):\n${out}")
    endforeach()
    file(GLOB got RELATIVE "${apt_root}/src" "${apt_root}/src/*")
    message(WARNING "quadphase: could not download ${arg_FILE} from Debian's ${arg_PACKAGE} source package "
                    "(got: ${got}); the package is probably no longer that version in ${arg_SUITE}.")
endfunction()

# Script mode: cmake -D ... -P cmake/DebianSource.cmake (see the top of this file).
if(CMAKE_SCRIPT_MODE_FILE AND CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
    foreach(required PACKAGE FILE APT_ROOT)
        if(NOT DEFINED ${required} OR "${${required}}" STREQUAL "")
            message(FATAL_ERROR "DebianSource.cmake: -D ${required}=... is required (see the top of this file)")
        endif()
    endforeach()
    get_filename_component(APT_ROOT "${APT_ROOT}" ABSOLUTE)
    set(path "${APT_ROOT}/src/${FILE}")
    set(reuse FALSE)
    if(SHA256 AND EXISTS "${path}")
        file(SHA256 "${path}" actual)
        if(actual STREQUAL SHA256)
            set(reuse TRUE)
            message(STATUS "quadphase: reusing ${path} (SHA-256 verified)")
        endif()
    endif()
    if(NOT reuse)
        set(specs "")
        if(VERSION)
            list(APPEND specs "${PACKAGE}=${VERSION}")
        endif()
        list(APPEND specs "${PACKAGE}")
        quadphase_fetch_debian_source(PACKAGE "${PACKAGE}" SPECS ${specs} FILE "${FILE}" APT_ROOT "${APT_ROOT}"
                                      MIRROR "${MIRROR}" SUITE "${SUITE}" KEYRING "${KEYRING}" OUT_VAR path)
        if(NOT path)
            message(FATAL_ERROR "quadphase: could not obtain ${FILE} (see the warnings above)")
        endif()
        if(SHA256)
            file(SHA256 "${path}" actual)
            if(NOT actual STREQUAL SHA256)
                message(FATAL_ERROR "quadphase: ${path} has SHA-256\n  ${actual}\nbut must have\n  ${SHA256}")
            endif()
            message(STATUS "quadphase: ${FILE}: SHA-256 verified (${SHA256})")
        endif()
    endif()
endif()
