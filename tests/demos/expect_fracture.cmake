# Runs a fracture demo (shatter-vase, shatter-glass) and checks what it must show: the break
# and last pictures, at least MIN_EVENTS fracture events and MIN_FRAGMENTS fragments, crack
# faces, mass and volume kept to 1e-9 (the cut adds up to round-off), momentum and angular
# momentum handed on to 1e-9 at every break, and at least JOINTS joints re-created.
include("${CMAKE_CURRENT_LIST_DIR}/DemoRunChecks.cmake")
string(REPLACE "|" ";" ARGS "${ARGS}")
run_demo(${ARGS})
expect_files(break.png final.png summary.json)
file(READ "${OUT}/summary.json" s)
string(JSON events GET "${s}" fracture_events)
string(JSON fragments GET "${s}" fragments)
string(JSON cracks GET "${s}" crack_faces)
if(events LESS ${MIN_EVENTS} OR fragments LESS ${MIN_FRAGMENTS} OR NOT cracks GREATER 0)
  message(FATAL_ERROR "expected >= ${MIN_EVENTS} breaks, >= ${MIN_FRAGMENTS} fragments and crack faces, got ${events}, ${fragments}, ${cracks}")
endif()
expect_kept(s mass_initial mass_final)
expect_kept(s volume_initial volume_final)
expect_momenta_kept(s)
expect_joints_recreated(s ${JOINTS})
