# Writes the man page allanlot.1 (cmake -P, from cmake/AllanlotInstall.cmake): help2man reads
# `allanlot --help` and `--version`; each command's --help is added as a section of its own, and
# the exit statuses and pointers to the docs from the include file written here.
# Inputs: HELP2MAN, ALLANLOT (the binary), OUTPUT (the page; OUTPUT.gz is the installed copy,
# compressed with gzip -9n as Debian policy asks), WORKDIR (scratch).
file(MAKE_DIRECTORY ${WORKDIR})
set(_commands analyze summarize simulate diagnose report export convert hat codev)
set(_include "${WORKDIR}/allanlot.h2m")
file(WRITE ${_include} "[DESCRIPTION]
allanlot characterizes the noise of inertial sensors (MEMS gyroscopes and accelerometers) and
clocks with the Allan variance family, for whole production lots: Allan-family deviations with
confidence intervals, the PSD and its equation (2) cross-check, the five-term noise model fit
(R, K, B, N, Q) in datasheet units, a lot summary with pass/fail against a spec, HTML reports
and Stable32/CSV exports.
")
foreach(_cmd ${_commands})
  execute_process(COMMAND ${ALLANLOT} ${_cmd} --help OUTPUT_VARIABLE _help
                  RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "${ALLANLOT} ${_cmd} --help failed (${_rc})")
  endif()
  # CLI11 prints the path it was started by; the page names the installed command.
  string(REPLACE "${ALLANLOT}" "allanlot" _help "${_help}")
  # Roff: a backslash must be doubled, and a line starting with '.' or ' would be a request.
  string(REPLACE "\\" "\\\\" _help "${_help}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" _help "${_help}")
  file(APPEND ${_include} "[COMMAND: ${_cmd}]\n.nf\n${_help}.fi\n")
endforeach()
file(APPEND ${_include} "[EXIT STATUS]
.TP
0
every input analysed (summarize: the summary was written)
.TP
1
some inputs or channels failed; the others were analysed, and each failure is named on
standard error as file:dataset: reason
.TP
2
usage error, or nothing could be analysed
.PP
Interrupted runs and the other commands' statuses: /usr/share/doc/allanlot/docs/cli.md.
[SEE ALSO]
The reference manual: /usr/share/doc/allanlot/docs/ (cli.md, formats.md, statistics.md,
fit-and-psd.md, diagnose.md, lots-and-slurm.md). Slurm job arrays:
/usr/share/allanlot/slurm/submit-lot --help.
")
execute_process(
  COMMAND ${HELP2MAN} --no-info --section=1 --source=allanlot
          "--name=Allan-variance noise characterization of sensor lots and clocks"
          --include=${_include} --output=${OUTPUT} ${ALLANLOT}
  RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "help2man failed (${_rc})")
endif()
find_program(_gzip gzip REQUIRED)
execute_process(COMMAND ${_gzip} -9nfk ${OUTPUT} RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "gzip of ${OUTPUT} failed (${_rc})")
endif()
