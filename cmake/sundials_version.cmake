# The SUNDIALS versions kanesens builds with. The integrator uses the SUNDIALS 6 API (SUNContext
# arguments everywhere, sunrealtype, CVodeSetProjFn); SUNDIALS 5 lacks it and SUNDIALS 7 changed
# it (SUNContext_Create's communicator, error handling), so any other major version stops the
# configure step here with one message instead of compile errors later.
#
#   include(cmake/sundials_version.cmake)
#   kanesens_check_sundials_version("${SUNDIALS_VERSION}")
#
# As a script (used by tests/product/test_sundials_version_check.sh):
#   cmake -DVERSION=7.1.1 -P cmake/sundials_version.cmake      # fails with the message
set(KANESENS_SUNDIALS_MAJOR 6)
set(KANESENS_SUNDIALS_TESTED 6.4.1)

function(kanesens_check_sundials_version version)
  string(REGEX MATCH "^[0-9]+" major "${version}")
  if(NOT major STREQUAL "${KANESENS_SUNDIALS_MAJOR}")
    if(version STREQUAL "")
      set(version "of unknown version")
    endif()
    message(FATAL_ERROR
      "kanesens needs SUNDIALS ${KANESENS_SUNDIALS_MAJOR}.x (tested with "
      "${KANESENS_SUNDIALS_TESTED}); CMake found SUNDIALS ${version}"
      "${SUNDIALS_DIR_NOTE}. Install SUNDIALS ${KANESENS_SUNDIALS_MAJOR} (Debian 12: "
      "libsundials-dev; Spack: sundials@6; conda-forge: sundials=6) and point CMake at it with "
      "-DSUNDIALS_DIR=<prefix>/lib/cmake/sundials.")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  kanesens_check_sundials_version("${VERSION}")
  message(STATUS "SUNDIALS ${VERSION}: supported")
endif()
