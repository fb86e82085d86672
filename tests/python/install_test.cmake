# ctest's python.install: `cmake --install BUILD` into STAGE (DESTDIR), then PYTHON imports
# ffdtool from STAGE/INSTALL_DIR, and only from there, and deforms a mesh with it.
file(REMOVE_RECURSE ${STAGE})
execute_process(COMMAND ${CMAKE_COMMAND} -E env DESTDIR=${STAGE} ${CMAKE_COMMAND} --install ${BUILD}
                RESULT_VARIABLE installed OUTPUT_QUIET)
if(NOT installed EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${installed})")
endif()
set(site ${STAGE}${INSTALL_DIR})
set(check [=[
import sys, numpy as np, ffdtool
assert ffdtool.__file__.startswith(sys.argv[1]), ffdtool.__file__
mesh = ffdtool.Mesh(np.random.default_rng(1).random((100, 3)))
lat = ffdtool.BSplineLattice(mesh, cells=[4, 4, 4])
lat.move([2, 2, 2], by=[0.1, 0, 0])
assert np.abs(lat(mesh.vertices) - mesh.vertices).max() > 0
print("installed ffdtool at", ffdtool.__file__)
]=])
execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c "${check}" ${site}
                RESULT_VARIABLE imported)
file(REMOVE_RECURSE ${STAGE})
if(NOT imported EQUAL 0)
  message(FATAL_ERROR "the installed package did not import and run (${imported})")
endif()
