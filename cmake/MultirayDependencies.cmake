# Every third-party library comes from Debian's packages (see README for the apt line).
find_package(Threads REQUIRED)
find_package(embree 3 REQUIRED)
find_package(TBB REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(tinyobjloader REQUIRED)
find_package(tinyxml2 REQUIRED)     # Mitsuba 3 scene XML (src/scene/load_mitsuba.cpp)
find_package(OpenEXR REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(nanoflann REQUIRED)  # k nearest samples of foveated sampling
find_package(dlib REQUIRED)       # dlib::dlib (needs libblas-dev, liblapack-dev, libjpeg-dev)

# Teem (NRRD volumes, src/volume). Debian's TeemConfig.cmake defines Teem_INCLUDE_DIRS but
# its imported target `teem` points into the package's build tree, so multiray::teem is
# made here from the installed library and headers (<teem/nrrd.h>).
find_package(Teem REQUIRED NO_MODULE)
find_library(MULTIRAY_TEEM_LIBRARY NAMES teem HINTS ${Teem_ROOT_DIR}/lib ${Teem_LIBRARY_DIRS}
             REQUIRED)
find_path(MULTIRAY_TEEM_INCLUDE_DIR teem/nrrd.h HINTS ${Teem_INCLUDE_DIRS} REQUIRED)
if(NOT TARGET multiray::teem)
  add_library(multiray::teem UNKNOWN IMPORTED)
  set_target_properties(multiray::teem PROPERTIES
    IMPORTED_LOCATION "${MULTIRAY_TEEM_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${MULTIRAY_TEEM_INCLUDE_DIR}")
endif()
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
# xxHash's XXH3: the images' and feature buffers' fingerprints (core/image.h), hashed every
# frame (the viewer twice); Debian's libxxhash-dev.
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)

# OpenCL backend (src/device/opencl). MULTIRAY_WITH_OPENCL:
#   AUTO (default) build it when the OpenCL loader and the C++ header are found, else warn;
#   ON   strict: fail the configure when it cannot be built (CI, packagers);
#   OFF  never build it.
# Sets MULTIRAY_OPENCL_ENABLED for src/device.
set(MULTIRAY_WITH_OPENCL AUTO CACHE STRING "Build the OpenCL device backend: AUTO, ON or OFF")
set_property(CACHE MULTIRAY_WITH_OPENCL PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${MULTIRAY_WITH_OPENCL}" _multiray_ocl_mode)
set(MULTIRAY_OPENCL_ENABLED OFF)
if(_multiray_ocl_mode STREQUAL "AUTO" OR _multiray_ocl_mode STREQUAL "ON")
  find_package(OpenCL QUIET)
  find_package(OpenCLHeaders QUIET)
  find_package(OpenCLHeadersCpp QUIET)
  if(OpenCL_FOUND AND TARGET OpenCL::HeadersCpp)
    set(MULTIRAY_OPENCL_ENABLED ON)
    message(STATUS "multiray: OpenCL backend enabled (${OpenCL_LIBRARIES})")
  else()
    set(_multiray_ocl_why "needs ocl-icd-opencl-dev, opencl-headers and opencl-clhpp-headers")
    if(_multiray_ocl_mode STREQUAL "ON")
      message(FATAL_ERROR "MULTIRAY_WITH_OPENCL=ON but OpenCL cannot be built: ${_multiray_ocl_why}")
    endif()
    message(WARNING "multiray: OpenCL backend disabled (${_multiray_ocl_why})")
  endif()
elseif(NOT _multiray_ocl_mode STREQUAL "OFF")
  message(FATAL_ERROR "MULTIRAY_WITH_OPENCL must be AUTO, ON or OFF, not '${MULTIRAY_WITH_OPENCL}'")
endif()

# assimp (Debian's libassimp-dev) reads the mesh formats without a dedicated loader
# (src/scene/load_assimp.cpp: FBX, COLLADA, 3DS, ...). MULTIRAY_WITH_ASSIMP:
#   AUTO (default) use it when found, else warn: those formats then give a one-line error;
#   ON   strict: fail the configure without it;  OFF  never use it.
# Sets MULTIRAY_ASSIMP_ENABLED for src/scene.
set(MULTIRAY_WITH_ASSIMP AUTO CACHE STRING "Read FBX, DAE, 3DS, ... through assimp: AUTO, ON or OFF")
set_property(CACHE MULTIRAY_WITH_ASSIMP PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${MULTIRAY_WITH_ASSIMP}" _multiray_assimp_mode)
set(MULTIRAY_ASSIMP_ENABLED OFF)
if(_multiray_assimp_mode STREQUAL "AUTO" OR _multiray_assimp_mode STREQUAL "ON")
  find_package(assimp 5 QUIET)
  if(assimp_FOUND AND TARGET assimp::assimp)
    set(MULTIRAY_ASSIMP_ENABLED ON)
    message(STATUS "multiray: assimp ${assimp_VERSION} enabled")
  elseif(_multiray_assimp_mode STREQUAL "ON")
    message(FATAL_ERROR "MULTIRAY_WITH_ASSIMP=ON but assimp 5 was not found (libassimp-dev)")
  else()
    message(WARNING "multiray: assimp not found (libassimp-dev): FBX, DAE, 3DS, ... disabled")
  endif()
elseif(NOT _multiray_assimp_mode STREQUAL "OFF")
  message(FATAL_ERROR "MULTIRAY_WITH_ASSIMP must be AUTO, ON or OFF, not '${MULTIRAY_WITH_ASSIMP}'")
endif()

# MPI (Debian's Open MPI) for `--distributed` runs: a master rank and worker ranks
# (src/device/remote, src/engine/rank_worker.*). MULTIRAY_WITH_MPI:
#   AUTO (default) build it when MPI's C++ bindings are found, else warn;
#   ON   strict: fail the configure without it;  OFF  never build it.
# Sets MULTIRAY_MPI_ENABLED for src/device and src/engine, and MULTIRAY_MPIEXEC for tests.
set(MULTIRAY_WITH_MPI AUTO CACHE STRING "Build the MPI master/worker support: AUTO, ON or OFF")
set_property(CACHE MULTIRAY_WITH_MPI PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${MULTIRAY_WITH_MPI}" _multiray_mpi_mode)
set(MULTIRAY_MPI_ENABLED OFF)
if(_multiray_mpi_mode STREQUAL "AUTO" OR _multiray_mpi_mode STREQUAL "ON")
  find_package(MPI QUIET COMPONENTS CXX)
  if(MPI_CXX_FOUND AND TARGET MPI::MPI_CXX AND MPIEXEC_EXECUTABLE)
    set(MULTIRAY_MPI_ENABLED ON)
    message(STATUS "multiray: MPI enabled (${MPIEXEC_EXECUTABLE})")
  elseif(_multiray_mpi_mode STREQUAL "ON")
    message(FATAL_ERROR "MULTIRAY_WITH_MPI=ON but MPI was not found (libopenmpi-dev, openmpi-bin)")
  else()
    message(WARNING "multiray: MPI not found (libopenmpi-dev, openmpi-bin): --distributed disabled")
  endif()
elseif(NOT _multiray_mpi_mode STREQUAL "OFF")
  message(FATAL_ERROR "MULTIRAY_WITH_MPI must be AUTO, ON or OFF, not '${MULTIRAY_WITH_MPI}'")
endif()

# The live viewer (`multiray view`, src/app/viewer): an HTTP + WebSocket server from
# Debian's civetweb. MULTIRAY_WITH_VIEWER: AUTO (default) build it when civetweb is found,
# else warn; ON strict; OFF never. Sets MULTIRAY_VIEWER_ENABLED for src/app.
set(MULTIRAY_WITH_VIEWER AUTO CACHE STRING "Build the live viewer (civetweb): AUTO, ON or OFF")
set_property(CACHE MULTIRAY_WITH_VIEWER PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${MULTIRAY_WITH_VIEWER}" _multiray_viewer_mode)
set(MULTIRAY_VIEWER_ENABLED OFF)
if(_multiray_viewer_mode STREQUAL "AUTO" OR _multiray_viewer_mode STREQUAL "ON")
  # Not find_package(civetweb): Debian's config file also imports the `civetweb` server
  # program and fails the configure when that package is not installed.
  find_path(CIVETWEB_INCLUDE_DIR civetweb.h)
  find_library(CIVETWEB_LIBRARY civetweb)
  if(CIVETWEB_INCLUDE_DIR AND CIVETWEB_LIBRARY AND NOT TARGET multiray_civetweb)
    add_library(multiray_civetweb UNKNOWN IMPORTED)
    set_target_properties(multiray_civetweb PROPERTIES IMPORTED_LOCATION "${CIVETWEB_LIBRARY}"
                          INTERFACE_INCLUDE_DIRECTORIES "${CIVETWEB_INCLUDE_DIR}")
  endif()
  if(TARGET multiray_civetweb)
    set(MULTIRAY_VIEWER_ENABLED ON)
    message(STATUS "multiray: live viewer enabled (civetweb)")
  elseif(_multiray_viewer_mode STREQUAL "ON")
    message(FATAL_ERROR "MULTIRAY_WITH_VIEWER=ON but civetweb was not found (libcivetweb-dev)")
  else()
    message(WARNING "multiray: civetweb not found (libcivetweb-dev): `multiray view` disabled")
  endif()
elseif(NOT _multiray_viewer_mode STREQUAL "OFF")
  message(FATAL_ERROR "MULTIRAY_WITH_VIEWER must be AUTO, ON or OFF, not '${MULTIRAY_WITH_VIEWER}'")
endif()

# zstd (Debian's libzstd-dev) compresses the results workers send to the master
# (`--result-encoding float+zstd` and `half+zstd`, src/distributed/pixel_codec.cpp).
# MULTIRAY_WITH_ZSTD: AUTO (default) use it when found, else warn: those encodings are then
# refused in one line and results travel as plain floats; ON strict; OFF never.
# Sets MULTIRAY_ZSTD_ENABLED (target PkgConfig::ZSTD) for src/distributed.
set(MULTIRAY_WITH_ZSTD AUTO CACHE STRING "Compress distributed results with zstd: AUTO, ON or OFF")
set_property(CACHE MULTIRAY_WITH_ZSTD PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${MULTIRAY_WITH_ZSTD}" _multiray_zstd_mode)
set(MULTIRAY_ZSTD_ENABLED OFF)
if(_multiray_zstd_mode STREQUAL "AUTO" OR _multiray_zstd_mode STREQUAL "ON")
  pkg_check_modules(ZSTD QUIET IMPORTED_TARGET libzstd)
  if(ZSTD_FOUND AND TARGET PkgConfig::ZSTD)
    set(MULTIRAY_ZSTD_ENABLED ON)
    message(STATUS "multiray: zstd ${ZSTD_VERSION} enabled (compressed results)")
  elseif(_multiray_zstd_mode STREQUAL "ON")
    message(FATAL_ERROR "MULTIRAY_WITH_ZSTD=ON but zstd was not found (libzstd-dev)")
  else()
    message(WARNING "multiray: zstd not found (libzstd-dev): --result-encoding *+zstd disabled")
  endif()
elseif(NOT _multiray_zstd_mode STREQUAL "OFF")
  message(FATAL_ERROR "MULTIRAY_WITH_ZSTD must be AUTO, ON or OFF, not '${MULTIRAY_WITH_ZSTD}'")
endif()
