# cmake -DOUTPUT=libmbrt.a -DAR=ar -DINPUTS="a.a|b.a" -P MergeStatic.cmake:
# one archive holding every object of the inputs (ar's MRI script).
file(REMOVE ${OUTPUT})
set(script "create ${OUTPUT}\n")
string(REPLACE "|" ";" inputs "${INPUTS}")
foreach(input IN LISTS inputs)
  string(APPEND script "addlib ${input}\n")
endforeach()
string(APPEND script "save\nend\n")
file(WRITE ${OUTPUT}.mri "${script}")
execute_process(COMMAND ${AR} -M INPUT_FILE ${OUTPUT}.mri RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "MergeStatic: ${AR} -M failed for ${OUTPUT}")
endif()
