# MuJoCo 2.2.2 from Debian. Its exported target names /usr/include/libqhull_r as an include
# directory (docs/mujoco.md note 1); drop it when libqhull-dev is absent so generation works.
find_package(mujoco REQUIRED)
get_target_property(_mj_inc mujoco::mujoco INTERFACE_INCLUDE_DIRECTORIES)
set(_mj_keep)
foreach(_d IN LISTS _mj_inc)
  if(EXISTS "${_d}")
    list(APPEND _mj_keep "${_d}")
  endif()
endforeach()
set_target_properties(mujoco::mujoco PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_mj_keep}")
