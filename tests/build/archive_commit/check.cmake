# cmake -DROMP_SOURCE_DIR=... -DWORK_DIR=... -P check.cmake
# `romp info` names romp's own commit: in its checkout, and in a `git archive` of it unpacked inside
# another git repository (as on a GPU machine), where git alone would name the outer repository's.
include("${ROMP_SOURCE_DIR}/cmake/RompCommit.cmake")
execute_process(COMMAND git -C "${ROMP_SOURCE_DIR}" rev-parse --short=12 HEAD
  OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc ERROR_QUIET)
if(NOT rc EQUAL 0)
  message(STATUS "skipped: the sources are not a git checkout")
  return()
endif()

romp_source_commit("${ROMP_SOURCE_DIR}" in_checkout)
if(NOT in_checkout MATCHES "^${head}(-dirty)?$")
  message(FATAL_ERROR "in the checkout: '${in_checkout}', expected ${head}")
endif()

file(REMOVE_RECURSE "${WORK_DIR}")
set(outer "${WORK_DIR}/outer")
file(MAKE_DIRECTORY "${outer}/romp")
execute_process(COMMAND git init -q "${outer}" COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND git -C "${outer}" -c user.name=t -c user.email=t@t commit -q --allow-empty -m outer
                COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND git -C "${ROMP_SOURCE_DIR}" archive --format=tar -o "${WORK_DIR}/romp.tar" HEAD
                COMMAND_ERROR_IS_FATAL ANY)
file(ARCHIVE_EXTRACT INPUT "${WORK_DIR}/romp.tar" DESTINATION "${outer}/romp")
romp_source_commit("${outer}/romp" in_archive)
file(REMOVE_RECURSE "${WORK_DIR}")
if(NOT in_archive STREQUAL head)
  message(FATAL_ERROR "an archive inside another repository: '${in_archive}', expected ${head}")
endif()
message(STATUS "checkout: ${in_checkout}; archive inside another repository: ${in_archive}")
