# cmake -DPROGRAM=... -DSUBCOMMAND=... -DFILE=... -DPHRASE=... [-DEXTRA=a;b;...] [-DOUTPUT=...]
#       -P expect_one_line_error.cmake
# Runs `PROGRAM SUBCOMMAND FILE EXTRA...` on input that must be refused and checks the contract of
# bad input: a non-zero exit code, nothing on stdout (nothing else done), one line on stderr
# that names the file and contains PHRASE, and, where OUTPUT is given, nothing written there.
if(DEFINED OUTPUT)
  file(REMOVE_RECURSE ${OUTPUT})
endif()
execute_process(COMMAND ${PROGRAM} ${SUBCOMMAND} ${FILE} ${EXTRA} RESULT_VARIABLE rc OUTPUT_VARIABLE out
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
if(DEFINED OUTPUT AND EXISTS ${OUTPUT})
  message(FATAL_ERROR "${OUTPUT} was written although the input was refused")
endif()
message(STATUS "${line}")
