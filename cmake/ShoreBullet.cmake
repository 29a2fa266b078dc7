# Bullet lookup that works with Debian's libbullet-dev.
#
# Debian ships BulletConfig.cmake (float) and BulletConfig-float64.cmake (double), but
# their paths are relative to the install prefix and they define no imported targets.
# This wraps the chosen build in one imported target, Shore::BulletDeps, that carries
# the include directory, the libraries and (for float64) BT_USE_DOUBLE_PRECISION.
# The same file is installed with the package so consumers get the same target.
if(TARGET Shore::BulletDeps)
  return()
endif()

if(SHORE_DOUBLE_PRECISION)
  set(_shore_bullet_cfg "BulletConfig-float64.cmake")
else()
  set(_shore_bullet_cfg "BulletConfig.cmake")
endif()

find_file(SHORE_BULLET_CONFIG_FILE_${SHORE_DOUBLE_PRECISION} ${_shore_bullet_cfg}
  PATH_SUFFIXES lib/x86_64-linux-gnu/cmake/bullet lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/bullet
                lib/cmake/bullet lib64/cmake/bullet
  PATHS /usr /usr/local)
set(_shore_bullet_file "${SHORE_BULLET_CONFIG_FILE_${SHORE_DOUBLE_PRECISION}}")
if(NOT _shore_bullet_file)
  message(FATAL_ERROR "Shore: Bullet's ${_shore_bullet_cfg} was not found. "
                      "On Debian: apt-get install libbullet-dev")
endif()

# Read the config in a scope of its own and resolve its relative paths.
include("${_shore_bullet_file}")
set(_root "${BULLET_ROOT_DIR}")
if(NOT IS_ABSOLUTE "${BULLET_INCLUDE_DIR}")
  set(BULLET_INCLUDE_DIR "${_root}/${BULLET_INCLUDE_DIR}")
endif()
if(NOT IS_ABSOLUTE "${BULLET_LIBRARY_DIRS}")
  set(BULLET_LIBRARY_DIRS "${_root}/${BULLET_LIBRARY_DIRS}")
endif()

add_library(Shore::BulletDeps INTERFACE IMPORTED)
set(_libs "")
# Only the parts Shore uses, in link order.
if(SHORE_DOUBLE_PRECISION)
  set(_names BulletDynamics-float64 BulletCollision-float64 LinearMath-float64)
else()
  set(_names BulletDynamics BulletCollision LinearMath)
endif()
foreach(_n IN LISTS _names)
  find_library(SHORE_BULLET_LIB_${_n} NAMES ${_n} PATHS "${BULLET_LIBRARY_DIRS}" NO_DEFAULT_PATH)
  if(NOT SHORE_BULLET_LIB_${_n})
    message(FATAL_ERROR "Shore: Bullet library ${_n} not found in ${BULLET_LIBRARY_DIRS}")
  endif()
  list(APPEND _libs "${SHORE_BULLET_LIB_${_n}}")
endforeach()
set_target_properties(Shore::BulletDeps PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${BULLET_INCLUDE_DIR}"
  INTERFACE_LINK_LIBRARIES "${_libs}")
if(SHORE_DOUBLE_PRECISION)
  set_property(TARGET Shore::BulletDeps PROPERTY INTERFACE_COMPILE_DEFINITIONS BT_USE_DOUBLE_PRECISION)
endif()
message(STATUS "Shore: Bullet ${BULLET_VERSION_STRING} "
               "(${_shore_bullet_cfg}, double precision: ${SHORE_DOUBLE_PRECISION})")
