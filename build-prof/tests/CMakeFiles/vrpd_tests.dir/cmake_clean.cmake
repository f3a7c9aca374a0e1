file(REMOVE_RECURSE
  "CMakeFiles/vrpd_tests.dir/main.cpp.o"
  "CMakeFiles/vrpd_tests.dir/main.cpp.o.d"
  "CMakeFiles/vrpd_tests.dir/test_sampling.cpp.o"
  "CMakeFiles/vrpd_tests.dir/test_sampling.cpp.o.d"
  "vrpd_tests"
  "vrpd_tests.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/vrpd_tests.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
