# The Python that FreeCAD runs, found from FreeCAD's own library: FreeCAD.so links exactly one
# libpython3.N, and the frepcore module must be built for that interpreter (FreeCAD 0.20 on
# bookworm and FreeCAD 1.0 on trixie run different ones). Without FreeCAD installed, the
# system python3 is taken. -DPython_EXECUTABLE=... overrides both.
#
# Sets FREECAD_LIB_DIR (the folder of FreeCAD.so, empty when none was found) and
# Python_EXECUTABLE (cached).

find_file(FREECAD_LIBRARY FreeCAD.so
  PATHS /usr/lib/freecad-python3/lib /usr/lib/freecad/lib /usr/local/lib/freecad/lib
  NO_DEFAULT_PATH)
set(FREECAD_LIB_DIR "")
if(FREECAD_LIBRARY)
  get_filename_component(FREECAD_LIB_DIR ${FREECAD_LIBRARY} DIRECTORY)
endif()

if(NOT Python_EXECUTABLE)
  set(_freecad_python_name "")
  if(FREECAD_LIBRARY AND CMAKE_READELF)
    execute_process(COMMAND ${CMAKE_READELF} -d ${FREECAD_LIBRARY}
                    OUTPUT_VARIABLE _freecad_dynamic ERROR_QUIET)
    string(REGEX MATCH "libpython(3\\.[0-9]+)" _freecad_libpython "${_freecad_dynamic}")
    if(CMAKE_MATCH_1)
      set(_freecad_python_name "python${CMAKE_MATCH_1}")
    endif()
  endif()
  # The distribution's interpreter first: another python3 earlier on PATH (pyenv, a venv)
  # would build a module FreeCAD cannot load.
  if(_freecad_python_name)
    find_program(_freecad_python NAMES ${_freecad_python_name} PATHS /usr/bin NO_DEFAULT_PATH)
    message(STATUS "FreeCAD (${FREECAD_LIBRARY}) links lib${_freecad_python_name}")
  else()
    find_program(_freecad_python NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
    message(STATUS "FreeCAD's library not found: building for the system python3")
  endif()
  if(NOT _freecad_python)
    message(FATAL_ERROR "No Python interpreter for FreeCAD found in /usr/bin "
                        "(looked for ${_freecad_python_name} python3); set -DPython_EXECUTABLE")
  endif()
  set(Python_EXECUTABLE ${_freecad_python} CACHE FILEPATH "Python that FreeCAD runs")
endif()
