file(REMOVE_RECURSE
  "CMakeFiles/vrpd_spirv"
  "spirv/commit_cells.h"
  "spirv/count_darts.h"
  "spirv/emit_samples.h"
  "spirv/init_cells.h"
  "spirv/refine_cells.h"
  "spirv/resolve_darts.h"
  "spirv/scan_add.h"
  "spirv/scan_blocks.h"
  "spirv/scan_sums.h"
  "spirv/scatter_cells.h"
  "spirv/throw_darts.h"
  "spirv/work_args.h"
)

# Per-language clean rules from dependency scanning.
foreach(lang )
  include(CMakeFiles/vrpd_spirv.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
