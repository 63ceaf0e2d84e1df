# cmake -DPROGRAM=... -DFILE=... -DPHRASE=... -DOUTPUT=... -P expect_levelset_refused.cmake
# Runs `PROGRAM levelset FILE --dx 0.1 -o OUTPUT` on a geometry that cannot make a level set and
# checks: a non-zero exit code, nothing on stdout, one line on stderr naming the file and
# containing PHRASE, and no output folder written.
file(REMOVE_RECURSE ${OUTPUT})
execute_process(COMMAND ${PROGRAM} levelset ${FILE} --dx 0.1 -o ${OUTPUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "exit code 0 for ${FILE}; stdout: ${out}")
endif()
if(NOT out STREQUAL "")
  message(FATAL_ERROR "stdout is not empty for ${FILE}: ${out}")
endif()
string(REGEX REPLACE "\n$" "" line "${err}")
if(line MATCHES "\n")
  message(FATAL_ERROR "more than one line on stderr: ${err}")
endif()
string(FIND "${line}" "${FILE}: " at_file)
string(FIND "${line}" "${PHRASE}" at_phrase)
if(at_file EQUAL -1 OR at_phrase EQUAL -1)
  message(FATAL_ERROR "stderr '${line}' does not name '${FILE}' and contain '${PHRASE}'")
endif()
if(EXISTS ${OUTPUT})
  message(FATAL_ERROR "${OUTPUT} was written although the level set was refused")
endif()
message(STATUS "${line}")
