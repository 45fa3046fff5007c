# Runs shatter-mpm and reads its ParaView files back with Python's vtk (read_vtk.py), which
# compares them with the CSV files of the same frames. Without Debian's python3 or its vtk the
# script prints "SKIPPED:" (the test's skip pattern).
if(NOT PYTHON)
  message("SKIPPED: no python3 in /usr/bin (Debian's python3-vtk9 reads the .vtp files)")
  return()
endif()
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${MPM}" "${SCENE}" --quiet --frames 3 --threads 1 --png-every 0 --out "${OUT}"
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "shatter-mpm failed (${rc}): ${err}")
endif()
execute_process(COMMAND "${PYTHON}" "${CMAKE_CURRENT_LIST_DIR}/read_vtk.py" "${OUT}" RESULT_VARIABLE rc OUTPUT_VARIABLE report
                ERROR_VARIABLE err)
message("${report}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the .vtp/.pvd files do not read back")
endif()
