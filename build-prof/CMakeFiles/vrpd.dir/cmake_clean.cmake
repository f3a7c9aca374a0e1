file(REMOVE_RECURSE
  "CMakeFiles/vrpd.dir/host/src/driver.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/driver.cpp.o.d"
  "CMakeFiles/vrpd.dir/host/src/host_engine.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/host_engine.cpp.o.d"
  "CMakeFiles/vrpd.dir/host/src/io.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/io.cpp.o.d"
  "CMakeFiles/vrpd.dir/host/src/plan.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/plan.cpp.o.d"
  "CMakeFiles/vrpd.dir/host/src/thread_pool.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/thread_pool.cpp.o.d"
  "CMakeFiles/vrpd.dir/host/src/vulkan_context.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/vulkan_context.cpp.o.d"
  "CMakeFiles/vrpd.dir/host/src/vulkan_engine.cpp.o"
  "CMakeFiles/vrpd.dir/host/src/vulkan_engine.cpp.o.d"
  "libvrpd.a"
  "libvrpd.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/vrpd.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
