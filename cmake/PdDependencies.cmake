# Finds every dependency. Each failure names the Debian 12 package to install
# (scripts/install-deps.sh installs them all).

macro(pd_require found what package)
  if(NOT ${found})
    message(FATAL_ERROR "${what} not found: install the Debian package '${package}' "
                        "(or run: sudo scripts/install-deps.sh)")
  endif()
endmacro()

# gmsh ships neither a CMake config nor a pkg-config file in Debian 12.
find_path(GMSH_INCLUDE_DIR gmsh.h)
find_library(GMSH_LIBRARY gmsh)
if(GMSH_INCLUDE_DIR AND GMSH_LIBRARY)
  set(GMSH_FOUND TRUE)
endif()
pd_require(GMSH_FOUND "gmsh C++ API (gmsh.h, libgmsh)" libgmsh-dev)
add_library(Gmsh::gmsh UNKNOWN IMPORTED)
set_target_properties(Gmsh::gmsh PROPERTIES
  IMPORTED_LOCATION ${GMSH_LIBRARY}
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES ${GMSH_INCLUDE_DIR})

find_package(Eigen3 3.3 QUIET NO_MODULE)
pd_require(Eigen3_FOUND "Eigen3" libeigen3-dev)

find_package(nanoflann QUIET)
pd_require(nanoflann_FOUND "nanoflann" libnanoflann-dev)

find_package(CGAL QUIET)
pd_require(CGAL_FOUND "CGAL" libcgal-dev)

find_package(Boost 1.74 QUIET COMPONENTS program_options)
pd_require(Boost_FOUND "Boost.Program_options" libboost-program-options-dev)

find_package(tomlplusplus QUIET)
pd_require(tomlplusplus_FOUND "toml++ (TOML parser for scene files)" libtomlplusplus-dev)

find_package(OpenMP QUIET COMPONENTS CXX)
pd_require(OpenMP_CXX_FOUND "OpenMP for C++" "libgomp1 (part of g++)")

find_package(VTK 9 QUIET COMPONENTS CommonCore CommonDataModel CommonExecutionModel IOXML IOImage)
pd_require(VTK_FOUND "VTK 9 (CommonCore, CommonDataModel, CommonExecutionModel, IOXML, IOImage)" libvtk9-dev)

if(PD_BUILD_TESTS)
  find_package(Catch2 2 QUIET)
  pd_require(Catch2_FOUND "Catch2 v2" catch2)
endif()

# MPI (Open MPI: libopenmpi-dev, openmpi-bin) for runs on several processes
# (docs/solver.md, "Running on several processes (MPI)"). Optional: AUTO
# builds with it when found; OFF builds the one-process solver as before; ON
# stops when it is missing.
set(PD_WITH_MPI AUTO CACHE STRING "Build pd-solve with MPI domain decomposition: AUTO, ON or OFF")
set_property(CACHE PD_WITH_MPI PROPERTY STRINGS AUTO ON OFF)
set(PD_MPI_ENABLED FALSE)
if(NOT PD_WITH_MPI STREQUAL "OFF")
  find_package(MPI QUIET COMPONENTS CXX)
  if(MPI_CXX_FOUND)
    set(PD_MPI_ENABLED TRUE)
  elseif(PD_WITH_MPI STREQUAL "ON")
    pd_require(MPI_CXX_FOUND "MPI for C++ (PD_WITH_MPI=ON)" "libopenmpi-dev")
  endif()
endif()
message(STATUS "pd-solve with MPI: ${PD_MPI_ENABLED}")
