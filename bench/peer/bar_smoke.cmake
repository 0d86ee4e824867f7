# CTest smoke test of pbd_bar (bench/peer/CMakeLists.txt): writes a 6×3×3 bar with make_bar.py, runs a few steps in
# float and in double, writes a reference trajectory in double and measures both against it, and checks the exit
# codes, the counts, that the JSON line holds finite numbers, that the bar sags, that the reference measured against
# itself gives 0 and that a bad reference (another dt) fails with exit code 1.
# Variables: PYTHON, MAKE_BAR, DRIVER, WORK.
file(MAKE_DIRECTORY "${WORK}")
set(mesh "${WORK}/bar6.txt")
set(ref "${WORK}/bar6_tip.txt")
execute_process(COMMAND "${PYTHON}" "${MAKE_BAR}" "${mesh}" --width 6 --height 3 --depth 3 --size 2 0.5 0.5
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "make_bar.py failed (${rc}): ${err}")
endif()
# Each run's arguments in one string (split below; the work directory's path has no spaces).
set(base "--steps 20 --substeps 4 --iterations 2 --threads 1")
set(runs "${base} --double --write-reference ${ref}" "${base} --double --reference ${ref}" "${base} --reference ${ref}"
         "--steps 5")
foreach(shown IN LISTS runs)
  separate_arguments(argv UNIX_COMMAND "${shown}")
  execute_process(COMMAND "${DRIVER}" --mesh "${mesh}" ${argv} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pbd_bar ${shown} failed (${rc}): ${err}")
  endif()
  set(keys particles tets ms_per_step cpu_ms_per_step sag_mm mean_sag_mm)
  if(shown MATCHES "--reference ")
    list(APPEND keys tip_rms_mm tip_final_mm tip_max_mm)
  endif()
  foreach(key ${keys})
    string(JSON v ERROR_VARIABLE jerr GET "${out}" ${key})
    if(jerr OR NOT v MATCHES "^[-+0-9.eE]+$")
      message(FATAL_ERROR "pbd_bar ${shown}: '${key}' is not a finite number in: ${out}")
    endif()
  endforeach()
  string(JSON np GET "${out}" particles)
  string(JSON nt GET "${out}" tets)
  if(NOT np EQUAL 54 OR NOT nt EQUAL 100)  # 6·3·3 vertices; 5·2·2 cells of 5 tets
    message(FATAL_ERROR "pbd_bar ${shown}: expected 54 particles and 100 tets: ${out}")
  endif()
  string(JSON sag GET "${out}" sag_mm)
  if(NOT sag GREATER 0)
    message(FATAL_ERROR "pbd_bar ${shown}: the tip did not sag: ${out}")
  endif()
  if(shown MATCHES "--double --reference")
    string(JSON rms GET "${out}" tip_rms_mm)
    if(NOT rms EQUAL 0)
      message(FATAL_ERROR "pbd_bar ${shown}: the reference's own run is ${rms} mm off it (deterministic: 0)")
    endif()
  endif()
  message(STATUS "${out}")
endforeach()
execute_process(COMMAND "${DRIVER}" --mesh "${mesh}" --steps 5 --dt 0.01 --reference "${ref}" RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT err MATCHES "dt")
  message(FATAL_ERROR "pbd_bar with a reference of another dt: expected exit code 1 naming dt, got ${rc}: ${err}")
endif()
