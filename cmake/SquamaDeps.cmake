# Every dependency is a Debian 12 package (scripts/deps installs them). Each is linked
# privately to the one module that needs it.
find_package(PkgConfig REQUIRED)
pkg_check_modules(CJSON REQUIRED IMPORTED_TARGET libcjson)
find_package(OpenMP REQUIRED COMPONENTS C)

if(NOT SQUAMA_FUZZ)
  find_package(OpenImageIO CONFIG REQUIRED)
  find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc saliency)
  pkg_check_modules(NLOPT REQUIRED IMPORTED_TARGET nlopt)
  find_package(GSL REQUIRED)
  find_package(Threads REQUIRED)
  pkg_check_modules(CMOCKA REQUIRED IMPORTED_TARGET cmocka)

  set(SQUAMA_HAVE_MPI OFF)
  if(NOT SQUAMA_MPI STREQUAL "OFF")
    if(SQUAMA_MPI STREQUAL "ON")
      find_package(MPI REQUIRED COMPONENTS C)
    else()
      find_package(MPI QUIET COMPONENTS C)
    endif()
    set(SQUAMA_HAVE_MPI ${MPI_C_FOUND})
  endif()
  message(STATUS "squama: OpenImageIO ${OpenImageIO_VERSION}, OpenCV ${OpenCV_VERSION}, "
                 "nlopt ${NLOPT_VERSION}, GSL ${GSL_VERSION}, cJSON ${CJSON_VERSION}, "
                 "MPI ${SQUAMA_HAVE_MPI}")
endif()
