file(REMOVE_RECURSE
  "CMakeFiles/vrpd_cli.dir/tools/bench.cpp.o"
  "CMakeFiles/vrpd_cli.dir/tools/bench.cpp.o.d"
  "CMakeFiles/vrpd_cli.dir/tools/vrpd.cpp.o"
  "CMakeFiles/vrpd_cli.dir/tools/vrpd.cpp.o.d"
  "vrpd"
  "vrpd.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/vrpd_cli.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
