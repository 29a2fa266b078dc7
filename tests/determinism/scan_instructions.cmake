# Disassembles binaries and fails if an instruction appears whose result IEEE-754 leaves
# unspecified, so that different CPUs (Intel, AMD) may round it differently:
# - reciprocal and reciprocal-square-root estimates: (v)rcp/rsqrt ps/ss/pd/sd/ph/sh and their
#   AVX-512 14/28-bit forms (vrcp14ps, vrsqrt28sd, ...), AVX-512ER's vexp2ps/pd;
# - x87 transcendentals (fsin, fcos, fsincos, fptan, fpatan, f2xm1, fyl2x, fyl2xp1).
# Usage: cmake -DOBJDUMP=<objdump> -DFILES="<a;b;...>" [-DEXPECT_FOUND=ON] -P scan_instructions.cmake
# EXPECT_FOUND=ON inverts the verdict: the scan must find such an instruction (self-test).
if(NOT OBJDUMP OR NOT FILES)
  message(FATAL_ERROR "scan_instructions: pass -DOBJDUMP=... -DFILES=...")
endif()
set(_pattern "[ \t](v?rsqrt(14|28)?(ps|pd|ss|sd|ph|sh)|v?rcp(14|28)?(ps|pd|ss|sd|ph|sh)|vexp2p[sd]|fsin|fcos|fsincos|fptan|fpatan|f2xm1|fyl2x|fyl2xp1)[ \t]")
set(_found "")
foreach(_file IN LISTS FILES)
  if(NOT EXISTS "${_file}")
    message(FATAL_ERROR "scan_instructions: ${_file} does not exist")
  endif()
  execute_process(COMMAND "${OBJDUMP}" -d --no-show-raw-insn "${_file}"
                  OUTPUT_VARIABLE _asm RESULT_VARIABLE _rc ERROR_VARIABLE _err)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "scan_instructions: ${OBJDUMP} failed on ${_file}: ${_err}")
  endif()
  string(REGEX MATCHALL "${_pattern}" _hits "${_asm}")
  list(LENGTH _hits _count)
  if(_count GREATER 0)
    list(REMOVE_DUPLICATES _hits)
    string(REPLACE ";" "," _names "${_hits}")
    string(REGEX REPLACE "[ \t]" "" _names "${_names}")
    list(APPEND _found "${_file}: ${_count} (${_names})")
  endif()
endforeach()
if(EXPECT_FOUND)
  if(NOT _found)
    message(FATAL_ERROR "scan_instructions self-test: no approximate instruction found in ${FILES}; the scan is blind")
  endif()
  message(STATUS "self-test: found ${_found}")
elseif(_found)
  string(REPLACE ";" "\n  " _report "${_found}")
  message(FATAL_ERROR "approximate or unspecified instructions in Shore's libraries (results would differ "
                      "between CPUs):\n  ${_report}")
else()
  message(STATUS "no approximate instructions in ${FILES}")
endif()
