
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/main/host/src/driver.cpp" "CMakeFiles/vrpd.dir/host/src/driver.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/driver.cpp.o.d"
  "/work/main/host/src/host_engine.cpp" "CMakeFiles/vrpd.dir/host/src/host_engine.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/host_engine.cpp.o.d"
  "/work/main/host/src/io.cpp" "CMakeFiles/vrpd.dir/host/src/io.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/io.cpp.o.d"
  "/work/main/host/src/plan.cpp" "CMakeFiles/vrpd.dir/host/src/plan.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/plan.cpp.o.d"
  "/work/main/host/src/thread_pool.cpp" "CMakeFiles/vrpd.dir/host/src/thread_pool.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/thread_pool.cpp.o.d"
  "/work/main/host/src/vulkan_context.cpp" "CMakeFiles/vrpd.dir/host/src/vulkan_context.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/vulkan_context.cpp.o.d"
  "/work/main/host/src/vulkan_engine.cpp" "CMakeFiles/vrpd.dir/host/src/vulkan_engine.cpp.o" "gcc" "CMakeFiles/vrpd.dir/host/src/vulkan_engine.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
