# cmake -DCOMPILER=... -DSOURCE=... -DINCLUDE=... -DCASE=... -DPHRASE=... -P expect_compile_error.cmake
# Compiles SOURCE with -DUNISPH_CASE=CASE and checks that it fails with PHRASE in the diagnostics.
execute_process(COMMAND ${COMPILER} -std=c++20 -fsyntax-only -I${INCLUDE} -DUNISPH_CASE=${CASE} ${SOURCE}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "case ${CASE} compiled, but it must not")
endif()
string(FIND "${out}${err}" "${PHRASE}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "case ${CASE} failed without the phrase '${PHRASE}':\n${err}")
endif()
message(STATUS "case ${CASE}: '${PHRASE}'")
