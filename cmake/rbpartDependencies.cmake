# The libraries rbpart links, all from Debian packages (scripts/install_deps.sh), as imported targets.
# Included by CMakeLists.txt and by the installed package (rbpartConfig.cmake), so a program that
# embeds the library links exactly what the library was built against:
#   Eigen3::Eigen, TBB::tbb, ZLIB::ZLIB     their own CMake packages
#   PkgConfig::RBPART_BULLET                Bullet in double precision (pkg-config bullet-float64)
#   rbpart::suitesparse                     SuiteSparse's AMD and CAMD orderings (solve/block_lu.cpp)
#   rbpart::metis                           METIS
find_package(Eigen3 3.3 REQUIRED CONFIG)
find_package(TBB REQUIRED CONFIG)
find_package(ZLIB REQUIRED)  # recordings are gzip streams (io/recording)
find_package(PkgConfig REQUIRED)
if(NOT TARGET PkgConfig::RBPART_BULLET)
  pkg_check_modules(RBPART_BULLET REQUIRED IMPORTED_TARGET bullet-float64)
endif()

if(NOT TARGET rbpart::suitesparse)
  find_path(RBPART_AMD_INCLUDE_DIR amd.h PATH_SUFFIXES suitesparse REQUIRED)
  set(rbpart_suitesparse_libraries "")
  foreach(lib amd camd suitesparseconfig)
    find_library(RBPART_SUITESPARSE_${lib} ${lib} REQUIRED)
    list(APPEND rbpart_suitesparse_libraries ${RBPART_SUITESPARSE_${lib}})
  endforeach()
  add_library(rbpart::suitesparse INTERFACE IMPORTED)
  set_target_properties(rbpart::suitesparse PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${RBPART_AMD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${rbpart_suitesparse_libraries}")
endif()

if(NOT TARGET rbpart::metis)
  find_path(RBPART_METIS_INCLUDE_DIR metis.h REQUIRED)
  find_library(RBPART_METIS_LIBRARY metis REQUIRED)
  add_library(rbpart::metis INTERFACE IMPORTED)
  set_target_properties(rbpart::metis PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${RBPART_METIS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${RBPART_METIS_LIBRARY}")
endif()
