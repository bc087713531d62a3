# Validation: a config from configs/validation, run, then coflow-check and
# references.csv (validate.sh). Included from tests/CMakeLists.txt.
# --- validation: a config from configs/validation + coflow-check + references.csv ---
add_executable(coflow-check validation/check/main.cpp validation/check/compare.cpp validation/flow/checks.cpp
  validation/granular/checks.cpp validation/point_particles/checks.cpp validation/resolved_particles/checks.cpp
  validation/two_phase/checks.cpp validation/fv/checks.cpp validation/fv/turbulence_checks.cpp
  validation/immersed_boundary/checks.cpp)
coflow_precompile(coflow-check <yaml-cpp/yaml.h>)
target_link_libraries(coflow-check PRIVATE coflow_fluid coflow_immersed coflow_particles coflow_catalog coflow_warnings)
set(validate ${CMAKE_CURRENT_SOURCE_DIR}/validation/validate.sh)
set(vcfg ${PROJECT_SOURCE_DIR}/configs/validation)
function(coflow_validation name mode config procs)
  add_test(NAME validation.${name}
    COMMAND ${validate} ${name} ${CMAKE_BINARY_DIR}/bin ${CMAKE_CURRENT_BINARY_DIR}/val-${name} ${mode}
            ${vcfg}/${config} ${ARGN})
  coflow_case_ranks(ranks ${vcfg}/${config} ${ARGN})  # `procs` was a guess; the config says
  set_tests_properties(validation.${name} PROPERTIES LABELS "validation;mpi" PROCESSORS ${ranks})
endfunction()
# One folder per physics, each with its checks (coflow-check modes) and tests.
foreach(physics flow fv granular immersed_boundary point_particles resolved_particles two_phase)
  include(${CMAKE_CURRENT_LIST_DIR}/${physics}/tests.cmake)
endforeach()

# coflow-check compare on run directories that hold no snapshots (output
# without run.output.every): a message and exit 1, not a crash (it read past
# an empty list before 2026-12-02).
add_test(NAME check.compare_without_snapshots
  COMMAND sh -c "d=$(mktemp -d) && cp '${PROJECT_SOURCE_DIR}/configs/quickstart.yaml' \"$d/config.yaml\" && \
'${CMAKE_BINARY_DIR}/bin/coflow-check' compare \"$d\" \"$d\"; rc=$?; rm -rf \"$d\"; echo \"exit $rc\"; test $rc -eq 1")
set_tests_properties(check.compare_without_snapshots PROPERTIES PASS_REGULAR_EXPRESSION
  "no fluid or particle snapshots to compare.*exit 1[\r\n]*$")
