# ctest fixture: a copy of IN (an IGES file of ours, in millimetres) stating inches (global
# parameters 14-15: unit flag 1, "IN"), written to OUT.
file(READ ${IN} text)
string(REPLACE ",1.,2,2HMM," ",1.,1,2HIN," text "${text}")
if(NOT text MATCHES ",1\\.,1,2HIN,")
  message(FATAL_ERROR "${IN}: its global section has no millimetre unit to replace")
endif()
file(WRITE ${OUT} "${text}")
