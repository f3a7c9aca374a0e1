
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/main/tools/bench.cpp" "CMakeFiles/vrpd_cli.dir/tools/bench.cpp.o" "gcc" "CMakeFiles/vrpd_cli.dir/tools/bench.cpp.o.d"
  "/work/main/tools/vrpd.cpp" "CMakeFiles/vrpd_cli.dir/tools/vrpd.cpp.o" "gcc" "CMakeFiles/vrpd_cli.dir/tools/vrpd.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  "/work/main/build-prof/CMakeFiles/vrpd.dir/DependInfo.cmake"
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
