# SPDX-License-Identifier: MIT
# cmake -P driver of robustness_secure_environment: a set-group-ID program ignores the QUADPHASE_* variables, and
# the validation log's descriptor is closed on exec.   -DCHILD=<secure_environment_child> -DWORK_DIR=<scratch>
# The child runs twice with the same variables (QUADPHASE_VALIDATE, _STOCK_TREE, _STRICT, _VALIDATE_LOG,
# _VALIDATE_LOG_EVERY): as it is, where it must obey them all (so the variables are seen, and the second run can
# only pass by ignoring them), and as a copy set-group-ID to a group other than ours, which the kernel starts in
# secure-execution mode (AT_SECURE: effective group not the real one), where it must obey none and write no log.
# Skipped, with the reason, where set-ID bits have no effect: a nosuid file system, no_new_privs, or a user who
# is not root and has no second group to give the copy.
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# run_child(<out_var> <program> <log>): the child's report line, with the variables set and the log at <log>.
function(run_child out_var program log)
    execute_process(
        COMMAND "${CMAKE_COMMAND}" -E env QUADPHASE_VALIDATE=1 QUADPHASE_STOCK_TREE=1 QUADPHASE_STRICT=1
                "QUADPHASE_VALIDATE_LOG=${log}" QUADPHASE_VALIDATE_LOG_EVERY=1 "${program}" "${log}"
        OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(NOT rc EQUAL 0 OR NOT out MATCHES "^at_secure=")
        message(FATAL_ERROR "${program} failed (${rc}):\n${out}\n${err}")
    endif()
    message(STATUS "${program}: ${out}")
    set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

function(skip reason)
    message("quadphase-test-skipped: ${reason}")
endfunction()

# The program as it is: every variable obeyed, the log written by this process and not inherited by its children.
get_filename_component(name "${CHILD}" NAME)
file(COPY "${CHILD}" DESTINATION "${WORK_DIR}/plain")
set(plain "${WORK_DIR}/plain/${name}")
run_child(report "${plain}" "${WORK_DIR}/plain.log")
set(expected "at_secure=0 nosuid=[01] no_new_privs=[01] validate=1 stock_tree=1 strict=1 log=cloexec")
if(NOT report MATCHES "^${expected}$")
    message(FATAL_ERROR "without set-ID bits: expected ${expected}")
endif()
file(STRINGS "${WORK_DIR}/plain.log" lines REGEX "UpdatePairs checked")
list(LENGTH lines n)
if(n LESS 3)
    message(FATAL_ERROR "without set-ID bits: ${n} summaries in the log, at least 3 expected (one per check)")
endif()
if(report MATCHES "nosuid=1")
    skip("${WORK_DIR} is on a file system mounted nosuid: set-ID bits have no effect there")
    return()
endif()
if(report MATCHES "no_new_privs=1")
    skip("the test runs with no_new_privs set: set-ID bits have no effect")
    return()
endif()

# A group other than our real one: any, for root; one of our other groups, for anyone else.
execute_process(COMMAND id -u OUTPUT_VARIABLE uid OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND id -g OUTPUT_VARIABLE gid OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND id -G OUTPUT_VARIABLE groups OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
set(group "")
if(uid EQUAL 0)
    set(group 65534)
    if(gid EQUAL group)
        set(group 65533)
    endif()
else()
    separate_arguments(groups UNIX_COMMAND "${groups}")
    list(REMOVE_ITEM groups "${gid}")
    if(groups)
        list(GET groups 0 group)
    endif()
endif()
if(group STREQUAL "")
    skip("user ${uid} is not root and belongs to no group but ${gid}: no set-group-ID copy can be made")
    return()
endif()

# The set-group-ID copy (chgrp first: it clears the bit).
file(COPY "${CHILD}" DESTINATION "${WORK_DIR}/setgid")
set(setgid "${WORK_DIR}/setgid/${name}")
execute_process(COMMAND chgrp "${group}" "${setgid}" COMMAND_ERROR_IS_FATAL ANY)
file(CHMOD "${setgid}" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE SETGID)
run_child(report "${setgid}" "${WORK_DIR}/setgid.log")
if(NOT report MATCHES "^at_secure=1 ")
    message(FATAL_ERROR "the set-group-ID copy (group ${group}) was not started in secure-execution mode")
endif()
set(expected "at_secure=1 nosuid=0 no_new_privs=0 validate=0 stock_tree=0 strict=0 log=none")
if(NOT report MATCHES "^${expected}$")
    message(FATAL_ERROR "set-group-ID: expected ${expected}")
endif()
if(EXISTS "${WORK_DIR}/setgid.log")
    message(FATAL_ERROR "set-group-ID: QUADPHASE_VALIDATE_LOG was obeyed: ${WORK_DIR}/setgid.log exists")
endif()
message(STATUS "set-group-ID: every QUADPHASE_* variable ignored, no log written")
