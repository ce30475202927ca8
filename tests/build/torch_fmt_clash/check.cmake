# cmake -DROMP_SOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=... -P check.cmake
# Configures this folder's project, then: `ahead` must build (romp's fmt and spdlog win over the
# stand-in Torch's fmt), and `shadowed` must fail on the stand-in's #error (the control).
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${CMAKE_CURRENT_LIST_DIR}" -B "${WORK_DIR}" -G "${GENERATOR}"
                        -DROMP_SOURCE_DIR=${ROMP_SOURCE_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the clash project failed:\n${log}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}" --target ahead
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "a file that includes Torch and spdlog does not compile when Torch's include folder "
                      "holds other fmt headers (PyTorch's wheel):\n${log}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}" --target shadowed
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(rc EQUAL 0 OR NOT log MATCHES "stand-in Torch's fmt header was picked up")
  message(FATAL_ERROR "the control compiled or failed otherwise: the stand-in's fmt is not where the wheel's "
                      "is, so the test proves nothing:\n${log}")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
message(STATUS "romp's fmt and spdlog are found ahead of Torch's include folder; without that the stand-in is hit")
