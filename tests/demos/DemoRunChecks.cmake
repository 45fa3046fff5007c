# What the fracture and tear demo checks share (included by expect_fracture.cmake and
# expect_tear.cmake, which run with -DDEMO, -DOUT and -DPYTHON): running the demo, the files it
# must write, and the conservation figures of its summary.json.

# Runs ${DEMO} --quiet --out ${OUT} plus the given arguments into a fresh ${OUT}; stops the
# test with the demo's error output when it exits non-zero.
function(run_demo)
  file(REMOVE_RECURSE "${OUT}")
  execute_process(COMMAND "${DEMO}" --quiet --out "${OUT}" ${ARGN} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${DEMO} failed (${rc}): ${err}")
  endif()
endfunction()

function(expect_files)
  foreach(f ${ARGN})
    if(NOT EXISTS "${OUT}/${f}")
      message(FATAL_ERROR "${DEMO} did not write ${OUT}/${f}")
    endif()
  endforeach()
endfunction()

# The summary's keys `a` and `b` agree to 1e-9 relative (CMake has no floating-point
# arithmetic: Python compares).
function(expect_kept summary a b)
  string(JSON va GET "${${summary}}" ${a})
  string(JSON vb GET "${${summary}}" ${b})
  execute_process(COMMAND ${PYTHON} -c "import sys; a,b=float(sys.argv[1]),float(sys.argv[2]); sys.exit(0 if abs(a-b) <= 1e-9*a else 1)" ${va} ${vb}
                  RESULT_VARIABLE same)
  if(NOT same EQUAL 0)
    message(FATAL_ERROR "${a} ${va} and ${b} ${vb} differ by more than 1e-9")
  endif()
endfunction()

# Momentum and angular momentum handed on to 1e-9 relative at every event.
function(expect_momenta_kept summary)
  foreach(key momentum_error_max angular_momentum_error_max)
    string(JSON v GET "${${summary}}" ${key})
    if(v GREATER 1e-9)
      message(FATAL_ERROR "${key} ${v} above 1e-9")
    endif()
  endforeach()
endfunction()

# At least `least` joints re-created (nothing is asked when it is 0).
function(expect_joints_recreated summary least)
  if(least GREATER 0)
    string(JSON recreated ERROR_VARIABLE none GET "${${summary}}" events joint_recreated)
    if(none OR recreated LESS ${least})
      message(FATAL_ERROR "expected >= ${least} joints re-created, got '${recreated}'")
    endif()
  endif()
endfunction()
