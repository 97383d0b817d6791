# Debian ships Bullet's double-precision build as BulletConfig-float64.cmake, but its paths are relative to
# BULLET_ROOT_DIR and BULLET_LIBRARIES names BulletInverseDynamics, which Debian does not ship. We wrap the three
# libraries we use and the BT_USE_DOUBLE_PRECISION define in one imported target, so a mismatch of define and
# libraries (which links, then gives silently wrong physics) cannot happen.
find_package(Bullet REQUIRED CONFIG CONFIGS BulletConfig-float64.cmake)
if(NOT TARGET Swarmform::Bullet)
  set(_bullet_root "${BULLET_ROOT_DIR}")
  set(_bullet_inc "${_bullet_root}/${BULLET_INCLUDE_DIR}")
  set(_bullet_libdir "${_bullet_root}/${BULLET_LIBRARY_DIRS}")
  add_library(Swarmform::Bullet INTERFACE IMPORTED GLOBAL)
  set(_libs)
  foreach(_lib BulletDynamics-float64 BulletCollision-float64 LinearMath-float64)
    find_library(_path_${_lib} NAMES ${_lib} PATHS ${_bullet_libdir} NO_DEFAULT_PATH REQUIRED)
    list(APPEND _libs ${_path_${_lib}})
  endforeach()
  set_target_properties(Swarmform::Bullet PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_bullet_inc}"
    INTERFACE_COMPILE_DEFINITIONS "BT_USE_DOUBLE_PRECISION"
    INTERFACE_LINK_LIBRARIES "${_libs}")
endif()
